// The command gate: what reaches the model, what is counted, and when the
// inputs fall back to their safe values. Times are given, not measured.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <limits>

#include <mbrt/rt/command_gate.hpp>

using namespace mbrt::rt;

namespace {

constexpr std::int64_t kMs = 1000000;
const std::array<mbrt::InputInfo, 2> kInputs{{{"tau", "joint_torque", "pin", -10.0, 10.0, 0.5},
                                              {"push", "joint_force", "rail", -2.0, 2.0, -1.0}}};
const GateTimes kTimes{50 * kMs, 20 * kMs};  // stale after 50 ms, late after 20 ms

using Gate = CommandGate<2>;
using Values = Gate::Values;

std::int64_t rejected(const Gate& g, CommandVerdict v) { return g.counts().by_verdict[static_cast<std::size_t>(v)]; }

}  // namespace

TEST_CASE("before any command the inputs are the safe values") {
  Gate g(kInputs, kTimes);
  const Values u = g.inputs_for_cycle(0);
  CHECK(u == Values{0.5, -1.0});
  CHECK(g.on_safe_values());
  CHECK(g.counts().safe_cycles == 1);
  CHECK(g.counts().stale == 0);  // never had a command: not a fall-back
}

TEST_CASE("a valid command is applied, values at the range limits included") {
  Gate g(kInputs, kTimes);
  CHECK(g.offer(0, 1 * kMs, {10.0, -2.0}, 0) == CommandVerdict::applied);
  CHECK(g.inputs_for_cycle(1 * kMs) == Values{10.0, -2.0});
  CHECK(g.counts().applied() == 1);
  CHECK(g.counts().rejected() == 0);
  CHECK(g.last_sequence() == 0);
}

TEST_CASE("NaN, Inf and out-of-range values are rejected and the last good command stays") {
  Gate g(kInputs, kTimes);
  REQUIRE(g.offer(0, 0, {1.0, 1.0}, 0) == CommandVerdict::applied);
  CHECK(g.offer(1, 0, {std::nan(""), 1.0}, 1 * kMs) == CommandVerdict::non_finite);
  CHECK(g.offer(2, 0, {1.0, std::numeric_limits<double>::infinity()}, 2 * kMs) == CommandVerdict::non_finite);
  CHECK(g.offer(3, 0, {10.001, 1.0}, 3 * kMs) == CommandVerdict::out_of_range);
  CHECK(g.offer(4, 0, {1.0, -2.5}, 4 * kMs) == CommandVerdict::out_of_range);
  CHECK(g.inputs_for_cycle(5 * kMs) == Values{1.0, 1.0});
  CHECK(rejected(g, CommandVerdict::non_finite) == 2);
  CHECK(rejected(g, CommandVerdict::out_of_range) == 2);
  CHECK(g.counts().missing == 0);  // every sequence number arrived
}

TEST_CASE("duplicates and older sequence numbers are rejected; gaps count as missing") {
  Gate g(kInputs, kTimes);
  REQUIRE(g.offer(5, 0, {1.0, 0.0}, 0) == CommandVerdict::applied);
  CHECK(g.offer(5, 0, {2.0, 0.0}, 1 * kMs) == CommandVerdict::duplicate);
  CHECK(g.offer(4, 0, {3.0, 0.0}, 2 * kMs) == CommandVerdict::out_of_order);
  CHECK(g.offer(9, 0, {4.0, 0.0}, 3 * kMs) == CommandVerdict::applied);
  CHECK(g.counts().missing == 3);  // 6, 7, 8
  CHECK(g.inputs_for_cycle(3 * kMs) == Values{4.0, 0.0});
}

TEST_CASE("a command older than the maximum age on arrival is late") {
  Gate g(kInputs, kTimes);
  CHECK(g.offer(0, 21 * kMs, {1.0, 0.0}, 0) == CommandVerdict::late);
  CHECK(g.inputs_for_cycle(0) == Values{0.5, -1.0});
  CHECK(rejected(g, CommandVerdict::late) == 1);
}

TEST_CASE("malformed messages are only counted") {
  Gate g(kInputs, kTimes);
  g.reject_malformed();
  g.reject_malformed();
  CHECK(rejected(g, CommandVerdict::malformed) == 2);
  CHECK(g.counts().rejected() == 2);
}

TEST_CASE("without commands for the stale timeout the inputs fall back to safe, and a restarted sequence is accepted") {
  Gate g(kInputs, kTimes);
  REQUIRE(g.offer(100, 0, {3.0, 1.0}, 0) == CommandVerdict::applied);
  CHECK(g.inputs_for_cycle(50 * kMs) == Values{3.0, 1.0});  // exactly the timeout: still fresh
  CHECK(g.inputs_for_cycle(51 * kMs) == Values{0.5, -1.0});
  CHECK(g.counts().stale == 1);
  CHECK(g.inputs_for_cycle(52 * kMs) == Values{0.5, -1.0});
  CHECK(g.counts().stale == 1);  // one fall-back, two cycles on safe values
  CHECK(g.counts().safe_cycles == 2);
  // The controller restarted and counts from zero again.
  CHECK(g.offer(0, 0, {-3.0, 0.0}, 60 * kMs) == CommandVerdict::applied);
  CHECK(g.inputs_for_cycle(60 * kMs) == Values{-3.0, 0.0});
  CHECK(!g.on_safe_values());
  CHECK(g.counts().missing == 0);
}

TEST_CASE("a restarted sequence is refused while the old one is still fresh") {
  Gate g(kInputs, kTimes);
  REQUIRE(g.offer(100, 0, {3.0, 1.0}, 0) == CommandVerdict::applied);
  CHECK(g.offer(0, 0, {-3.0, 0.0}, 10 * kMs) == CommandVerdict::out_of_order);
}

TEST_CASE("an LCM command's age counts from the state it answers and saturates for absurd time stamps") {
  constexpr std::int64_t now_us = 1'700'000'000'000'000;
  CHECK(lcm_command_age_ns(now_us, now_us - 7, now_us - 20) == 20000);  // from the state it answers
  CHECK(lcm_command_age_ns(now_us, now_us - 7, 0) == 7000);             // no state: from its own time stamp
  // 1.8e16 us (570 years) old: in nanoseconds 2^64 + 384, which wrapped to a fresh 384 ns.
  const std::int64_t ancient_us = now_us - 18'446'744'073'709'552;
  CHECK(lcm_command_age_ns(now_us, ancient_us, 0) == std::numeric_limits<std::int64_t>::max());
  Gate g(kInputs, kTimes);
  CHECK(g.offer(0, lcm_command_age_ns(now_us, ancient_us, 0), {1.0, 1.0}, 0) == CommandVerdict::late);
  CHECK(lcm_command_age_ns(now_us, std::numeric_limits<std::int64_t>::max(), 0) == std::numeric_limits<std::int64_t>::min());
}

TEST_CASE("a jump across the whole int64 range of sequence numbers saturates the missing count") {
  constexpr std::int64_t lowest = std::numeric_limits<std::int64_t>::min(), highest = std::numeric_limits<std::int64_t>::max();
  Gate g(kInputs, kTimes);
  REQUIRE(g.offer(lowest, 0, {1.0, 1.0}, 0) == CommandVerdict::applied);
  CHECK(g.offer(highest, 0, {2.0, 1.0}, 1 * kMs) == CommandVerdict::applied);
  CHECK(g.counts().missing == highest);  // 2^64 - 2 never seen
  CHECK(g.offer(highest, 0, {2.0, 1.0}, 2 * kMs) == CommandVerdict::duplicate);
  CHECK(g.counts().missing == highest);
}
