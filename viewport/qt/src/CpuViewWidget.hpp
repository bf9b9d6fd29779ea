#pragma once
// The viewport without Vulkan: the CPU reference tracer (the same algorithm
// as the GPU tracer) traces each new view on a worker thread and this widget
// paints the shaded picture, with the axis gizmo, and says which tracer
// draws. Meshes and the ground grid are not drawn here.

#include "kerf/viewport/ViewportRenderer.hpp"
#include "kerf/viewport/qt/ViewportWidget.hpp"

#include <QImage>
#include <QWidget>

#include <condition_variable>
#include <mutex>
#include <thread>

namespace kerf::qt {

class CpuViewWidget : public QWidget {
    Q_OBJECT
public:
    CpuViewWidget(ViewportWidget* owner, QString reason);
    ~CpuViewWidget() override;

    void show(const vk::ViewportScene& scene);
    QImage grab(const vk::ViewportScene& scene, int timeoutMs);

signals:
    void frameDrawn(const kerf::qt::ViewportStatus& status);

protected:
    void paintEvent(QPaintEvent*) override;
    void resizeEvent(QResizeEvent*) override;
    void mousePressEvent(QMouseEvent* e) override;
    void mouseMoveEvent(QMouseEvent* e) override;
    void mouseReleaseEvent(QMouseEvent* e) override;
    void wheelEvent(QWheelEvent* e) override;
    void keyPressEvent(QKeyEvent* e) override;

private:
    void work();

    ViewportWidget* owner_;
    QString reason_;
    QImage picture_;   // GUI thread
    glm::dvec3 right_{1, 0, 0}, up_{0, 0, 1}, forward_{0, 1, 0};

    std::mutex mutex_;
    std::condition_variable wake_, grabbed_;
    vk::ViewportScene scene_;
    QSize size_;
    bool dirty_ = false, stop_ = false;
    std::uint64_t frames_ = 0;
    std::uint64_t sceneSerial_ = 0, renderedSerial_ = 0; // scenes handed in; the last one drawn
    QImage lastImage_;
    std::thread worker_;
};

} // namespace kerf::qt
