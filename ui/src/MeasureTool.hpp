#pragma once
// Measuring in the viewport: with the tool on, the cursor snaps to corners,
// hole centres, edges and faces (on the exact field, SnapPoint.hpp); two
// clicks give a distance, drawn as a dimension in the view and written in
// the Measure panel, kept until cleared (Esc) or the next measurement. The
// bounding box of the selection (or of the part) is measured the same way:
// its edges in the view, its size beside them and in the panel.

#include "kerf/viewport/qt/ViewportWidget.hpp"

#include <QObject>
#include <QString>

#include <glm/vec3.hpp>

#include <string>
#include <vector>

class QLabel;

namespace kerf::ui {

class DocumentSession;

class MeasureTool : public QObject {
    Q_OBJECT
public:
    MeasureTool(DocumentSession* session, qt::ViewportWidget* viewport, QLabel* panel, QObject* parent = nullptr);

    /// Turns measuring on (a fresh measurement, snapping on) or off (the last
    /// dimension stays until cleared).
    void setActive(bool on);
    bool active() const { return active_; }
    /// A click on the viewport while measuring (the point already snapped).
    void click(const qt::ViewportPick& pick);
    /// Measures the box around these nodes (the whole part when empty), in
    /// the background; the panel says so meanwhile.
    void showBoundingBox(const std::vector<std::string>& nodeIds);
    /// Clears the points, the dimension and the box. False when there was nothing.
    bool clear();

signals:
    /// A line for the status bar.
    void message(const QString& text);

private:
    DocumentSession* session_;
    qt::ViewportWidget* viewport_;
    QLabel* panel_;
    bool active_ = false;
    struct Point {
        glm::dvec3 at;
        SnapKind kind;
    };
    std::vector<Point> points_;
    std::uint64_t boxRequest_ = 0; // the newest bounding box asked for
};

} // namespace kerf::ui
