#include "mbrt/rt/hil_report.hpp"

#include <sstream>

namespace mbrt::rt {

namespace {

std::string percentiles(const LatencyHistogram& h) {
  std::ostringstream o;
  o << "{\"count\": " << h.count() << ", \"min\": " << h.min() << ", \"p50\": " << h.percentile(0.5)
    << ", \"p99\": " << h.percentile(0.99) << ", \"p999\": " << h.percentile(0.999) << ", \"max\": " << h.max() << "}";
  return o.str();
}

// JSON string escaping for the few free-text fields (paths, URLs, warnings).
std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    if (c == '\n') {
      q += "\\n";
      continue;
    }
    q += c;
  }
  return q + "\"";
}

}  // namespace

std::string to_json(const HilRunStats& s) {
  std::ostringstream o;
  o << "{\n  \"model\": " << quoted(s.model) << ",\n  \"transport\": " << quoted(s.transport)
    << ",\n  \"rate_hz\": " << s.rate_hz << ",\n  \"steps_per_cycle\": " << s.steps_per_cycle
    << ",\n  \"workspace_bytes\": " << s.workspace_bytes
    << ",\n  \"cycles\": " << s.cycles << ",\n  \"deadline_misses\": " << s.deadline_misses
    << ",\n  \"overruns\": " << s.overruns << ",\n  \"step_ns\": " << percentiles(s.step_ns)
    << ",\n  \"cycle_ns\": " << percentiles(s.cycle_ns) << ",\n  \"wake_jitter_ns\": " << percentiles(s.wake_jitter_ns)
    << ",\n  \"command_rtt_ns\": " << percentiles(s.command_rtt_ns)
    << ",\n  \"commands_applied\": " << s.commands.applied() << ",\n  \"commands_rejected\": {";
  for (int v = 1; v < kCommandVerdicts; ++v) {
    o << (v > 1 ? ", " : "") << "\"" << to_string(static_cast<CommandVerdict>(v)) << "\": "
      << s.commands.by_verdict[static_cast<std::size_t>(v)];
  }
  o << "},\n  \"commands_missing\": " << s.commands.missing << ",\n  \"commands_stale\": " << s.commands.stale
    << ",\n  \"safe_cycles\": " << s.commands.safe_cycles << ",\n  \"step_failures\": " << s.step_failures
    << ",\n  \"state_finite\": " << (s.state_finite ? "true" : "false") << ",\n  \"realtime\": {\"memory_locked\": "
    << (s.realtime.memory_locked ? "true" : "false") << ", \"fifo\": " << (s.realtime.fifo ? "true" : "false")
    << ", \"pinned\": " << (s.realtime.pinned ? "true" : "false") << ", \"warnings\": " << quoted(s.realtime.warnings)
    << "}\n}\n";
  return o.str();
}

}  // namespace mbrt::rt
