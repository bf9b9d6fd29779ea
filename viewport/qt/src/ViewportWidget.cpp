#include "kerf/viewport/qt/ViewportWidget.hpp"

#include "ViewportBackend.hpp"
#include "kerf/tracer/ExactTracer.hpp"
#include "kerf/viewport/GpuVoxelWorker.hpp"
#include "kerf/viewport/OverlayMeshes.hpp"

#include <algorithm>
#include <QKeyEvent>
#include <QLabel>
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

// Overlay colours (linear RGB).
constexpr glm::vec3 kMarkerColor{1.0f, 0.78f, 0.05f};
constexpr glm::vec3 kDimensionColor{1.0f, 0.45f, 0.02f};
constexpr glm::vec3 kBoxColor{0.10f, 0.42f, 1.0f};
constexpr glm::vec3 kSnapColor{1.0f, 0.20f, 0.60f};
constexpr glm::vec3 kFaceSnapColor{0.85f, 0.85f, 0.85f};
constexpr glm::vec3 kHotColor{1.0f, 0.85f, 0.10f};
constexpr glm::vec3 kAxisColor[3] = {{0.85f, 0.10f, 0.08f}, {0.10f, 0.62f, 0.12f}, {0.10f, 0.28f, 0.95f}};
// Sizes on screen, in pixels.
constexpr double kMarkerPixels = 5.0;
constexpr double kSnapPixels = 6.0;
constexpr double kBarPixels = 1.3;
constexpr double kArrowPixels = 2.2;
constexpr double kSnapRadiusPixels = 10.0;
constexpr double kGizmoGrabPixels = 7.0;
// Markers are resized when the zoom changes their size on screen by more than this.
constexpr double kRescaleRatio = 1.15;

} // namespace

ViewportWidget::ViewportWidget(QWidget* parent) : QWidget(parent)
{
    qRegisterMetaType<ViewportStatus>();
    qRegisterMetaType<ViewportPick>();
    qRegisterMetaType<ViewRequirement>();
    qRegisterMetaType<GizmoDrag>();
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
    // A native window of its own, so that it stays above the Vulkan window.
    label_ = new QLabel(this);
    label_->setObjectName("viewport.dimension");
    label_->setAttribute(Qt::WA_NativeWindow);
    label_->setAttribute(Qt::WA_TransparentForMouseEvents);
    label_->setStyleSheet("QLabel { background: #fffbe6; color: #202020; border: 1px solid #e07000;"
                          " padding: 1px 4px; font-weight: bold; }");
    label_->hide();
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
    if (gpuRequest_ && !s.gpuRefusal.isEmpty() && s.gpuRefusedRevision == gpuRequest_->revision &&
        gpuRefusalTold_ != s.gpuRefusedRevision) {
        gpuRefusalTold_ = s.gpuRefusedRevision;
        emit gpuVoxelizerRefused(s.gpuRefusal);
    }
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
    scene.gpuVoxels = gpuRequest_;
    scene.section = section_;
    scene.selectedFeatureNodes = selected_;
    scene.grid = grid_;
    scene.axes = axes_;
    scene.meshes = meshes_;
    const double scale = camera().millimetresPerPixel(overlayReference());
    if (overlaysDirty_ || !(overlayScale_ > 0.0) || scale > overlayScale_ * kRescaleRatio ||
        scale * kRescaleRatio < overlayScale_)
        rebuildOverlays();
    scene.markers = markers_;
    scene.ghosts = ghosts_;
    scene.quality = exactEdges_ ? TraceQuality::Exact : TraceQuality::Voxels;
    scene.bricks = bricks_;
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
    placeLabel();
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
    if (snapshot_) frameOnFirstPart();
    refitIfRescaled();
    sceneChanged();
}

void ViewportWidget::frameOnFirstPart()
{
    if (viewFramed_ || partBounds().isEmpty()) return;
    const QSize px = pixelSize();
    view_.setStandardView("iso", partBounds(), double(px.width()) / px.height());
    viewFramed_ = true;
    framedExtent_ = partExtent();
}

bool ViewportWidget::hasHardwareGpu() const { return status_.vulkan && backend_ && backend_->hardwareGpu(); }

void ViewportWidget::setGpuVoxelSource(std::shared_ptr<const Tape> tape, const GridLayout& layout,
                                       std::uint64_t revision, std::size_t memoryBudget,
                                       std::optional<std::vector<long>> dirtyTiles, std::uint64_t dirtySince)
{
    if (!canVoxelizeOnGpu()) return;
    auto request = std::make_shared<vk::GpuVoxelRequest>();
    request->revision = revision;
    request->tape = std::move(tape);
    request->layout = layout;
    request->memoryBudget = memoryBudget;
    request->dirtyTiles = std::move(dirtyTiles);
    request->dirtySince = dirtySince;
    gpuRequest_ = std::move(request);
    frameOnFirstPart();
    refitIfRescaled();
    sceneChanged();
}

void ViewportWidget::clearGpuVoxelSource()
{
    if (!gpuRequest_) return;
    gpuRequest_.reset();
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
    // A part with nothing to show (all undone, all hidden) has no scale: the
    // view stays, and what comes back is judged against what was framed.
    // (Framed on "nothing", a table redone from nothing stayed framed on
    // the first 20 mm box its undo had passed through.)
    if (!viewFramed_ || partExtent() == 0.0 || !ViewController::rescaled(framedExtent_, partExtent())) return;
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
    markerPoints_ = points;
    overlaysChanged();
}

void ViewportWidget::setDimension(std::optional<std::pair<glm::dvec3, glm::dvec3>> ends, const QString& text)
{
    dimension_ = std::move(ends);
    if (dimension_) boxShown_.reset();
    label_->setText(dimension_ ? text : QString());
    overlaysChanged();
}

void ViewportWidget::setBoxShown(std::optional<Aabb> box, const QString& text)
{
    boxShown_ = std::move(box);
    if (boxShown_) dimension_.reset();
    label_->setText(boxShown_ ? text : QString());
    overlaysChanged();
}

QString ViewportWidget::dimensionText() const { return dimension_ || boxShown_ ? label_->text() : QString(); }

void ViewportWidget::setGhosts(std::vector<PlacedMesh> ghosts)
{
    ghosts_ = std::make_shared<const std::vector<PlacedMesh>>(std::move(ghosts));
    sceneChanged();
}

Aabb ViewportWidget::ghostBounds() const
{
    Aabb bounds;
    if (ghosts_)
        for (const PlacedMesh& g : *ghosts_) bounds = bounds.merged(g.worldBounds());
    return bounds;
}

void ViewportWidget::setMoveGizmo(std::optional<glm::dvec3> origin)
{
    if (origin == gizmoOrigin_) return;
    gizmoOrigin_ = origin;
    if (!gizmoOrigin_ && drag_ != Drag::Gizmo) gizmoHot_ = GizmoHandle::None;
    overlaysChanged();
}

void ViewportWidget::cancelGizmoDrag()
{
    if (drag_ == Drag::Gizmo) endGizmoDrag(true);
}

std::optional<MoveGizmo> ViewportWidget::moveGizmo() const
{
    if (!gizmoOrigin_ || snapping_) return std::nullopt;
    return MoveGizmo::at(*gizmoOrigin_, camera());
}

void ViewportWidget::setSnapping(bool on)
{
    snapping_ = on;
    hoverSnap_.reset();
    overlaysChanged();
}

std::optional<SnapPoint> ViewportWidget::snapAt(QPointF position) const
{
    if (!pickTape_ || pickTape_->empty()) return std::nullopt;
    const double dpr = devicePixel(QPointF(1, 0)).x - devicePixel(QPointF(0, 0)).x;
    SnapOptions options;
    options.radiusPixels = kSnapRadiusPixels * dpr;
    return kerf::snapAt(*pickTape_, camera(), devicePixel(position), options);
}

Camera ViewportWidget::camera() const
{
    const QSize px = pixelSize();
    return view_.camera(px.width(), px.height(), partBounds());
}

glm::dvec2 ViewportWidget::devicePixel(QPointF position) const
{
    const double dpr = double(pixelSize().width()) / std::max(1, width());
    return {position.x() * dpr, position.y() * dpr};
}

glm::dvec3 ViewportWidget::overlayReference() const
{
    if (gizmoOrigin_) return *gizmoOrigin_;
    if (dimension_) return 0.5 * (dimension_->first + dimension_->second);
    if (boxShown_) return boxShown_->center();
    if (!markerPoints_.empty()) return markerPoints_.front();
    return view_.target();
}

void ViewportWidget::overlaysChanged()
{
    overlaysDirty_ = true;
    sceneChanged();
}

void ViewportWidget::rebuildOverlays() const
{
    const Camera cam = camera();
    overlayScale_ = cam.millimetresPerPixel(overlayReference());
    overlaysDirty_ = false;
    const auto pixels = [&](const glm::dvec3& at, double n) { return n * std::max(cam.millimetresPerPixel(at), 1e-9); };
    auto list = std::make_shared<std::vector<PlacedMesh>>();
    for (const auto& p : markerPoints_) list->push_back(markerMesh(p, pixels(p, kMarkerPixels), kMarkerColor));
    if (dimension_) {
        const auto& [a, b] = *dimension_;
        list->push_back(barMesh(a, b, pixels(0.5 * (a + b), kBarPixels), kDimensionColor));
    }
    if (boxShown_) list->push_back(boxEdgesMesh(*boxShown_, pixels(boxShown_->center(), kBarPixels), kBoxColor));
    if (hoverSnap_)
        list->push_back(markerMesh(hoverSnap_->point, pixels(hoverSnap_->point, kSnapPixels),
                                   hoverSnap_->kind == SnapKind::Face ? kFaceSnapColor : kSnapColor));
    const bool dragging = drag_ == Drag::Gizmo && gizmoOrigin_;
    if (const auto g = dragging ? std::optional<MoveGizmo>(MoveGizmo::at(*gizmoOrigin_, cam)) : moveGizmo()) {
        const double r = pixels(g->origin, kArrowPixels);
        for (GizmoHandle h : {GizmoHandle::X, GizmoHandle::Y, GizmoHandle::Z}) {
            if (!g->usable(cam, h)) continue;
            const int i = gizmoAxisIndex(h);
            list->push_back(arrowMesh(g->origin, gizmoAxis(h), g->armLength, r, h == gizmoHot_ ? kHotColor : kAxisColor[i]));
        }
        for (GizmoHandle h : {GizmoHandle::PlaneYZ, GizmoHandle::PlaneZX, GizmoHandle::PlaneXY}) {
            if (!g->usable(cam, h)) continue;
            const int n = gizmoAxisIndex(h);
            const glm::dvec3 u = gizmoAxis(GizmoHandle(int(GizmoHandle::X) + (n + 1) % 3)),
                             v = gizmoAxis(GizmoHandle(int(GizmoHandle::X) + (n + 2) % 3));
            const double a = MoveGizmo::kPlaneFrom * g->armLength, b = MoveGizmo::kPlaneTo * g->armLength;
            list->push_back(quadMesh({g->origin + a * u + a * v, g->origin + b * u + a * v, g->origin + b * u + b * v,
                                      g->origin + a * u + b * v},
                                     h == gizmoHot_ ? kHotColor : 0.8f * kAxisColor[n]));
        }
    }
    markers_ = std::move(list);
}

void ViewportWidget::placeLabel()
{
    std::optional<glm::dvec3> anchor;
    if (dimension_) anchor = 0.5 * (dimension_->first + dimension_->second);
    else if (boxShown_) anchor = boxShown_->max;
    const auto at = anchor ? camera().project(*anchor) : std::nullopt;
    if (!at || label_->text().isEmpty()) {
        label_->hide();
        return;
    }
    const double dpr = double(pixelSize().width()) / std::max(1, width());
    label_->adjustSize();
    QPoint p(int(at->x / dpr) + 10, int(at->y / dpr) - label_->height() - 6);
    p.setX(std::clamp(p.x(), 0, std::max(0, width() - label_->width())));
    p.setY(std::clamp(p.y(), 0, std::max(0, height() - label_->height())));
    label_->move(p);
    label_->show();
    label_->raise();
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

void ViewportWidget::setBrickRenderer(bool on)
{
    bricks_ = on;
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
    const bool was = orthographic();
    view_.setProjection(on ? Projection::Orthographic : Projection::Perspective);
    sceneChanged();
    if (was != on) emit orthographicChanged(on);
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
    if (pressButton_ == Qt::LeftButton) {
        if (const auto g = moveGizmo()) {
            const double dpr = devicePixel(QPointF(1, 0)).x - devicePixel(QPointF(0, 0)).x;
            const GizmoHandle h = g->handleAt(camera(), devicePixel(pressAt_), kGizmoGrabPixels * dpr);
            if (h != GizmoHandle::None) {
                drag_ = Drag::Gizmo;
                gizmoHot_ = h;
                gizmoDrag_ = GizmoDrag{};
                gizmoDrag_.handle = h;
                gizmoDrag_.millimetresPerPixel = camera().millimetresPerPixel(g->origin);
                pressOrigin_ = g->origin;
                emit gizmoDragStarted();
                overlaysChanged();
                return;
            }
        }
    }
    if (pressButton_ == Qt::LeftButton && !(e->modifiers() & Qt::ShiftModifier)) pivot_ = surfacePointAt(pressAt_);
}

void ViewportWidget::onMove(QMouseEvent* e)
{
    const QPointF at = e->position();
    if (drag_ == Drag::None) {
        // Hovering: what a click would take.
        if (snapping_) {
            const auto snap = snapAt(at);
            const bool same = snap.has_value() == hoverSnap_.has_value() &&
                              (!snap || (snap->point == hoverSnap_->point && snap->kind == hoverSnap_->kind));
            hoverSnap_ = snap;
            if (!same) overlaysChanged();
        } else if (const auto g = moveGizmo()) {
            const double dpr = devicePixel(QPointF(1, 0)).x - devicePixel(QPointF(0, 0)).x;
            const GizmoHandle h = g->handleAt(camera(), devicePixel(at), kGizmoGrabPixels * dpr);
            if (h != gizmoHot_) {
                gizmoHot_ = h;
                overlaysChanged();
            }
        }
        return;
    }
    if (drag_ == Drag::Gizmo) {
        if (gizmoDrag_.typed.isEmpty()) emitGizmoDrag(at, e->modifiers());
        return;
    }
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

void ViewportWidget::emitGizmoDrag(QPointF at, Qt::KeyboardModifiers modifiers)
{
    // The gizmo as it stood when the drag began: the feature follows the
    // drag, the measure of the drag does not.
    const MoveGizmo g{pressGizmoOrigin(), 1.0};
    const auto d = g.displacement(camera(), gizmoDrag_.handle, devicePixel(pressAt_), devicePixel(at));
    if (!d) return;
    gizmoDrag_.displacement = *d;
    gizmoDrag_.free = modifiers & Qt::ControlModifier;
    emit gizmoDragged(gizmoDrag_);
}

void ViewportWidget::endGizmoDrag(bool cancelled)
{
    drag_ = Drag::None;
    gizmoHot_ = GizmoHandle::None;
    gizmoDrag_ = GizmoDrag{};
    pressOrigin_.reset();
    emit gizmoDragFinished(cancelled);
    overlaysChanged();
}

void ViewportWidget::onRelease(QMouseEvent* e)
{
    if (drag_ == Drag::Gizmo) {
        if (e->button() == Qt::LeftButton) endGizmoDrag(false);
        return;
    }
    const bool click = drag_ == Drag::Pending && e->button() == Qt::LeftButton;
    drag_ = Drag::None;
    if (!click) return;
    ViewportPick pick = pickAt(e->position());
    if (snapping_) {
        if (const auto snap = snapAt(e->position())) {
            pick.hit = true;
            pick.point = snap->point;
            pick.snap = snap->kind;
            if (snap->feature < pickTape_->features().size()) pick.nodeId = pickTape_->features()[snap->feature].nodeId;
        }
    }
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
    if (drag_ == Drag::Gizmo) {
        // A distance typed during the drag: digits, a point, a sign; a space
        // and a slash for fractions of an inch ("1 1/2").
        const QString t = e->text();
        if (e->key() == Qt::Key_Escape) {
            endGizmoDrag(true);
        } else if (e->key() == Qt::Key_Return || e->key() == Qt::Key_Enter) {
            endGizmoDrag(false);
        } else if (e->key() == Qt::Key_Backspace) {
            gizmoDrag_.typed.chop(1);
            emit gizmoDragged(gizmoDrag_);
        } else if (t.size() == 1 && (t[0].isDigit() || t == "." || t == "-" || t == "," || t == "/" ||
                                     (t == " " && !gizmoDrag_.typed.isEmpty()))) {
            gizmoDrag_.typed += t == "," ? QString(".") : t;
            emit gizmoDragged(gizmoDrag_);
        } else {
            e->ignore();
            return;
        }
        e->accept();
        return;
    }
    switch (e->key()) {
    case Qt::Key_F: fitAll(); break;
    case Qt::Key_0: setStandardView("iso"); break;
    case Qt::Key_1: setStandardView("front"); break;
    case Qt::Key_3: setStandardView("right"); break;
    case Qt::Key_7: setStandardView("top"); break;
    case Qt::Key_5: setOrthographic(!orthographic()); break;
    case Qt::Key_Escape: emit escapePressed(); break;
    default: e->ignore(); return;
    }
    e->accept();
}

} // namespace kerf::qt
