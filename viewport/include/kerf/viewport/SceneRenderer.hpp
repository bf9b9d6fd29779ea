#pragma once
// Turns a trace into a picture and mixes ordinary meshes in by depth:
//  1. the part pass (a full-screen triangle) shades the traced depth,
//     normal and feature (lambert, headlight, hemisphere fill, specular,
//     silhouette and feature edges, per-feature colour, the selection
//     tinted and outlined, section caps hatched) and writes the part's depth
//     into the depth buffer: the depth prepass;
//  2. the mesh pass rasterizes reference meshes with the same projection,
//     depth-tested against it, so each hides the other where it is in front;
//  3. optionally the ground grid (the plane z = 0, depth tested, blended),
//     ghosts (translucent meshes over everything: a selected hole's tool
//     body), marker meshes drawn over everything (measured points, the move
//     gizmo, dimensions), and the axis gizmo in a corner.
// Offscreen (headless) render() reads the colour image back as RGBA; a
// window's frame is record()ed and its colour image copied to the screen.
//
// Threading: one thread. The context must outlive the renderer. One frame
// in flight: record() may be called again only after the commands it
// recorded before have finished (per-frame buffers are reused).

#include "kerf/tracer/Image.hpp"
#include "kerf/viewport/BrickRenderer.hpp"
#include "kerf/viewport/ComputeTracer.hpp"
#include "kerf/viewport/ReferenceMesh.hpp"

#include <functional>
#include <memory>
#include <vector>

namespace kerf::vk {

struct SceneOptions {
    bool edges = true;
    ShadeOptions lights;                          // directions and strengths (ShadeOptions::forCamera)
    glm::vec3 defaultColor{0.71f, 0.49f, 0.30f};  // linear; parts without a colour
    float edgeDarkening = 0.65f;
    /// Features (indices into the features list) drawn as selected.
    std::vector<std::uint32_t> selectedFeatures;
    glm::vec3 highlight{0.10f, 0.42f, 1.0f}; // linear
    float highlightStrength = 0.45f;
    bool grid = false; // the ground grid on z = 0
    bool axes = false; // the axis gizmo, lower left
    /// The section plane the trace cut along (for the caps' colour); unused
    /// when the trace had none.
    glm::vec3 capColor{0.80f, 0.16f, 0.12f};
    /// Voxels, or the hybrid refinement on the exact field (TraceQuality.hpp).
    TraceQuality quality = TraceQuality::Voxels;
};

class SceneRenderer {
public:
    explicit SceneRenderer(const Context& ctx);
    ~SceneRenderer();

    /// Replaces the meshes drawn with the part (uploads them).
    void setMeshes(const std::vector<PlacedMesh>& meshes);
    /// Replaces the markers: meshes drawn over everything (measured points).
    void setMarkers(const std::vector<PlacedMesh>& markers);
    /// Replaces the ghosts: meshes blended over everything with their
    /// PlacedMesh::opacity, under the markers.
    void setGhosts(const std::vector<PlacedMesh>& ghosts);

    /// Traces `voxels` with `tracer`, shades, draws the meshes and reads the
    /// picture back. `features` gives the per-feature colours. The trace is
    /// recorded only when the camera, the image size, the section, the
    /// voxels or the quality changed since the last frame; shading and
    /// meshes are drawn every frame.
    RgbaImage render(ComputeTracer& tracer, const VoxelAddresses& voxels, const Camera& camera,
                     const std::vector<Feature>& features, const SceneOptions& options = {},
                     const Section& section = {});

    /// As render(), recorded into `cb` and not read back: afterwards the
    /// colour image (colorImage(), R8G8B8A8 UNORM holding sRGB values, the
    /// camera's size) is in TRANSFER_SRC_OPTIMAL layout, ready to be copied.
    void record(VkCommandBuffer cb, ComputeTracer& tracer, const VoxelAddresses& voxels, const Camera& camera,
                const std::vector<Feature>& features, const SceneOptions& options = {}, const Section& section = {});
    /// The same with the brick renderer's picture of the part (voxels only:
    /// no exact edges; SceneOptions::quality is ignored).
    RgbaImage render(BrickRenderer& bricks, const Camera& camera, const std::vector<Feature>& features,
                     const SceneOptions& options = {}, const Section& section = {});
    void record(VkCommandBuffer cb, BrickRenderer& bricks, const Camera& camera, const std::vector<Feature>& features,
                const SceneOptions& options = {}, const Section& section = {});
    VkImage colorImage() const;
    /// Reads the last recorded picture back (after its commands finished;
    /// waits for the copy). Empty before the first frame.
    RgbaImage readPicture() const;

    /// Whether the last frame traced (false: it reused the previous trace).
    bool lastFrameTraced() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace kerf::vk
