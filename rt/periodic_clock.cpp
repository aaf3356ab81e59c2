#include "mbrt/rt/periodic_clock.hpp"

#include <cerrno>
#include <ctime>

namespace mbrt::rt {

namespace {
constexpr std::int64_t kNsPerS = 1000000000;

std::int64_t to_ns(const timespec& t) noexcept { return t.tv_sec * kNsPerS + t.tv_nsec; }

std::int64_t now_ns(clockid_t clock) noexcept {
  timespec t{};
  clock_gettime(clock, &t);
  return to_ns(t);
}
}  // namespace

std::int64_t monotonic_ns() noexcept { return now_ns(CLOCK_MONOTONIC); }
std::int64_t realtime_us() noexcept { return now_ns(CLOCK_REALTIME) / 1000; }

PeriodicClock::PeriodicClock(std::int64_t period_ns) noexcept
    : period_ns_(period_ns), release_ns_(monotonic_ns() + period_ns) {}

std::int64_t PeriodicClock::wait_for_release() noexcept {
  const timespec at{static_cast<time_t>(release_ns_ / kNsPerS), static_cast<long>(release_ns_ % kNsPerS)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, nullptr) == EINTR) {
  }
  return monotonic_ns() - release_ns_;
}

bool PeriodicClock::finish_cycle(std::int64_t now_ns) noexcept {
  const std::int64_t deadline = release_ns_ + period_ns_;
  release_ns_ = deadline;
  if (now_ns <= deadline) return false;
  ++misses_;
  const std::int64_t skipped = (now_ns - deadline) / period_ns_ + 1;  // releases at or before now
  overruns_ += skipped;
  release_ns_ += skipped * period_ns_;
  return true;
}

}  // namespace mbrt::rt
