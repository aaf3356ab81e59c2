// The specializations the generator makes when a scene does not need the
// general code. Each flag permits one; `--no-specialize` clears them all and
// the step is the general one, which gives the same results to round-off
// (tests/test_specializations.cpp compares the two);
// `--no-specialize=NAME,...` clears the ones named.
#pragma once

#include <string>
#include <utility>

namespace mbrt::codegen {

struct Specializations {
  bool principal_axes = true;   // diagonal inertia: PrincipalInertia, no product terms
  bool isotropic = true;        // equal principal moments: no gyroscopic torque
  bool single_stage = true;     // no velocity-dependent loads: one implicit stage per step
  bool gravity_free = true;     // no gravity: no gravity term at all
  bool folded_weights = true;   // gravity: m g as one constant per body
  bool unloaded_bodies = true;  // bodies without applied loads: M^-1 F is zero, not computed
  bool no_drivers = true;       // no drivers: no explicit time terms phi_t
  bool sparse_factor = true;    // Cholesky factor over S's block pattern (else every block)
  bool planar = true;           // motion in a coordinate plane: two coordinates and an angle per body, in-plane rows only

  static Specializations none() { return {false, false, false, false, false, false, false, false, false}; }
};

// Each flag by the name --no-specialize=NAME and the reports use.
inline constexpr std::pair<const char*, bool Specializations::*> kSpecializationNames[] = {
    {"principal_axes", &Specializations::principal_axes}, {"isotropic", &Specializations::isotropic},
    {"single_stage", &Specializations::single_stage},     {"gravity_free", &Specializations::gravity_free},
    {"folded_weights", &Specializations::folded_weights}, {"unloaded_bodies", &Specializations::unloaded_bodies},
    {"no_drivers", &Specializations::no_drivers},         {"sparse_factor", &Specializations::sparse_factor},
    {"planar", &Specializations::planar},
};

// One specialization that applied to a model, and the code it left out.
struct Skipped {
  std::string specialization;  // the flag's name above
  std::string removed;
};

// One specialization turned on that the scene did not allow, and why.
struct NotApplied {
  std::string specialization;
  std::string reason;
};

}  // namespace mbrt::codegen
