// The tree steps (include/mbrt/schemes/tree.hpp) on their own, without
// the generator: a pendulum in its joint angle written by hand as the Model
// the template takes (a point mass m on a massless rod of length L, pinned
// at the origin about y, gravity -g z): q'' = -(g / L) sin q.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Core>

#include <mbrt/schemes/tree.hpp>
#include <mbrt/sin_cos.hpp>

namespace {

constexpr double kLength = 0.8, kG = 9.81;

using Dofs = std::array<double, 1>;
using HalfAngles = std::array<mbrt::SinCos, 1>;

struct State {
  double t = 0.0;
  Dofs q{}, qd{}, qdd{};
  std::array<mbrt::RigidState, 1> rigid;
};

struct Kinematics {};
struct Loads {};

struct Workspace {
  double t0;
  Dofs q0, qd0, qdd0;
  HalfAngles half_angles;
  Dofs rates;
  std::array<Dofs, 12> stage_rates, stage_accelerations;  // up to rk8-tree's twelve stages
  Kinematics k;
  Loads l;
};

struct Pendulum {
  using State = ::State;
  using Workspace = ::Workspace;
  using Dofs = ::Dofs;
  using HalfAngles = ::HalfAngles;
  static constexpr double kStep = 1e-3;
  static constexpr int kStages = 1;
  static constexpr bool kExternalLoads = false;
  static constexpr bool kBodyStatesEachStep = true;

  static void half_angles(const Dofs& q, HalfAngles& ha) { ha[0] = mbrt::sin_cos(0.5 * q[0]); }
  static void body_states(const Dofs&, const HalfAngles& ha, const Dofs& qd, State& s) {
    const double c = ha[0].c * ha[0].c - ha[0].s * ha[0].s, sn = 2.0 * ha[0].s * ha[0].c;
    s.rigid[0].r = {kLength * sn, 0.0, -kLength * c};
    s.rigid[0].p = {ha[0].c, 0.0, ha[0].s, 0.0};
    s.rigid[0].v = {kLength * c * qd[0], 0.0, kLength * sn * qd[0]};
    s.rigid[0].w = {0.0, qd[0], 0.0};
  }
  static void kinematics(const State&, Kinematics&) {}
  static void tree_loads(const Kinematics&, const State&, Loads&) {}
  static void joint_accelerations(const State&, const HalfAngles& ha, const Dofs&, const Kinematics&, const Loads&,
                                  Dofs& qdd) {
    qdd[0] = -(kG / kLength) * 2.0 * ha[0].s * ha[0].c;
  }
};

// midpoint-tree's step takes the same model with its own number of passes.
struct MidpointPendulum : Pendulum {
  static constexpr int kStages = 3;
};

// The Runge-Kutta steps take as many recursions as their tableaus' stages.
struct Rk4Pendulum : Pendulum {
  static constexpr int kStages = 4;
};
struct Rk8Pendulum : Pendulum {
  static constexpr int kStages = 12;
};

// rk4-tree's step on the small-angle pendulum, q'' = -(g / L) q, at a step
// large enough for every term of the method to show.
struct LinearPendulum : Rk4Pendulum {
  static constexpr double kStep = 0.05;
  static void joint_accelerations(const State& s, const HalfAngles&, const Dofs&, const Kinematics&, const Loads&,
                                  Dofs& qdd) {
    qdd[0] = -(kG / kLength) * s.q[0];
  }
};
struct LinearPendulum8 : LinearPendulum {
  static constexpr int kStages = 12;
};

State start(double angle) {
  State s;
  s.q[0] = angle;
  HalfAngles ha;
  Pendulum::half_angles(s.q, ha);
  Pendulum::body_states(s.q, ha, s.qd, s);
  Pendulum::joint_accelerations(s, ha, s.qd, {}, {}, s.qdd);
  return s;
}

double energy(const State& s) {  // per unit mass
  return 0.5 * s.rigid[0].v.squaredNorm() + kG * s.rigid[0].r.z();
}

// A step of the template on the pendulum.
using Step = mbrt::StepStatus (*)(State&, Workspace&) noexcept;

// Swings from rest at an angle: the period from the downward zero crossings,
// the largest energy change relative to the swing's (e0 + g L is its kinetic
// energy at the bottom) and the last state.
struct Swing {
  double period_error = 0.0;  // relative to 2 pi sqrt(L / g)
  double drift = 0.0;
  State end;
};

Swing swing(Step step, double amplitude, int steps) {
  State s = start(amplitude);
  Workspace w;
  const double omega = std::sqrt(kG / kLength);
  const double e0 = energy(s);
  double drift = 0.0, previous = s.q[0], first = -1.0, last = -1.0;
  int crossings = 0;
  for (int k = 0; k < steps; ++k) {
    REQUIRE(step(s, w) == mbrt::StepStatus::ok);
    drift = std::max(drift, std::abs(energy(s) - e0) / (e0 + kG * kLength));
    if (previous > 0.0 && s.q[0] <= 0.0) {
      const double t = s.t - Pendulum::kStep * s.q[0] / (s.q[0] - previous);
      if (first < 0.0) first = t;
      last = t;
      ++crossings;
    }
    previous = s.q[0];
  }
  REQUIRE(crossings > 3);
  return {(last - first) / (crossings - 1) * omega / (2.0 * M_PI) - 1.0, drift, s};
}

// One good step, then one from a state with an infinite entry in `poisoned`:
// the step must report it and leave the state as it was.
void check_restored(Step step, Dofs State::*poisoned) {
  State s = start(0.5);
  Workspace w;
  REQUIRE(step(s, w) == mbrt::StepStatus::ok);
  (s.*poisoned)[0] = std::numeric_limits<double>::infinity();
  const State before = s;
  CHECK(step(s, w) == mbrt::StepStatus::non_finite);
  CHECK(s.t == before.t);
  CHECK(s.q[0] == before.q[0]);
  CHECK(s.qd[0] == before.qd[0]);
  CHECK(s.qdd[0] == before.qdd[0]);
  CHECK(s.rigid[0].r == before.rigid[0].r);
}

const double kOmegaH = std::sqrt(kG / kLength) * Pendulum::kStep;

}  // namespace

TEST_CASE("the tree template's small-amplitude period is 2 pi sqrt(L / g), energy within (w h)^2 / 2") {
  const Swing r = swing(&mbrt::schemes::tree_step<Pendulum>, 1e-3, 20000);
  MESSAGE("period error " << r.period_error << ", energy drift " << r.drift << " (w h = " << kOmegaH << ")");
  CHECK(std::abs(r.period_error) < kOmegaH * kOmegaH / 2.0);
  CHECK(r.drift < kOmegaH * kOmegaH / 2.0);
  CHECK(std::abs(r.end.rigid[0].r.norm() - kLength) < 1e-15);
}

// The implicit midpoint rule turns a harmonic oscillator by 2 atan(w h / 2)
// a step (Hairer, Lubich & Wanner 2006, section I.5), so its period is long
// by (w h)^2 / 12 where kick-drift-kick's, 2 asin(w h / 2), is short by
// (w h)^2 / 24; the amplitude a lengthens both by a^2 / 16. It keeps
// quadratic invariants, so the energy holds to what three fixed-point passes
// leave, about (w h / 2)^6, and to the rounding of g z, 1e-10 of the swing's.
TEST_CASE("the midpoint template's small-amplitude period is long by (w h)^2 / 12, energy kept to round-off") {
  const double amplitude = 1e-3;
  const Swing r = swing(&mbrt::schemes::tree_midpoint_step<MidpointPendulum>, amplitude, 40000);
  const double expected = (1.0 + amplitude * amplitude / 16.0) * kOmegaH / (2.0 * std::atan(0.5 * kOmegaH)) - 1.0;
  MESSAGE("period error " << r.period_error << " (expected " << expected << "), energy drift " << r.drift);
  CHECK(std::abs(r.period_error - expected) < 0.02 * expected);
  CHECK(r.drift < 1e-8);
  CHECK(std::abs(r.end.rigid[0].r.norm() - kLength) < 1e-15);
}

// The classical Runge-Kutta method maps a linear system y' = A y by the
// Taylor polynomial of exp(h A) of degree four (Hairer, Norsett & Wanner
// 1993, "Solving Ordinary Differential Equations I", section II.1): N steps
// of the template must give T^N y0, T computed here. A wrong weight or stage
// point changes T by at least a term of (w h)^4 / 24 = 4e-5 a step.
TEST_CASE("the rk4 template steps the linear pendulum by the degree-four Taylor polynomial of exp(h A)") {
  const double w2 = kG / kLength, h = LinearPendulum::kStep;
  Eigen::Matrix2d hA;
  hA << 0.0, h, -w2 * h, 0.0;
  const Eigen::Matrix2d T =
      Eigen::Matrix2d::Identity() + hA + hA * hA / 2.0 + hA * hA * hA / 6.0 + hA * hA * hA * hA / 24.0;
  State s = start(0.3);
  s.qd[0] = 0.7;
  Eigen::Vector2d y(s.q[0], s.qd[0]);
  Workspace w;
  for (int k = 0; k < 200; ++k) {
    REQUIRE(mbrt::schemes::tree_rk4_step<LinearPendulum>(s, w) == mbrt::StepStatus::ok);
    y = T * y;
  }
  MESSAGE("after 200 steps: q " << s.q[0] << " (T^N: " << y[0] << "), qd " << s.qd[0] << " (" << y[1] << ")");
  CHECK(std::abs(s.q[0] - y[0]) < 1e-12);
  CHECK(std::abs(s.qd[0] - y[1]) < 1e-12);
  CHECK(std::abs(s.t - 200 * h) < 1e-12);
}

// On y' = A y a Runge-Kutta method's step is y -> R(h A) y, with R built
// stage by stage from its tableau: K_i = A (I + h sum_j a_ij K_j), R = I + h
// sum_i b_i K_i. Method: ClassicalRungeKutta4 or DormandPrince8.
template <class Method>
Eigen::Matrix2d step_matrix(const Eigen::Matrix2d& A, double h) {
  std::array<Eigen::Matrix2d, Method::kStages> K;
  Eigen::Matrix2d R = Eigen::Matrix2d::Identity();
  for (int i = 0; i < Method::kStages; ++i) {
    Eigen::Matrix2d point = Eigen::Matrix2d::Identity();
    for (int j = 0; j < i; ++j) point += h * Method::a[i][j] * K[j];
    K[i] = A * point;
    R += h * Method::b[i] * K[i];
  }
  return R;
}

// rk8-tree's method is of order eight: R(z) = exp(z) + O(z^9). Here w h =
// 0.175, so a method of order seven would leave (w h)^8 / 8! = 2e-11 of
// exp(h A) each step; this one must be within a few (w h)^9 / 9! = 4e-13.
// The template's 200 steps must give R^N y0 to round-off.
TEST_CASE("the rk8 template steps the linear pendulum by its tableau's R(h A), which is exp(h A) to order eight") {
  const double w = std::sqrt(kG / kLength), h = LinearPendulum8::kStep;
  Eigen::Matrix2d A, flow;
  A << 0.0, 1.0, -w * w, 0.0;
  flow << std::cos(w * h), std::sin(w * h) / w, -w * std::sin(w * h), std::cos(w * h);
  const Eigen::Matrix2d R = step_matrix<mbrt::schemes::DormandPrince8>(A, h);
  const Eigen::Matrix2d R4 = step_matrix<mbrt::schemes::ClassicalRungeKutta4>(A, h);
  const double ninth = std::pow(w * h, 9) / 362880.0;
  MESSAGE("|R - exp(h A)|: " << (R - flow).cwiseAbs().maxCoeff() << " ((w h)^9 / 9! = " << ninth
                             << "); the classical method's " << (R4 - flow).cwiseAbs().maxCoeff());
  CHECK((R - flow).cwiseAbs().maxCoeff() < 4.0 * ninth);
  CHECK((R4 - flow).cwiseAbs().maxCoeff() > 1e3 * ninth);
  State s = start(0.3);
  s.qd[0] = 0.7;
  Eigen::Vector2d y(s.q[0], s.qd[0]);
  Workspace ws;
  for (int k = 0; k < 200; ++k) {
    REQUIRE(mbrt::schemes::tree_rk8_step<LinearPendulum8>(s, ws) == mbrt::StepStatus::ok);
    y = R * y;
  }
  MESSAGE("after 200 steps: q " << s.q[0] << " (R^N: " << y[0] << "), qd " << s.qd[0] << " (" << y[1] << ")");
  CHECK(std::abs(s.q[0] - y[0]) < 1e-12);
  CHECK(std::abs(s.qd[0] - y[1]) < 1e-12);
  CHECK(std::abs(s.t - 200 * h) < 1e-12);
}

TEST_CASE("the rk4 template restores the joint coordinates and the bodies after a non-finite step") {
  check_restored(&mbrt::schemes::tree_rk4_step<Rk4Pendulum>, &State::qd);
}

TEST_CASE("the rk8 template restores the joint coordinates and the bodies after a non-finite step") {
  check_restored(&mbrt::schemes::tree_rk8_step<Rk8Pendulum>, &State::qd);
}

TEST_CASE("the midpoint template restores the joint coordinates and the bodies after a non-finite step") {
  check_restored(&mbrt::schemes::tree_midpoint_step<MidpointPendulum>, &State::qd);
}

TEST_CASE("the tree template restores the joint coordinates and the bodies after a non-finite step") {
  check_restored(&mbrt::schemes::tree_step<Pendulum>, &State::qdd);
}
