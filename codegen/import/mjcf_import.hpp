// Reads an MJCF file with MuJoCo's own compiler (mj_loadXML) into an
// ImportedModel, from the compiled mjModel and its kinematics at qpos0
// (https://mujoco.readthedocs.io/en/2.2.2/XMLreference.html).
// docs/import.md says what maps to what.
#pragma once

#include <string>

#include "imported_model.hpp"

namespace mbrt::codegen {

// Throws std::runtime_error naming the file (with MuJoCo's message, which
// gives the element and line) or the body, joint or equality mbrt cannot model.
ImportedModel import_mjcf(const std::string& path);

}  // namespace mbrt::codegen
