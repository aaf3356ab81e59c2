// Coulomb joint friction (docs/friction.md) in the schemes in absolute
// coordinates that take it (staggered-pcst, baumgarte, blajer,
// rk4-projected), against closed forms and the energy balance: a pendulum
// with a friction moment whose turning angles follow from the energy it
// loses (all four schemes); blocks on inclines held and sliding under
// constant friction forces (staggered-pcst) and under load-dependent
// friction mu |R| (all four); a closed four-bar with a friction moment in
// one ground pin, whose loss of energy is the moment times the pin's travel
// and which comes to rest where gravity's moment about the pin is below the
// friction (staggered-pcst, rk4-projected); the stick-slip oscillator on a
// moving belt (all four); a 7-link spatial arm with friction in every joint
// (staggered-pcst). Every step returns ok with a finite state; the step
// allocates nothing; the schemes that cannot take friction refuse it.
//
// What is read from the state, independently of the friction code: joint
// angles and rates from the bodies' Euler parameters and angular
// velocities (a revolute joint to the ground turns its body about the joint
// axis), slides from the body's position along the joint axis, energies
// from masses, inertias, velocities and heights. Signs: friction is
// reported along the model's joint coordinate (the `joint_position`
// output's): body 2 relative to body 1, positive about (along) the joint
// axis as the model file gives it.
//
// Tolerances: as in test_joint_friction.cpp, the friction impulse acts on
// the end-of-step rates and moves the positions as a force constant over
// the step, so motion under constant forces is exact to round-off and the
// error comes from the steps in which a joint turns or sticks: (T / I) h^2
// in angle, T |qdd| h^2 in energy (3e-6 J on the pendulum).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

#include "step_allocations.hpp"
#include "friction_arm_7_pcst.hpp"
#include "friction_belt_baumgarte.hpp"
#include "friction_belt_blajer.hpp"
#include "friction_belt_pcst.hpp"
#include "friction_belt_rk4p.hpp"
#include "friction_four_bar_pcst.hpp"
#include "friction_four_bar_rk4p.hpp"
#include "friction_incline_mu_baumgarte.hpp"
#include "friction_incline_mu_blajer.hpp"
#include "friction_incline_mu_pcst.hpp"
#include "friction_incline_mu_rk4p.hpp"
#include "friction_incline_pcst.hpp"
#include "friction_model_errors.hpp"
#include "friction_pendulum_baumgarte.hpp"
#include "friction_pendulum_blajer.hpp"
#include "friction_pendulum_pcst.hpp"
#include "friction_pendulum_rk4p.hpp"
#include "friction_references.hpp"

namespace {

using friction_reference::kG;
const double kDeg = std::acos(-1.0) / 180.0;

// A rigid body's kinetic and gravitational energy: m v^2 / 2 + w.J w / 2 -
// m g.r, w in body axes and J the diagonal of the inertia in body axes.
double energy_of(const mbrt::RigidState& b, double m, const mbrt::Vec3& inertia, const mbrt::Vec3& gravity) {
  return 0.5 * m * b.v.squaredNorm() + 0.5 * b.w.dot(inertia.cwiseProduct(b.w)) - m * gravity.dot(b.r);
}

// A body's turn about world y (its z axis (sin a, 0, cos a)) and about
// world z (its x axis (cos a, sin a, 0)), from its Euler parameters.
double turn_about_y(const mbrt::RigidState& b) {
  const mbrt::Mat3 r = mbrt::rotation_matrix(b.p);
  return std::atan2(r(0, 2), r(2, 2));
}
double turn_about_z(const mbrt::RigidState& b) {
  const mbrt::Mat3 r = mbrt::rotation_matrix(b.p);
  return std::atan2(r(1, 0), r(0, 0));
}

// An angle difference in (-pi, pi].
double wrapped(double a) { return std::remainder(a, 2.0 * std::acos(-1.0)); }

// Every body's state and every friction joint's output is finite.
template <class State>
bool all_finite(const State& s) {
  for (const mbrt::RigidState& b : s.rigid) {
    if (!b.r.allFinite() || !b.p.allFinite() || !b.v.allFinite() || !b.w.allFinite()) return false;
  }
  for (std::size_t k = 0; k < s.friction.size(); ++k) {
    if (!std::isfinite(s.friction[k]) || !(s.stuck[k] == 0.0 || s.stuck[k] == 1.0)) return false;
  }
  return std::isfinite(s.t);
}

// One generated model: its state, step and workspace; friction takes the
// spatial step (the planar one has no friction impulse: docs/friction.md).
#define FRICTION_MODEL_BASICS(ns)                                                                                  \
  using State = mbrt::models::ns::State;                                                                           \
  using Workspace = mbrt::models::ns::Workspace;                                                                   \
  static constexpr const char* kScheme = mbrt::models::ns::kScheme;                                                \
  static State initial_state() { return mbrt::models::ns::initial_state(); }                                       \
  static mbrt::StepStatus step(State& s) { return mbrt::models::ns::step(s); }                                     \
  static mbrt::StepStatus step(State& s, Workspace& w) { return mbrt::models::ns::step(s, w); }                    \
  using Reactions = mbrt::models::ns::Reactions;                                                                   \
  static void reactions(const State& s, Reactions& r) { mbrt::models::ns::reactions(s, r); }                       \
  static_assert(std::is_same_v<decltype(Workspace::k), mbrt::models::ns::detail::Kinematics>,                      \
                "a model with joint friction takes the spatial step");                                             \
  static_assert(std::is_same_v<decltype(State::friction), std::array<double, mbrt::models::ns::kFrictionJoints>>); \
  static_assert(std::is_same_v<decltype(State::stuck), std::array<double, mbrt::models::ns::kFrictionJoints>>)

// tests/models/friction_pendulum.yaml: a 1 kg, 1 m rod on a pin about y,
// T = 0.2 N m, from rest at 0.5 rad. kSmoothRise: the scheme's own largest
// rise of the energy in one step on the same pendulum without friction
// (spatial step, from 0.5 rad, 8000 steps; measured with the generator
// before friction: staggered-pcst 8.8e-9 J, baumgarte and blajer 1.1e-8 J,
// rk4-projected 7e-15 J).
#define PENDULUM_MODEL(Name, ns, smooth_rise)                   \
  struct Name {                                                 \
    FRICTION_MODEL_BASICS(ns);                                  \
    static_assert(mbrt::models::ns::kFrictionJoints == 1);      \
    static constexpr int rod = mbrt::models::ns::rigid::rod;    \
    static constexpr int pin = mbrt::models::ns::friction::pin; \
    static constexpr int pin_constraint = mbrt::models::ns::constraint::pin; \
    static constexpr double kSmoothRise = smooth_rise;          \
  }

PENDULUM_MODEL(PendulumPcst, friction_pendulum_pcst, 2e-8);
PENDULUM_MODEL(PendulumBaumgarte, friction_pendulum_baumgarte, 2e-8);
PENDULUM_MODEL(PendulumBlajer, friction_pendulum_blajer, 2e-8);
PENDULUM_MODEL(PendulumRk4, friction_pendulum_rk4p, 1e-13);

// The rod's angle from the downward vertical, positive about +y (the pin's
// axis, so the joint coordinate plus 0.5 rad), its rate and its energy.
double pendulum_angle(const mbrt::RigidState& rod) { return turn_about_y(rod); }
double pendulum_rate(const mbrt::RigidState& rod) { return (mbrt::rotation_matrix(rod.p) * rod.w).y(); }
double pendulum_energy(const mbrt::RigidState& rod) {
  return energy_of(rod, 1.0, mbrt::Vec3(1.0 / 12.0, 1.0 / 12.0, 0.001), mbrt::Vec3(0.0, 0.0, -kG));
}

template <class M>
void check_pendulum() {
  const double mgd = 1.0 * kG * 0.5, torque = 0.2, theta0 = 0.5;
  // Reference: the energy balance between turning points
  // (friction_reference::turning_angles), to the first at which it sticks.
  const std::vector<double> expected = friction_reference::turning_angles(theta0, mgd, torque);
  REQUIRE(expected.size() == 7);  // six swings: 0.5, 0.418, ..., then stuck
  CHECK(std::string(M::State::friction_joints[M::pin]) == "pin");
  typename M::State s = M::initial_state();
  REQUIRE(pendulum_angle(s.rigid[M::rod]) == doctest::Approx(theta0).epsilon(1e-12));
  friction_reference::TurningPoints turning;
  double energy = pendulum_energy(s.rigid[M::rod]), largest_rise = -1.0;
  bool finite = true;
  int against_rate = 0, at_limit = 0, slipping = 0;
  for (int i = 0; i < 8000; ++i) {
    REQUIRE(M::step(s) == mbrt::StepStatus::ok);
    finite = finite && all_finite(s);
    const mbrt::RigidState& rod = s.rigid[M::rod];
    const double e = pendulum_energy(rod), rate = pendulum_rate(rod);
    largest_rise = std::max(largest_rise, e - energy);
    energy = e;
    const bool stuck = s.stuck[M::pin] == 1.0;
    // Coulomb's law: slipping, the full moment against the rate; stuck, within the limit.
    if (!stuck) {
      ++slipping;
      if (std::abs(std::abs(s.friction[M::pin]) - torque) <= 1e-12 * torque) ++at_limit;
      if (s.friction[M::pin] * rate <= 0.0 || std::abs(rate) < 1e-9) ++against_rate;
    } else {
      CHECK(std::abs(s.friction[M::pin]) <= torque * (1.0 + 1e-12));
    }
    // Within a step of the turn: off by at most |qdd| h^2 / 2 = 4e-6 rad.
    turning.add(pendulum_angle(rod), rate, stuck);
  }
  CHECK(finite);
  CHECK(slipping > 4000);
  CHECK(at_limit == slipping);
  CHECK(against_rate == slipping);
  // Friction only takes energy out: a rise in a step only where the friction
  // reverses inside it (first order, T |qdd| h^2 = 3e-6 J), plus the
  // scheme's own error without friction.
  MESSAGE(std::string(M::kScheme) << ": largest energy rise in a step " << largest_rise << " J");
  CHECK(largest_rise <= 3e-6 + M::kSmoothRise);
  REQUIRE(turning.angles.size() == expected.size() - 1);
  double turning_error = 0.0;
  for (std::size_t n = 0; n < turning.angles.size(); ++n) {
    INFO("turning angle ", n + 1);
    CHECK(std::abs(turning.angles[n] - expected[n + 1]) < 1e-4);
    turning_error = std::max(turning_error, std::abs(turning.angles[n] - expected[n + 1]));
  }
  // Stuck at the last turn, where gravity's moment is below T; the friction
  // holds it: m g d sin(theta) about +y (gravity's moment is -m g d sin(theta)),
  // to the O(h^2) of the smooth step's velocity from rest.
  const double theta = pendulum_angle(s.rigid[M::rod]);
  MESSAGE(std::string(M::kScheme) << ": turning angles off by up to " << turning_error << " rad; stuck at " << theta
                                  << " rad with friction off m g d sin(theta) by "
                                  << s.friction[M::pin] / (mgd * std::sin(theta)) - 1.0 << " (relative)");
  CHECK(s.stuck[M::pin] == 1.0);
  CHECK(mgd * std::abs(std::sin(theta)) <= torque);
  CHECK(std::abs(std::abs(theta) - expected.back()) < 1e-4);
  CHECK(s.friction[M::pin] == doctest::Approx(mgd * std::sin(theta)).epsilon(1e-5).scale(0));
  // Stuck, it stays (the hold): 2000 more steps, stuck in each, turned by < 1e-9 rad.
  bool stuck_throughout = true;
  double creep = 0.0;
  for (int i = 0; i < 2000; ++i) {
    REQUIRE(M::step(s) == mbrt::StepStatus::ok);
    finite = finite && all_finite(s);
    stuck_throughout = stuck_throughout && s.stuck[M::pin] == 1.0;
    creep = std::max(creep, std::abs(pendulum_angle(s.rigid[M::rod]) - theta));
  }
  MESSAGE(std::string(M::kScheme) << ": held for 2000 steps, turned by " << creep << " rad");
  CHECK(finite);
  CHECK(stuck_throughout);
  CHECK(creep < 1e-9);
  // At rest on the pin (Newton's and Euler's laws for a body at rest): the
  // friction holds gravity's moment, m g d sin(theta), and the pin carries
  // the weight, m g up, with no moment about the transverse axes. Both to
  // the splitting's O(h^2): each step's impulse stops the smooth step's
  // trial motion from rest, h^2 alpha / 2 = 2.7e-8 rad, over which gravity's
  // moment changes by 7e-6 of itself (measured: friction 3.7e-6 relative
  // off, the pin force 7.7e-7 N). The multipliers include the friction
  // impulses' share of the pin's load: without it the pin would carry the
  // load of a rod starting to swing, m d alpha = 0.027 N off.
  CHECK(s.friction[M::pin] == doctest::Approx(mgd * std::sin(theta)).epsilon(1e-5).scale(0));
  typename M::Reactions r;
  M::reactions(s, r);
  const mbrt::JointReaction& pin = r[static_cast<std::size_t>(M::pin_constraint)];
  MESSAGE(std::string(M::kScheme) << ": pin force at rest " << pin.force.transpose() << " N");
  CHECK((pin.force - mbrt::Vec3(0.0, 0.0, kG)).norm() < 1e-5);
  CHECK(std::abs(pin.torque.x()) < 1e-9);
  CHECK(std::abs(pin.torque.z()) < 1e-9);
}

}  // namespace

TEST_CASE("a pendulum with a friction moment turns at the angles its energy loss gives, sticks and stays") {
  SUBCASE("staggered-pcst") { check_pendulum<PendulumPcst>(); }
  SUBCASE("baumgarte") { check_pendulum<PendulumBaumgarte>(); }
  SUBCASE("blajer") { check_pendulum<PendulumBlajer>(); }
  SUBCASE("rk4-projected") { check_pendulum<PendulumRk4>(); }
}

TEST_CASE("constant friction forces on an incline: held where F >= m g sin(theta), else a = g sin(theta) - F / m") {
  // tests/models/friction_incline.yaml in staggered-pcst: 2 kg blocks on
  // ground prismatics down 30 degrees, axis (cos 30, 0, -sin 30) downhill;
  // 12 N holds the first (m g sin 30 = 9.81 N), 3 N lets the second slide.
  // Reference: Newton's second law along the axis under constant forces.
  namespace m = mbrt::models::friction_incline_pcst;
  static_assert(std::is_same_v<decltype(m::Workspace::k), m::detail::Kinematics>, "the spatial step");
  static_assert(m::kFrictionJoints == 2);
  const mbrt::Vec3 axis(std::cos(30 * kDeg), 0.0, -std::sin(30 * kDeg));
  const double mass = 2.0, a = kG * std::sin(30 * kDeg) - 3.0 / mass;  // 3.405 m/s^2
  m::State s = m::initial_state();
  const mbrt::Vec3 held0 = s.rigid[m::rigid::held].r, sliding0 = s.rigid[m::rigid::sliding].r;
  bool finite = true, held_stuck = true, slide_slipping = true;
  double held_moved = 0.0, held_speed = 0.0, slide_error = 0.0;
  for (int i = 0; i < 2000; ++i) {
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    finite = finite && all_finite(s);
    held_stuck = held_stuck && s.stuck[m::friction::hold] == 1.0;
    slide_slipping = slide_slipping && s.stuck[m::friction::slide] == 0.0;
    held_moved = std::max(held_moved, (s.rigid[m::rigid::held].r - held0).norm());
    held_speed = std::max(held_speed, s.rigid[m::rigid::held].v.norm());
    const double x = (s.rigid[m::rigid::sliding].r - sliding0).dot(axis);
    slide_error = std::max(slide_error, std::abs(x - 0.5 * a * s.t * s.t) / (0.5 * a * s.t * s.t));
  }
  CHECK(finite);
  CHECK(held_stuck);
  CHECK(slide_slipping);
  CHECK(s.t == doctest::Approx(2.0).epsilon(1e-12));
  MESSAGE("held block moved by " << held_moved << " m; sliding block off a t^2 / 2 by " << slide_error << " relative");
  CHECK(held_moved < 1e-10);
  CHECK(held_speed < 1e-10);
  CHECK(slide_error < 1e-9);
  CHECK(s.rigid[m::rigid::sliding].v.dot(axis) == doctest::Approx(a * s.t).epsilon(1e-9));
  // Along the joint axis (downhill): the slider's friction is -F; the held
  // block's balances gravity's pull, -m g sin 30.
  CHECK(s.friction[m::friction::slide] == doctest::Approx(-3.0).epsilon(1e-12));
  CHECK(s.friction[m::friction::hold] == doctest::Approx(-mass * kG * std::sin(30 * kDeg)).epsilon(1e-9));
}

namespace {

// tests/models/friction_incline_mu.yaml: 2 kg blocks on ground prismatics
// down 26 and 27 degrees, mu_s = 0.5, mu_k = 0.4, R = m g cos(theta).
#define INCLINE_MU_MODEL(Name, ns)                                   \
  struct Name {                                                      \
    FRICTION_MODEL_BASICS(ns);                                       \
    static_assert(mbrt::models::ns::kFrictionJoints == 2);           \
    static constexpr int held = mbrt::models::ns::rigid::held;       \
    static constexpr int sliding = mbrt::models::ns::rigid::sliding; \
    static constexpr int hold = mbrt::models::ns::friction::hold;    \
    static constexpr int slide = mbrt::models::ns::friction::slide;  \
  }

INCLINE_MU_MODEL(InclineMuPcst, friction_incline_mu_pcst);
INCLINE_MU_MODEL(InclineMuRk4, friction_incline_mu_rk4p);
INCLINE_MU_MODEL(InclineMuBaumgarte, friction_incline_mu_baumgarte);
INCLINE_MU_MODEL(InclineMuBlajer, friction_incline_mu_blajer);

template <class M>
void check_incline_mu() {
  const double mass = 2.0, mu_s = 0.5, mu_k = 0.4;
  const mbrt::Vec3 axis27(std::cos(27 * kDeg), 0.0, -std::sin(27 * kDeg));
  // Reference: the Coulomb limits with R = m g cos(theta) (the joint point
  // is the centre of mass, so friction along the axis loads it with no
  // moment): held at 26 degrees (tan 26 = 0.488 <= mu_s); at 27 (0.510 >
  // mu_s) sliding with a = g (sin 27 - mu_k cos 27) = 0.9573 m/s^2 from
  // the first step on (breaking loose from rest under the kinetic limit).
  REQUIRE(std::tan(26 * kDeg) <= mu_s);
  REQUIRE(std::tan(27 * kDeg) > mu_s);
  const double a = kG * (std::sin(27 * kDeg) - mu_k * std::cos(27 * kDeg));
  CHECK(std::string(M::State::friction_joints[M::hold]) == "hold");
  CHECK(std::string(M::State::friction_joints[M::slide]) == "slide");
  typename M::State s = M::initial_state();
  const mbrt::Vec3 held0 = s.rigid[M::held].r, sliding0 = s.rigid[M::sliding].r;
  bool finite = true, held_stuck = true, slide_slipping = true;
  double held_moved = 0.0, held_speed = 0.0, holding_error = 0.0, slide_error = 0.0, kinetic_error = 0.0;
  for (int i = 0; i < 2000; ++i) {
    REQUIRE(M::step(s) == mbrt::StepStatus::ok);
    finite = finite && all_finite(s);
    held_stuck = held_stuck && s.stuck[M::hold] == 1.0;
    slide_slipping = slide_slipping && s.stuck[M::slide] == 0.0;
    held_moved = std::max(held_moved, (s.rigid[M::held].r - held0).norm());
    held_speed = std::max(held_speed, s.rigid[M::held].v.norm());
    // Holding: friction along the (downhill) axis balances gravity's pull.
    holding_error = std::max(holding_error, std::abs(s.friction[M::hold] / (-mass * kG * std::sin(26 * kDeg)) - 1.0));
    const double x = (s.rigid[M::sliding].r - sliding0).dot(axis27), x_exact = 0.5 * a * s.t * s.t;
    slide_error = std::max(slide_error, std::abs(x / x_exact - 1.0));
    const double kinetic = -mu_k * mass * kG * std::cos(27 * kDeg);  // along the axis, against the slide
    kinetic_error = std::max(kinetic_error, std::abs(s.friction[M::slide] / kinetic - 1.0));
    if (i == 0) {
      // Loose from the first step: a step under mu_s would leave x at 9 %
      // of a h^2 / 2 and every later x behind by (mu_s - mu_k) g cos 27 h t.
      CHECK(s.stuck[M::slide] == 0.0);
      CHECK(x == doctest::Approx(x_exact).epsilon(1e-6).scale(0));
    }
  }
  MESSAGE(std::string(M::kScheme) << ": held block moved by " << held_moved << " m, holding friction off by "
                                  << holding_error << "; slider off a t^2 / 2 by " << slide_error
                                  << ", its friction off mu_k m g cos 27 by " << kinetic_error << " (relative)");
  CHECK(finite);
  CHECK(held_stuck);
  CHECK(slide_slipping);
  CHECK(held_moved < 1e-10);
  CHECK(held_speed < 1e-10);
  CHECK(holding_error < 1e-9);
  CHECK(slide_error < 1e-6);
  CHECK(kinetic_error < 1e-6);
  CHECK(s.rigid[M::sliding].v.dot(axis27) == doctest::Approx(a * s.t).epsilon(1e-6));
  // The sliding block stays on its line (the joint), across the slope.
  const mbrt::Vec3 d = s.rigid[M::sliding].r - sliding0;
  CHECK((d - d.dot(axis27) * axis27).norm() < 1e-9);
}

}  // namespace

TEST_CASE("load-dependent friction mu |R| on inclines: held at 26 degrees, sliding from the first step at 27") {
  SUBCASE("staggered-pcst") { check_incline_mu<InclineMuPcst>(); }
  SUBCASE("rk4-projected") { check_incline_mu<InclineMuRk4>(); }
  SUBCASE("baumgarte") { check_incline_mu<InclineMuBaumgarte>(); }
  SUBCASE("blajer") { check_incline_mu<InclineMuBlajer>(); }
}

namespace {

// tests/models/friction_four_bar.yaml: four_bar.yaml with T = 2 N m in
// pin_o (ground - crank, axis +z).
#define FOUR_BAR_MODEL(Name, ns)                                     \
  struct Name {                                                      \
    FRICTION_MODEL_BASICS(ns);                                       \
    static_assert(mbrt::models::ns::kFrictionJoints == 1);           \
    static constexpr int crank = mbrt::models::ns::rigid::crank;     \
    static constexpr int coupler = mbrt::models::ns::rigid::coupler; \
    static constexpr int rocker = mbrt::models::ns::rigid::rocker;   \
    static constexpr int pin_o = mbrt::models::ns::friction::pin_o;  \
  }

FOUR_BAR_MODEL(FourBarPcst, friction_four_bar_pcst);
FOUR_BAR_MODEL(FourBarRk4, friction_four_bar_rk4p);

// The four-bar's potential energy V = g (y_A + y_B) (unit masses: the
// rods' centres at A / 2, (A + B) / 2, (B + C) / 2) as a function of the
// crank angle phi about +z, in closed form: the crank's tip A = (-sin phi,
// cos phi); the rocker's tip B at sqrt(10) from A and 2 from C = (3, 0),
// on the left of A -> C, where the model starts (A = (0, 1), B = (3, 2));
// the linkage is a Grashof crank-rocker (1 + sqrt(10) < 2 + 3), so B never
// changes side.
double four_bar_potential(double phi) {
  const double ax = -std::sin(phi), ay = std::cos(phi), cx = 3.0, cy = 0.0;
  const double coupler2 = 10.0, rocker2 = 4.0;
  const double dx = cx - ax, dy = cy - ay, d = std::hypot(dx, dy);
  const double along = (coupler2 - rocker2 + d * d) / (2.0 * d), across = std::sqrt(coupler2 - along * along);
  const double by = ay + along * dy / d + across * dx / d;  // left of A -> C: (-dy, dx) / d
  return kG * (ay + by);
}

// dV/dphi by central differences of the closed form (truncation and
// round-off below 1e-8 N m).
double four_bar_moment(double phi) {
  const double e = 1e-5;
  return (four_bar_potential(phi + e) - four_bar_potential(phi - e)) / (2.0 * e);
}

// The mechanism's energy from its bodies' states (energy_of): the
// coupler's inertia product Jxy multiplies only w_x w_y, zero in its motion
// about z, so the diagonal suffices.
template <class M>
double four_bar_energy(const typename M::State& s) {
  const mbrt::Vec3 g(0.0, -kG, 0.0);
  return energy_of(s.rigid[M::crank], 1.0, mbrt::Vec3(0.0833583333333, 0.00005, 0.0833583333333), g) +
         energy_of(s.rigid[M::coupler], 1.0, mbrt::Vec3(0.0833808333333, 0.7500275, 0.833358333333), g) +
         energy_of(s.rigid[M::rocker], 1.0, mbrt::Vec3(0.333358333333, 0.00005, 0.333358333333), g);
}

template <class M>
void check_four_bar() {
  const double torque = 2.0;
  typename M::State s = M::initial_state();
  // The closed form agrees with the model's start: V = 3 g, an equilibrium
  // (V' = 0); the energy read from the state is the model file's: the
  // crank at -1 rad/s (centre at 0.5 m/s), the coupler translating at 1 m/s,
  // the rocker at -0.5 rad/s (centre at 0.5 m/s).
  REQUIRE(four_bar_potential(0.0) == doctest::Approx(3.0 * kG).epsilon(1e-12));
  REQUIRE(std::abs(four_bar_moment(0.0)) < 1e-8);
  const double kinetic0 = 0.5 * 0.25 + 0.5 * 0.0833583333333 + 0.5 * 1.0 + 0.5 * 0.25 + 0.5 * 0.333358333333 * 0.25;
  REQUIRE(four_bar_energy<M>(s) == doctest::Approx(3.0 * kG + kinetic0).epsilon(1e-12));
  const double e0 = four_bar_energy<M>(s);
  double phi = turn_about_z(s.rigid[M::crank]), travel = 0.0, largest_gap = 0.0;
  bool finite = true;
  int last_slip = -1;
  for (int i = 0; i < 9000; ++i) {
    REQUIRE(M::step(s) == mbrt::StepStatus::ok);
    finite = finite && all_finite(s);
    const double next = turn_about_z(s.rigid[M::crank]);
    travel += std::abs(wrapped(next - phi));
    phi = next;
    // Energy balance: what the mechanism lost is the friction moment's work, T times the pin's travel.
    largest_gap = std::max(largest_gap, std::abs(e0 - four_bar_energy<M>(s) - torque * travel));
    if (s.stuck[M::pin_o] == 0.0) last_slip = i;
  }
  const double lost = e0 - four_bar_energy<M>(s);
  MESSAGE(std::string(M::kScheme) << ": lost " << lost << " J over " << travel
                                  << " rad of the pin; largest gap to T * travel " << largest_gap
                                  << " J; last slipped in step " << last_slip);
  CHECK(finite);
  CHECK(lost > 20.0);  // most of the 0.83 J + V(0) - V_min it had (about 25 J)
  CHECK(largest_gap < 1e-3 * lost);
  // At rest, stuck (from about 6.5 s on), with the crank where gravity's
  // moment about the pin is within T; the friction balances it: friction +
  // (-dV/dphi) = 0 along +z, the pin's axis.
  CHECK(last_slip < 8000);
  CHECK(s.stuck[M::pin_o] == 1.0);
  for (const mbrt::RigidState& b : s.rigid) {
    CHECK(b.v.norm() < 1e-9);
    CHECK(b.w.norm() < 1e-9);
  }
  MESSAGE(std::string(M::kScheme) << ": at rest at phi = " << phi << " rad, friction " << s.friction[M::pin_o]
                                  << " N m, off dV/dphi by " << s.friction[M::pin_o] / four_bar_moment(phi) - 1.0
                                  << " (relative)");
  CHECK(std::abs(four_bar_moment(phi)) <= torque);
  CHECK(s.friction[M::pin_o] == doctest::Approx(four_bar_moment(phi)).epsilon(1e-5));
  // And stays: 2000 more steps, stuck in each, the crank turned by < 1e-9 rad.
  const double held = phi;
  bool stuck_throughout = true;
  double creep = 0.0;
  for (int i = 0; i < 2000; ++i) {
    REQUIRE(M::step(s) == mbrt::StepStatus::ok);
    finite = finite && all_finite(s);
    stuck_throughout = stuck_throughout && s.stuck[M::pin_o] == 1.0;
    creep = std::max(creep, std::abs(wrapped(turn_about_z(s.rigid[M::crank]) - held)));
  }
  CHECK(finite);
  CHECK(stuck_throughout);
  CHECK(creep < 1e-9);
}

}  // namespace

TEST_CASE("a four-bar with a frictional pin loses T times the pin's travel and comes to rest where |dV/dphi| <= T") {
  SUBCASE("staggered-pcst") { check_four_bar<FourBarPcst>(); }
  SUBCASE("rk4-projected") { check_four_bar<FourBarRk4>(); }
}

namespace {

// tests/models/friction_belt.yaml in one scheme: the 1e8 kg belt carries the
// 1 kg block, so the friction joint's column of K is the block's (the belt
// barely moves), its share through S.
#define CHECK_BELT(ns)                                                                              \
  friction_reference::check_belt_phases(                                                            \
      mbrt::models::ns::initial_state(), mbrt::models::ns::kStep,                                    \
      [](mbrt::models::ns::State& s) { return mbrt::models::ns::step(s) == mbrt::StepStatus::ok; }, \
      [](const mbrt::models::ns::State& s) { return s.rigid[mbrt::models::ns::rigid::block].r[0]; }, \
      [](const mbrt::models::ns::State& s) { return s.rigid[mbrt::models::ns::rigid::belt].v[0]; }, \
      [](const mbrt::models::ns::State& s) { return s.stuck[mbrt::models::ns::friction::contact]; })

}  // namespace

TEST_CASE("stick-slip on a moving belt: the closed-form stick and slip phases") {
  SUBCASE("staggered-pcst") { CHECK_BELT(friction_belt_pcst); }
  SUBCASE("rk4-projected") { CHECK_BELT(friction_belt_rk4p); }
  SUBCASE("baumgarte") { CHECK_BELT(friction_belt_baumgarte); }
  SUBCASE("blajer") { CHECK_BELT(friction_belt_blajer); }
}

TEST_CASE("stress: friction in every joint of a 7-link spatial arm in staggered-pcst") {
  // Configured from tests/models/stress/arm_7.yaml (tests/CMakeLists.txt): joint
  // rates up to 8 rad/s, falling under gravity against 2 N m in every joint,
  // 20 s at 1 ms. K couples all seven joints through the mechanism.
  namespace m = mbrt::models::friction_arm_7_pcst;
  m::State s = m::initial_state();
  static m::Workspace w;
  const double start = m::energy(s).total();
  double energy = start, largest_rise = -1.0;
  int last_slip = 0;
  bool finite = true;
  for (int i = 1; i <= 20000; ++i) {
    REQUIRE(m::step(s, w) == mbrt::StepStatus::ok);
    finite = finite && all_finite(s);
    const double e = m::energy(s).total();
    largest_rise = std::max(largest_rise, e - energy);
    energy = e;
    for (double stuck : s.stuck) last_slip = stuck == 1.0 ? last_slip : i;
  }
  MESSAGE("arm_7 staggered-pcst: largest energy rise in a step " << largest_rise << " J, last slip at step " << last_slip);
  CHECK(finite);
  // The same arm without friction rises by up to 1e-3 J in a step at 1 ms
  // (docs/stability.md); here friction takes out more than the step adds.
  CHECK(largest_rise < 1e-9);
  CHECK(energy < start - 50.0);
  // At rest with every joint stuck, and staying there.
  CHECK(last_slip < 15000);
  const m::State rest = s;
  for (int i = 0; i < 1000; ++i) REQUIRE(m::step(s, w) == mbrt::StepStatus::ok);
  for (std::size_t b = 0; b < s.rigid.size(); ++b) {
    CHECK((s.rigid[b].r - rest.rigid[b].r).norm() < 1e-10);
    CHECK(s.rigid[b].v.norm() < 1e-9);
    CHECK(s.rigid[b].w.norm() < 1e-9);
  }
}

TEST_CASE("the friction step allocates nothing in the absolute-coordinate schemes, stuck or slipping") {
  // The pendulum swings, turns and sticks in 6000 steps.
  CHECK(allocations_in<PendulumPcst>(6000) == 0);
  CHECK(allocations_in<PendulumBaumgarte>(100) == 0);
  CHECK(allocations_in<PendulumBlajer>(100) == 0);
  CHECK(allocations_in<PendulumRk4>(100) == 0);
  // One block held, one sliding, in every step.
  CHECK(allocations_in<InclineMuPcst>(10) == 0);
  CHECK(allocations_in<InclineMuRk4>(10) == 0);
  // A closed loop with redundant rows.
  CHECK(allocations_in<FourBarPcst>(100) == 0);
  CHECK(allocations_in<FourBarRk4>(100) == 0);
}

TEST_CASE("joint friction in absolute coordinates: which schemes take it, and the errors that name the joint") {
  using friction_errors::error_of;
  using friction_errors::pendulum_with;
  using friction_errors::check;
  const std::string constant = pendulum_with(", friction: {torque: 0.2}");
  const std::string load = pendulum_with(", friction: {static: 0.3, kinetic: 0.2, radius: 0.01}");
  const std::string slide = pendulum_with(", friction: {static: 0.3, kinetic: 0.2}", "prismatic");
  for (const char* scheme : {"staggered-pcst", "baumgarte", "blajer", "rk4-projected"}) {
    INFO(scheme);
    const std::string solver = std::string("solver: {scheme: ") + scheme + "}\n";
    CHECK(error_of(constant + solver) == "(no error)");
    CHECK(error_of(load + solver) == "(no error)");
    CHECK(error_of(slide + solver) == "(no error)");
  }
  // staggered-nps and ali3p keep no factor of S = B M^-1 B^T at the step's end.
  for (const char* scheme : {"staggered-nps", "ali3p"}) {
    INFO(scheme);
    check(constant + "solver: {scheme: " + scheme + "}\n", "joints.pin.friction",
          "joint friction needs staggered-pcst, baumgarte, blajer, rk4-projected or a tree scheme");
  }
  // staggered4's middle substep runs backwards in time.
  check(constant + "solver: {scheme: staggered4}\n", "joints.pin.friction", "steps forward in time");
  // A joint a driver moves cannot slip.
  check(constant + "drivers:\n  - {name: motor, type: joint_angle, joint: pin, function: {polynomial: [0, 1]}}\n"
                   "solver: {scheme: staggered-pcst}\n",
        "joints.pin.friction", "a driven joint does not slip");
  check(slide + "drivers:\n  - {name: push, type: joint_distance, joint: pin, function: {polynomial: [0, 0.1]}}\n"
                "solver: {scheme: rk4-projected}\n",
        "joints.pin.friction", "a driven joint does not slip");
}
