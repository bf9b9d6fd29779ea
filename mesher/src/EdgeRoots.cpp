#include "kerf/mesher/EdgeRoots.hpp"

#include <algorithm>
#include <cmath>

namespace kerf {

double EdgeRootFinder::clampToEdge(double t) const { return std::clamp(t, margin_, 1.0 - margin_); }

std::uint64_t EdgeRootFinder::solve(const Tape& tape, std::span<const EdgeRootJob> jobs, double* roots)
{
    std::uint64_t evaluations = 0;
    state_.resize(jobs.size());
    active_.clear();
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        const EdgeRootJob& j = jobs[i];
        // An end exactly on the surface is the root.
        if (j.f0 == 0.0) {
            roots[i] = clampToEdge(0.0);
            continue;
        }
        if (j.f1 == 0.0) {
            roots[i] = clampToEdge(1.0);
            continue;
        }
        state_[i] = {0.0, 1.0, j.f0, j.f1, j.f0, j.f1, 1.0, -1, 0, false};
        active_.push_back(std::uint32_t(i));
    }
    const glm::dvec3 origin = tape.origin();
    for (int iteration = 0; !active_.empty(); ++iteration) {
        const std::size_t n = active_.size();
        t_.resize(n);
        x_.resize(n);
        y_.resize(n);
        z_.resize(n);
        f_.resize(n);
        for (std::size_t k = 0; k < n; ++k) {
            State& s = state_[active_[k]];
            double t = 0.5 * (s.a + s.b);
            if (!s.bisect) {
                const double falsi = s.a - s.wa * (s.b - s.a) / (s.wb - s.wa);
                if (falsi > s.a && falsi < s.b) t = falsi; // else (NaN, outside, on an end): bisect
            }
            t_[k] = t;
            const glm::dvec3 p = jobs[active_[k]].at(t);
            x_[k] = p.x - origin.x;
            y_[k] = p.y - origin.y;
            z_[k] = p.z - origin.z;
        }
        points_.evaluate(tape, x_.data(), y_.data(), z_.data(), n, f_.data());
        evaluations += n;
        std::size_t kept = 0;
        for (std::size_t k = 0; k < n; ++k) {
            const std::uint32_t i = active_[k];
            State& s = state_[i];
            const double t = t_[k], f = f_[k];
            if (f == 0.0) { // exactly on the surface
                roots[i] = clampToEdge(t);
                continue;
            }
            if ((f < 0.0) == (s.fa < 0.0)) {
                s.a = t;
                s.fa = s.wa = f;
                if (s.last == 0) s.wb *= 0.5; // a moved twice: pull the falsi point towards b
                s.last = 0;
            } else {
                s.b = t;
                s.fb = s.wb = f;
                if (s.last == 1) s.wa *= 0.5;
                s.last = 1;
            }
            // Safeguard: the bracket must halve every three steps, or the
            // next step bisects.
            s.bisect = false;
            if (++s.sinceCheck == 3) {
                s.bisect = s.b - s.a > 0.5 * s.widthAtCheck;
                s.widthAtCheck = s.b - s.a;
                s.sinceCheck = 0;
            }
            if (s.b - s.a <= kRootTolerance || iteration >= 200) {
                // False position with the true end values, inside the bracket.
                double r = s.a - s.fa * (s.b - s.a) / (s.fb - s.fa);
                if (!(r >= s.a && r <= s.b)) r = 0.5 * (s.a + s.b);
                roots[i] = clampToEdge(r);
                continue;
            }
            active_[kept++] = i;
        }
        active_.resize(kept);
    }
    return evaluations;
}

} // namespace kerf
