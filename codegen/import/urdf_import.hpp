// Reads a URDF file (http://wiki.ros.org/urdf/XML) with urdfdom into an
// ImportedModel. docs/import.md says what maps to what.
#pragma once

#include <string>

#include "imported_model.hpp"

namespace mbrt::codegen {

// Throws std::runtime_error naming the file (and the joint or link) when
// the file cannot be read or has what mbrt cannot model.
ImportedModel import_urdf(const std::string& path);

}  // namespace mbrt::codegen
