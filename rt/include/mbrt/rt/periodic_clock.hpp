// Releases a loop at absolute times start + k * period on CLOCK_MONOTONIC
// (clock_nanosleep with TIMER_ABSTIME, so sleep errors never accumulate).
//
// Overrun policy: cycle k must finish by release k + 1 (its deadline). A
// cycle that finishes later is a deadline miss. If it ran past further
// releases, those releases are skipped, not made up in a burst: the next
// cycle starts at the first release still ahead, and each skipped release
// counts as an overrun. Simulated time then falls behind wall time by the
// skipped periods; the loop itself never stops.
#pragma once

#include <cstdint>

namespace mbrt::rt {

std::int64_t monotonic_ns() noexcept;
std::int64_t realtime_us() noexcept;  // wall clock, for message time stamps (LCM utime)

class PeriodicClock {
 public:
  // The first release is one period from now.
  explicit PeriodicClock(std::int64_t period_ns) noexcept;

  // Sleeps until the next release; returns how late the wake-up was (ns).
  std::int64_t wait_for_release() noexcept;

  // Ends the current cycle at time now_ns: true if it missed its deadline.
  bool finish_cycle(std::int64_t now_ns) noexcept;

  std::int64_t release_ns() const noexcept { return release_ns_; }
  std::int64_t deadline_misses() const noexcept { return misses_; }
  std::int64_t overruns() const noexcept { return overruns_; }

 private:
  std::int64_t period_ns_;
  std::int64_t release_ns_;
  std::int64_t misses_ = 0;
  std::int64_t overruns_ = 0;
};

}  // namespace mbrt::rt
