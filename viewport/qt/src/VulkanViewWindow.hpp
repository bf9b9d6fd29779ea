#pragma once
// A QWindow with a Vulkan surface, drawn by a ViewportRenderer on a render
// thread of its own: the GUI thread hands it scenes and is never blocked by
// a frame. Input events go to the owning ViewportWidget.
//
// Surface lifetime: the swapchain is released (and the render thread
// stopped) when Qt announces that the surface is about to be destroyed, and
// in the destructor, before QWindow destroys the platform window.

#include "kerf/viewport/ViewportRenderer.hpp"
#include "kerf/viewport/VulkanContext.hpp"
#include "kerf/viewport/qt/ViewportWidget.hpp"

#include <QWindow>

#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>

class QVulkanInstance;

namespace kerf::qt {

class VulkanViewWindow : public QWindow {
    Q_OBJECT
public:
    /// Throws VulkanError when no device can serve the viewport.
    VulkanViewWindow(QVulkanInstance* instance, ViewportWidget* owner, const vk::ContextOptions& options);
    ~VulkanViewWindow() override;

    void show(const vk::ViewportScene& scene);
    QImage grab(const vk::ViewportScene& scene, int timeoutMs);
    QString deviceDescription() const;
    bool hardwareGpu() const;

signals:
    void frameDrawn(const kerf::qt::ViewportStatus& status);
    void failed(const QString& reason);

protected:
    void exposeEvent(QExposeEvent*) override;
    void resizeEvent(QResizeEvent*) override;
    bool event(QEvent* e) override;
    void mousePressEvent(QMouseEvent* e) override;
    void mouseMoveEvent(QMouseEvent* e) override;
    void mouseReleaseEvent(QMouseEvent* e) override;
    void wheelEvent(QWheelEvent* e) override;
    void keyPressEvent(QKeyEvent* e) override;

private:
    void startThread();
    void stopThread();
    void renderLoop();
    void schedule();

    ViewportWidget* owner_;
    std::unique_ptr<vk::Context> context_;

    std::mutex mutex_;
    std::condition_variable wake_, grabbed_;
    vk::ViewportScene scene_;
    int width_ = 0, height_ = 0;
    bool dirty_ = false, stop_ = false;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    std::uint64_t frames_ = 0;
    bool grabRequested_ = false;
    QImage grabbedImage_;
    bool grabDone_ = false;
    std::thread thread_;
    std::unique_ptr<vk::ViewportRenderer> renderer_; // render thread only
    double lastTraceMs_ = -1.0;                      // render thread only
};

} // namespace kerf::qt
