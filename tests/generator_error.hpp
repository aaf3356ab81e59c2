// The generator's analysis error for a model text, or "" when it passes.
#pragma once

#include <exception>
#include <string>

#include "analysis.hpp"
#include "model.hpp"

inline std::string generator_error(const std::string& yaml, const std::string& file = "modal.yaml") {
  try {
    mbrt::codegen::analyse(mbrt::codegen::parse_model(yaml, file));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}
