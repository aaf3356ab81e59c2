// Emits a model's CAN interface: <name>.dbc (the frames and signals of
// include/mbrt/can_frames.hpp for this model) and <name>_can.hpp (its frame
// IDs and pack/unpack of Outputs and Inputs), in classic CAN frames or, with
// fd, CAN FD frames of up to 64 bytes. Only for models with both inputs and
// outputs.
#pragma once

#include <vector>

#include "emit_cpp.hpp"

namespace mbrt::codegen {

std::vector<GeneratedFile> emit_can(const Model& model, bool fd);

}  // namespace mbrt::codegen
