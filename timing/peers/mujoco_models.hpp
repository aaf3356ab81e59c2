// The work-precision mechanisms in MuJoCo's MJCF: minimal (joint)
// coordinates, closed loops by `connect` equality constraints.
#pragma once

#include <string>

#include "problems.hpp"

namespace timing {

std::string mujoco_mjcf(const Problem& p);

}  // namespace timing
