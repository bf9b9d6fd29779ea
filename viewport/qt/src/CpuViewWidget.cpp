#include "CpuViewWidget.hpp"

#include "ViewportBackend.hpp"
#include "kerf/tracer/ReferenceTracer.hpp"

#include <QMouseEvent>
#include <QPainter>
#include <QWheelEvent>

#include <chrono>
#include <cstring>

namespace kerf::qt {

CpuViewWidget::CpuViewWidget(ViewportWidget* owner, QString reason) : QWidget(owner), owner_(owner), reason_(std::move(reason))
{
    setFocusPolicy(Qt::StrongFocus);
    setMouseTracking(true); // hovering shows snaps and the gizmo handle under the cursor
    setAttribute(Qt::WA_OpaquePaintEvent);
    worker_ = std::thread([this] { work(); });
}

CpuViewWidget::~CpuViewWidget()
{
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    worker_.join();
}

void CpuViewWidget::show(const vk::ViewportScene& scene)
{
    {
        std::lock_guard lock(mutex_);
        scene_ = scene;
        size_ = size() * devicePixelRatioF();
        dirty_ = true;
        ++sceneSerial_;
    }
    wake_.notify_all();
}

QImage CpuViewWidget::grab(const vk::ViewportScene& scene, int timeoutMs)
{
    std::unique_lock lock(mutex_);
    scene_ = scene;
    size_ = size() * devicePixelRatioF();
    dirty_ = true;
    // The picture of this scene: a frame under way (of an older scene) that
    // ends meanwhile does not count.
    const std::uint64_t wanted = ++sceneSerial_;
    wake_.notify_all();
    if (!grabbed_.wait_for(lock, std::chrono::milliseconds(timeoutMs),
                           [&] { return renderedSerial_ >= wanted || stop_; }))
        return {};
    return lastImage_;
}

void CpuViewWidget::work()
{
    std::shared_ptr<const VoxelSnapshot> flattenedFrom;
    FlatVoxelBuffers buffers;
    for (;;) {
        vk::ViewportScene scene;
        QSize size;
        std::uint64_t serial = 0;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || dirty_; });
            if (stop_) return;
            scene = scene_;
            size = size_;
            serial = sceneSerial_;
            dirty_ = false;
        }
        const auto start = std::chrono::steady_clock::now();
        if (scene.snapshot != flattenedFrom) {
            buffers = scene.snapshot ? FlatVoxelBuffers::flatten(*scene.snapshot) : FlatVoxelBuffers{};
            flattenedFrom = scene.snapshot;
        }
        const double scale = std::clamp(scene.resolutionScale, 0.05, 1.0);
        const int w = std::max(1, int(size.width() * scale)), h = std::max(1, int(size.height() * scale));
        const Aabb bounds = scene.snapshot ? scene.snapshot->layout.bounds() : Aabb::empty();
        const Camera camera = scene.view.camera(w, h, bounds);
        const auto traceStart = std::chrono::steady_clock::now();
        TraceImage image = scene.snapshot ? traceVoxels(buffers, camera, 0, scene.section, scene.quality) : TraceImage(w, h);
        const double traceMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - traceStart).count();
        // Selected features in the highlight colour; caps in the section colour.
        std::vector<Feature> features = scene.snapshot && scene.snapshot->features ? *scene.snapshot->features
                                                                                   : std::vector<Feature>{};
        for (auto& f : features)
            if (scene.selectedFeatureNodes && scene.selectedFeatureNodes->count(f.nodeId)) {
                f.hasColor = true;
                f.color = {90, 160, 255};
            }
        const std::uint32_t capIndex = std::uint32_t(features.size());
        Feature cap;
        cap.hasColor = true;
        cap.color = {230, 110, 95};
        features.push_back(cap);
        for (auto& id : image.feature)
            if (id == kSectionCap) id = capIndex;
        const RgbaImage rgba = shade(image, features, ShadeOptions::forCamera(camera));
        QImage picture(rgba.width, rgba.height, QImage::Format_RGBA8888);
        for (int y = 0; y < rgba.height; ++y)
            std::memcpy(picture.scanLine(y), rgba.pixels.data() + std::size_t(y) * std::size_t(rgba.width) * 4,
                        std::size_t(rgba.width) * 4);
        ViewportStatus s;
        s.vulkan = false;
        s.device = tr("CPU reference tracer");
        s.fallbackReason = reason_;
        s.traceMs = traceMs;
        s.frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        s.voxelBytes = buffers.bytes();
        s.shownVersion = scene.snapshot ? scene.snapshot->version : 0;
        s.shownRevision = scene.snapshot ? scene.snapshot->documentRevision : 0;
        s.shownComplete = scene.snapshot && scene.snapshot->complete;
        // The voxelizer's occlusion picture: a full-resolution trace of the
        // very view it plans for.
        if (scene.snapshot && scale == 1.0 && scene.occlusionView &&
            viewRequirement(camera, scene.occlusionView->pixelsPerVoxel) == *scene.occlusionView)
            s.picture = std::make_shared<const OcclusionMap>(
                OcclusionMap::fromDepths(*scene.occlusionView, image.width, image.height, image.depth));
        const glm::dvec3 right = camera.right(), up = camera.up(), forward = camera.forward();
        {
            std::lock_guard lock(mutex_);
            s.frames = ++frames_;
            lastImage_ = picture;
            renderedSerial_ = serial;
        }
        grabbed_.notify_all();
        QMetaObject::invokeMethod(
            this,
            [this, picture, right, up, forward] {
                picture_ = picture;
                right_ = right;
                up_ = up;
                forward_ = forward;
                update();
            },
            Qt::QueuedConnection);
        emit frameDrawn(s);
    }
}

void CpuViewWidget::paintEvent(QPaintEvent*)
{
    QPainter p(this);
    p.setRenderHint(QPainter::SmoothPixmapTransform);
    if (picture_.isNull())
        p.fillRect(rect(), QColor(60, 63, 68));
    else
        p.drawImage(rect(), picture_);
    // The axis gizmo, as the GPU pass draws it.
    const QPointF centre(56, height() - 56);
    struct Axis {
        glm::dvec3 dir;
        QColor color;
    } axes[3] = {{{1, 0, 0}, QColor(230, 64, 56)}, {{0, 1, 0}, QColor(90, 204, 64)}, {{0, 0, 1}, QColor(64, 115, 242)}};
    std::sort(std::begin(axes), std::end(axes), [&](const Axis& a, const Axis& b) {
        return glm::dot(a.dir, forward_) > glm::dot(b.dir, forward_); // farthest first
    });
    p.setRenderHint(QPainter::Antialiasing);
    for (const Axis& a : axes) {
        const QPointF tip = centre + 36.0 * QPointF(glm::dot(a.dir, right_), -glm::dot(a.dir, up_));
        p.setPen(QPen(a.color, 3.0, Qt::SolidLine, Qt::RoundCap));
        p.drawLine(centre, tip);
    }
    p.setPen(QColor(235, 235, 235));
    p.drawText(rect().adjusted(8, 6, -8, -6), Qt::AlignTop | Qt::AlignRight,
               tr("CPU reference tracer: %1").arg(reason_));
}

void CpuViewWidget::resizeEvent(QResizeEvent*) { owner_->sceneChanged(); }
void CpuViewWidget::mousePressEvent(QMouseEvent* e) { owner_->onPress(e); }
void CpuViewWidget::mouseMoveEvent(QMouseEvent* e) { owner_->onMove(e); }
void CpuViewWidget::mouseReleaseEvent(QMouseEvent* e) { owner_->onRelease(e); }
void CpuViewWidget::wheelEvent(QWheelEvent* e) { owner_->onWheel(e); }
void CpuViewWidget::keyPressEvent(QKeyEvent* e) { owner_->onKey(e); }

namespace {

class CpuBackend : public ViewportBackend {
public:
    CpuBackend(ViewportWidget* owner, const QString& reason) : widget_(new CpuViewWidget(owner, reason))
    {
        QObject::connect(widget_, &CpuViewWidget::frameDrawn, owner,
                         [owner](const ViewportStatus& s) { owner->onFrame(s); });
    }
    ~CpuBackend() override { delete widget_; }
    QWidget* widget() override { return widget_; }
    void show(const vk::ViewportScene& scene) override { widget_->show(scene); }
    QImage grab(const vk::ViewportScene& scene, int timeoutMs) override { return widget_->grab(scene, timeoutMs); }
    QSize pixelSize() const override { return widget_->size() * widget_->devicePixelRatioF(); }

private:
    CpuViewWidget* widget_;
};

} // namespace

std::unique_ptr<ViewportBackend> makeCpuBackend(ViewportWidget* owner)
{
    return std::make_unique<CpuBackend>(owner, owner->status().fallbackReason);
}

} // namespace kerf::qt
