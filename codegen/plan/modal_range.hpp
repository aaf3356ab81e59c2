// How far a modal body can bend before the step's frame mass stops being
// positive definite (docs/flexible.md, "Limits"). The step
// takes the bending's shortening in the body's first moment but not in its
// inertia or its modes' mass, so the reduced mass Mf(q) - S(q) S(q)^T loses
// definiteness at a finite deflection; past it the step's Cholesky factor
// of that mass is wrong: a step can stop, or run on a wrong inverse, which
// moves the frame wrongly where its joints do not hold it. The generator
// finds that deflection and says so before a run that could reach it.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <mbrt/modal_body.hpp>

#include "modal_body.hpp"
#include "stable_step.hpp"

namespace mbrt::codegen {

struct ModalRange {
  bool bounded = false;           // the reduced mass loses definiteness within the body's range
  double strain_energy = 0.0;     // J: the least strain energy found at which it does
  double node_displacement = 0.0; // m: the largest node displacement at that deflection
  std::string node;               // that node
  double span = 0.0;              // m: the largest distance between the body's nodes
  Eigen::VectorXd deflection;     // the modal coordinates there
};

// The constants the generated step holds for the body (emit_modal.cpp
// writes the same fields).
template <int N>
inline mbrt::ModalBody<N> step_constants(const ModalPlan& p) {
  mbrt::ModalBody<N> b;
  b.St_T = p.St_T;
  b.Sr_T = p.Sr_T;
  b.stiffness = p.omega.cwiseAbs2();
  b.damping = p.damping;
  b.kg_cases = 0;
  for (size_t k = 0; k < p.kg.size(); ++k) {
    b.kg[k] = p.kg[k];
    if (!p.kg[k].isZero(0.0)) b.kg_cases |= 1u << k;
  }
  for (size_t k = 0; k < 9; ++k) b.E[k] = p.E[k], b.G[k] = p.G[k];
  b.J = p.J;
  b.m = p.m;
  return b;
}

// Searches deflections q = t d over directions d in the modes (each mode,
// then pseudo-random combinations, fixed seed) out to a node displacement of
// kModalRangeSpan of the body's span, for the least strain energy q^T K q / 2
// at which the smallest eigenvalue of the reduced mass (as
// include/mbrt/modal_body.hpp forms it) reaches zero.
inline constexpr double kModalRangeSpan = 0.5;
ModalRange modal_definite_range(const ModalPlan& p);

// A warning for stderr for each modal body whose range is bounded where the
// scene could bend it that far: its energy bound is above the range's
// strain energy, or drivers, inputs or applied forces can put in more.
std::string modal_range_warning(const Model& model, const StableStep& s, const std::vector<ModalPlan>& plans);

}  // namespace mbrt::codegen
