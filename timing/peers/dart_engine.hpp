// DART 6.12 as a work-precision engine: its articulated-body forward dynamics
// (Featherstone's recursion) in joint coordinates on the problem's tree, at a
// fixed step. Trees only (the pendulum, the arm and the chains): the loop
// problems would need DART's constraint solver and are not built (dart_builds).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "measure.hpp"
#include "peer_engine.hpp"

namespace timing {

// DART's integrators by name: "semi_implicit_euler", World::step, the one a
// World steps with. DART 6.12 also ships an RK4Integrator, not offered on a
// World or Skeleton: it steps an IntegrableSystem the user writes, is declared
// abstract (integratePos, integrateVel left pure), and its fourth stage
// starts from q1 + h/2 dq2 + h dq3 instead of q1 + h dq3 (its published
// source; through a skeleton its error on the 10-link chain halves with h,
// first order): not compared.
const std::vector<std::string>& dart_methods();

// Whether DART builds the problem's mechanism (trees of revolute joints).
bool dart_builds(const Problem& p);

Measurement run_dart(const Problem& p, const std::string& method, double h);

// The problem's mechanism in DART at rest, ready to step.
std::unique_ptr<PeerEngine> dart_engine(const Problem& p, const std::string& method, double h);

}  // namespace timing
