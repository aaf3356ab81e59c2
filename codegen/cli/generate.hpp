// The generator pipeline: model file -> validated model -> analysis ->
// consistency check (or projection) -> emitted C++ on disk.
#pragma once

#include <optional>
#include <string>

#include "emit_cpp.hpp"
#include "specializations.hpp"
#include "stable_step.hpp"

namespace mbrt::codegen {

// Command-line overrides of the model file's solver settings.
struct GenerateOptions {
  std::optional<std::string> scheme;
  std::optional<double> step;
  std::optional<int> euler_updates;
  std::optional<int> parallel_parts;
  std::optional<int> parallel_min_rows;
  std::optional<std::string> parallel_interface;  // direct | pcg
  std::optional<int> pcg_iterations;
  std::optional<std::string> pcg_preconditioner;  // block | diagonal
  std::optional<std::string> body_states;         // each_step | on_demand
  std::optional<std::string> name;  // replaces the model's name (and C++ namespace)
  std::optional<std::string> ali3p_projection;  // bayo | cuadrado
  std::optional<std::string> ali3p_integrator;  // trapezoidal | generalized_alpha
  bool project_initial = false;
  bool can_fd = false;  // the CAN layout in CAN FD frames rather than classic ones
  Specializations specialize;  // --no-specialize[=NAME,...] clears flags
};

struct Generated {
  Model model;
  Analysis analysis;
  GeneratedCode code;
  StableStep stable;  // printed as a warning on stderr when the step is above it
};

// Throws std::invalid_argument ("--OPTION: what was expected, got what")
// on an option value no model could take; generate() checks them first.
void check_generate_options(const GenerateOptions& options);

// Throws ModelError on a bad model, including inconsistent initial
// conditions without --project-initial.
Generated generate(const std::string& model_path, const GenerateOptions& options);

// Writes <name>.hpp and <name>.cpp into dir (created if missing); files whose
// content is unchanged are not touched, so builds stay incremental.
void write_generated(const GeneratedCode& code, const std::string& dir);

}  // namespace mbrt::codegen
