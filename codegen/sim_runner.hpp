// `mbrt sim`: generate, compile (cached by content hash) and run a model.
#pragma once

#include <string>
#include <vector>

#include "generate.hpp"

namespace mbrt::codegen {

struct SimOptions {
  GenerateOptions generate;
  std::vector<std::string> driver_args;  // passed through: --t-end, --out, --every, --velocities
  std::string cache_dir;                 // empty: $MBRT_CACHE_DIR, else $XDG_CACHE_HOME/mbrt, else ~/.cache/mbrt
  bool verbose = false;
};

// Returns the simulation's exit code. Throws ModelError or std::runtime_error.
int run_simulation(const std::string& model_path, const SimOptions& options);

// The compiled executable for a model (built if not cached); for tests.
std::string build_simulator(const Generated& generated, const SimOptions& options);

}  // namespace mbrt::codegen
