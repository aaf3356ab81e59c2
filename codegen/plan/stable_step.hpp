// The step a scene allows, estimated at generation time from the fastest
// rotation its energy allows and its stiffest spring (docs/stability.md,
// "Stable step estimate"). `gen --report` prints it; gen, sim, hil and stub
// warn before the run when the model's step is above it.
#pragma once

#include <string>
#include <vector>

#include "analysis.hpp"

namespace mbrt::codegen {

struct StableStep {
  double energy_bound = 0.0;       // J: initial kinetic + elastic energy + the largest fall gravity allows
  double fastest_rotation = 0.0;   // rad/s: the energy bound, about each body's inboard joint, largest over the bodies
  std::string fastest_body;
  std::vector<double> rotation_bound;  // rad/s: the energy bound of each body (Model::bodies; 0 where it cannot turn)
  std::vector<double> lowest_mode;     // rad/s: each modal body's lowest frequency, clamped (Model::modal)
  double rotation_per_step = 0.0;  // rad: what the scheme keeps bounded, measured (docs/stability.md)
  double stiffest_frequency = 0.0; // rad/s: sqrt(k (1/m1 + 1/m2)) of the stiffest spring; 0 without springs
  std::string stiffest_element;
  double stable_step = 0.0;        // s: min(rotation_per_step / fastest_rotation, 2 / stiffest_frequency); 0 = no bound
  bool exceeded = false;           // the model's solver.step is above stable_step
  std::string note;                // what the estimate leaves out, when the scene has it
};

// modal_plans: the analysis's plans of Model::modal where the caller has
// them (a structure's eigenproblem is the generator's largest), else solved here.
StableStep estimate_stable_step(const Model& model, const std::vector<ModalPlan>& modal_plans = {});

// A warning for stderr when the step is above the estimate, else "".
std::string stable_step_warning(const Model& model, const StableStep& s);

// A modal body from a file without geometric stiffness of spin: a warning for stderr
// where the scene's energy could spin it faster than kModalSpinLimit of its
// lowest frequency, else "".
inline constexpr double kModalSpinLimit = 0.3;
std::string modal_spin_warning(const Model& model, const StableStep& s);

// staggered-tree's kick-drift-kick in joint coordinates is not symplectic
// where the mass matrix M(q) varies (two joints or more): a warning for
// stderr when the step is above kTreeEnergyStep, else "".
inline constexpr double kTreeEnergyStep = 1e-4;  // s
std::string tree_energy_warning(const Model& model);

}  // namespace mbrt::codegen
