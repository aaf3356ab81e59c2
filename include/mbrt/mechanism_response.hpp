// The response of a mechanism to impulses on its bodies, with its joints
// taking their share: what contacts on jointed bodies (contacts.hpp) and
// joint friction in the absolute-coordinate schemes
// (schemes/joint_friction_absolute.hpp) move the bodies by.
#pragma once

#include <type_traits>

#include "mbrt/types.hpp"

namespace mbrt {

// Whether a generated model has per-mechanism kernels (jacobian_times_in,
// solve_in, subtract_constraint_forces_in; emitted for contact mechanisms).
template <class M, class = void>
struct has_mechanism_kernels : std::false_type {};
template <class M>
struct has_mechanism_kernels<M, std::void_t<decltype(&M::solve_in)>> : std::true_type {};

// A generated model's view of its joints for impulses on jointed bodies
// (contacts, joint friction): an impulse's response with the joints is the
// free response x = M^-1 J^T P less M^-1 B^T z, z = S^-1 B x (S = B M^-1 B^T factorized by the scheme at
// the step's end), so that the joints move with it (B dv = 0). The scheme's
// factor is of S + eps I (its penalty or regularization, about 1e-6): two
// refinements z += (S + eps I)^-1 (B x - S z) make the joints rigid to
// round-off, each gaining a factor eps / (S's smallest eigenvalue). Left
// compliant by eps, joints would let a statically indeterminate mechanism
// (a box of two welded halves on four corners) carry internal friction
// forces, and it would slide where it sticks.
template <class M>
struct Joints {
  static constexpr int kRefinements = 2;
  const typename M::ConstraintSystem* c;  // null where no impulse acts on a body in a joint
  // (x) => (x with the joints' share; z, the joints' impulses), over one
  // group's mechanism (M::kContactGroups index) or, group < 0, all of them.
  typename M::Rows constrain(typename M::BodyVectors& x, int group = -1) const noexcept {
    const typename M::Rows bx = jacobian_times(group, x);
    typename M::Rows z = bx;
    solve(group, z);
    for (int i = 0; i < kRefinements; ++i) {
      typename M::BodyVectors d;
      for (Vec6& e : d) e.setZero();
      subtract_forces(group, z, d);  // d = -M^-1 B^T z
      typename M::Rows r = bx + jacobian_times(group, d);  // B x - S z
      solve(group, r);
      z += r;
    }
    subtract_forces(group, z, x);
    return z;
  }

 private:
  // The whole model's kernels or one mechanism's (a constant per call site:
  // the same work every step).
  typename M::Rows jacobian_times(int group, const typename M::BodyVectors& u) const noexcept {
    if constexpr (has_mechanism_kernels<M>::value) {
      if (group >= 0) return M::jacobian_times_in(group, *c, u);
    }
    return M::jacobian_times(*c, u);
  }
  void solve(int group, typename M::Rows& x) const noexcept {
    if constexpr (has_mechanism_kernels<M>::value) {
      if (group >= 0) return M::solve_in(group, *c, x);
    }
    M::solve(*c, x);
  }
  void subtract_forces(int group, const typename M::Rows& z, typename M::BodyVectors& u) const noexcept {
    if constexpr (has_mechanism_kernels<M>::value) {
      if (group >= 0) return M::subtract_constraint_forces_in(group, *c, z, 1.0, u);
    }
    M::subtract_constraint_forces(*c, z, 1.0, u);
  }
};

}  // namespace mbrt
