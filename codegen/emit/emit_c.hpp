// Emits a model's C interface: <name>_c.h (a C11 header: sizes, index
// constants, name tables, the state as a plain struct, init, step, energy,
// reactions, outputs) and <name>_c.cpp (its implementation over <name>.hpp).
// Every model has one; docs/c_interface.md.
#pragma once

#include <vector>

#include "emit_cpp.hpp"

namespace mbrt::codegen {

std::vector<GeneratedFile> emit_c(const Model& model, const Analysis& analysis);

}  // namespace mbrt::codegen
