// Prints an imported model as an mbrt model file (README.md, "Model file").
#pragma once

#include <string>

#include "imported_model.hpp"

namespace mbrt::codegen {

// The model file's text: a header comment naming the source, its notes and
// warnings, then the model. Names become [a-z][a-z0-9_]* (lowercase, other
// characters as _, a leading x_ where the first is not a letter), made unique
// with _2, _3, ...; a renamed element carries its source name in a comment.
std::string model_yaml(const ImportedModel& model);

}  // namespace mbrt::codegen
