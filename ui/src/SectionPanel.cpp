#include "SectionPanel.hpp"

#include "QuantityEdit.hpp"

#include <QCheckBox>
#include <QComboBox>
#include <QSignalBlocker>
#include <QSlider>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>

namespace kerf::ui {

namespace {
constexpr int kSliderSteps = 1000;
}

SectionPanel::SectionPanel(std::function<Aabb()> partBounds, std::function<glm::dvec3()> eye, QWidget* parent)
    : QWidget(parent), partBounds_(std::move(partBounds)), eye_(std::move(eye))
{
    auto* layout = new QVBoxLayout(this);
    on_ = new QCheckBox(tr("Section view"), this);
    on_->setObjectName("section.enabled");
    axis_ = new QComboBox(this);
    axis_->setObjectName("section.axis");
    axis_->addItems({tr("Across X"), tr("Across Y"), tr("Across Z")});
    slider_ = new QSlider(Qt::Horizontal, this);
    slider_->setObjectName("section.slider");
    slider_->setRange(0, kSliderSteps);
    slider_->setValue(kSliderSteps / 2);
    offset_ = new QuantityEdit(QuantityEdit::Unit::Length, this);
    offset_->setObjectName("section.offset");
    flip_ = new QCheckBox(tr("Keep the other side"), this);
    flip_->setObjectName("section.flip");
    layout->addWidget(on_);
    layout->addWidget(axis_);
    layout->addWidget(slider_);
    layout->addWidget(offset_);
    layout->addWidget(flip_);
    layout->addStretch(1);

    connect(slider_, &QSlider::valueChanged, this, [this] {
        placed_ = true;
        offset_->showValue(sliderOffset());
        publish();
    });
    connect(offset_, &QuantityEdit::valueChanged, this, [this] {
        placed_ = true;
        followOffset();
        publish();
    });
    connect(axis_, &QComboBox::currentIndexChanged, this, [this] {
        offset_->showValue(sliderOffset()); // the same place along the new axis
        faceTheEye();
        publish();
    });
    connect(on_, &QCheckBox::toggled, this, [this](bool on) {
        if (placed_) followOffset();
        else offset_->showValue(sliderOffset());
        if (on) faceTheEye();
        publish();
    });
    connect(flip_, &QCheckBox::toggled, this, &SectionPanel::publish);
}

Section SectionPanel::section() const
{
    if (!on_->isChecked()) return Section{};
    return Section::alongAxis(axis_->currentIndex(), offset_->value(), flip_->isChecked());
}

std::pair<double, double> SectionPanel::extent() const
{
    const Aabb b = partBounds_();
    const int a = axis_->currentIndex();
    return {b.min[a], b.max[a]};
}

double SectionPanel::sliderOffset() const
{
    const auto [lo, hi] = extent();
    return lo + (hi - lo) * slider_->value() / double(kSliderSteps);
}

void SectionPanel::followOffset()
{
    const auto [lo, hi] = extent();
    const double t = hi > lo ? (offset_->value() - lo) / (hi - lo) : 0.5;
    const QSignalBlocker block(slider_);
    slider_->setValue(int(std::lround(std::clamp(t, 0.0, 1.0) * kSliderSteps)));
}

void SectionPanel::publish() { emit sectionChanged(section()); }

void SectionPanel::faceTheEye()
{
    if (!eye_) return;
    // The plane cuts away where (axis) > offset, or < offset when flipped:
    // away goes the half the eye is in.
    const int a = axis_->currentIndex();
    const QSignalBlocker block(flip_);
    flip_->setChecked(eye_()[a] < offset_->value());
}

} // namespace kerf::ui
