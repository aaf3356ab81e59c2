#include "mbrt/rt/hil_report.hpp"

#include <nlohmann/json.hpp>

namespace mbrt::rt {

namespace {

nlohmann::ordered_json percentiles(const LatencyHistogram& h) {
  return {{"count", h.count()}, {"min", h.min()},   {"p50", h.percentile(0.5)},
          {"p99", h.percentile(0.99)}, {"p999", h.percentile(0.999)}, {"max", h.max()}};
}

}  // namespace

std::string to_json(const HilRunStats& s) {
  nlohmann::ordered_json rejected = nlohmann::ordered_json::object();
  for (int v = 1; v < kCommandVerdicts; ++v)
    rejected[to_string(static_cast<CommandVerdict>(v))] = s.commands.by_verdict[static_cast<std::size_t>(v)];
  const nlohmann::ordered_json j = {
      {"model", s.model},
      {"transport", s.transport},
      {"rate_hz", s.rate_hz},
      {"steps_per_cycle", s.steps_per_cycle},
      {"workspace_bytes", s.workspace_bytes},
      {"cycles", s.cycles},
      {"deadline_misses", s.deadline_misses},
      {"overruns", s.overruns},
      {"step_ns", percentiles(s.step_ns)},
      {"cycle_ns", percentiles(s.cycle_ns)},
      {"wake_jitter_ns", percentiles(s.wake_jitter_ns)},
      {"command_rtt_ns", percentiles(s.command_rtt_ns)},
      {"commands_applied", s.commands.applied()},
      {"commands_rejected", rejected},
      {"commands_missing", s.commands.missing},
      {"commands_stale", s.commands.stale},
      {"safe_cycles", s.commands.safe_cycles},
      {"step_failures", s.step_failures},
      {"state_finite", s.state_finite},
      {"realtime",
       {{"memory_locked", s.realtime.memory_locked},
        {"fifo", s.realtime.fifo},
        {"pinned", s.realtime.pinned},
        {"warnings", s.realtime.warnings}}}};
  return j.dump(2) + "\n";
}

}  // namespace mbrt::rt
