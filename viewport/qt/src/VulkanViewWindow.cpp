#include "VulkanViewWindow.hpp"

#include "ViewportBackend.hpp"
#include "kerf/viewport/VulkanError.hpp"

#include <QExposeEvent>
#include <QGuiApplication>
#include <QMouseEvent>
#include <QPlatformSurfaceEvent>
#include <QVulkanInstance>
#include <QWheelEvent>

#include <chrono>

namespace kerf::qt {

namespace {

QImage toQImage(const RgbaImage& picture)
{
    QImage image(picture.width, picture.height, QImage::Format_RGBA8888);
    for (int y = 0; y < picture.height; ++y)
        std::memcpy(image.scanLine(y), picture.pixels.data() + std::size_t(y) * std::size_t(picture.width) * 4,
                    std::size_t(picture.width) * 4);
    return image;
}

} // namespace

VulkanViewWindow::VulkanViewWindow(QVulkanInstance* instance, ViewportWidget* owner, const vk::ContextOptions& options)
    : owner_(owner)
{
    setSurfaceType(QSurface::VulkanSurface);
    setVulkanInstance(instance);
    context_ = std::make_unique<vk::Context>(options);
}

VulkanViewWindow::~VulkanViewWindow() { stopThread(); }

QString VulkanViewWindow::deviceDescription() const { return QString::fromStdString(context_->deviceDescription()); }

bool VulkanViewWindow::hardwareGpu() const { return !context_->isCpuDevice(); }

void VulkanViewWindow::schedule()
{
    {
        std::lock_guard lock(mutex_);
        const QSize px = size() * devicePixelRatio();
        width_ = px.width();
        height_ = px.height();
        dirty_ = true;
    }
    wake_.notify_all();
}

void VulkanViewWindow::show(const vk::ViewportScene& scene)
{
    {
        std::lock_guard lock(mutex_);
        scene_ = scene;
    }
    schedule();
}

QImage VulkanViewWindow::grab(const vk::ViewportScene& scene, int timeoutMs)
{
    std::unique_lock lock(mutex_);
    if (!thread_.joinable()) return {};
    scene_ = scene;
    grabRequested_ = true;
    grabDone_ = false;
    dirty_ = true;
    wake_.notify_all();
    if (!grabbed_.wait_for(lock, std::chrono::milliseconds(timeoutMs), [&] { return grabDone_; })) {
        grabRequested_ = false;
        return {};
    }
    return std::move(grabbedImage_);
}

void VulkanViewWindow::exposeEvent(QExposeEvent*)
{
    if (isExposed() && !thread_.joinable()) startThread();
    schedule();
}

void VulkanViewWindow::resizeEvent(QResizeEvent*) { schedule(); }

bool VulkanViewWindow::event(QEvent* e)
{
    if (e->type() == QEvent::PlatformSurface &&
        static_cast<QPlatformSurfaceEvent*>(e)->surfaceEventType() == QPlatformSurfaceEvent::SurfaceAboutToBeDestroyed)
        stopThread();
    return QWindow::event(e);
}

void VulkanViewWindow::startThread()
{
    const VkSurfaceKHR surface = QVulkanInstance::surfaceForWindow(this);
    if (!surface) {
        emit failed(tr("the window system gave no Vulkan surface"));
        return;
    }
    {
        std::lock_guard lock(mutex_);
        surface_ = surface;
        stop_ = false;
    }
    thread_ = std::thread([this] { renderLoop(); });
}

void VulkanViewWindow::stopThread()
{
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
    // The render thread is gone: the swapchain can go before the surface does.
    if (renderer_) renderer_->releaseSurface();
    renderer_.reset();
    surface_ = VK_NULL_HANDLE;
    std::lock_guard lock(mutex_);
    grabDone_ = true; // nobody waits for a frame that will not come
    grabbed_.notify_all();
}

void VulkanViewWindow::renderLoop()
{
    for (;;) {
        vk::ViewportScene scene;
        int w = 0, h = 0;
        bool grab = false;
        VkSurfaceKHR surface;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || dirty_; });
            if (stop_) return;
            scene = scene_;
            w = width_;
            h = height_;
            grab = grabRequested_;
            dirty_ = false;
            surface = surface_;
        }
        try {
            if (!renderer_)
                renderer_ = std::make_unique<vk::ViewportRenderer>(*context_, surface, vk::StreamingOptions{}, [this] {
                    // The GPU voxelizer has a build (or went idle): draw a frame.
                    {
                        std::lock_guard lock(mutex_);
                        dirty_ = true;
                    }
                    wake_.notify_all();
                });
            const vk::FrameStats f = renderer_->drawFrame(scene, w, h);
            ViewportStatus s;
            s.vulkan = true;
            s.device = QString::fromStdString(context_->deviceDescription());
            s.frameMs = f.frameMs;
            s.bricks = f.drewBricks;
            // A reshaded frame keeps the last trace's time. A CPU implementation
            // (lavapipe) has no meaningful GPU timestamps: its frame time,
            // which the trace dominates, stands in.
            if (f.traced) lastTraceMs_ = context_->isCpuDevice() ? f.frameMs : f.traceGpuMs;
            s.traceMs = lastTraceMs_;
            s.voxelBytes = f.residentBytes;
            s.shownVersion = f.shownVersion;
            s.shownRevision = f.shownRevision;
            s.shownComplete = f.shownComplete;
            s.streaming = !f.upToDate;
            s.gpuVoxels = f.gpuVoxels;
            s.gpuBusy = f.gpuBusy;
            s.gpuBuildMs = f.gpuBuildMs;
            s.gpuRefusal = QString::fromStdString(f.gpuRefusal);
            s.gpuRefusedRevision = f.gpuRefusedRevision;
            s.picture = f.picture;
            s.validationErrors = context_->validationErrors();
            if (s.validationErrors > 0) {
                const auto messages = context_->validationMessages();
                if (!messages.empty()) s.lastValidationMessage = QString::fromStdString(messages.back());
            }
            bool grabNow = false;
            {
                std::lock_guard lock(mutex_);
                s.frames = ++frames_;
                // Keep going while tiles stream in; a frame that could not be
                // presented (no area) waits for the next expose or resize.
                if (!f.upToDate && f.presented) dirty_ = true;
                grabNow = grab && f.presented;
            }
            if (grabNow) {
                // Read back outside the window's lock: the read-back takes the
                // device's command pool and queue locks, and holding the
                // window's around them closed a lock cycle through the GPU
                // voxelizer's thread, presentation and the GUI thread
                // (ThreadSanitizer, the GPU voxelizer scenario).
                QImage picture = toQImage(renderer_->lastPicture());
                std::lock_guard lock(mutex_);
                grabbedImage_ = std::move(picture);
                grabRequested_ = false;
                grabDone_ = true;
                grabbed_.notify_all();
            }
            emit frameDrawn(s);
        } catch (const std::exception& e) {
            emit failed(QString::fromUtf8(e.what()));
            std::lock_guard lock(mutex_);
            grabDone_ = true;
            grabbed_.notify_all();
            return;
        }
    }
}

void VulkanViewWindow::mousePressEvent(QMouseEvent* e) { owner_->onPress(e); }
void VulkanViewWindow::mouseMoveEvent(QMouseEvent* e) { owner_->onMove(e); }
void VulkanViewWindow::mouseReleaseEvent(QMouseEvent* e) { owner_->onRelease(e); }
void VulkanViewWindow::wheelEvent(QWheelEvent* e) { owner_->onWheel(e); }
void VulkanViewWindow::keyPressEvent(QKeyEvent* e) { owner_->onKey(e); }

// ---------------------------------------------------------------------------

namespace {

// One Vulkan instance for the application, made by Qt so that it has the
// window system's surface extensions, then adopted by each viewport's Context.
QVulkanInstance* sharedInstance(bool validation, QString& error)
{
    static QVulkanInstance* instance = nullptr;
    static QString failure;
    if (instance || !failure.isEmpty()) {
        error = failure;
        return instance;
    }
    auto* inst = new QVulkanInstance;
    inst->setApiVersion(QVersionNumber(1, 2));
    // Kerf counts validation messages itself (Context); Qt's own redirect
    // would print them twice.
    inst->setFlags(QVulkanInstance::NoDebugOutputRedirect);
    if (validation) {
        inst->setLayers({"VK_LAYER_KHRONOS_validation"});
        inst->setExtensions({"VK_EXT_debug_utils"});
    }
    if (!inst->create()) {
        failure = QObject::tr("no Vulkan instance (VkResult %1)").arg(int(inst->errorCode()));
        delete inst;
        error = failure;
        return nullptr;
    }
    instance = inst;
    return instance;
}

class VulkanBackend : public ViewportBackend {
public:
    explicit VulkanBackend(ViewportWidget* owner)
    {
        if (qEnvironmentVariableIsSet("KERF_NO_VULKAN"))
            throw std::runtime_error("Vulkan is switched off (KERF_NO_VULKAN is set)");
        const bool validation = qEnvironmentVariableIsSet("KERF_VULKAN_VALIDATION");
        QString error;
        QVulkanInstance* instance = sharedInstance(validation, error);
        if (!instance) throw std::runtime_error(error.toStdString());
        vk::ContextOptions options;
        options.presentation = true;
        options.externalInstance = instance->vkInstance();
        options.validation = validation && instance->layers().contains("VK_LAYER_KHRONOS_validation");
        options.preferCpu = qEnvironmentVariableIsSet("KERF_PREFER_CPU_VULKAN");
        window_ = new VulkanViewWindow(instance, owner, options);
        container_ = QWidget::createWindowContainer(window_, owner);
        container_->setFocusPolicy(Qt::StrongFocus);
        container_->setMinimumSize(64, 64);
        QObject::connect(window_, &VulkanViewWindow::frameDrawn, owner,
                         [owner](const ViewportStatus& s) { owner->onFrame(s); });
        QObject::connect(window_, &VulkanViewWindow::failed, owner,
                         [owner](const QString& reason) { owner->onBackendFailed(reason); });
    }
    ~VulkanBackend() override { delete container_; } // deletes the window too

    QWidget* widget() override { return container_; }
    void show(const vk::ViewportScene& scene) override { window_->show(scene); }
    QImage grab(const vk::ViewportScene& scene, int timeoutMs) override { return window_->grab(scene, timeoutMs); }
    QSize pixelSize() const override { return window_->size() * window_->devicePixelRatio(); }
    bool hardwareGpu() const override { return window_->hardwareGpu(); }

private:
    VulkanViewWindow* window_ = nullptr;
    QWidget* container_ = nullptr;
};

} // namespace

std::unique_ptr<ViewportBackend> makeVulkanBackend(ViewportWidget* owner)
{
    try {
        return std::make_unique<VulkanBackend>(owner);
    } catch (const vk::VulkanError& e) {
        throw std::runtime_error(e.what());
    }
}

} // namespace kerf::qt
