#pragma once
// What a tracer produces (depth, normal and feature per pixel), how it is
// shaded for a person to look at, and how that is written to a PNG file.
//
// Pixels are stored row by row from the top-left one: index = x + width * y.

#include "kerf/evaluator/Tape.hpp"
#include "kerf/tracer/Camera.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <vector>

namespace kerf {

inline constexpr std::uint32_t kNoFeature = std::numeric_limits<std::uint32_t>::max();

/// The raw result of tracing one image.
struct TraceImage {
    int width = 0, height = 0;
    /// Distance along the pixel's ray from its origin to the hit, in mm;
    /// +infinity where the ray hits nothing.
    std::vector<float> depth;
    /// Unit outward surface normal at the hit, world frame; zero where nothing is hit.
    std::vector<glm::vec3> normal;
    /// Index into the part's features of the surface hit; kNoFeature where
    /// nothing is hit or the feature is unknown.
    std::vector<std::uint32_t> feature;
    /// False when the tracing was cancelled part way: rows are missing (misses).
    bool complete = true;

    TraceImage() = default;
    TraceImage(int w, int h);
    std::size_t index(int x, int y) const { return std::size_t(x) + std::size_t(width) * std::size_t(y); }
    bool hit(std::size_t i) const { return depth[i] < std::numeric_limits<float>::infinity(); }
};

/// 8-bit RGBA pixels, non-premultiplied, sRGB.
struct RgbaImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> pixels; // 4 bytes per pixel
};

/// Lighting for shade(). Directions are unit vectors in the world frame,
/// strengths multiply the surface colour (linear RGB).
struct ShadeOptions {
    /// Towards the key light.
    glm::vec3 lightDirection{-0.35f, -0.55f, 0.76f};
    float keyStrength = 0.5f;
    /// Towards the viewer: a weak headlight, so that no visible face is
    /// left to the fill light alone.
    glm::vec3 viewDirection{0.0f, -1.0f, 0.0f};
    float headlightStrength = 0.35f;
    /// The hemisphere fill: sky colour for normals along worldUp, ground
    /// colour for normals against it.
    glm::vec3 sky{0.49f, 0.50f, 0.53f};
    glm::vec3 ground{0.21f, 0.20f, 0.18f};
    glm::vec3 worldUp{0.0f, 0.0f, 1.0f};

    /// Key light above, to the left of and behind the viewer, headlight
    /// along the view: every standard view is lit from the front.
    static ShadeOptions forCamera(const Camera& camera);
};

/// Shades a traced image: Lambert key light and headlight plus hemisphere fill, each
/// feature in its colour (Feature::color) or a default wood tone, over a
/// vertical background gradient. Features out of range shade in the default
/// tone. Pure function; safe from any thread.
RgbaImage shade(const TraceImage& image, const std::vector<Feature>& features, const ShadeOptions& options = {});

/// Writes `rgba` (width * height * 4 bytes) as a PNG, atomically (a temporary
/// file in the same folder, then rename). Throws std::runtime_error naming
/// the file on failure; the target is then untouched.
void writePng(const std::filesystem::path& path, const std::uint8_t* rgba, int width, int height);
inline void writePng(const std::filesystem::path& path, const RgbaImage& image)
{
    writePng(path, image.pixels.data(), image.width, image.height);
}

} // namespace kerf
