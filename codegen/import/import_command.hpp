// `mbrt import SOURCE -o MODEL.yaml`: a URDF (.urdf) or MJCF (.xml) file as
// an mbrt model file (docs/import.md).
#pragma once

#include <string>

namespace mbrt::codegen {

// Writes `source` as the model file `out`. Returns the exit code: 0, or 2 for
// a source that is neither .urdf nor .xml, an unwritable `out` or a missing
// parser library (printed on stderr); throws std::runtime_error naming the
// file for a bad source.
int run_import(const std::string& source, const std::string& out);

}  // namespace mbrt::codegen
