// relightd's frame pacing: sleeping to a tick, and the budget that lets a
// live change render between ticks without exceeding --fps on average.
#pragma once

#include <algorithm>
#include <cstdint>
#include <ctime>

namespace relight::daemon {

// Sleeps until `deadline_us` on CLOCK_MONOTONIC, or until a signal.
inline void SleepUntil(int64_t deadline_us) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(deadline_us / 1000000);
  ts.tv_nsec = static_cast<long>((deadline_us % 1000000) * 1000);
  clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
}

// When a live change may be rendered between ticks: at most one render per
// period on average. With `burst` (ticks following live input) one render
// may come up to a period early (GCRA with a tolerance of one period), so a
// console sending at the frame rate with jitter is rendered on arrival
// instead of locking onto the tick phase and waiting nearly a period.
// Without it: one period after the last render, as replays always did.
// Following live input, ticks wait for the budget too, so it bounds every
// render, not only early ones.
class RenderBudget {
 public:
  RenderBudget(int64_t period_us, bool burst) : period_us_(period_us), burst_(burst) {}
  // The earliest time the next render may start.
  int64_t EarliestUs() const { return burst_ ? next_us_ - period_us_ : last_us_ + period_us_; }
  bool Allows(int64_t now_us) const { return now_us >= EarliestUs(); }
  void Spend(int64_t now_us) {
    last_us_ = now_us;
    next_us_ = std::max(next_us_, now_us) + period_us_;
  }

 private:
  int64_t period_us_;
  bool burst_;
  int64_t last_us_ = INT64_MIN / 2;  // start of the last render
  int64_t next_us_ = INT64_MIN / 2;  // GCRA's theoretical time of the next render
};

}  // namespace relight::daemon
