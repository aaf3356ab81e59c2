// Operations on a generated model's State that every scheme shares: the
// State holds rigid bodies, particles and the multipliers in fixed arrays.
#pragma once

#include <cmath>
#include <type_traits>
#include <utility>

#include "mbrt/body_state.hpp"

namespace mbrt::schemes {

inline bool all_finite(const Vec3& x) noexcept { return std::isfinite(x.sum()); }
inline bool all_finite(const Vec4& x) noexcept { return std::isfinite(x.sum()); }

// Models with modal bodies (docs/flexible.md) hold their coordinates too.
template <class State, class = void>
struct has_modal_bodies : std::false_type {};
template <class State>
struct has_modal_bodies<State, std::void_t<decltype(std::declval<State&>().modal_q)>> : std::true_type {};

// Whether every position, velocity and multiplier is finite.
template <class State>
bool finite(const State& s) noexcept {
  bool ok = std::isfinite(s.lambda.sum());
  for (const RigidState& x : s.rigid) ok = ok && all_finite(x.r) && all_finite(x.p) && all_finite(x.v) && all_finite(x.w);
  for (const ParticleState& x : s.particle) ok = ok && all_finite(x.r) && all_finite(x.v);
  if constexpr (has_modal_bodies<State>::value) {
    for (std::size_t b = 0; b < s.modal_q.size(); ++b) ok = ok && std::isfinite(s.modal_q[b].sum() + s.modal_p[b].sum());
  }
  return ok;
}

// (from) => (s): positions and time of another state.
template <class State>
void set_positions(const State& from, State& s) noexcept {
  for (std::size_t b = 0; b < s.rigid.size(); ++b) {
    s.rigid[b].r = from.rigid[b].r;
    s.rigid[b].p = from.rigid[b].p;
  }
  for (std::size_t b = 0; b < s.particle.size(); ++b) s.particle[b].r = from.particle[b].r;
  if constexpr (has_modal_bodies<State>::value) s.modal_q = from.modal_q;
  s.t = from.t;
}

}  // namespace mbrt::schemes
