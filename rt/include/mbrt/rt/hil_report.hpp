// What a HIL run measured, and its JSON form (written once, after the loop).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "mbrt/rt/command_gate.hpp"
#include "mbrt/rt/latency_histogram.hpp"
#include "mbrt/rt/realtime_setup.hpp"

namespace mbrt::rt {

struct HilRunStats {
  std::string model;
  std::string transport;  // "lcm udpm://...", ...
  double rate_hz = 0.0;
  int steps_per_cycle = 1;
  std::size_t workspace_bytes = 0;  // the step's caller-owned workspace
  std::int64_t cycles = 0;
  std::int64_t deadline_misses = 0;
  std::int64_t overruns = 0;
  LatencyHistogram step_ns;         // all steps of one cycle
  LatencyHistogram cycle_ns;        // release to end of the cycle's work
  LatencyHistogram wake_jitter_ns;  // wake-up minus release
  LatencyHistogram command_rtt_ns;  // state published to the command answering it applied
  CommandCounts commands;
  std::int64_t step_failures = 0;   // steps refused (non-finite or not positive): state kept
  bool state_finite = true;
  RealtimeStatus realtime;
};

std::string to_json(const HilRunStats& stats);

}  // namespace mbrt::rt
