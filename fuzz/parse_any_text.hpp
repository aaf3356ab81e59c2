// The property the model-file fuzzer checks: any text given to the parser,
// the analysis and the initial-state check and projection (what `mbrt gen`
// does before emitting code) either yields a model or a ModelError naming
// where it went wrong. Anything else (another exception, a crash, a hang, a
// sanitizer report) is a bug.
#pragma once

#include <string>

#include "analysis.hpp"
#include "initial_conditions.hpp"
#include "model.hpp"

namespace mbrt::fuzz {

inline void parse_any_text(const std::string& text) {
  try {
    codegen::Model model = codegen::parse_model(text, "fuzz.yaml");
    const codegen::Analysis analysis = codegen::analyse(model);
    codegen::initial_residual(model, analysis);
    codegen::project_initial_state(model, analysis);
  } catch (const codegen::ModelError&) {
    // the expected rejection of a bad file
  }
}

}  // namespace mbrt::fuzz
