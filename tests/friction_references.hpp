// Closed forms the joint-friction tests check against (docs/friction.md),
// shared by the tree schemes' test (test_joint_friction.cpp) and the
// absolute-coordinate schemes' (test_joint_friction_absolute.cpp): the
// turning angles of a pendulum with a constant friction moment, from its
// energy balance, the record of where a simulated one turned, and the
// stick-slip phases of a block on a moving belt.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include <doctest/doctest.h>

namespace friction_reference {

inline constexpr double kG = 9.81;

// |theta_next| from |theta|: between two turning points (at rest) the
// pendulum's loss of potential energy is the friction moment's work,
// m g d (cos|theta_next| - cos|theta|) = T (|theta| + |theta_next|), solved
// by bisection on (0, |theta|).
inline double next_turning_angle(double theta, double mgd, double torque) {
  double lo = 0.0, hi = theta;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    const double residual = mgd * (std::cos(mid) - std::cos(theta)) - torque * (theta + mid);
    (residual > 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The turning angles |theta_n| from rest at theta0 (theta0 first) to the
// first at which the friction holds the pendulum, m g d |sin theta| <= T.
inline std::vector<double> turning_angles(double theta0, double mgd, double torque) {
  std::vector<double> angles{theta0};
  while (mgd * std::sin(angles.back()) > torque) angles.push_back(next_turning_angle(angles.back(), mgd, torque));
  return angles;
}

// |theta| where a simulated joint turned: its rate changed sign, or it
// stuck, after moving. Fed once per step; within a step of the true turn,
// off by at most |qdd| h^2 / 2.
struct TurningPoints {
  std::vector<double> angles;
  double last_rate = 0.0;
  void add(double theta, double rate, bool stuck) {
    if (last_rate != 0.0 && (rate * last_rate < 0.0 || stuck)) angles.push_back(std::abs(theta));
    last_rate = stuck ? 0.0 : rate;
  }
};

// tests/models/friction_belt.yaml: m = 1 kg, k = 100 N/m, v_b = 0.1 m/s,
// F_s = 2.5 N, F_k = 1 N. Stuck, the block rides the belt until k x = F_s;
// slipping, x - F_k/k = u0 cos(w t) + (v_b/w) sin(w t), u0 = (F_s - F_k)/k,
// until its velocity is the belt's again, at w t = 2 pi - 2 atan(u0 w / v_b),
// where u = -u0 (the oscillation's energy is the same at both ends).
// block_x(s), belt_v(s), stuck(s): the block's position, the belt's velocity
// and the friction joint's stick state; step(s) advances by h.
template <class State, class Step, class BlockX, class BeltV, class Stuck>
void check_belt_phases(State s, double h, const Step& step, const BlockX& block_x, const BeltV& belt_v,
                       const Stuck& stuck_of) {
  const double mass = 1.0, k = 100.0, vb = 0.1, fs = 2.5, fk = 1.0, w = std::sqrt(k / mass);
  const double u0 = (fs - fk) / k;
  const double slip = (2.0 * M_PI - 2.0 * std::atan(u0 * w / vb)) / w;  // 0.4318 s
  const double restick_x = fk / k - u0;                                   // -0.005 m
  const double stick = (fs / k - restick_x) / vb;                         // 0.3 s
  const double first_stick = (fs / k) / vb;                               // 0.25 s from x = 0

  std::vector<double> changes, x_at_change;  // times the stick state changed, and x there
  double stuck = 1.0;                          // it starts moving with the belt
  for (int i = 0; i < 3000; ++i) {
    REQUIRE(step(s));
    if (stuck_of(s) != stuck) {
      stuck = stuck_of(s);
      changes.push_back(s.t);
      x_at_change.push_back(block_x(s));
    }
  }
  // 3 s: breaks loose at 0.25 s, then slip 0.43 s, stick 0.3 s, ...: 8 changes.
  REQUIRE(changes.size() >= 8);
  CHECK(std::abs(changes[0] - first_stick) < 2.0 * h);
  for (std::size_t c = 1; c < changes.size(); ++c) {
    const bool slipped = c % 2 == 1;  // changes[c - 1] broke loose, changes[c] stuck again
    INFO("phase ", c, slipped ? " (slip)" : " (stick)");
    CHECK(std::abs(changes[c] - changes[c - 1] - (slipped ? slip : stick)) < 2.0 * h);
    // Breaking loose where the spring reaches F_s, sticking again at (2 F_k - F_s)/k.
    CHECK(std::abs(x_at_change[c] - (slipped ? restick_x : fs / k)) < 2.0 * vb * h);
  }
  // The belt keeps its speed.
  CHECK(std::abs(belt_v(s) - vb) < 1e-6);
}

}  // namespace friction_reference
