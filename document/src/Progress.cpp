#include "kerf/document/Progress.hpp"

#include <algorithm>
#include <atomic>
#include <mutex>

namespace kerf {

namespace {
// Reports closer than this to the last one sent are dropped: about 200 over the whole work.
constexpr double kReportStep = 0.005;
} // namespace

struct Progress::Reports {
    OnFraction onFraction;
    std::mutex mutex;
    double sent = -1.0;
};

struct Progress::Stop {
    Cancelled condition;
    std::shared_ptr<Stop> parent; // orCancelledWhen: the original work's reasons too
    std::atomic<bool> latched{false};

    bool check()
    {
        if (latched.load(std::memory_order_relaxed)) return true;
        if ((condition && condition()) || (parent && parent->check())) {
            latched.store(true, std::memory_order_relaxed);
            return true;
        }
        return false;
    }
};

Progress::Progress(OnFraction onFraction, Cancelled cancelled)
{
    if (onFraction) {
        reports_ = std::make_shared<Reports>();
        reports_->onFraction = std::move(onFraction);
    }
    if (cancelled) {
        stop_ = std::make_shared<Stop>();
        stop_->condition = std::move(cancelled);
    }
}

bool Progress::cancelled() const { return stop_ && stop_->check(); }

bool Progress::reporting() const { return reports_ != nullptr; }

void Progress::report(double fraction) const
{
    if (!reports_) return;
    const double f = begin_ + (end_ - begin_) * std::clamp(fraction, 0.0, 1.0);
    std::lock_guard lock(reports_->mutex);
    // The last report (1) always goes out; the others only a step past the previous one.
    if (f < reports_->sent + kReportStep && !(f >= 1.0 && reports_->sent < 1.0)) return;
    reports_->sent = f;
    reports_->onFraction(f);
}

Progress Progress::stage(double begin, double end) const
{
    Progress s = *this;
    s.begin_ = begin_ + (end_ - begin_) * std::clamp(begin, 0.0, 1.0);
    s.end_ = begin_ + (end_ - begin_) * std::clamp(end, 0.0, 1.0);
    return s;
}

Progress Progress::orCancelledWhen(Cancelled condition) const
{
    Progress p = *this;
    if (!condition) return p;
    p.stop_ = std::make_shared<Stop>();
    p.stop_->condition = std::move(condition);
    p.stop_->parent = stop_;
    return p;
}

} // namespace kerf
