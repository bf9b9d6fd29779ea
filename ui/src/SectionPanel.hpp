#pragma once
// The Section panel: a clipping plane across X, Y or Z at an offset typed in
// millimetres or dragged on a slider that spans the part, and which side is
// kept. It emits the section to show; the window passes it to the viewport.
//
// The typed offset is the truth and the slider follows it: a typed value is
// never replaced by the slider's rounding, nor lost when the section is
// turned off and on. The first time it is turned on it cuts through the
// middle of the part; after that where it was left.
//
// Turned on, or put across another axis, it keeps the half away from the
// eye, so that the cut faces the viewer ("Keep the other side" shows the
// choice, and the person may change it): a newcomer sectioned across Y
// looking from the front and saw the uncut face of the half kept.

#include "kerf/document/Aabb.hpp"
#include "kerf/tracer/Section.hpp"

#include <QWidget>

#include <glm/vec3.hpp>

#include <functional>
#include <utility>

class QCheckBox;
class QComboBox;
class QSlider;

namespace kerf::ui {

class QuantityEdit;

class SectionPanel : public QWidget {
    Q_OBJECT
public:
    /// `partBounds` gives the extent the slider spans (asked each time: the
    /// part changes); `eye`, where the view looks from (world mm).
    SectionPanel(std::function<Aabb()> partBounds, std::function<glm::dvec3()> eye, QWidget* parent = nullptr);

    /// The section as set (an empty Section when it is off).
    Section section() const;

signals:
    void sectionChanged(const Section& section);

private:
    std::pair<double, double> extent() const;
    double sliderOffset() const;
    void followOffset();
    void publish();
    /// Ticks "Keep the other side" where that keeps the half away from the eye.
    void faceTheEye();

    std::function<Aabb()> partBounds_;
    std::function<glm::dvec3()> eye_;
    QCheckBox* on_;
    QComboBox* axis_;
    QSlider* slider_;
    QuantityEdit* offset_;
    QCheckBox* flip_;
    bool placed_ = false; // the offset was typed or slid (kept from then on)
};

} // namespace kerf::ui
