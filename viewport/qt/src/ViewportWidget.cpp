#include "kerf/viewport/qt/ViewportWidget.hpp"

#include "ViewportBackend.hpp"
#include "kerf/tracer/ExactTracer.hpp"

#include <algorithm>
#include <QKeyEvent>
#include <QMouseEvent>
#include <QTimer>
#include <QVBoxLayout>
#include <QWheelEvent>

#include <glm/glm.hpp>

#include <cmath>

namespace kerf::qt {

namespace {

constexpr double kDragThresholdPixels = 3.0;
// A trace slower than this while the camera moves is done at half the
// resolution until the motion stops (lavapipe, very large windows).
constexpr double kInteractiveTraceBudgetMs = 25.0;

// A small octahedron around `p` (flat triangles, outward normals).
PlacedMesh markerMesh(const glm::dvec3& p, double radius)
{
    PlacedMesh m;
    m.id = "marker";
    m.color = {1.0f, 0.78f, 0.05f};
    const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int sx : {0, 1})
        for (int sy : {2, 3})
            for (int sz : {4, 5}) {
                glm::dvec3 a = axes[sx], b = axes[sy], c = axes[sz];
                // Counter-clockwise seen from outside.
                if (glm::dot(glm::cross(b - a, c - a), a + b + c) < 0.0) std::swap(b, c);
                const glm::vec3 n = glm::normalize(glm::vec3(a + b + c));
                for (const glm::dvec3& v : {a, b, c}) {
                    m.mesh.positions.push_back(p + radius * v);
                    m.mesh.normals.push_back(n);
                }
            }
    m.mesh.bounds = Aabb{p - glm::dvec3(radius), p + glm::dvec3(radius)};
    return m;
}

} // namespace

ViewportWidget::ViewportWidget(QWidget* parent) : QWidget(parent)
{
    qRegisterMetaType<ViewportStatus>();
    qRegisterMetaType<ViewportPick>();
    qRegisterMetaType<ViewRequirement>();
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(0, 0, 0, 0);
    setMinimumSize(160, 120);
    tellView_ = new QTimer(this);
    tellView_->setSingleShot(true);
    tellView_->setInterval(500);
    connect(tellView_, &QTimer::timeout, this, &ViewportWidget::tellSettledView);
    settle_ = new QTimer(this);
    settle_->setSingleShot(true);
    settle_->setInterval(180);
    connect(settle_, &QTimer::timeout, this, [this] {
        interactive_ = false;
        sceneChanged();
    });
    try {
        backend_ = makeVulkanBackend(this);
        layout->addWidget(backend_->widget());
        status_.vulkan = true;
    } catch (const std::exception& e) {
        useCpu(QString::fromUtf8(e.what()));
    }
}

ViewportWidget::~ViewportWidget() = default;

void ViewportWidget::useCpu(const QString& reason)
{
    status_ = ViewportStatus{};
    status_.vulkan = false;
    status_.device = tr("CPU reference tracer");
    status_.fallbackReason = reason;
    if (backend_) {
        layout()->removeWidget(backend_->widget());
        backend_.reset();
    }
    backend_ = makeCpuBackend(this);
    layout()->addWidget(backend_->widget());
    sceneChanged();
}

void ViewportWidget::onBackendFailed(const QString& reason)
{
    if (!status_.vulkan) return;
    useCpu(tr("Vulkan failed: %1").arg(reason));
    emit backendChanged();
}

void ViewportWidget::onFrame(const ViewportStatus& s)
{
    if (s.vulkan != status_.vulkan) return; // a late frame of a backend that is gone
    const QString reason = status_.fallbackReason;
    status_ = s;
    status_.picture.reset(); // handed on, not kept
    if (!s.vulkan) status_.fallbackReason = reason;
    emit frameDrawn();
    if (s.picture) emit pictureTaken(s.picture);
    // The settled view goes with its first picture, or at once while there
    // are no voxels to take a picture of.
    if (untoldView_ && ((s.picture && s.picture->view == *untoldView_) || !snapshot_)) tellSettledView();
}

QSize ViewportWidget::pixelSize() const
{
    const QSize s = backend_ ? backend_->pixelSize() : size() * devicePixelRatioF();
    return {std::max(s.width(), 1), std::max(s.height(), 1)};
}

Aabb ViewportWidget::partBounds() const
{
    Aabb b = Aabb::empty();
    if (pickTape_ && pickTape_->bounds().isBounded()) b = pickTape_->bounds();
    else if (snapshot_) b = snapshot_->layout.bounds();
    if (meshes_)
        for (const auto& m : *meshes_) b = b.merged(m.worldBounds());
    return b;
}

vk::ViewportScene ViewportWidget::scene() const
{
    vk::ViewportScene scene;
    scene.view = view_;
    scene.snapshot = snapshot_;
    scene.section = section_;
    scene.selectedFeatureNodes = selected_;
    scene.grid = grid_;
    scene.axes = axes_;
    scene.meshes = meshes_;
    scene.markers = markers_;
    scene.quality = exactEdges_ ? TraceQuality::Exact : TraceQuality::Voxels;
    scene.resolutionScale = interactive_ && status_.traceMs > kInteractiveTraceBudgetMs ? 0.5 : 1.0;
    // At rest, each new trace of the settled view tells the voxelizer what
    // the part hides.
    if (!interactive_) scene.occlusionView = settledView_;
    return scene;
}

void ViewportWidget::sceneChanged()
{
    if (!backend_) return;
    // At rest, the voxelizer learns what this view needs (before the frame,
    // whose trace of this view becomes its occlusion picture).
    bool settled = false;
    if (!interactive_) {
        const QSize px = pixelSize();
        const ViewRequirement v = viewRequirement(view_.camera(px.width(), px.height(), partBounds()));
        if (!settledView_ || !(*settledView_ == v)) {
            settledView_ = v;
            settled = true;
        }
    }
    backend_->show(scene());
    if (settled) {
        untoldView_ = settledView_;
        tellView_->start();
    }
}

void ViewportWidget::tellSettledView()
{
    tellView_->stop();
    if (!untoldView_) return;
    const ViewRequirement v = *untoldView_;
    untoldView_.reset();
    emit viewSettled(v);
}

void ViewportWidget::setSnapshot(std::shared_ptr<const VoxelSnapshot> snapshot)
{
    snapshot_ = std::move(snapshot);
    if (!viewFramed_ && snapshot_ && !partBounds().isEmpty()) {
        const QSize px = pixelSize();
        view_.setStandardView("iso", partBounds(), double(px.width()) / px.height());
        viewFramed_ = true;
        framedExtent_ = partExtent();
    }
    refitIfRescaled();
    sceneChanged();
}

void ViewportWidget::setPickTape(std::shared_ptr<const Tape> tape)
{
    pickTape_ = std::move(tape);
    refitIfRescaled();
}

double ViewportWidget::partExtent() const
{
    const Aabb b = partBounds();
    if (b.isEmpty() || !b.isBounded()) return 0.0;
    const glm::dvec3 size = b.max - b.min;
    return std::max({size.x, size.y, size.z});
}

void ViewportWidget::refitIfRescaled()
{
    if (!viewFramed_ || !ViewController::rescaled(framedExtent_, partExtent())) return;
    const QSize px = pixelSize();
    view_.fit(partBounds(), double(px.width()) / px.height());
    framedExtent_ = partExtent();
    sceneChanged();
}

void ViewportWidget::setMeshes(std::vector<PlacedMesh> meshes)
{
    meshes_ = std::make_shared<const std::vector<PlacedMesh>>(std::move(meshes));
    sceneChanged();
}

void ViewportWidget::setMarkers(const std::vector<glm::dvec3>& points)
{
    auto list = std::make_shared<std::vector<PlacedMesh>>();
    const double radius = view_.heightAtTarget() * 0.006;
    for (const auto& p : points) list->push_back(markerMesh(p, radius));
    markers_ = std::move(list);
    sceneChanged();
}

void ViewportWidget::setSelectedFeatureNodes(std::unordered_set<std::string> nodeIds)
{
    selected_ = std::make_shared<const std::unordered_set<std::string>>(std::move(nodeIds));
    sceneChanged();
}

void ViewportWidget::setSection(const Section& section)
{
    section_ = section;
    sceneChanged();
}

void ViewportWidget::setGridVisible(bool on)
{
    grid_ = on;
    sceneChanged();
}

void ViewportWidget::setExactEdges(bool on)
{
    exactEdges_ = on;
    sceneChanged();
}

void ViewportWidget::setAxesVisible(bool on)
{
    axes_ = on;
    sceneChanged();
}

void ViewportWidget::setStandardView(const QString& name)
{
    const QSize px = pixelSize();
    const Aabb b = partBounds();
    view_.setStandardView(name.toStdString(), b.isEmpty() ? Aabb{glm::dvec3(-100), glm::dvec3(100)} : b,
                          double(px.width()) / px.height());
    viewFramed_ = !b.isEmpty();
    framedExtent_ = partExtent();
    sceneChanged();
}

void ViewportWidget::fitAll()
{
    const QSize px = pixelSize();
    view_.fit(partBounds(), double(px.width()) / px.height());
    framedExtent_ = partExtent();
    sceneChanged();
}

void ViewportWidget::setOrthographic(bool on)
{
    view_.setProjection(on ? Projection::Orthographic : Projection::Perspective);
    sceneChanged();
}

bool ViewportWidget::orthographic() const { return view_.projection() == Projection::Orthographic; }

void ViewportWidget::setView(const ViewController& view)
{
    view_ = view;
    viewFramed_ = true;
    framedExtent_ = partExtent();
    sceneChanged();
}

QImage ViewportWidget::grabFrame(int timeoutMs)
{
    if (!backend_) return {};
    vk::ViewportScene full = scene();
    full.resolutionScale = 1.0; // a picture for a person: full resolution
    return backend_->grab(full, timeoutMs);
}

ViewportPick ViewportWidget::pickAt(QPointF position) const
{
    ViewportPick pick;
    if (!pickTape_ || pickTape_->empty()) return pick;
    const QSize px = pixelSize();
    const double dpr = double(px.width()) / std::max(1, width());
    const Camera camera = view_.camera(px.width(), px.height(), partBounds());
    const Ray ray = camera.ray(position.x() * dpr, position.y() * dpr);
    // Hit tolerance: far below a pixel at any zoom a person uses.
    const double epsilon = std::max(1e-6, 1e-6 * glm::length(pickTape_->bounds().size()));
    const ExactHit h = castExactRay(*pickTape_, ray, epsilon);
    if (!h.hit) return pick;
    pick.hit = true;
    pick.point = h.point;
    pick.normal = h.normal;
    if (h.feature < pickTape_->features().size()) pick.nodeId = pickTape_->features()[h.feature].nodeId;
    return pick;
}

std::optional<glm::dvec3> ViewportWidget::surfacePointAt(QPointF position) const
{
    const ViewportPick p = pickAt(position);
    if (!p.hit) return std::nullopt;
    return p.point;
}

void ViewportWidget::resizeEvent(QResizeEvent* e)
{
    QWidget::resizeEvent(e);
    sceneChanged(); // another size: another pixel size for the voxelizer
}

void ViewportWidget::interacting()
{
    interactive_ = true;
    settle_->start();
}

void ViewportWidget::onPress(QMouseEvent* e)
{
    pressAt_ = lastAt_ = e->position();
    pressButton_ = e->button();
    drag_ = Drag::Pending;
    pivot_.reset();
    if (pressButton_ == Qt::LeftButton && !(e->modifiers() & Qt::ShiftModifier)) pivot_ = surfacePointAt(pressAt_);
}

void ViewportWidget::onMove(QMouseEvent* e)
{
    if (drag_ == Drag::None) return;
    const QPointF at = e->position();
    if (drag_ == Drag::Pending) {
        const QPointF d = at - pressAt_;
        if (std::hypot(d.x(), d.y()) < kDragThresholdPixels) return;
        const bool pan = pressButton_ == Qt::MiddleButton ||
                         (pressButton_ == Qt::LeftButton && (e->modifiers() & Qt::ShiftModifier)) ||
                         pressButton_ == Qt::RightButton;
        drag_ = pan ? Drag::Pan : Drag::Orbit;
    }
    const QPointF d = at - lastAt_;
    lastAt_ = at;
    if (drag_ == Drag::Orbit) {
        view_.orbit(d.x(), d.y(), pivot_);
    } else {
        const QSize px = pixelSize();
        const double dpr = double(px.width()) / std::max(1, width());
        view_.pan(d.x() * dpr, d.y() * dpr, px.height());
    }
    interacting();
    sceneChanged();
}

void ViewportWidget::onRelease(QMouseEvent* e)
{
    const bool click = drag_ == Drag::Pending && e->button() == Qt::LeftButton;
    drag_ = Drag::None;
    if (!click) return;
    ViewportPick pick = pickAt(e->position());
    pick.modifiers = e->modifiers();
    emit clicked(pick);
}

void ViewportWidget::onWheel(QWheelEvent* e)
{
    const double steps = e->angleDelta().y() / 120.0;
    if (steps == 0.0) return;
    const double factor = std::pow(0.85, steps);
    const QPointF at = e->position();
    glm::dvec3 about;
    if (const auto p = surfacePointAt(at)) {
        about = *p;
    } else {
        const QSize px = pixelSize();
        const double dpr = double(px.width()) / std::max(1, width());
        about = view_.pointOnTargetPlane(at.x() * dpr, at.y() * dpr, px.width(), px.height());
    }
    view_.zoom(factor, about);
    interacting();
    sceneChanged();
    e->accept();
}

void ViewportWidget::onKey(QKeyEvent* e)
{
    switch (e->key()) {
    case Qt::Key_F: fitAll(); break;
    case Qt::Key_0: setStandardView("iso"); break;
    case Qt::Key_1: setStandardView("front"); break;
    case Qt::Key_3: setStandardView("right"); break;
    case Qt::Key_7: setStandardView("top"); break;
    case Qt::Key_5: setOrthographic(!orthographic()); break;
    default: e->ignore(); return;
    }
    e->accept();
}

} // namespace kerf::qt
