// Operations on a generated model's State that every scheme shares: the
// State holds rigid bodies, particles and the multipliers in fixed arrays.
#pragma once

#include <cmath>

#include "mbrt/body_state.hpp"

namespace mbrt::schemes {

inline bool all_finite(const Vec3& x) noexcept { return std::isfinite(x.sum()); }
inline bool all_finite(const Vec4& x) noexcept { return std::isfinite(x.sum()); }

// Whether every position, velocity and multiplier is finite.
template <class State>
bool finite(const State& s) noexcept {
  bool ok = std::isfinite(s.lambda.sum());
  for (const RigidState& x : s.rigid) ok = ok && all_finite(x.r) && all_finite(x.p) && all_finite(x.v) && all_finite(x.w);
  for (const ParticleState& x : s.particle) ok = ok && all_finite(x.r) && all_finite(x.v);
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
  s.t = from.t;
}

}  // namespace mbrt::schemes
