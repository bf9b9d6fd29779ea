#pragma once
// How ViewportWidget draws: the Vulkan engine in a window (VulkanViewWindow)
// or the CPU reference tracer in a plain widget (CpuViewWidget). Private to
// the viewport module.

#include "kerf/viewport/ViewportRenderer.hpp"
#include "kerf/viewport/qt/ViewportWidget.hpp"

#include <QImage>
#include <QWidget>

#include <memory>

namespace kerf::qt {

class ViewportBackend {
public:
    virtual ~ViewportBackend() = default;
    /// The child widget that goes into the viewport's layout.
    virtual QWidget* widget() = 0;
    /// Schedules a frame of this scene (the newest one wins).
    virtual void show(const vk::ViewportScene& scene) = 0;
    /// The next frame's picture (waits at most timeoutMs; null on timeout).
    virtual QImage grab(const vk::ViewportScene& scene, int timeoutMs) = 0;
    /// Size of the drawing surface in device pixels.
    virtual QSize pixelSize() const = 0;
    /// Whether it draws on a real GPU (not a CPU implementation of Vulkan).
    virtual bool hardwareGpu() const { return false; }
};

/// The Vulkan backend; throws std::runtime_error with the reason when there
/// is no usable Vulkan device (or KERF_NO_VULKAN is set).
std::unique_ptr<ViewportBackend> makeVulkanBackend(ViewportWidget* owner);
std::unique_ptr<ViewportBackend> makeCpuBackend(ViewportWidget* owner);

} // namespace kerf::qt
