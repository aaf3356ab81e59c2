// Whether a scene qualifies for planar coordinates (docs/specializations.md,
// "planar"), and its constraint blocks in planar form.
#pragma once

#include "analysis.hpp"

namespace mbrt::codegen {

// The plan for a model whose analysis is otherwise complete; refusal says
// why a scene does not qualify.
PlanarPlan plan_planar(const Model& model, const Analysis& a);

}  // namespace mbrt::codegen
