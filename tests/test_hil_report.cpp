// The HIL report holds the contract's fields with the values measured.
#include <doctest/doctest.h>

#include <string>

#include <mbrt/rt/hil_report.hpp>

using namespace mbrt::rt;

namespace {
bool contains(const std::string& text, const std::string& phrase) { return text.find(phrase) != std::string::npos; }
}  // namespace

TEST_CASE("the report has cycles, misses, percentiles per histogram and commands by reason") {
  HilRunStats s;
  s.model = "arm";
  s.transport = "lcm udpm://239.255.76.67:7667?ttl=0";
  s.cycles = 1000;
  s.deadline_misses = 2;
  s.overruns = 3;
  for (int i = 1; i <= 100; ++i) s.step_ns.record(i);
  s.wake_jitter_ns.record(7);
  s.commands.by_verdict[0] = 900;
  s.commands.by_verdict[static_cast<std::size_t>(CommandVerdict::non_finite)] = 4;
  s.commands.stale = 1;
  s.state_finite = false;
  s.realtime.warnings = "mlockall failed\n";
  const std::string json = to_json(s);
  CHECK(contains(json, "\"cycles\": 1000,"));
  CHECK(contains(json, "\"deadline_misses\": 2,"));
  CHECK(contains(json, "\"overruns\": 3,"));
  CHECK(contains(json, "\"step_ns\": {\"count\": 100, \"min\": 1, \"p50\": 50, \"p99\": 99, \"p999\": 100, \"max\": 100}"));
  CHECK(contains(json, "\"wake_jitter_ns\": {\"count\": 1, \"min\": 7, \"p50\": 7,"));
  CHECK(contains(json, "\"commands_applied\": 900,"));
  CHECK(contains(json, "\"non_finite\": 4"));
  CHECK(contains(json, "\"commands_stale\": 1,"));
  CHECK(contains(json, "\"state_finite\": false"));
  CHECK(contains(json, "\"warnings\": \"mlockall failed\\n\""));
}
