#pragma once
// Progress and cancellation of long work, one type for every stage that can
// take seconds: the voxelizer, the mesher and the exporter, the tracers, the
// accuracy measures (in the spirit of openvdb's util::Interrupter and
// manifold's ExecutionContext). It lives at the bottom of the core so that
// every module can take it; it knows nothing of threads, terminals or Qt.
//
// - cancelled(): polled by the work, from any thread, now and then (between
//   tiles, rows, batches of cells). Once it has said true it says true for
//   good, so the work can stop at its own pace and every caller up the
//   stack sees the same answer.
// - report(fraction): the part of this work done, in [0, 1], from any
//   thread. The callback sees the reports serialized (never two at once),
//   non-decreasing, and about 200 at most over the whole work.
// - stage(begin, end): a step of the work that covers [begin, end] of its
//   fraction (meshing 0 to 0.6, checking 0.6 to 1): the step reports 0 to 1.
// - orCancelledWhen(condition): the same work with one more reason to stop
//   (a deadline, a newer edit); the original is not affected.
//
// A default-constructed Progress is never cancelled and reports to no one.

#include <functional>
#include <memory>

namespace kerf {

class Progress {
public:
    using OnFraction = std::function<void(double fraction)>;
    using Cancelled = std::function<bool()>;

    Progress() = default;
    explicit Progress(OnFraction onFraction, Cancelled cancelled = {});

    /// A Progress that only stops, never reports.
    static Progress cancelledWhen(Cancelled cancelled) { return Progress({}, std::move(cancelled)); }

    /// True once the work was asked to stop; stays true.
    bool cancelled() const;

    /// This work's fraction done, in [0, 1] (clamped).
    void report(double fraction) const;

    /// Whether anyone listens to report(): work may skip counting otherwise.
    bool reporting() const;

    /// A step of this work covering [begin, end] of its fraction.
    Progress stage(double begin, double end) const;

    /// This work with `condition` as a further reason to stop.
    Progress orCancelledWhen(Cancelled condition) const;

private:
    struct Reports;    // the callback and what it was last told, shared by the stages
    struct Stop;       // the conditions and the latch, shared by the stages
    std::shared_ptr<Reports> reports_;
    std::shared_ptr<Stop> stop_;
    double begin_ = 0.0;
    double end_ = 1.0;
};

} // namespace kerf
