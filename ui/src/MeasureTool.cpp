#include "MeasureTool.hpp"

#include "LengthDisplay.hpp"

#include "DocumentSession.hpp"
#include "NodeText.hpp"
#include "kerf/document/NodePlacement.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/evaluator/TightBounds.hpp"

#include <QFutureWatcher>
#include <QLabel>
#include <QtConcurrent/QtConcurrentRun>

#include <glm/geometric.hpp>

#include <cmath>
#include <optional>

namespace kerf::ui {

namespace {

// In the user's unit ("32.00 mm", "1 1/4\""), no "-0.00" for a difference
// that rounds to nothing; in lists the millimetres are said once at the end.
QString length(double mm) { return LengthDisplay::instance().readout(mm); }
QString number(double mm) { return LengthDisplay::instance().bare(mm); }
QString unit() { return LengthDisplay::instance().suffix(); }

QString pointText(const glm::dvec3& p)
{
    return QStringLiteral("(%1, %2, %3)%4").arg(number(p.x), number(p.y), number(p.z), unit());
}

QString snapText(SnapKind kind)
{
    switch (kind) {
    case SnapKind::Vertex: return MeasureTool::tr("corner");
    case SnapKind::CircleCentre: return MeasureTool::tr("centre");
    case SnapKind::Edge: return MeasureTool::tr("edge");
    case SnapKind::Face: break;
    }
    return MeasureTool::tr("face");
}

struct BoxResult {
    std::optional<Aabb> box;
    QString error;
};

} // namespace

MeasureTool::MeasureTool(DocumentSession* session, qt::ViewportWidget* viewport, QLabel* panel, QObject* parent)
    : QObject(parent), session_(session), viewport_(viewport), panel_(panel)
{
}

void MeasureTool::setActive(bool on)
{
    active_ = on;
    viewport_->setSnapping(on);
    if (!on) {
        // An unfinished measurement goes; a finished one (or a box) stays until cleared.
        if (points_.size() == 1) clear();
        if (viewport_->dimensionText().isEmpty()) panel_->clear();
        return;
    }
    clear();
    panel_->setText(tr("Click two points on the part. Corners, hole centres and edges snap; Esc clears."));
    emit message(tr("Measure: click two points (corners, hole centres and edges snap). Esc clears, M ends."));
}

bool MeasureTool::clear()
{
    const bool had = !points_.empty() || !viewport_->dimensionText().isEmpty();
    points_.clear();
    ++boxRequest_; // a box still being measured is not shown
    viewport_->setMarkers({});
    viewport_->setDimension(std::nullopt);
    viewport_->setBoxShown(std::nullopt);
    if (had) panel_->setText(active_ ? tr("Click two points on the part.") : QString());
    return had;
}

void MeasureTool::click(const qt::ViewportPick& pick)
{
    if (!pick.hit) {
        emit message(tr("Nothing of the part under the cursor: click on the part."));
        return;
    }
    if (points_.size() == 2) clear();
    points_.push_back({pick.point, pick.snap});
    std::vector<glm::dvec3> at;
    for (const auto& p : points_) at.push_back(p.at);
    viewport_->setMarkers(at);
    const Point& a = points_.front();
    if (points_.size() == 1) {
        panel_->setText(tr("Point 1: %1 %2\nClick the second point.").arg(snapText(a.kind), pointText(a.at)));
        return;
    }
    const Point& b = points_.back();
    const glm::dvec3 d = b.at - a.at;
    const QString distance = length(glm::length(d));
    panel_->setText(tr("Distance: %1\nΔX %2   ΔY %3   ΔZ %4%5\nfrom %6 %7\nto %8 %9")
                        .arg(distance, number(d.x), number(d.y), number(d.z), unit(), snapText(a.kind),
                             pointText(a.at), snapText(b.kind), pointText(b.at)));
    viewport_->setDimension(std::make_pair(a.at, b.at), distance);
}

void MeasureTool::showBoundingBox(const std::vector<std::string>& nodeIds)
{
    clear();
    const Document doc = session_->document();
    QString what;
    std::vector<Tape> tapes;
    try {
        if (nodeIds.empty()) {
            tapes.push_back(compileTape(doc));
        } else {
            for (const auto& id : nodeIds) tapes.push_back(compileTape(edit::documentOfNodeAlone(doc, id)));
            const Node* first = doc.root.find(nodeIds.front());
            what = nodeIds.size() == 1 && first ? featureName(*first) : tr("the %n selected features", "", int(nodeIds.size()));
        }
    } catch (const std::exception& e) {
        panel_->setText(QString::fromUtf8(e.what()));
        return;
    }
    panel_->setText(what.isEmpty() ? tr("Measuring the part…") : tr("Measuring %1…").arg(what));
    const std::uint64_t request = ++boxRequest_;
    auto* watcher = new QFutureWatcher<BoxResult>(this);
    connect(watcher, &QFutureWatcher<BoxResult>::finished, this, [this, watcher, request, what] {
        const BoxResult r = watcher->result();
        watcher->deleteLater();
        if (request != boxRequest_) return; // cleared or asked again meanwhile
        if (!r.error.isEmpty()) {
            panel_->setText(tr("No bounding box: %1").arg(r.error));
            return;
        }
        if (!r.box) {
            panel_->setText(what.isEmpty() ? tr("The part is empty.") : tr("%1 is empty.").arg(what));
            return;
        }
        const Aabb& b = *r.box;
        const glm::dvec3 s = b.size();
        const QString size = tr("%1 x %2 x %3%4").arg(number(s.x), number(s.y), number(s.z), unit());
        panel_->setText((what.isEmpty() ? tr("Bounding box: %1").arg(size)
                                        : tr("Bounding box of %1: %2").arg(what, size)) +
                        tr("\nX %1 … %2\nY %3 … %4\nZ %5 … %6")
                            .arg(number(b.min.x), number(b.max.x), number(b.min.y), number(b.max.y), number(b.min.z),
                                 number(b.max.z)));
        viewport_->setBoxShown(b, size);
    });
    watcher->setFuture(QtConcurrent::run([tapes = std::move(tapes)]() -> BoxResult {
        BoxResult r;
        try {
            for (const Tape& t : tapes)
                if (const auto tb = tightBounds(t, 1e-3)) r.box = r.box ? r.box->merged(tb->outer) : tb->outer;
        } catch (const std::exception& e) {
            r.error = QString::fromUtf8(e.what());
        }
        return r;
    }));
}

} // namespace kerf::ui
