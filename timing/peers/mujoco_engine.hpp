// MuJoCo 2.2.2 as a work-precision engine: its fixed-step integrators on the
// problem's MJCF (mujoco_models.hpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "measure.hpp"
#include "peer_engine.hpp"

namespace timing {

// MuJoCo's integrators by name: "euler" (semi-implicit), "rk4".
const std::vector<std::string>& mujoco_methods();

Measurement run_mujoco(const Problem& p, const std::string& method, double h);

// The problem's mechanism in MuJoCo at rest, ready to step.
std::unique_ptr<PeerEngine> mujoco_engine(const Problem& p, const std::string& method, double h);

}  // namespace timing
