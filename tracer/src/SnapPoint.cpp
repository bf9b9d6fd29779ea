#include "kerf/tracer/SnapPoint.hpp"

#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/tracer/ExactTracer.hpp"

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <numbers>

namespace kerf {

const char* snapKindName(SnapKind kind)
{
    switch (kind) {
    case SnapKind::Face: return "face";
    case SnapKind::Edge: return "edge";
    case SnapKind::Vertex: return "corner";
    case SnapKind::CircleCentre: return "centre";
    }
    return "face";
}

namespace {

// Rim samples that must lie on the surface for a circle to count as an edge
// of the part (a hole cut by the board's edge keeps most of its rim).
constexpr int kRimSamples = 12;
constexpr int kRimSamplesOnSurface = 8;

class Snapper {
public:
    Snapper(const Tape& tape, const Camera& camera, glm::dvec2 pixel, const SnapOptions& options)
        : tape_(tape), camera_(camera), pixel_(pixel), options_(options),
          ray_(camera.ray(pixel.x, pixel.y)), epsilon_(std::max(1e-6, 1e-6 * glm::length(tape.bounds().size())))
    {
        hit_ = castExactRay(tape_, ray_, epsilon_);
    }

    std::optional<SnapPoint> run()
    {
        for (const ShapeInstance& s : tape_.shapes()) {
            if (!nearCursor(s.worldBounds)) continue;
            const Affine toWorld = s.worldToLocal.inverseOrthogonal();
            switch (s.kind) {
            case ShapeKind::Box: boxCandidates(s, toWorld); break;
            case ShapeKind::Cylinder: roundCandidates(s, toWorld, s.param[0], s.param[0], s.param[1]); break;
            case ShapeKind::Cone: roundCandidates(s, toWorld, s.param[0], s.param[1], s.param[2]); break;
            default: break;
            }
        }
        for (const auto& best : best_)
            if (best) return best->snap;
        if (hit_.hit) return SnapPoint{SnapKind::Face, ontoSurface(hit_.point), hit_.feature};
        return std::nullopt;
    }

private:
    struct Scored {
        SnapPoint snap;
        double pixels = 0.0;
    };

    double field(const glm::dvec3& p) { return points_.evaluate(tape_, p.x - tape_.origin().x, p.y - tape_.origin().y, p.z - tape_.origin().z); }
    bool onSurface(const glm::dvec3& p) { return std::abs(field(p)) <= options_.onSurface; }

    // The ray stops within its epsilon of the surface: a few Newton steps
    // along the gradient put the point on it (to rounding, on flat faces).
    glm::dvec3 ontoSurface(glm::dvec3 p)
    {
        const glm::dvec3 o = tape_.origin();
        for (int i = 0; i < 3; ++i) {
            const Dual<double> f = gradients_.evaluate(tape_, p.x - o.x, p.y - o.y, p.z - o.z);
            const glm::dvec3 g(f.d[0], f.d[1], f.d[2]);
            const double g2 = glm::dot(g, g);
            if (f.v == 0.0 || !(g2 > 0.0)) break;
            const glm::dvec3 next = p - (f.v / g2) * g;
            if (glm::length(next - p) > 10.0 * epsilon_) break; // not near a smooth piece: keep the hit
            p = next;
        }
        return p;
    }

    std::optional<double> pixelsFromCursor(const glm::dvec3& p) const
    {
        const auto at = camera_.project(p);
        if (!at) return std::nullopt;
        return glm::length(*at - pixel_);
    }

    // Whether any part of a box's image comes within the snap radius.
    bool nearCursor(const Aabb& box) const
    {
        if (box.isEmpty() || !box.isBounded()) return false;
        glm::dvec2 lo(1e300), hi(-1e300);
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 corner((c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                                    (c & 4) ? box.max.z : box.min.z);
            const auto at = camera_.project(corner);
            if (!at) return true; // reaches behind the eye: cannot rule it out
            lo = glm::min(lo, *at);
            hi = glm::max(hi, *at);
        }
        const double r = options_.radiusPixels;
        return pixel_.x >= lo.x - r && pixel_.x <= hi.x + r && pixel_.y >= lo.y - r && pixel_.y <= hi.y + r;
    }

    // Nothing of the part lies in front of `p` along the line of sight.
    bool visible(const glm::dvec3& p)
    {
        const auto at = camera_.project(p);
        if (!at) return false;
        const Ray r = camera_.ray(at->x, at->y);
        const ExactHit h = castExactRay(tape_, r, epsilon_);
        if (!h.hit) return true; // the line of sight grazes the silhouette
        const double depth = glm::dot(p - r.origin, r.direction);
        const double slack = std::max(3.0 * camera_.millimetresPerPixel(p), 10.0 * options_.onSurface);
        return h.depth >= depth - slack;
    }

    void offer(SnapKind kind, const glm::dvec3& p, double pixels, std::uint32_t feature)
    {
        auto& slot = best_[rank(kind)];
        if (slot && slot->pixels <= pixels) return;
        slot = Scored{SnapPoint{kind, p, feature}, pixels};
    }

    static int rank(SnapKind kind)
    {
        switch (kind) {
        case SnapKind::Vertex: return 0;
        case SnapKind::CircleCentre: return 1;
        case SnapKind::Edge: return 2;
        default: return 3;
        }
    }

    void boxCandidates(const ShapeInstance& s, const Affine& toWorld)
    {
        if (s.param[3] > 0.0) return; // rounded: no sharp corners or edges
        const glm::dvec3 half(s.param[0], s.param[1], s.param[2]);
        std::array<glm::dvec3, 8> corners;
        for (int c = 0; c < 8; ++c)
            corners[c] = toWorld.apply(glm::dvec3((c & 1) ? half.x : -half.x, (c & 2) ? half.y : -half.y,
                                                  (c & 4) ? half.z : -half.z));
        for (const glm::dvec3& c : corners) {
            const auto px = pixelsFromCursor(c);
            if (px && *px <= options_.radiusPixels && onSurface(c) && visible(c)) offer(SnapKind::Vertex, c, *px, s.feature);
        }
        for (int a = 0; a < 8; ++a)
            for (int bit : {1, 2, 4}) {
                if (a & bit) continue;
                edgeCandidate(corners[a], corners[a | bit], s.feature);
            }
    }

    // The point of segment [a, b] nearest the cursor's ray.
    void edgeCandidate(const glm::dvec3& a, const glm::dvec3& b, std::uint32_t feature)
    {
        const glm::dvec3 u = b - a, w = a - ray_.origin;
        const double uu = glm::dot(u, u), ud = glm::dot(u, ray_.direction);
        const double denom = uu - ud * ud;
        if (uu <= 0.0 || denom <= 1e-12 * uu) return; // seen end on
        const double s = std::clamp((ud * glm::dot(ray_.direction, w) - glm::dot(u, w)) / denom, 0.0, 1.0);
        const glm::dvec3 q = a + s * u;
        const auto px = pixelsFromCursor(q);
        if (px && *px <= options_.radiusPixels && onSurface(q) && visible(q)) offer(SnapKind::Edge, q, *px, feature);
    }

    // Cylinders and cones (local axis z, radius rBottom at z = -halfHeight to
    // rTop at +halfHeight): the centre of a rim lying in a face across the
    // axis: the face under the cursor, or either end.
    void roundCandidates(const ShapeInstance& s, const Affine& toWorld, double rBottom, double rTop, double halfHeight)
    {
        const glm::dvec3 axis = glm::normalize(toWorld.applyLinear(glm::dvec3(0, 0, 1)));
        std::array<double, 3> heights{-halfHeight, halfHeight, 0.0};
        int count = 2;
        if (hit_.hit && std::abs(glm::dot(hit_.normal, axis)) > 0.98) {
            const double t = s.worldToLocal.apply(hit_.point).z;
            if (t > -halfHeight && t < halfHeight) heights[count++] = t;
        }
        for (int i = 0; i < count; ++i) {
            const double t = heights[i];
            const double radius = rBottom + (rTop - rBottom) * (t + halfHeight) / (2.0 * halfHeight);
            if (!(radius > 0.0)) continue;
            const glm::dvec3 centre = toWorld.apply(glm::dvec3(0, 0, t));
            // Where the cursor's ray meets the rim's plane.
            const double along = glm::dot(ray_.direction, axis);
            if (std::abs(along) < 1e-9) continue; // the rim seen edge on
            const double k = glm::dot(centre - ray_.origin, axis) / along;
            if (k <= 0.0) continue;
            const glm::dvec3 onPlane = ray_.origin + k * ray_.direction;
            glm::dvec3 radial = onPlane - centre;
            const double r = glm::length(radial);
            radial = r > 0.0 ? radial / r : glm::normalize(toWorld.applyLinear(glm::dvec3(1, 0, 0)));
            const glm::dvec3 rimPoint = centre + radius * radial;
            const auto toRim = pixelsFromCursor(rimPoint), toCentre = pixelsFromCursor(centre);
            if (!toRim || !toCentre) continue;
            const double px = std::min(*toRim, *toCentre);
            if (px > options_.radiusPixels) continue;
            if (!rimOnSurface(toWorld, radius, t) || !visible(rimPoint)) continue;
            offer(SnapKind::CircleCentre, centre, px, s.feature);
        }
    }

    bool rimOnSurface(const Affine& toWorld, double radius, double t)
    {
        int on = 0;
        for (int i = 0; i < kRimSamples; ++i) {
            const double a = 2.0 * std::numbers::pi * i / kRimSamples;
            if (onSurface(toWorld.apply(glm::dvec3(radius * std::cos(a), radius * std::sin(a), t)))) ++on;
        }
        return on >= kRimSamplesOnSurface;
    }

    const Tape& tape_;
    const Camera& camera_;
    glm::dvec2 pixel_;
    SnapOptions options_;
    Ray ray_;
    double epsilon_;
    ExactHit hit_;
    PointEvaluator<double> points_;
    GradientEvaluator<double> gradients_;
    std::array<std::optional<Scored>, 3> best_; // vertex, centre, edge
};

} // namespace

std::optional<SnapPoint> snapAt(const Tape& tape, const Camera& camera, glm::dvec2 pixel, const SnapOptions& options)
{
    if (tape.empty()) return std::nullopt;
    return Snapper(tape, camera, pixel, options).run();
}

} // namespace kerf
