// Emits a model's LCM interface: <name>.lcm (the state and command message
// types, fixed-size fields only, for lcm-gen) and <name>_lcm.hpp (copying
// Outputs and Inputs to and from those messages). Only for models with both
// inputs and outputs.
#pragma once

#include <vector>

#include "emit_cpp.hpp"

namespace mbrt::codegen {

std::vector<GeneratedFile> emit_lcm(const Model& model);

// LCM channel names the HIL loop uses unless told otherwise.
std::string state_channel(const Model& model);    // <name>_STATE
std::string command_channel(const Model& model);  // <name>_COMMAND

}  // namespace mbrt::codegen
