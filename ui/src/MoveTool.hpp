#pragma once
// Moving the selected feature with the viewport's gizmo: the gizmo sits at
// the centre of the feature (its first copy), a drag along an arrow or in a
// square moves it live, snapped to other features (faces and centres lined
// up) or else to round steps of the grid (Ctrl: no snapping); digits typed
// during the drag give the exact distance. A drag is one undo step; Esc
// puts the feature back and leaves no step.

#include "kerf/document/Aabb.hpp"
#include "kerf/document/Document.hpp"
#include "kerf/document/MoveSnap.hpp"
#include "kerf/viewport/qt/ViewportWidget.hpp"

#include <QObject>
#include <QString>

#include <string>
#include <vector>

namespace kerf::ui {

class DocumentSession;

class MoveTool : public QObject {
    Q_OBJECT
public:
    MoveTool(DocumentSession* session, qt::ViewportWidget* viewport, QObject* parent = nullptr);

    /// The feature the gizmo moves: one selected node, not the root (empty:
    /// no gizmo). Call again when the document changes: the gizmo follows.
    void setNode(const std::string& id);
    /// Hides the gizmo while another tool (measuring) uses the clicks.
    void setEnabled(bool on);
    bool dragging() const { return dragging_; }

signals:
    /// A line for the status bar (what the drag does; empty when it ends).
    void message(const QString& text);

private:
    void place();
    void started();
    void dragged(const qt::GizmoDrag& drag);
    void finished(bool cancelled);

    DocumentSession* session_;
    qt::ViewportWidget* viewport_;
    std::string id_;
    bool enabled_ = true;
    // The drag under way.
    bool dragging_ = false, moved_ = false;
    Document start_;
    Aabb startBounds_;
    std::vector<SnapTarget> targets_;
    QString lastText_;
};

} // namespace kerf::ui
