#pragma once
// Turns a trace into a picture and mixes ordinary meshes in by depth:
//  1. the part pass (a full-screen triangle) shades the traced depth,
//     normal and feature (lambert, headlight, hemisphere fill, specular,
//     silhouette and feature edges, per-feature colour) and writes the
//     part's depth into the depth buffer: the depth prepass;
//  2. the mesh pass rasterizes reference meshes with the same projection,
//     depth-tested against it, so each hides the other where it is in front.
// Offscreen (headless): the colour image is read back as RGBA.
//
// Threading: one thread. The context must outlive the renderer.

#include "kerf/tracer/Image.hpp"
#include "kerf/viewport/ComputeTracer.hpp"
#include "kerf/viewport/ReferenceMesh.hpp"

#include <memory>
#include <vector>

namespace kerf::vk {

struct SceneOptions {
    bool edges = true;
    ShadeOptions lights;            // directions and strengths (ShadeOptions::forCamera)
    glm::vec3 defaultColor{0.71f, 0.49f, 0.30f}; // linear; parts without a colour
    float edgeDarkening = 0.65f;
};

class SceneRenderer {
public:
    explicit SceneRenderer(const Context& ctx);
    ~SceneRenderer();

    /// Replaces the meshes drawn with the part (uploads them).
    void setMeshes(const std::vector<PlacedMesh>& meshes);

    /// Traces `voxels` with `tracer`, shades, draws the meshes and reads the
    /// picture back. `features` gives the per-feature colours. The trace is
    /// recorded only when the camera, the image size or the voxels changed
    /// since the last frame; shading and meshes are drawn every frame.
    RgbaImage render(ComputeTracer& tracer, const VoxelAddresses& voxels, const Camera& camera,
                     const std::vector<Feature>& features, const SceneOptions& options = {});
    /// Whether the last render() traced (false: it reused the previous trace).
    bool lastFrameTraced() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace kerf::vk
