#pragma once
// The viewport of the desktop application: the Vulkan engine in a window
// of the widget layout (a QWindow with a Vulkan surface, rendered on its
// own thread), or, when there is no usable Vulkan device, the CPU
// reference tracer painting into an ordinary widget, saying so.
//
// Input: left drag orbits about the point under the cursor, middle drag (or
// shift + left drag) pans, the wheel zooms towards the point under the
// cursor; a click picks the feature under the cursor (exact ray against the
// part's field). Standard views, fit all and the projection are commands.
//
// Over the part: the move gizmo of the selected feature (its arrows and
// squares take a left drag before the camera does; digits typed during the
// drag give the distance, Esc cancels), measured points and dimensions with
// their values in a label, a box's edges, and ghosts (a selected hole's tool
// body, translucent). While snapping is on (measuring), the cursor shows the
// corner, hole centre, edge or face a click would take.
//
// Threading: every function is for the GUI thread. Frames are drawn on a
// render thread (Vulkan) or a worker (CPU), from a copy of the scene made
// when something changes; the GUI thread never waits for a frame, except
// in grabFrame(), which is for tests and screenshots.
//
// No Vulkan type appears here: Vulkan stays inside the viewport module.

#include "kerf/evaluator/Tape.hpp"
#include "kerf/tracer/MoveGizmo.hpp"
#include "kerf/tracer/Section.hpp"
#include "kerf/tracer/SnapPoint.hpp"
#include "kerf/tracer/ViewController.hpp"
#include "kerf/viewport/ReferenceMesh.hpp"
#include "kerf/voxelizer/OcclusionMap.hpp"
#include "kerf/voxelizer/VoxelSnapshot.hpp"

#include <QImage>
#include <QPointF>
#include <QWidget>

#include <glm/vec3.hpp>

#include <memory>
#include <optional>
#include <string>
#include <unordered_set>
#include <vector>

class QLabel;
class QMouseEvent;
class QWheelEvent;
class QKeyEvent;

namespace kerf::vk {
struct ViewportScene;
struct GpuVoxelRequest;
}

namespace kerf::qt {

class ViewportBackend;

/// What the status bar shows about the viewport.
struct ViewportStatus {
    bool vulkan = false;
    QString device;          // "NVIDIA ... (discrete GPU, Vulkan 1.3)" or "CPU reference tracer"
    QString fallbackReason;  // why the CPU tracer is used, if it is
    double frameMs = 0.0;    // the last frame, on the render thread
    double traceMs = -1.0;   // the last trace (GPU timestamps or CPU wall time)
    bool bricks = false;     // the brick renderer drew the last frame
    std::size_t voxelBytes = 0;   // voxel memory on the device (or in the CPU buffers)
    std::uint64_t shownVersion = 0;   // snapshot version on screen
    std::uint64_t shownRevision = 0;  // the document revision it shows
    bool shownComplete = false;       // ... at full depth
    bool streaming = false;           // a newer snapshot is still being uploaded
    bool gpuVoxels = false;           // the voxels shown were built by the GPU voxelizer
    bool gpuBusy = false;             // ... which is building a newer document
    double gpuBuildMs = -1.0;         // the shown GPU build, from its request to its result
    QString gpuRefusal;               // why the GPU voxelizer could not build the last request
    std::uint64_t gpuRefusedRevision = 0;
    std::uint64_t frames = 0;         // frames drawn so far
    int validationErrors = 0;         // Vulkan validation errors seen (with KERF_VULKAN_VALIDATION set)
    QString lastValidationMessage;    // the newest validation message, if any
    /// The frame's trace as the voxelizer's occlusion picture (a full
    /// resolution trace of the settled view), else null.
    std::shared_ptr<const OcclusionMap> picture;
};

/// A click on the viewport: what is under the cursor (nothing when the
/// click hit no surface).
struct ViewportPick {
    bool hit = false;
    glm::dvec3 point{0.0};    // world, mm
    glm::dvec3 normal{0.0};
    std::string nodeId;       // the feature's node ("" when none)
    Qt::KeyboardModifiers modifiers;
    /// With snapping on: what the point is (a corner, a hole centre, ...);
    /// `point` is then the snapped point.
    kerf::SnapKind snap = kerf::SnapKind::Face;
};

/// A drag of the move gizmo, as far as it has come.
struct GizmoDrag {
    kerf::GizmoHandle handle = kerf::GizmoHandle::None;
    glm::dvec3 displacement{0.0}; // world mm, as dragged (unsnapped)
    double millimetresPerPixel = 0.0; // at the gizmo: how far a pixel reaches there
    bool free = false;            // Ctrl held: no snapping
    QString typed;                // a distance typed during the drag ("" when none)
};

class ViewportWidget : public QWidget {
    Q_OBJECT
public:
    explicit ViewportWidget(QWidget* parent = nullptr);
    ~ViewportWidget() override;

    /// The newest voxel publication (the viewport streams towards it and
    /// keeps showing what it has until all of it is resident).
    void setSnapshot(std::shared_ptr<const VoxelSnapshot> snapshot);
    /// The part's field, for picking (exact rays).
    void setPickTape(std::shared_ptr<const Tape> tape);
    /// Whether this viewport can voxelize on the GPU (it draws with Vulkan).
    bool canVoxelizeOnGpu() const { return status_.vulkan; }
    /// Whether the Vulkan device is a real GPU (not a CPU implementation
    /// such as lavapipe, where the CPU voxelizer is the faster).
    bool hasHardwareGpu() const;
    /// Voxelize this document revision's `tape` on the GPU, on this grid,
    /// within `memoryBudget` bytes of device memory (0: half of it): the
    /// viewport shows the GPU's builds from now on (its preview, then full
    /// depth) instead of the snapshots. A refusal (beyond the budget) comes
    /// as gpuVoxelizerRefused(); the caller falls back. `dirtyTiles`: the
    /// tiles this revision differs in from revision `dirtySince` (same
    /// grid), rebuilt alone into the build on screen; none: every tile.
    void setGpuVoxelSource(std::shared_ptr<const Tape> tape, const GridLayout& layout, std::uint64_t revision,
                           std::size_t memoryBudget = 0, std::optional<std::vector<long>> dirtyTiles = {},
                           std::uint64_t dirtySince = 0);
    /// Back to the CPU voxelizer's snapshots (the GPU's last build stays on
    /// screen until they are on the device).
    void clearGpuVoxelSource();
    bool voxelizesOnGpu() const { return gpuRequest_ != nullptr; }
    void setMeshes(std::vector<PlacedMesh> meshes);
    /// Points drawn as markers (measured points).
    void setMarkers(const std::vector<glm::dvec3>& points);
    /// A dimension: a line between two points with `text` beside it, until
    /// cleared (none).
    void setDimension(std::optional<std::pair<glm::dvec3, glm::dvec3>> ends, const QString& text = {});
    /// A box drawn by its edges, `text` beside it (none: no box).
    void setBoxShown(std::optional<Aabb> box, const QString& text = {});
    /// The dimension's or the box's label as shown ("" when none).
    QString dimensionText() const;
    /// Translucent meshes over everything (a selected tool body).
    void setGhosts(std::vector<PlacedMesh> ghosts);
    bool hasGhosts() const { return ghosts_ && !ghosts_->empty(); }
    /// Where the ghosts are (empty: none).
    Aabb ghostBounds() const;
    /// Ends a gizmo drag under way as if Esc had been pressed in the view.
    void cancelGizmoDrag();
    /// The move gizmo at this world point (none: no gizmo).
    void setMoveGizmo(std::optional<glm::dvec3> origin);
    std::optional<glm::dvec3> moveGizmoOrigin() const { return gizmoOrigin_; }
    /// The gizmo as drawn in the current view (none when there is none).
    std::optional<MoveGizmo> moveGizmo() const;
    /// Clicks and the cursor snap to corners, hole centres and edges (measuring).
    void setSnapping(bool on);
    /// The snap under a widget position (logical pixels), on the exact field.
    std::optional<SnapPoint> snapAt(QPointF position) const;
    /// The camera of the current view, in device pixels.
    Camera camera() const;
    /// Device pixels of a widget position (logical pixels).
    glm::dvec2 devicePixel(QPointF position) const;
    /// Features of these (primitive) node ids are drawn selected.
    void setSelectedFeatureNodes(std::unordered_set<std::string> nodeIds);
    void setSection(const Section& section);
    const Section& section() const { return section_; }
    void setGridVisible(bool on);
    /// The hybrid refinement: edges and intersections from the exact field
    /// near the surface (slower; TraceQuality.hpp), or voxels alone.
    void setExactEdges(bool on);
    /// Draw the part with the brick renderer where it can (no section, no
    /// exact edges, voxels of the CPU voxelizer), else with the tracer.
    void setBrickRenderer(bool on);
    void setAxesVisible(bool on);

    /// Standard views by name (iso, front, back, left, right, top, bottom),
    /// framing the part.
    void setStandardView(const QString& name);
    void fitAll();
    void setOrthographic(bool on);
    bool orthographic() const;
    const ViewController& view() const { return view_; }
    void setView(const ViewController& view);

    ViewportStatus status() const { return status_; }
    /// The view at rest the voxelizer was last told of (none before the first frame).
    std::optional<ViewRequirement> settledView() const { return settledView_; }
    /// The next frame's picture, as drawn (waits for it, at most timeoutMs).
    QImage grabFrame(int timeoutMs = 10000);
    /// Casts the exact ray under a widget position (logical pixels).
    ViewportPick pickAt(QPointF position) const;

protected:
    void resizeEvent(QResizeEvent* e) override;

signals:
    /// A click (press and release without a drag) on the viewport.
    void clicked(const kerf::qt::ViewportPick& pick);
    /// The move gizmo: a drag began on a handle, went on (or a distance was
    /// typed), ended (Enter or the button let go) or was cancelled (Esc).
    void gizmoDragStarted();
    void gizmoDragged(const kerf::qt::GizmoDrag& drag);
    void gizmoDragFinished(bool cancelled);
    /// Esc in the view with no drag under way (clears a measurement).
    void escapePressed();
    /// The projection changed (from the View menu, or key 5 in the view):
    /// for the menu's check mark.
    void orthographicChanged(bool on);
    /// A frame was drawn; status() has its figures.
    void frameDrawn();
    /// The viewport fell back to the CPU tracer (the reason in status()).
    void backendChanged();
    /// The camera came to rest somewhere new (or the window changed size):
    /// what the voxelizer should refine for. Emitted with the first picture
    /// of that view (pictureTaken just before), or alone when the viewport
    /// shows no voxels yet or no picture comes within half a second.
    void viewSettled(const kerf::ViewRequirement& view);
    /// A picture of the settled view: what hides what, for the voxelizer
    /// (Voxelizer::setOcclusion).
    void pictureTaken(std::shared_ptr<const kerf::OcclusionMap> picture);
    /// The GPU voxelizer cannot build the current request (the reason in
    /// words): the owner goes back to the CPU voxelizer.
    void gpuVoxelizerRefused(const QString& reason);

public:
    // For the drawing surfaces (VulkanViewWindow, CpuViewWidget): input
    // they receive, and what they report.
    void onPress(QMouseEvent* e);
    void onMove(QMouseEvent* e);
    void onRelease(QMouseEvent* e);
    void onWheel(QWheelEvent* e);
    void onKey(QKeyEvent* e);
    void onBackendFailed(const QString& reason);
    void onFrame(const ViewportStatus& status);
    void sceneChanged();

private:
    void interacting();
    QSize pixelSize() const;
    Aabb partBounds() const;
    std::optional<glm::dvec3> surfacePointAt(QPointF position) const;
    void useCpu(const QString& reason);
    vk::ViewportScene scene() const; // what the next frame shows

    ViewController view_;
    bool viewFramed_ = false;
    double framedExtent_ = 0.0; // the part's largest extent when the view last framed it (mm)
    std::shared_ptr<const VoxelSnapshot> snapshot_;
    std::shared_ptr<const Tape> pickTape_;
    std::shared_ptr<const vk::GpuVoxelRequest> gpuRequest_;
    std::uint64_t gpuRefusalTold_ = 0; // the revision whose refusal was signalled
    void frameOnFirstPart();
    std::shared_ptr<const std::vector<PlacedMesh>> meshes_;
    mutable std::shared_ptr<const std::vector<PlacedMesh>> markers_;
    std::shared_ptr<const std::unordered_set<std::string>> selected_;
    Section section_;
    bool grid_ = true, axes_ = true, exactEdges_ = false, bricks_ = false;

    // Mouse state.
    enum class Drag { None, Pending, Orbit, Pan, Gizmo };
    Drag drag_ = Drag::None;
    QPointF pressAt_, lastAt_;
    Qt::MouseButton pressButton_ = Qt::NoButton;
    std::optional<glm::dvec3> pivot_;
    class QTimer* settle_ = nullptr; // ends the interactive (reduced resolution) phase
    bool interactive_ = false;
    std::optional<ViewRequirement> settledView_;
    // A settled view not yet told: it goes with the first picture of it (so
    // that the voxelizer's first plan for it knows what the part hides), or
    // alone when no such picture comes (no voxels yet) or after a while.
    std::optional<ViewRequirement> untoldView_;
    class QTimer* tellView_ = nullptr;
    double partExtent() const;
    void refitIfRescaled();
    void tellSettledView();

    // What is drawn over the part (markers and ghosts in the scene).
    std::vector<glm::dvec3> markerPoints_;
    std::optional<std::pair<glm::dvec3, glm::dvec3>> dimension_;
    std::optional<Aabb> boxShown_;
    std::optional<SnapPoint> hoverSnap_;
    bool snapping_ = false;
    std::optional<glm::dvec3> gizmoOrigin_;
    GizmoHandle gizmoHot_ = GizmoHandle::None; // under the cursor, or being dragged
    GizmoDrag gizmoDrag_;
    std::shared_ptr<const std::vector<PlacedMesh>> ghosts_;
    mutable double overlayScale_ = 0.0; // mm per pixel the markers were sized for
    mutable bool overlaysDirty_ = true;
    QLabel* label_ = nullptr; // the dimension's value, over the view
    std::optional<glm::dvec3> pressOrigin_; // the gizmo's origin when its drag began
    glm::dvec3 pressGizmoOrigin() const { return pressOrigin_.value_or(gizmoOrigin_.value_or(glm::dvec3(0.0))); }
    glm::dvec3 overlayReference() const; // where overlay sizes are measured
    void overlaysChanged();
    void rebuildOverlays() const;
    void placeLabel();
    void endGizmoDrag(bool cancelled);
    void emitGizmoDrag(QPointF at, Qt::KeyboardModifiers modifiers);

    std::unique_ptr<ViewportBackend> backend_;
    ViewportStatus status_;
};

} // namespace kerf::qt

Q_DECLARE_METATYPE(kerf::qt::ViewportPick)
Q_DECLARE_METATYPE(kerf::qt::ViewportStatus)
Q_DECLARE_METATYPE(kerf::qt::GizmoDrag)
Q_DECLARE_METATYPE(kerf::ViewRequirement)
