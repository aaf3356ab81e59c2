// The periodic clock's overrun policy, driven with given end-of-cycle times
// (no timing asserts): a cycle ending after its deadline is a miss, and the
// releases it ran past are skipped and counted.
#include <doctest/doctest.h>

#include <mbrt/rt/periodic_clock.hpp>

using mbrt::rt::PeriodicClock;

TEST_CASE("cycles ending by their deadline advance the release by one period") {
  constexpr std::int64_t P = 1000000;
  PeriodicClock clock(P);
  const std::int64_t r0 = clock.release_ns();
  CHECK(!clock.finish_cycle(r0 + P / 2));
  CHECK(clock.release_ns() == r0 + P);
  CHECK(!clock.finish_cycle(r0 + 2 * P));  // exactly at the deadline
  CHECK(clock.release_ns() == r0 + 2 * P);
  CHECK(clock.deadline_misses() == 0);
  CHECK(clock.overruns() == 0);
}

TEST_CASE("a late cycle is a miss and the releases it ran past are skipped") {
  constexpr std::int64_t P = 1000000;
  PeriodicClock clock(P);
  const std::int64_t r0 = clock.release_ns();
  CHECK(clock.finish_cycle(r0 + P + 1));  // ran past the release at r0 + P
  CHECK(clock.release_ns() == r0 + 2 * P);
  CHECK(clock.overruns() == 1);
  CHECK(clock.finish_cycle(r0 + 2 * P + 3 * P + P / 2));  // ran past r0 + 3P, 4P and 5P
  CHECK(clock.release_ns() == r0 + 6 * P);
  CHECK(clock.deadline_misses() == 2);
  CHECK(clock.overruns() == 4);
}

TEST_CASE("waiting never returns before the release") {
  PeriodicClock clock(200000);
  for (int i = 0; i < 5; ++i) {
    CHECK(clock.wait_for_release() >= 0);
    clock.finish_cycle(mbrt::rt::monotonic_ns());
  }
}
