// Emits a model's C++: <name>.hpp (sizes, State, the step's interface) and
// <name>.cpp (the staggered-pcst step as a pipeline of named stages over the
// model's fixed sparsity).
#pragma once

#include <string>
#include <vector>

#include "analysis.hpp"

namespace mbrt::codegen {

struct GeneratedFile {
  std::string name;
  std::string text;
};

struct GeneratedCode {
  std::string header;       // <name>.hpp
  std::string source;       // <name>.cpp
  std::string header_name;  // "<name>.hpp"
  std::string source_name;  // "<name>.cpp"
  std::vector<GeneratedFile> interface_files;  // the C interface; LCM types, DBC and packing (models with inputs and outputs)
};

GeneratedCode emit_cpp(const Model& model, const Analysis& analysis);

}  // namespace mbrt::codegen
