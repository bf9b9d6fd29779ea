#include "kerf/tracer/Image.hpp"

#include "kerf/document/AtomicFile.hpp"

#include <glm/geometric.hpp>

#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace kerf {

namespace {

// Unfinished wood (a light oak), for features without a colour.
constexpr Color kWood{210, 170, 120};

float srgbToLinear(std::uint8_t c)
{
    const float v = float(c) / 255.0f;
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

std::uint8_t linearToSrgb(float v)
{
    v = std::clamp(v, 0.0f, 1.0f);
    const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
    return std::uint8_t(std::lround(s * 255.0f));
}

glm::vec3 linear(Color c) { return {srgbToLinear(c.r), srgbToLinear(c.g), srgbToLinear(c.b)}; }

} // namespace

TraceImage::TraceImage(int w, int h)
    : width(w), height(h), depth(std::size_t(w) * std::size_t(h), std::numeric_limits<float>::infinity()),
      normal(std::size_t(w) * std::size_t(h), glm::vec3(0.0f)), feature(std::size_t(w) * std::size_t(h), kNoFeature)
{
}

ShadeOptions ShadeOptions::forCamera(const Camera& camera)
{
    ShadeOptions o;
    const glm::dvec3 l = -camera.forward() + 0.8 * camera.up() - 0.5 * camera.right();
    o.lightDirection = glm::vec3(glm::normalize(l));
    o.viewDirection = glm::vec3(-camera.forward());
    return o;
}

RgbaImage shade(const TraceImage& image, const std::vector<Feature>& features, const ShadeOptions& options)
{
    RgbaImage out;
    out.width = image.width;
    out.height = image.height;
    out.pixels.resize(std::size_t(image.width) * std::size_t(image.height) * 4);

    // Linear colours of the features once, not per pixel.
    std::vector<glm::vec3> palette(features.size());
    for (std::size_t f = 0; f < features.size(); ++f)
        palette[f] = linear(features[f].hasColor ? features[f].color : kWood);
    const glm::vec3 wood = linear(kWood);
    const glm::vec3 light = glm::normalize(options.lightDirection);
    const glm::vec3 up = glm::normalize(options.worldUp);
    const glm::vec3 view = glm::normalize(options.viewDirection);
    const glm::vec3 backgroundTop = linear({206, 212, 220}), backgroundBottom = linear({142, 148, 158});

    for (int y = 0; y < image.height; ++y) {
        const float v = image.height > 1 ? float(y) / float(image.height - 1) : 0.0f;
        const glm::vec3 background = backgroundTop + (backgroundBottom - backgroundTop) * v;
        for (int x = 0; x < image.width; ++x) {
            const std::size_t i = image.index(x, y);
            glm::vec3 c = background;
            if (image.hit(i)) {
                const std::uint32_t f = image.feature[i];
                const glm::vec3 base = f < palette.size() ? palette[f] : wood;
                const glm::vec3 n = image.normal[i];
                const float key = options.keyStrength * std::max(0.0f, glm::dot(n, light)) +
                                  options.headlightStrength * std::max(0.0f, glm::dot(n, view));
                const float h = 0.5f + 0.5f * glm::dot(n, up);
                const glm::vec3 fill = options.ground + (options.sky - options.ground) * h;
                c = base * (fill + glm::vec3(key));
            }
            std::uint8_t* p = &out.pixels[4 * i];
            p[0] = linearToSrgb(c.r);
            p[1] = linearToSrgb(c.g);
            p[2] = linearToSrgb(c.b);
            p[3] = 255;
        }
    }
    return out;
}

void writePng(const std::filesystem::path& path, const std::uint8_t* rgba, int width, int height)
{
    if (width <= 0 || height <= 0 || !rgba) throw std::runtime_error(path.string() + ": cannot write an empty image");
    std::string bytes;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size));
    };
    if (!stbi_write_png_to_func(append, &bytes, width, height, 4, rgba, width * 4))
        throw std::runtime_error(path.string() + ": PNG encoding failed");
    writeFileAtomically(path, bytes);
}

} // namespace kerf
