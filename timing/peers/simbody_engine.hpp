// Simbody 3.7 as a work-precision engine: its integrators at a fixed step on
// the problem's mechanism in minimal (mobilizer) coordinates, loops closed by
// ball constraints and projected back onto them after each step.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "measure.hpp"
#include "peer_engine.hpp"

namespace timing {

// Simbody's integrators by name: "rk_merson" (4th order), "semi_explicit_euler".
const std::vector<std::string>& simbody_methods();

Measurement run_simbody(const Problem& p, const std::string& method, double h);

// The problem's mechanism in Simbody at its initial state, ready to step.
std::unique_ptr<PeerEngine> simbody_engine(const Problem& p, const std::string& method, double h);

}  // namespace timing
