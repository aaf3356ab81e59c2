// The step of staggered4 (docs/schemes.md, "staggered4"): three
// staggered-pcst steps (include/mbrt/schemes/staggered.hpp) of lengths g1 h,
// g0 h and g1 h, g1 = 1 / (2 - 2^(1/3)), g0 = 1 - 2 g1 = -1.70 h: Yoshida's
// triple jump (Yoshida 1990, "Construction of higher order symplectic
// integrators", Phys. Lett. A 150; Hairer, Lubich & Wanner 2006, "Geometric
// Numerical Integration", section II.4). staggered-pcst's step is symmetric
// to the convergence of its position stage (RATTLE's kick, drift and
// velocity projection, with a symmetric splitting of the free rotation), so
// the composition is of order four and symmetric again: its energy error
// oscillates rather than drifts.
//
// Outer and Middle are a generated model's struct ModelAt<0> and ModelAt<1>:
// the same kernels, with kStep the outer and the middle substep, and
// kFullStep h. The Workspace holds start, the state at t.
#pragma once

#include <type_traits>

#include "mbrt/schemes/staggered.hpp"

namespace mbrt::schemes {

// (s at t) => (s at t + h). Allocates nothing, throws nothing, fixed work; on
// a non-finite result or a lost factorization in any substep s keeps its
// old value.
template <class Outer, class Middle>
StepStatus staggered4_step(typename Outer::State& s, typename Outer::Workspace& w) noexcept {
  static_assert(std::is_same_v<typename Outer::State, typename Middle::State>);
  w.start = s;
  StepStatus status = staggered_step<Outer>(s, w);
  if (status == StepStatus::ok) status = staggered_step<Middle>(s, w);
  if (status == StepStatus::ok) status = staggered_step<Outer>(s, w);
  if (status != StepStatus::ok) {
    s = w.start;
    return status;
  }
  s.t = w.start.t + Outer::kFullStep;  // g1 + g0 + g1 = 1 up to round-off
  return status;
}

}  // namespace mbrt::schemes
