// Consistency of the model file's initial state with its constraints, and
// the mass-orthogonal projection that `--project-initial` applies.
#pragma once

#include "analysis.hpp"

namespace mbrt::codegen {

struct InitialResidual {
  double position = 0.0;    // max |phi|
  int position_block = -1;  // Analysis::constraints index of the worst row, -1 if none
  double velocity = 0.0;    // max |phi_dot|
  int velocity_block = -1;
};

// Residuals larger than this are reported as inconsistent initial conditions.
constexpr double kInitialTolerance = 1e-8;

InitialResidual initial_residual(const Model& model, const Analysis& analysis);

// Moves positions, then velocities, to the constraint manifold along
// M^-1 B^T (the smallest change in the kinetic-energy metric): Newton steps
// on phi, then u -= M^-1 B^T S^+ B u. Redundant rows are handled by the
// pseudo-inverse. Throws ModelError if the positions do not converge.
void project_initial_state(Model& model, const Analysis& analysis);

}  // namespace mbrt::codegen
