// `mbrt import SOURCE -o MODEL.yaml`: a URDF (.urdf) or MJCF (.xml) file as
// an mbrt model file (docs/import.md).
#pragma once

#include <string>
#include <vector>

namespace mbrt::codegen {

// Runs the command on its arguments (those after "import"). Returns the exit
// code: 0, or 2 for a bad command line or a missing parser library (printed
// on stderr); throws std::runtime_error naming the file for a bad source.
int run_import(const std::vector<std::string>& args);

}  // namespace mbrt::codegen
