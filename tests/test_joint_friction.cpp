// Constant Coulomb friction in revolute and prismatic joints (docs/friction.md)
// against closed forms: blocks on an incline that stick and slide
// (rk4-tree, staggered-tree), a pendulum with a friction moment whose
// turning angles follow from the energy it loses (rk4-tree), and a two-link
// arm on springs whose shoulder sticks while its elbow slips, swings and
// sticks (midpoint-tree). The model keys' errors name file, line and key;
// the step allocates nothing, stuck or slipping.
//
// Tolerances: the friction impulse acts on the end-of-step rates and moves
// the positions as a force constant over the step, so a motion under
// constant forces is integrated exactly and the error comes from the steps
// in which a joint turns or sticks: one step's worth of the friction
// acceleration, (T / I) h^2 in position (T / I = 0.6 rad/s^2 on the
// pendulum, 0.5 on the elbow: 6e-7 rad at h = 1e-3), plus where a turning
// point falls between two steps, half the acceleration there times h^2
// (below 1.2e-5 rad). The checks allow 1e-4 rad; measured errors are in
// docs/friction.md.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "arm3_friction.hpp"
#include "friction_arm.hpp"
#include "friction_belt.hpp"
#include "friction_load_pendulum.hpp"
#include "friction_spindown.hpp"
#include "friction_arm_7.hpp"
#include "friction_spatial_chain_16_revolute.hpp"
#include "friction_incline.hpp"
#include "friction_incline_tree.hpp"
#include "friction_pendulum.hpp"
#include "friction_model_errors.hpp"
#include "friction_references.hpp"

namespace {

using friction_reference::kG;

// The incline in one scheme: the held block (12 N > m g sin 30 = 9.81 N)
// never moves; the sliding one (3 N) moves by a t^2 / 2.
#define CHECK_INCLINE(ns)                                                                   \
  do {                                                                                      \
    namespace m = mbrt::models::ns;                                                         \
    m::State s = m::initial_state();                                                        \
    const double a = kG * 0.5 - 3.0 / 2.0;                                                  \
    const int steps = 2000;                                                                 \
    for (int i = 0; i < steps; ++i) {                                                       \
      REQUIRE(m::step(s) == mbrt::StepStatus::ok);                                          \
      CHECK(s.stuck[m::friction::hold] == 1.0);                                             \
      CHECK(s.stuck[m::friction::slide] == 0.0);                                            \
      CHECK(std::abs(s.q[m::body::held]) < 1e-15);                                          \
      CHECK(std::abs(s.qd[m::body::held]) < 1e-14);                                         \
    }                                                                                       \
    const double t = s.t;                                                                   \
    CHECK(s.t == doctest::Approx(2.0).epsilon(1e-12));                                      \
    CHECK(s.q[m::body::sliding] == doctest::Approx(0.5 * a * t * t).epsilon(1e-12));        \
    CHECK(s.qd[m::body::sliding] == doctest::Approx(a * t).epsilon(1e-12));                 \
    CHECK(s.friction[m::friction::slide] == doctest::Approx(-3.0).epsilon(1e-12));          \
    /* holding: friction balances gravity's pull exactly */                                 \
    CHECK(s.friction[m::friction::hold] == doctest::Approx(-2.0 * kG * 0.5).epsilon(1e-12)); \
  } while (false)

}  // namespace

TEST_CASE("a block on an incline sticks when m g sin(theta) <= F and slides with a = g sin(theta) - F / m") {
  SUBCASE("rk4-tree") { CHECK_INCLINE(friction_incline); }
  SUBCASE("staggered-tree") { CHECK_INCLINE(friction_incline_tree); }
}

TEST_CASE("a pendulum with a friction moment turns at the angles its energy loss gives and sticks") {
  namespace m = mbrt::models::friction_pendulum;
  const double mgd = 1.0 * kG * 0.5, torque = 0.2, theta0 = 0.5;
  // The closed-form turning angles, to the first at which it sticks.
  const std::vector<double> expected = friction_reference::turning_angles(theta0, mgd, torque);
  REQUIRE(expected.size() == 7);  // six swings: 0.5, 0.418, ..., then stuck
  m::State s = m::initial_state();
  friction_reference::TurningPoints turning;  // |theta| where the rate changes sign or stops
  double energy = m::energy(s).total();
  for (int i = 0; i < 8000; ++i) {
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    const double theta = theta0 + s.q[m::body::rod], rate = s.qd[m::body::rod];
    const double e = m::energy(s).total();
    // Dissipates, but for the steps it turns in: friction reversing inside a step
    // is first order, up to T |qdd| h^2 = 3e-6 J there (docs/friction.md).
    CHECK(e <= energy + 3e-6);
    energy = e;
    // Within h of the turn: off by at most |qdd| h^2 / 2 = 4e-6 rad.
    turning.add(theta, rate, s.stuck[0] == 1.0);
  }
  REQUIRE(turning.angles.size() == expected.size() - 1);
  for (std::size_t n = 0; n < turning.angles.size(); ++n) {
    INFO("turning angle ", n + 1);
    CHECK(std::abs(turning.angles[n] - expected[n + 1]) < 1e-4);
  }
  const double theta = theta0 + s.q[m::body::rod];
  CHECK(s.stuck[0] == 1.0);
  CHECK(mgd * std::abs(std::sin(theta)) <= torque);
  CHECK(std::abs(std::abs(theta) - expected.back()) < 1e-4);
  // Holds gravity's moment, to rk4's velocity after h from rest, h a (1 + h^2 a' / 6): 3e-6.
  CHECK(s.friction[0] == doctest::Approx(mgd * std::sin(theta)).epsilon(1e-5).scale(0));
  // Stuck, it stays: the angle creeps by rk4's h^4 / 24 |a' a| a step (1e-13 rad).
  const double held = s.q[m::body::rod];
  for (int i = 0; i < 2000; ++i) REQUIRE(m::step(s) == mbrt::StepStatus::ok);
  CHECK(std::abs(s.q[m::body::rod] - held) < 1e-9);
  CHECK(s.stuck[0] == 1.0);
}

// The arm's joint-space mass matrix at elbow angle q2 (the textbook
// two-link form with the links' centres c1, c2 and own moments I1, I2).
std::array<double, 3> arm_mass_matrix(double q2) {
  const double m1 = 1.0, m2 = 0.8, i1 = 0.0208333, i2 = 0.0106667, l1 = 0.5, c1 = 0.25, c2 = 0.2;
  const double m22 = i2 + m2 * c2 * c2, m12 = m22 + m2 * l1 * c2 * std::cos(q2);
  const double m11 = i1 + m1 * c1 * c1 + m22 + m2 * (l1 * l1 + 2.0 * l1 * c2 * std::cos(q2));
  return {m11, m12, m22};
}

TEST_CASE("two friction joints: M^-1's columns, stick below the limit, slip and dissipation above") {
  namespace m = mbrt::models::friction_arm;
  // Started at 0.7 rad the spring's 0.3 N m is below the elbow's 0.5 N m, and
  // the shoulder feels no net moment: both stick, at rest.
  m::Parameters p = m::kDefaultParameters;
  REQUIRE(m::set_parameter(p, "elbow.coordinate", 0.7));
  m::State s = m::initial_state(p);
  static m::Workspace w;
  for (int i = 0; i < 1000; ++i) REQUIRE(m::step(s, w) == mbrt::StepStatus::ok);
  // The columns of M^-1 the step used, against the inverse of the closed-form
  // M. They are taken where the frictionless step ends, h^2/2 |qdd| = 8e-6 rad
  // from the held angle (|qdd| = 0.3 N m * 53.7 /(kg m^2)): 4e-5 relative at
  // 5 rad^-1 relative sensitivity.
  const auto [m11, m12, m22] = arm_mass_matrix(0.7);
  const double det = m11 * m22 - m12 * m12;
  const m::FrictionColumns& g = w.friction_columns;
  CHECK(g[m::friction::shoulder][m::body::upper] == doctest::Approx(m22 / det).epsilon(4e-5));
  CHECK(g[m::friction::shoulder][m::body::fore] == doctest::Approx(-m12 / det).epsilon(4e-5));
  CHECK(g[m::friction::elbow][m::body::upper] == doctest::Approx(-m12 / det).epsilon(4e-5));
  CHECK(g[m::friction::elbow][m::body::fore] == doctest::Approx(m11 / det).epsilon(4e-5));
  // M^-1 is symmetric: the two off-diagonal entries come from different columns.
  CHECK(g[m::friction::shoulder][m::body::fore] == doctest::Approx(g[m::friction::elbow][m::body::upper]).epsilon(1e-12));
  // Held: no rate, and the joints stay where they started.
  CHECK(std::abs(s.qd[m::body::upper]) < 1e-12);
  CHECK(std::abs(s.qd[m::body::fore]) < 1e-12);
  CHECK(std::abs(s.q[m::body::upper]) < 1e-6);
  CHECK(std::abs(s.q[m::body::fore] - 0.7) < 1e-6);
  const double held_upper = s.q[m::body::upper], held_fore = s.q[m::body::fore];
  for (int i = 0; i < 1000; ++i) REQUIRE(m::step(s, w) == mbrt::StepStatus::ok);
  CHECK(std::abs(s.q[m::body::upper] - held_upper) < 1e-14);
  CHECK(std::abs(s.q[m::body::fore] - held_fore) < 1e-14);
  CHECK(s.stuck[m::friction::elbow] == 1.0);
  CHECK(s.stuck[m::friction::shoulder] == 1.0);
  // The spring's 0.3 N m, to the splitting's O(h) (the columns and rates taken 8e-6 rad away).
  CHECK(s.friction[m::friction::elbow] == doctest::Approx(-0.3).epsilon(2e-5).scale(0));

  // Started at 0, 1 N m exceeds it: the elbow slips, and the energy never grows.
  s = m::initial_state();
  double e = m::energy(s).total();
  for (int i = 0; i < 1000; ++i) {
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    const double next = m::energy(s).total();
    CHECK(next <= e + 1e-12);
    e = next;
  }
  CHECK(s.q[m::body::fore] > 0.01);
  CHECK(e < m::energy(m::initial_state()).total() - 0.01);
}

TEST_CASE("the friction step allocates nothing and takes stuck and slipping states alike") {
  namespace m = mbrt::models::friction_incline;
  m::State s = m::initial_state();
  m::Workspace w;
  AllocationCounter counter;
  for (int i = 0; i < 2; ++i) REQUIRE(m::step(s, w) == mbrt::StepStatus::ok);
  CHECK(counter.count() == 0);
  CHECK(s.stuck[m::friction::hold] == 1.0);
  CHECK(s.stuck[m::friction::slide] == 0.0);
}

TEST_CASE("friction keys: errors name the file, line and key") {
  using friction_errors::error_of;
  using friction_errors::pendulum_with;
  const mbrt::codegen::Model ok = mbrt::codegen::parse_model(pendulum_with(", friction: {torque: 0.2}"), "arm.yaml");
  CHECK(ok.joints[0].friction.kinetic == 0.2);
  CHECK(ok.joints[0].friction.static_limit == 0.2);
  using friction_errors::check;
  check(pendulum_with(", friction: {torque: -0.2}"), "joints[0].friction.torque", "expected a number >= 0");
  check(pendulum_with(", friction: {force: 3}"), "joints[0].friction.force", "revolute joint's friction is a torque");
  check(pendulum_with(", friction: {torque: 3}", "prismatic"), "joints[0].friction.torque",
        "prismatic joint's friction is a force");
  check(pendulum_with(", friction: {torque: 3, viscous: 1}"), "joints[0].friction.viscous", "unknown key 'viscous'");
  check(pendulum_with(", friction: {static_torque: 0.1, kinetic_torque: 0.2}"), "joints[0].friction.static_torque",
        "expected a number >= kinetic_torque (0.2)");
  check(pendulum_with(", friction: {static_torque: 0.3}"), "joints[0].friction.static_torque",
        "give both static_torque and kinetic_torque");
  check(pendulum_with(", friction: {torque: 0.3, kinetic_torque: 0.2}"), "joints[0].friction.kinetic_torque",
        "give one form of friction: torque, or static_torque and kinetic_torque");
  check(pendulum_with(", friction: {static_force: 3, kinetic_force: 2}"), "joints[0].friction.static_force",
        "revolute joint's friction is a torque");
  check(pendulum_with(", friction: {}"), "joints[0].friction", "expected torque, or static_torque and kinetic_torque, or static and kinetic");
  const mbrt::codegen::Model two =
      mbrt::codegen::parse_model(pendulum_with(", friction: {static_force: 3, kinetic_force: 2}", "prismatic"), "arm.yaml");
  CHECK(two.joints[0].friction.static_limit == 3.0);
  CHECK(two.joints[0].friction.kinetic == 2.0);
  const mbrt::codegen::Model pin = mbrt::codegen::parse_model(
      pendulum_with(", friction: {static: 0.3, kinetic: 0.2, radius: 0.01}"), "arm.yaml");
  CHECK(pin.joints[0].friction.static_per_load == doctest::Approx(0.003).scale(0));
  CHECK(pin.joints[0].friction.kinetic_per_load == doctest::Approx(0.002).scale(0));
  CHECK(pin.joints[0].friction.static_limit == 0.0);
  check(pendulum_with(", friction: {static: 0.2, kinetic: 0.3, radius: 0.01}"), "joints[0].friction.static",
        "expected a number >= kinetic (0.3)");
  check(pendulum_with(", friction: {static: 0.3, kinetic: 0.2}"), "joints[0].friction.radius", "missing required key 'radius'");
  check(pendulum_with(", friction: {static: 0.3, kinetic: 0.2, radius: 0.01}", "prismatic"), "joints[0].friction.radius",
        "a prismatic joint's friction takes no radius");
  check(pendulum_with(", friction: {torque: 0.3, static: 0.2}"), "joints[0].friction.static",
        "give one form of friction");
  check(pendulum_with(", friction: {torque: 0.1}", "spherical"), "joints[0].friction", "does not apply to a spherical joint");
  // The absolute-coordinate schemes that keep no factor of S refuse it
  // (staggered-pcst, baumgarte, blajer, rk4-projected take it:
  // test_joint_friction_absolute.cpp).
  check(pendulum_with(", friction: {torque: 0.1}") + "solver: {scheme: staggered-nps}\n", "joints.pin.friction",
        "joint friction needs staggered-pcst, baumgarte, blajer, rk4-projected or a tree scheme");
  // A friction output names a joint with friction.
  const std::string output = "inputs:\n  - {name: tau, type: joint_torque, joint: pin, min: -1, max: 1, safe: 0}\n"
                             "outputs:\n  - {name: f, type: joint_friction, joint: pin}\n";
  const std::string what = error_of(pendulum_with("") + output);
  INFO(what);
  CHECK(what.find("arm.yaml:10") != std::string::npos);
  CHECK(what.find("outputs[0].joint") != std::string::npos);
  CHECK(what.find("joint 'pin' has no friction") != std::string::npos);
  CHECK(error_of(pendulum_with(", friction: {torque: 0.1}") + output + "solver: {scheme: rk4-tree}\n") == "(no error)");
}

namespace {

// Model ns from its initial state for `steps` steps: every step finite, the
// energy's largest rise in one step, the final state, the step at which
// every joint was last not stuck.
template <class State>
struct FrictionRun {
  State s;
  bool finite = true;
  double largest_rise = 0.0;
  int last_slip = 0;
};

template <class State, class Step, class Energy>
FrictionRun<State> run_with_friction(State s, Step step, Energy energy, int steps) {
  FrictionRun<State> run{s};
  double e = energy(s);
  for (int i = 0; i < steps; ++i) {
    run.finite = run.finite && step(run.s) == mbrt::StepStatus::ok;
    const double next = energy(run.s);
    run.largest_rise = std::max(run.largest_rise, next - e);
    e = next;
    if constexpr (requires { run.s.stuck; }) {
      for (double stuck : run.s.stuck) if (stuck == 0.0) run.last_slip = i;
    }
  }
  return run;
}

}  // namespace

TEST_CASE("stress: friction in every joint of a 7-link spatial arm and a 16-link spatial chain") {
  // Configured from tests/models/stress/ (tests/CMakeLists.txt): the arm starts
  // with joint rates up to 8 rad/s and falls under gravity against 2 N m in
  // every joint; the chain is released bent against 0.05 N m. 20 s at 1 ms.
  // Friction takes energy out every step: the energy may rise by round-off
  // only, where the same arm without friction rises by up to 1.3e-3 J in a
  // step (rk4-tree's own error at 1 ms).
  SUBCASE("arm") {
    namespace m = mbrt::models::friction_arm_7;
    const auto energy = [](const m::State& s) { return m::energy(s).total(); };
    const auto run = run_with_friction(m::initial_state(), [](m::State& s) { return m::step(s); }, energy, 20000);
    CHECK(run.finite);
    CHECK(run.largest_rise < 1e-11);
    CHECK(energy(run.s) < energy(m::initial_state()) - 50.0);
    // It comes to rest with every joint stuck (measured: at 11.6 s), and stays
    // there to round-off.
    CHECK(run.last_slip < 15000);
    m::State s = run.s;
    for (int i = 0; i < 1000; ++i) REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    for (std::size_t j = 0; j < s.q.size(); ++j) {
      CHECK(std::abs(s.q[j] - run.s.q[j]) < 1e-12);
      CHECK(std::abs(s.qd[j]) < 1e-12);
    }
  }
  SUBCASE("chain") {
    namespace m = mbrt::models::friction_spatial_chain_16_revolute;
    const auto energy = [](const m::State& s) { return m::energy(s).total(); };
    const auto run = run_with_friction(m::initial_state(), [](m::State& s) { return m::step(s); }, energy, 20000);
    CHECK(run.finite);
    CHECK(run.largest_rise < 1e-11);
    CHECK(energy(run.s) < energy(m::initial_state()) - 5.0);
  }
}

TEST_CASE("the frictional demo arm publishes each joint's friction torque and stick state") {
  // examples/hil_demo/arm3_friction.yaml: horizontal, so gravity loads only
  // the bearings; 0.5, 0.3, 0.1 N m of friction at shoulder, elbow, wrist.
  namespace m = mbrt::models::arm3_friction;
  m::State s = m::initial_state();
  m::Outputs y{};
  // 0.4 N m at the shoulder is held: nothing moves, the shoulder's friction is -0.4 N m.
  s.inputs[m::input::tau_shoulder] = 0.4;
  for (int i = 0; i < 100; ++i) REQUIRE(m::step(s) == mbrt::StepStatus::ok);
  m::outputs(s, y);
  CHECK(y[m::output::shoulder_stuck] == 1.0);
  CHECK(y[m::output::elbow_stuck] == 1.0);
  CHECK(y[m::output::wrist_stuck] == 1.0);
  CHECK(y[m::output::shoulder_friction] == doctest::Approx(-0.4).epsilon(1e-9));
  CHECK(std::abs(y[m::output::shoulder_angle]) < 1e-12);
  // 2 N m turns it: the shoulder slips forward against its full 0.5 N m.
  s.inputs[m::input::tau_shoulder] = 2.0;
  for (int i = 0; i < 100; ++i) REQUIRE(m::step(s) == mbrt::StepStatus::ok);
  m::outputs(s, y);
  CHECK(y[m::output::shoulder_stuck] == 0.0);
  CHECK(y[m::output::shoulder_rate] > 0.0);
  CHECK(y[m::output::shoulder_friction] == doctest::Approx(-0.5).epsilon(1e-12));
  CHECK(y[m::output::shoulder_friction] == s.friction[m::friction::shoulder]);
  CHECK(y[m::output::elbow_stuck] == s.stuck[m::friction::elbow]);

  // The CAN description gives the friction signals their units.
  std::ifstream dbc(MBRT_ARM3_FRICTION_DBC);
  REQUIRE(dbc.good());
  std::string line, friction_line, stuck_line;
  while (std::getline(dbc, line)) {
    if (line.find("SG_ shoulder_friction ") != std::string::npos) friction_line = line;
    if (line.find("SG_ shoulder_stuck ") != std::string::npos) stuck_line = line;
  }
  CHECK(friction_line.find("\"N m\"") != std::string::npos);
  CHECK(stuck_line.find("\"\"") != std::string::npos);
}

TEST_CASE("stick-slip on a moving belt: static and kinetic friction give the closed-form stick and slip phases") {
  namespace m = mbrt::models::friction_belt;
  friction_reference::check_belt_phases(
      m::initial_state(), m::kStep, [](m::State& s) { return m::step(s) == mbrt::StepStatus::ok; },
      [](const m::State& s) { return s.rigid[m::rigid::block].r[0]; },
      [](const m::State& s) { return s.rigid[m::rigid::belt].v[0]; },
      [](const m::State& s) { return s.stuck[m::friction::contact]; });
}

TEST_CASE("load-dependent pin friction: a spinning disk stops at the closed-form time, a rod is held below mu_s r") {
  SUBCASE("spin-down: moment mu_k r m g, the centre at rest") {
    // tests/models/friction_spindown.yaml: m = 2 kg, J = 0.04 kg m^2, omega0 =
    // 10 rad/s, mu_k = 0.1, r = 0.01 m: alpha = mu_k r m g / J.
    namespace m = mbrt::models::friction_spindown;
    const double alpha = 0.1 * 0.01 * 2.0 * kG / 0.04, omega0 = 10.0;
    const double stop = omega0 / alpha, angle = omega0 * omega0 / (2.0 * alpha);  // 20.387 s, 101.94 rad
    m::State s = m::initial_state();
    int stopped_at = -1;
    for (int i = 0; i < 25000; ++i) {
      REQUIRE(m::step(s) == mbrt::StepStatus::ok);
      if (i == 9999) {  // t = 10 s, sliding: omega0 - alpha t, and the friction is -mu_k r m g
        // The transverse reaction from the multipliers is m g to 1e-8 (measured).
        CHECK(s.qd[m::body::disk] == doctest::Approx(omega0 - alpha * 10.0).epsilon(1e-7));
        CHECK(s.q[m::body::disk] == doctest::Approx(omega0 * 10.0 - 0.5 * alpha * 100.0).epsilon(1e-7));
        CHECK(s.friction[m::friction::axle] == doctest::Approx(-alpha * 0.04).epsilon(1e-7).scale(0));
      }
      if (stopped_at < 0 && s.stuck[m::friction::axle] == 1.0) stopped_at = i;
    }
    CHECK(std::abs((stopped_at + 1) * m::kStep - stop) < 2.0 * m::kStep);
    CHECK(s.q[m::body::disk] == doctest::Approx(angle).epsilon(1e-6));
    CHECK(s.qd[m::body::disk] == 0.0);
    CHECK(s.stuck[m::friction::axle] == 1.0);
  }
  SUBCASE("held at rest where m g d sin(theta) <= mu_s r m g") {
    // tests/models/friction_load_pendulum.yaml: d = 0.5 m, mu_s r = 0.003 m.
    namespace m = mbrt::models::friction_load_pendulum;
    for (const double theta : {0.0059, -0.0059, 0.0061, 0.02}) {
      INFO("theta0 = ", theta);
      m::Parameters p = m::kDefaultParameters;
      REQUIRE(m::set_parameter(p, "pin.coordinate", theta));
      m::State s = m::initial_state(p);
      for (int i = 0; i < 500; ++i) REQUIRE(m::step(s) == mbrt::StepStatus::ok);
      const bool held = 0.5 * std::sin(std::abs(theta)) <= 0.3 * 0.01;
      CHECK((s.stuck[m::friction::pin] == 1.0) == held);
      if (held) {
        // The first step, from rest, moves it by rk4's O(h^4) before it is held.
        CHECK(std::abs(s.q[m::body::rod] - theta) < 1e-12);
        CHECK(s.friction[m::friction::pin] == doctest::Approx(kG * 0.5 * std::sin(theta)).epsilon(1e-6));
      } else {
        CHECK(std::abs(s.q[m::body::rod]) < std::abs(theta));  // it swung down
      }
    }
  }
}
