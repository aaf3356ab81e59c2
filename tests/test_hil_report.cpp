// The HIL report holds the contract's fields with the values measured, as
// valid JSON (parsed strictly).
#include <doctest/doctest.h>

#include <string>

#include <nlohmann/json.hpp>

#include <mbrt/rt/hil_report.hpp>

using namespace mbrt::rt;

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
  const nlohmann::json j = nlohmann::json::parse(to_json(s));
  CHECK(j.at("model") == "arm");
  CHECK(j.at("transport") == "lcm udpm://239.255.76.67:7667?ttl=0");
  CHECK(j.at("cycles") == 1000);
  CHECK(j.at("deadline_misses") == 2);
  CHECK(j.at("overruns") == 3);
  CHECK(j.at("step_ns") == nlohmann::json{{"count", 100}, {"min", 1}, {"p50", 50}, {"p99", 99}, {"p999", 100}, {"max", 100}});
  CHECK(j.at("wake_jitter_ns").at("count") == 1);
  CHECK(j.at("wake_jitter_ns").at("min") == 7);
  CHECK(j.at("wake_jitter_ns").at("p50") == 7);
  CHECK(j.at("commands_applied") == 900);
  CHECK(j.at("commands_rejected").at("non_finite") == 4);
  CHECK(j.at("commands_stale") == 1);
  CHECK(j.at("state_finite") == false);
  CHECK(j.at("realtime").at("warnings") == "mlockall failed\n");
}

TEST_CASE("free text with quotes, tabs and control characters stays valid JSON") {
  HilRunStats s;
  s.model = "arm\t\"2\"\\";
  s.realtime.warnings = std::string("bell\a and nul-free \x01 control");
  const nlohmann::json j = nlohmann::json::parse(to_json(s));
  CHECK(j.at("model") == "arm\t\"2\"\\");
  CHECK(j.at("realtime").at("warnings") == s.realtime.warnings);
}
