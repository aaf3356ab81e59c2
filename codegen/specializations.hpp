// The specializations the generator makes when a scene does not need the
// general code. Each flag permits one; `--no-specialize` clears them all and
// the step is the general one, which gives the same results to round-off
// (tests/test_specializations.cpp compares the two).
#pragma once

#include <string>

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

  static Specializations none() { return {false, false, false, false, false, false, false, false}; }
};

// One specialization that applied to a model, and the code it left out.
struct Skipped {
  std::string specialization;  // the flag's name above
  std::string removed;
};

}  // namespace mbrt::codegen
