// `mbrt gen --report`: what the generator left out of a model's step and what
// the step costs. The counts come from the compiled program `mbrt sim` runs
// (flop_count.hpp); the predicted time multiplies the floating-point
// operations by the nanoseconds per operation measured on a reference model
// (timing/flop_calibration writes timing/results/flop_calibration.csv).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "flop_count.hpp"
#include "sim_runner.hpp"

namespace mbrt::codegen {

struct StepReport {
  std::string model;
  std::string scheme;
  std::vector<std::string> turned_off;  // specializations --no-specialize turned off
  std::vector<Skipped> skipped;
  std::vector<NotApplied> not_applied;
  size_t bodies = 0;                // rigid bodies and particles: flops_per_body divides by it
  size_t source_bytes = 0;          // generated <name>.hpp and <name>.cpp
  size_t executable_bytes = 0;      // the compiled sim program (model, driver and runtime)
  StepCount per_step;
  std::optional<double> ns_per_flop;  // calibration, when timing/results has one
  std::string calibration;            // where it came from, or why there is none
  StableStep stable;
  Partition partition;  // the parallel step's parts (docs/parallel.md)
};

// Compiles the model's sim program (cached) and counts one step under valgrind.
StepReport report_step(const Generated& generated, const SimOptions& options);

// One JSON object; predicted_ns_per_step is null without a calibration.
std::string report_json(const StepReport& report);

}  // namespace mbrt::codegen
