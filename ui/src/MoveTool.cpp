#include "MoveTool.hpp"

#include "Expression.hpp"
#include "LengthDisplay.hpp"

#include "DocumentSession.hpp"
#include "NodeText.hpp"
#include "kerf/document/DocumentEdits.hpp"
#include "kerf/document/NodePlacement.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"

#include <QRegularExpression>

#include <glm/geometric.hpp>

#include <unordered_set>

namespace kerf::ui {

namespace {

// How near (pixels) another feature's face or centre pulls the dragged one.
constexpr double kAlignPixels = 8.0;

const char* const kAxisName[3] = {"X", "Y", "Z"};

// "32 mm", "-48.5 mm"; in inches "1 1/4\"" or "≈ 1 17/64\"".
QString distanceText(double mm)
{
    if (LengthDisplay::instance().unit() == LengthUnit::Inches) return LengthDisplay::instance().readout(mm);
    return QString::number(mm, 'f', 2).remove(QRegularExpression("\\.?0+$")) + " mm";
}

} // namespace

MoveTool::MoveTool(DocumentSession* session, qt::ViewportWidget* viewport, QObject* parent)
    : QObject(parent), session_(session), viewport_(viewport)
{
    connect(viewport_, &qt::ViewportWidget::gizmoDragStarted, this, &MoveTool::started);
    connect(viewport_, &qt::ViewportWidget::gizmoDragged, this, &MoveTool::dragged);
    connect(viewport_, &qt::ViewportWidget::gizmoDragFinished, this, &MoveTool::finished);
}

void MoveTool::setNode(const std::string& id)
{
    if (dragging_) return; // the drag's own edits: the gizmo follows in place()
    id_ = id == session_->document().root.id ? std::string() : id;
    place();
}

void MoveTool::setEnabled(bool on)
{
    enabled_ = on;
    place();
}

void MoveTool::place()
{
    std::optional<glm::dvec3> origin;
    if (enabled_ && !id_.empty() && session_->document().root.find(id_)) {
        const Aabb b = edit::firstInstanceBounds(session_->document(), id_);
        if (!b.isEmpty() && b.isBounded()) origin = b.center();
    }
    viewport_->setMoveGizmo(origin);
}

void MoveTool::started()
{
    if (id_.empty()) return;
    dragging_ = true;
    moved_ = false;
    start_ = session_->document();
    startBounds_ = edit::firstInstanceBounds(start_, id_);
    // Every other primitive copy, by its placed bounds: what the drag lines up with.
    const Node* node = start_.root.find(id_);
    const std::unordered_set<std::string> moving = node ? edit::idsInSubtree(*node) : std::unordered_set<std::string>{};
    targets_.clear();
    try {
        const Tape tape = compileTape(start_);
        for (const ShapeInstance& s : tape.shapes()) {
            const std::string& owner = tape.features()[s.feature].nodeId;
            if (moving.count(owner)) continue;
            const Node* n = start_.root.find(owner);
            targets_.push_back({n ? featureName(*n).toStdString() : owner, s.worldBounds});
        }
    } catch (const std::exception&) {
        // Nothing to line up with: the grid still snaps.
    }
}

void MoveTool::dragged(const qt::GizmoDrag& drag)
{
    if (!dragging_) return;
    const int axis = gizmoAxisIndex(drag.handle);
    if (axis < 0) return;
    const double reach = kAlignPixels * drag.millimetresPerPixel;
    const LengthUnit unit = LengthDisplay::instance().unit();
    const double step = drag.free ? 0.0 : gridStepFor(drag.millimetresPerPixel, unit);
    glm::dvec3 delta(0.0);
    QString how;
    if (!isPlaneHandle(drag.handle)) {
        const double raw = drag.displacement[axis];
        if (!drag.typed.isEmpty()) {
            // In the unit shown: "48.5" is millimetres or inches, "1 1/2" an inch and a half.
            const std::optional<double> typed = evaluateLength(drag.typed.toStdString(), unit).value;
            delta[axis] = typed.value_or(0.0);
            const QString mark = unit == LengthUnit::Inches ? QStringLiteral("\"") : QStringLiteral(" mm");
            how = tr("typed: %1%2, Enter to finish").arg(drag.typed, mark);
        } else if (drag.free) {
            delta[axis] = raw;
            how = tr("no snapping");
        } else {
            const AxisSnap s = snapAxisMove(startBounds_, axis, raw, targets_, reach, step, unit);
            delta[axis] = s.delta;
            how = QString::fromStdString(s.reason);
        }
    } else {
        QStringList reasons;
        for (int a = 0; a < 3; ++a) {
            if (a == axis) continue;
            const AxisSnap s = drag.free ? AxisSnap{drag.displacement[a], {}}
                                         : snapAxisMove(startBounds_, a, drag.displacement[a], targets_, reach, step, unit);
            delta[a] = s.delta;
            if (!s.reason.empty()) reasons << QString("%1 %2").arg(kAxisName[a], QString::fromStdString(s.reason));
        }
        how = drag.free ? tr("no snapping") : reasons.join("; ");
    }
    const Node* node = start_.root.find(id_);
    if (!node) return;
    // A coordinate set by an expression stays as its expression says.
    std::vector<int> held;
    delta = edit::moveKeepingExpressions(start_, id_, delta, &held);
    QStringList heldText;
    for (const int a : held) {
        const std::string& expression = node->expressions.at("transform.translate[" + std::to_string(a) + "]");
        heldText << tr("its %1 is set by =%2").arg(kAxisName[a], QString::fromStdString(expression));
    }
    const QString heldNote = heldText.join(tr(" and "));
    QString where;
    if (!isPlaneHandle(drag.handle)) {
        where = tr("%1 along %2").arg(distanceText(delta[axis]), kAxisName[axis]);
    } else {
        QStringList parts;
        for (int a = 0; a < 3; ++a)
            if (a != axis) parts << QString("%1 %2").arg(kAxisName[a], distanceText(delta[a]));
        where = tr("by %1").arg(parts.join(", "));
    }
    const QString text = tr("Move %1 %2").arg(featureName(*node), where);
    QString error;
    const std::string id = id_;
    const Document start = start_;
    if (!session_->preview(text, [&](Document& d) {
            d = start;
            edit::moveNodeInWorld(d, id, delta);
        }, &error)) {
        emit message(error);
        return;
    }
    moved_ = moved_ || delta != glm::dvec3(0.0);
    place();
    if (!heldNote.isEmpty() && delta == glm::dvec3(0.0))
        emit message(tr("%1 stays where it is: %2. Change that in the Properties.").arg(featureName(*node), heldNote));
    else if (!heldNote.isEmpty())
        emit message(tr("%1 (%2%3, which stays). Type a distance; Esc cancels.")
                         .arg(text, how.isEmpty() ? QString() : how + "; ", heldNote));
    else
        emit message(tr("%1 (%2). Type a distance; Esc cancels.").arg(text, how));
}

void MoveTool::finished(bool cancelled)
{
    if (!dragging_) return;
    dragging_ = false;
    // One step for the drag, or none: Esc takes it back, Redo keeps what it had.
    session_->endPreview(!cancelled);
    emit message(cancelled && moved_ ? tr("Move cancelled.") : QString());
    place();
}

} // namespace kerf::ui
