// `mbrt sim`, `mbrt hil` and `mbrt stub`: generate, compile (cached by
// content hash) and run a program built around a model: the simulator, the
// real-time HIL loop, or the PD controller stub.
#pragma once

#include <string>
#include <vector>

#include "generate.hpp"

namespace mbrt::codegen {

enum class Program { sim, hil, pd_controller };

struct SimOptions {
  GenerateOptions generate;
  std::vector<std::string> driver_args;  // passed through to the program
  std::string cache_dir;                 // empty: $MBRT_CACHE_DIR, else $XDG_CACHE_HOME/mbrt, else ~/.cache/mbrt
  bool verbose = false;
};

// Compiles (or takes from the cache) and runs the program around a generated
// model. Returns the program's exit code. Throws std::runtime_error.
int run_program(Program program, const Generated& generated, const SimOptions& options);

// The compiled executable for a model (built if not cached).
std::string build_program(Program program, const Generated& generated, const SimOptions& options);

// The directory holding the Python package mbrt (mbrt sweep's tool):
// <prefix>/share/mbrt/python when installed, else the source tree's python/.
std::string python_package_dir();

}  // namespace mbrt::codegen
