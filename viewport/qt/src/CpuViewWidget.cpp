#include "CpuViewWidget.hpp"

#include "ViewportBackend.hpp"
#include "kerf/tracer/ReferenceTracer.hpp"

#include <QMouseEvent>
#include <QPainter>
#include <QWheelEvent>

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <cstring>

namespace kerf::qt {

namespace {

// Ghosts (translucent) and markers drawn over the traced picture, as the GPU
// pass draws them over everything: flat-lit triangles, farthest first.
void paintOverlays(QImage& picture, const Camera& camera, const vk::ViewportScene& scene)
{
    struct Flat {
        QPolygonF corners;
        double depth;
        QColor color;
    };
    const auto lit = [&](const PlacedMesh& m, const glm::vec3& normal) {
        const double facing = std::abs(glm::dot(glm::dvec3(normal), camera.forward()));
        const auto channel = [&](float linear) {
            return int(std::clamp(std::pow(linear * (0.35 + 0.65 * facing), 1.0 / 2.2), 0.0, 1.0) * 255.0);
        };
        return QColor(channel(m.color.r), channel(m.color.g), channel(m.color.b), int(m.opacity * 255.0f));
    };
    QPainter p(&picture);
    p.setRenderHint(QPainter::Antialiasing);
    for (const auto* list : {scene.ghosts.get(), scene.markers.get()}) {
        if (!list) continue;
        std::vector<Flat> flats;
        for (const PlacedMesh& m : *list)
            for (std::size_t i = 0; i + 2 < m.mesh.positions.size(); i += 3) {
                Flat f{{}, 0.0, lit(m, m.mesh.normals[i])};
                bool seen = true;
                for (std::size_t k = i; k < i + 3 && seen; ++k) {
                    const glm::dvec3 w = m.worldFromLocal.apply(m.mesh.positions[k]);
                    const auto at = camera.project(w);
                    seen = at.has_value();
                    if (seen) f.corners << QPointF(at->x, at->y);
                    f.depth += glm::dot(w - camera.eye(), camera.forward());
                }
                if (seen) flats.push_back(std::move(f));
            }
        std::sort(flats.begin(), flats.end(), [](const Flat& a, const Flat& b) { return a.depth > b.depth; });
        for (const Flat& f : flats) {
            p.setPen(f.color.alpha() == 255 ? QPen(f.color, 0.5) : QPen(Qt::NoPen));
            p.setBrush(f.color);
            p.drawPolygon(f.corners);
        }
    }
}

} // namespace

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
    // What the last trace showed: a scene that changes only what is drawn
    // over the part (a hover snap, the gizmo) is shaded again, not traced.
    struct TraceKey {
        const VoxelSnapshot* snapshot = nullptr;
        glm::dvec3 eye{0.0}, forward{0.0}, up{0.0};
        double halfHeight = 0.0;
        int width = 0, height = 0;
        Projection projection = Projection::Perspective;
        Section section;
        TraceQuality quality = TraceQuality::Voxels;
        bool operator==(const TraceKey&) const = default;
    };
    std::optional<TraceKey> tracedKey;
    TraceImage traced(1, 1);
    double tracedMs = 0.0; // how long that trace took (reported again while it is reused)
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
        const TraceKey key{scene.snapshot.get(), camera.eye(),   camera.forward(), camera.up(),   camera.halfHeight(),
                           w,                    h,              camera.projection(), scene.section, scene.quality};
        if (!tracedKey || !(*tracedKey == key)) {
            traced = scene.snapshot ? traceVoxels(buffers, camera, 0, scene.section, scene.quality) : TraceImage(w, h);
            tracedKey = key;
            tracedMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - traceStart).count();
        }
        const double traceMs = tracedMs;
        TraceImage image = traced;
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
        paintOverlays(picture, camera, scene);
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
