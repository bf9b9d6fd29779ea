#include "kerf/tracer/ExactTracer.hpp"

#include "kerf/evaluator/PointEvaluator.hpp"
#include "kerf/voxelizer/WorkerArena.hpp"

#include <glm/geometric.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace kerf {

namespace {

// The ray came within epsilon of the surface at p (field f there): whether
// the field rises on beyond at half its slope or more instead of going
// below zero, as past a sheet of no thickness (a blind hole's mouth cut
// flush with a face is 0 across it) and never past a surface the ray
// enters. The refinement's rule (ReferenceTracer.cpp, onlyTouches), at the
// scale of epsilon.
constexpr double kTouchNear = 20.0, kTouchFar = 100.0;

bool onlyTouches(const Tape& tape, PointEvaluator<double>& points, const glm::dvec3& p, const glm::dvec3& direction,
                 double f, double epsilon)
{
    const glm::dvec3 a = p + kTouchNear * epsilon * direction, b = p + kTouchFar * epsilon * direction;
    return points.evaluate(tape, a.x, a.y, a.z) > f + 0.5 * kTouchNear * epsilon &&
           points.evaluate(tape, b.x, b.y, b.z) > f + 0.5 * kTouchFar * epsilon;
}

constexpr int kPacket = 64;      // rays marched together: one evaluator block
constexpr int kMaxSteps = 4000;  // a ray still marching after this many steps skims a surface: a miss
constexpr double kFarMm = 1.0e7; // where rays end when the part is unbounded (a halfspace)

struct RayState {
    glm::dvec3 origin{0.0}; // relative to the tape's origin
    glm::dvec3 direction{0.0};
    double t = 0.0, tEnd = 0.0;
    int steps = 0;
    bool active = false, hit = false;
};

// Clips a ray to a box: the parameter range inside it, or false.
bool clip(const glm::dvec3& o, const glm::dvec3& d, const Aabb& box, double& tNear, double& tFar)
{
    tNear = 0.0;
    tFar = kFarMm;
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) {
            if (o[a] < box.min[a] || o[a] > box.max[a]) return false;
            continue;
        }
        double t0 = (box.min[a] - o[a]) / d[a], t1 = (box.max[a] - o[a]) / d[a];
        if (t0 > t1) std::swap(t0, t1);
        tNear = std::max(tNear, t0);
        tFar = std::min(tFar, t1);
    }
    return tNear <= tFar;
}

class PacketTracer {
public:
    PacketTracer(const Tape& tape, const Camera& camera, double epsilon, TraceImage& image)
        : tape_(tape), camera_(camera), epsilon_(epsilon), image_(image), box_(tape.bounds().grown(2.0 * epsilon))
    {
    }

    // Traces pixels [x0, x0 + count) of row y, count <= kPacket.
    void trace(int y, int x0, int count)
    {
        std::array<RayState, kPacket> rays;
        int active = 0;
        for (int i = 0; i < count; ++i) {
            const Ray r = camera_.ray(x0 + i, y);
            RayState& s = rays[std::size_t(i)];
            s.origin = r.origin - tape_.origin();
            s.direction = r.direction;
            double tNear = 0.0, tFar = 0.0;
            if (!tape_.empty() && clip(r.origin, r.direction, box_, tNear, tFar)) {
                s.t = tNear;
                s.tEnd = tFar;
                s.active = true;
                ++active;
            }
        }
        // March every active ray by its field value, one batched evaluation per round.
        std::array<int, kPacket> which;
        while (active > 0) {
            int n = 0;
            for (int i = 0; i < count; ++i) {
                const RayState& s = rays[std::size_t(i)];
                if (!s.active) continue;
                const glm::dvec3 p = s.origin + s.t * s.direction;
                x_[std::size_t(n)] = p.x;
                y_[std::size_t(n)] = p.y;
                z_[std::size_t(n)] = p.z;
                which[std::size_t(n++)] = i;
            }
            points_.evaluate(tape_, x_.data(), y_.data(), z_.data(), std::size_t(n), d_.data());
            for (int k = 0; k < n; ++k) {
                RayState& s = rays[std::size_t(which[std::size_t(k)])];
                const double f = d_[std::size_t(k)];
                if (f < epsilon_ && onlyTouches(tape_, points_, s.origin + s.t * s.direction, s.direction, f, epsilon_)) {
                    s.t += kTouchFar * epsilon_; // a sheet of no thickness: on past it
                    continue;
                }
                if (f < epsilon_) {
                    s.hit = true;
                    s.active = false;
                    --active;
                    continue;
                }
                s.t += f;
                if (s.t > s.tEnd || ++s.steps > kMaxSteps || !std::isfinite(f)) {
                    s.active = false;
                    --active;
                }
            }
        }
        // Normals and features of the hits, batched too.
        int n = 0;
        std::array<int, kPacket> hits;
        for (int i = 0; i < count; ++i) {
            const RayState& s = rays[std::size_t(i)];
            if (!s.hit) continue;
            const glm::dvec3 p = s.origin + s.t * s.direction;
            x_[std::size_t(n)] = p.x;
            y_[std::size_t(n)] = p.y;
            z_[std::size_t(n)] = p.z;
            hits[std::size_t(n++)] = i;
        }
        if (n == 0) return;
        gradients_.evaluate(tape_, x_.data(), y_.data(), z_.data(), std::size_t(n), d_.data(), gx_.data(), gy_.data(),
                            gz_.data(), features_.data());
        for (int k = 0; k < n; ++k) {
            const std::size_t kk = std::size_t(k);
            const RayState& s = rays[std::size_t(hits[kk])];
            const std::size_t i = image_.index(x0 + hits[kk], y);
            glm::dvec3 g(gx_[kk], gy_[kk], gz_[kk]);
            const double len = glm::length(g);
            image_.depth[i] = float(s.t);
            image_.normal[i] = len > 0.0 && std::isfinite(len) ? glm::vec3(g / len) : glm::vec3(-s.direction);
            image_.feature[i] = features_[kk];
        }
    }

private:
    const Tape& tape_;
    const Camera& camera_;
    double epsilon_;
    TraceImage& image_;
    Aabb box_;
    PointEvaluator<double> points_;
    GradientEvaluator<double> gradients_;
    std::array<double, kPacket> x_{}, y_{}, z_{}, d_{}, gx_{}, gy_{}, gz_{};
    std::array<std::uint32_t, kPacket> features_{};
};

} // namespace

TraceImage traceExact(const Tape& tape, const Camera& camera, double epsilon, int threads, const Progress& work)
{
    if (!(epsilon > 0.0)) throw std::invalid_argument("traceExact: epsilon must be positive");
    TraceImage image(camera.width(), camera.height());
    if (tape.empty()) return image;
    tbb::task_arena arena = workerArena(threads);
    std::atomic<int> rowsDone{0};
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, image.height), [&](const tbb::blocked_range<int>& rows) {
            PacketTracer tracer(tape, camera, epsilon, image); // scratch memory for this task
            for (int y = rows.begin(); y != rows.end(); ++y) {
                if (work.cancelled()) return;
                for (int x = 0; x < image.width; x += kPacket)
                    tracer.trace(y, x, std::min(kPacket, image.width - x));
                if (work.reporting()) work.report(double(++rowsDone) / double(image.height));
            }
        });
    });
    image.complete = !work.cancelled();
    return image;
}

ExactHit castExactRay(const Tape& tape, const Ray& ray, double epsilon)
{
    if (!(epsilon > 0.0)) throw std::invalid_argument("castExactRay: epsilon must be positive");
    ExactHit h;
    double t = 0.0, tEnd = 0.0;
    if (tape.empty() || !clip(ray.origin, ray.direction, tape.bounds().grown(2.0 * epsilon), t, tEnd)) return h;
    PointEvaluator<double> points;
    const glm::dvec3 o = ray.origin - tape.origin();
    for (int step = 0; step < kMaxSteps && t <= tEnd; ++step) {
        const glm::dvec3 p = o + t * ray.direction;
        const double f = points.evaluate(tape, p.x, p.y, p.z);
        if (!std::isfinite(f)) return h;
        if (f < epsilon && onlyTouches(tape, points, p, ray.direction, f, epsilon)) {
            t += kTouchFar * epsilon; // a sheet of no thickness: on past it
            continue;
        }
        if (f < epsilon) {
            GradientEvaluator<double> gradients;
            double d = 0.0, gx = 0.0, gy = 0.0, gz = 0.0;
            std::uint32_t feature = kNoFeature;
            gradients.evaluate(tape, &p.x, &p.y, &p.z, 1, &d, &gx, &gy, &gz, &feature);
            const glm::dvec3 g(gx, gy, gz);
            const double len = glm::length(g);
            h.hit = true;
            h.depth = t;
            h.point = ray.origin + t * ray.direction;
            h.normal = len > 0.0 && std::isfinite(len) ? g / len : -ray.direction;
            h.feature = feature;
            return h;
        }
        t += f;
    }
    return h;
}

} // namespace kerf
