// The work-precision mechanisms in MuJoCo's MJCF: minimal (joint)
// coordinates, closed loops by `connect` equality constraints.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "problems.hpp"

namespace timing {

// A model as MJCF text: the main file and the files it includes, by name.
struct Mjcf {
  std::string main;
  std::vector<std::pair<std::string, std::string>> includes;
};

Mjcf mujoco_mjcf(const Problem& p);

}  // namespace timing
