// Runtime parameters (docs/parameters.md): a value set at run time gives the
// closed-form period of the new value, the same trajectory as the model
// generated with that value folded, and neither setting nor stepping
// allocates; bad `tunable:` entries and keys a scheme folds are errors naming
// file, line and key. Masses in staggered-nps, ali3p and rk4-projected:
// test_parameters_mass.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "allocation_counter.hpp"
#include "analysis.hpp"
#include "model.hpp"
#include "parameters.hpp"
#include "torsion_rotor_spatial.hpp"
#include "tunable_pendulum.hpp"
#include "tunable_rotor.hpp"
#include "tunable_slider.hpp"
#include "arm_7_rk4.hpp"
#include "tunable_arm_7.hpp"
#include "tunable_rotor_rk4_tree.hpp"
#include "tunable_tree_pendulum_midpoint.hpp"
#include "tunable_tree_pendulum_rk4.hpp"
#include "tunable_tree_pendulum_staggered.hpp"

using namespace mbrt::codegen;

namespace {

constexpr double kPi = std::numbers::pi;

// The period of a sampled oscillation about c: twice the mean spacing of its
// crossings of c (linear interpolation), over the first n crossings.
template <class State, class Step, class Signal>
double period(State s, Step step, Signal f, double c, int n) {
  std::vector<double> crossings;
  double t0 = s.t, f0 = f(s) - c;
  while (static_cast<int>(crossings.size()) < n && s.t < 100.0) {
    REQUIRE(step(s) == mbrt::StepStatus::ok);
    const double f1 = f(s) - c;
    if ((f0 < 0.0) != (f1 < 0.0)) crossings.push_back(t0 + (s.t - t0) * f0 / (f0 - f1));
    t0 = s.t;
    f0 = f1;
  }
  REQUIRE(static_cast<int>(crossings.size()) == n);
  return 2.0 * (crossings.back() - crossings.front()) / (n - 1);
}

std::string what_of(const std::string& yaml, mbrt::Scheme scheme = mbrt::Scheme::staggered_pcst) {
  try {
    Model m = parse_model(yaml, "model.yaml");
    m.solver.scheme = scheme;
    analyse(m);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "(no error)";
}

const std::string kPendulum = R"(name: p
gravity: [0, -9.81, 0]
bodies:
  - {name: bob, mass: 1.0, particle: true, position: [0, -1, 0]}
  - {name: arm, mass: 1.0, inertia: [1, 2, 3, 0.1, 0, 0]}
joints:
  - {name: bar, type: distance, body1: ground, body2: bob, point1: [0, 0, 0], point2: [0, -1, 0]}
)";

const std::string kTree = R"(name: t
gravity: [0, -9.81, 0]
bodies:
  - {name: arm, mass: 1.0, inertia: [1, 2, 3], position: [0, -1, 0]}
joints:
  - {name: pin, type: revolute, body1: ground, body2: arm, point: [0, 0, 0], axis: [0, 0, 1]}
)";

// The tree pendulum (tests/models/tunable_tree_pendulum.yaml) in one scheme:
// the small-swing period of the values set, the potential and kinetic
// energy of a set joint coordinate and rate against closed forms, and the
// sign of a joint whose body 1 is the tree's child.
template <class Step, class Start, class Energy, class State>
void check_tree_pendulum(Step step, Start start, Energy energy, State s0, double tolerance) {
  constexpr double d = 0.5;
  const auto x_a = [](const State& s) { return s.rigid[0].r.x(); };
  for (const auto& [mass, jyy, g] : {std::tuple{3.0, 0.1, 9.81}, std::tuple{0.5, 0.02, 1.62}}) {
    auto p = s0.params;
    p.value[0] = 0.0;
    p.value[2] = -g;  // gravity.z
    p.value[3] = mass;  // bar_a.mass
    p.value[5] = jyy;   // bar_a.inertia.yy
    p.value[7] = 0.01;  // pin_a.coordinate: a swing of 0.01 rad lengthens the period by 6e-6
    const State s = start(p);
    const double expected = 2.0 * kPi * std::sqrt((jyy + mass * d * d) / (mass * g * d));
    CHECK(period(s, step, x_a, 0.0, 5) == doctest::Approx(expected).epsilon(tolerance));
  }
  // A turn theta of pin_a about +y swings bar_a's centre to x = -d sin(theta);
  // pin_b's body 1 is its bar, so the bar turns by -theta: x = 1 + d sin(theta).
  auto p = s0.params;
  const double theta = 0.7, rate = 1.3, m = 2.0, jyy = 0.04, g = 9.81;
  p.value[7] = theta;   // pin_a.coordinate
  p.value[9] = theta;   // pin_b.coordinate
  const State s = start(p);
  CHECK(s.rigid[0].r.x() == doctest::Approx(-d * std::sin(theta)).epsilon(1e-14).scale(0));
  CHECK(s.rigid[1].r.x() == doctest::Approx(1.0 + d * std::sin(theta)).epsilon(1e-14));
  const double lift = 2.0 * m * g * d * (1.0 - std::cos(theta));  // both bars, from hanging
  CHECK(energy(s).potential - energy(s0).potential == doctest::Approx(lift).epsilon(1e-12));
  // A rate turns the bar about the pin: kinetic energy (J + m d^2) rate^2 / 2.
  p.value[8] = rate;   // pin_a.rate
  p.value[10] = rate;  // pin_b.rate
  const State moving = start(p);
  CHECK(energy(moving).kinetic == doctest::Approx((jyy + m * d * d) * rate * rate).epsilon(1e-12));
  CHECK(moving.rigid[0].w.y() == doctest::Approx(rate).epsilon(1e-14));
  CHECK(moving.rigid[1].w.y() == doctest::Approx(-rate).epsilon(1e-14));
}

}  // namespace

TEST_CASE("the pendulum's period follows sqrt(L / g) and not the mass, set at run time") {
  namespace m = mbrt::models::tunable_pendulum;
  const auto x = [](const m::State& s) { return s.particle[m::particle::bob].r.x(); };
  const auto step = [](m::State& s) { return m::step(s); };
  for (const double g : {9.81, 1.62, 24.8}) {
    m::Parameters p = m::kDefaultParameters;
    REQUIRE(m::set_parameter(p, "gravity.y", -g));
    REQUIRE(m::set_parameter(p, "bob.mass", 3.0));
    // The amplitude 0.05 / sqrt(g L) rad lengthens the period by theta0^2 / 16 < 1e-4.
    CHECK(period(m::initial_state(p), step, x, 0.0, 5) == doctest::Approx(2.0 * kPi * std::sqrt(1.0 / g)).epsilon(5e-4));
  }
  m::Parameters p = m::kDefaultParameters;
  CHECK_FALSE(m::set_parameter(p, "bob.colour", 1.0));
  p.value[m::parameter::bob_velocity_x] = 0.02;  // by index
  CHECK(m::initial_state(p).particle[m::particle::bob].v.x() == 0.02);
  // Moving the bob off its bar is reported, not hidden.
  p.value[m::parameter::bob_position_x] = 0.5;
  CHECK(m::constraint_violation(m::initial_state(p)).position > 0.1);
}

TEST_CASE("a tunable inertia and joint spring give the rotor the period 2 pi sqrt(Jzz / k) of the values set") {
  namespace m = mbrt::models::tunable_rotor;
  const auto angle = [](const m::State& s) { return 2.0 * std::atan2(s.rigid[0].p[3], s.rigid[0].p[0]); };
  const auto step = [](m::State& s) { return m::step(s); };
  for (const auto& [jzz, k] : {std::pair{0.05, 2.0}, std::pair{0.2, 2.0}, std::pair{0.05, 8.0}}) {
    m::Parameters p = m::kDefaultParameters;
    REQUIRE(m::set_parameter(p, "rotor.inertia.zz", jzz));
    REQUIRE(m::set_parameter(p, "shaft.spring.stiffness", k));
    CHECK(period(m::initial_state(p), step, angle, 0.1, 5) == doctest::Approx(2.0 * kPi * std::sqrt(jzz / k)).epsilon(1e-3));
  }
}

TEST_CASE("a tunable mass and spring_damper give the slider the period 2 pi sqrt(m / k) of the values set") {
  namespace m = mbrt::models::tunable_slider;
  const auto x = [](const m::State& s) { return s.rigid[0].r.x(); };
  const auto step = [](m::State& s) { return m::step(s); };
  for (const auto& [mass, k] : {std::pair{1.0, 20.0}, std::pair{4.5, 20.0}, std::pair{1.0, 80.0}}) {
    m::State s = m::initial_state();
    REQUIRE(m::set_parameter(s.params, "block.mass", mass));  // between runs, on the state itself
    REQUIRE(m::set_parameter(s.params, "forces.0.stiffness", k));
    s = m::initial_state(s.params);
    CHECK(period(s, step, x, 1.0, 5) == doctest::Approx(2.0 * kPi * std::sqrt(mass / k)).epsilon(1e-3));
  }
}

TEST_CASE("tunable at the folded values: the same trajectory as the folded model to round-off") {
  namespace t = mbrt::models::tunable_rotor;
  namespace f = mbrt::models::torsion_rotor_spatial;  // torsion_rotor.yaml, --no-specialize=planar
  t::State a = t::initial_state();
  f::State b = f::initial_state();
  for (int i = 0; i < 2000; ++i) {
    REQUIRE(t::step(a) == mbrt::StepStatus::ok);
    REQUIRE(f::step(b) == mbrt::StepStatus::ok);
  }
  CHECK((a.rigid[0].p - b.rigid[0].p).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((a.rigid[0].w - b.rigid[0].w).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(std::abs(t::energy(a).total() - f::energy(b).total()) < 1e-12);
}

TEST_CASE("the tree schemes read gravity, mass, inertia and joint coordinates and rates at run time") {
  namespace r = mbrt::models::tunable_tree_pendulum_rk4;
  namespace m = mbrt::models::tunable_tree_pendulum_midpoint;
  namespace k = mbrt::models::tunable_tree_pendulum_staggered;
  // The parameters' order, which check_tree_pendulum indexes by.
  const std::vector<std::string> names = {"gravity.x", "gravity.y", "gravity.z", "bar_a.mass", "bar_a.inertia.xx",
                                          "bar_a.inertia.yy", "bar_a.inertia.zz", "pin_a.coordinate", "pin_a.rate",
                                          "pin_b.coordinate", "pin_b.rate"};
  for (size_t i = 0; i < names.size(); ++i) CHECK(r::kParameterInfo[i].name == names[i]);
  // rk4-tree is exact to 1e-12 in the period here; the second-order schemes'
  // period errors are (omega h)^2 / 24 and below, 2e-6 at omega = 7 rad/s.
  SUBCASE("rk4-tree") {
    check_tree_pendulum([](r::State& s) { return r::step(s); }, [](const r::Parameters& p) { return r::initial_state(p); },
                        [](const r::State& s) { return r::energy(s); }, r::initial_state(), 2e-5);
  }
  SUBCASE("midpoint-tree") {
    check_tree_pendulum([](m::State& s) { return m::step(s); }, [](const m::Parameters& p) { return m::initial_state(p); },
                        [](const m::State& s) { return m::energy(s); }, m::initial_state(), 2e-5);
  }
  SUBCASE("staggered-tree") {
    check_tree_pendulum([](k::State& s) { return k::step(s); }, [](const k::Parameters& p) { return k::initial_state(p); },
                        [](const k::State& s) { return k::energy(s); }, k::initial_state(), 2e-5);
  }
}

TEST_CASE("rk4-tree: a tunable inertia and joint spring give the rotor 2 pi sqrt(Jzz / k)") {
  namespace m = mbrt::models::tunable_rotor_rk4_tree;
  const auto angle = [](const m::State& s) { return s.q[0]; };
  const auto step = [](m::State& s) { return m::step(s); };
  for (const auto& [jzz, k] : {std::pair{0.05, 2.0}, std::pair{0.2, 2.0}, std::pair{0.05, 8.0}}) {
    m::Parameters p = m::kDefaultParameters;
    REQUIRE(m::set_parameter(p, "rotor.inertia.zz", jzz));
    REQUIRE(m::set_parameter(p, "shaft.spring.stiffness", k));
    CHECK(period(m::initial_state(p), step, angle, 0.1, 5) == doctest::Approx(2.0 * kPi * std::sqrt(jzz / k)).epsilon(1e-5));
  }
}

TEST_CASE("rk4-tree, arm_7 tunable at the folded values: the folded arm's trajectory to round-off") {
  namespace t = mbrt::models::tunable_arm_7;
  namespace f = mbrt::models::arm_7_rk4;
  t::State a = t::initial_state();
  f::State b = f::initial_state();
  CHECK(a.q == b.q);
  CHECK(a.qd == b.qd);
  for (int i = 0; i < 1000; ++i) {
    REQUIRE(t::step(a) == mbrt::StepStatus::ok);
    REQUIRE(f::step(b) == mbrt::StepStatus::ok);
  }
  for (size_t i = 0; i < a.q.size(); ++i) CHECK(std::abs(a.q[i] - b.q[i]) < 1e-11);
  CHECK(std::abs(t::energy(a).total() - f::energy(b).total()) < 1e-10);
  // A heavier tool swings the arm otherwise: the parameters reach the recursion.
  t::Parameters p = t::kDefaultParameters;
  REQUIRE(t::set_parameter(p, "link_6.mass", 3.0));
  t::State c = t::initial_state(p);
  for (int i = 0; i < 1000; ++i) REQUIRE(t::step(c) == mbrt::StepStatus::ok);
  CHECK(std::abs(c.q[1] - b.q[1]) > 1e-3);
}

TEST_CASE("setting parameters and stepping allocate nothing") {
  namespace m = mbrt::models::tunable_slider;
  static m::Workspace w;
  m::State s = m::initial_state();
  AllocationCounter counter;
  REQUIRE(m::set_parameter(s.params, "block.mass", 2.0));
  s = m::initial_state(s.params);
  for (int i = 0; i < 100; ++i) REQUIRE(m::step(s, w) == mbrt::StepStatus::ok);
  REQUIRE(m::set_parameter(s.params, "forces.0.damping", 0.5));  // mid-run
  for (int i = 0; i < 100; ++i) REQUIRE(m::step(s, w) == mbrt::StepStatus::ok);
  CHECK(counter.count() == 0);
}

TEST_CASE("a tree scheme's parameters: setting and stepping allocate nothing") {
  namespace m = mbrt::models::tunable_arm_7;
  static m::Workspace w;
  m::State s = m::initial_state();
  AllocationCounter counter;
  REQUIRE(m::set_parameter(s.params, "link_6.inertia.zz", 1e-3));
  REQUIRE(m::set_parameter(s.params, "joint_2.coordinate", 0.4));
  s = m::initial_state(s.params);
  for (int i = 0; i < 100; ++i) REQUIRE(m::step(s, w) == mbrt::StepStatus::ok);
  REQUIRE(m::set_parameter(s.params, "gravity.z", -1.62));  // mid-run
  for (int i = 0; i < 100; ++i) REQUIRE(m::step(s, w) == mbrt::StepStatus::ok);
  CHECK(counter.count() == 0);
}

TEST_CASE("tunable keys: names, and errors naming file, line and key") {
  Model m = parse_model(kPendulum + "tunable: [gravity, bob.mass, arm.angular_velocity.z]\n", "model.yaml");
  CHECK(tunable_names(m) ==
        std::vector<std::string>{"gravity.x", "gravity.y", "gravity.z", "bob.mass", "arm.angular_velocity.z"});
  const std::string unknown = what_of(kPendulum + "tunable:\n  - bob.mass\n  - bob.colour\n");
  CHECK(unknown.find("model.yaml:10:5: tunable[1]: 'bob.colour' is not a tunable key") == 0);
  CHECK(what_of(kPendulum + "tunable: [bob.inertia]\n").find("is not a tunable key") != std::string::npos);  // a particle
  CHECK(what_of(kPendulum + "tunable: [arm.inertia]\n").find("has products") != std::string::npos);
  CHECK(what_of(kPendulum + "tunable: [bob.mass, bob]\n").find("marked tunable twice") != std::string::npos);
  for (const mbrt::Scheme tree : {mbrt::Scheme::rk4_tree, mbrt::Scheme::midpoint_tree, mbrt::Scheme::staggered_tree}) {
    CHECK(what_of(kTree + "tunable: [gravity, arm.mass, arm.inertia, pin]\n", tree) == "(no error)");
    CHECK(what_of(kTree + "tunable: [arm.position.x]\n", tree).find("mark JOINT.coordinate and JOINT.rate instead") !=
          std::string::npos);
  }
  CHECK(what_of(kTree + "tunable: [pin.rate]\n").find(
            "model.yaml:7:11: tunable: 'pin.rate': scheme staggered-pcst cannot take pin.rate at run time; joint "
            "coordinates are the initial state of the tree schemes") == 0);
  // Every scheme in absolute coordinates reads masses from the parameters (test_parameters_mass.cpp).
  for (const mbrt::Scheme scheme : {mbrt::Scheme::staggered_nps, mbrt::Scheme::ali3p, mbrt::Scheme::rk4_projected}) {
    CHECK(what_of(kPendulum + "tunable: [bob.mass]\n", scheme) == "(no error)");
  }
  CHECK(what_of(kPendulum + "tunable: [gravity]\n", mbrt::Scheme::ali3p) == "(no error)");
  CHECK(what_of(kPendulum + "tunable: [bob.mass]\n", mbrt::Scheme::blajer) == "(no error)");
  try {
    load_model(MBRT_TEST_MODELS "/bad/unknown_tunable.yaml");
    FAIL("unknown_tunable.yaml parsed");
  } catch (const ModelError& e) {
    CHECK(std::string(e.what()).find("unknown_tunable.yaml:9:5: tunable[0]: 'bob.colour'") != std::string::npos);
  }
  // A file that names no scheme: a tunable body state needs staggered-pcst,
  // other keys leave a tree in rk4-tree.
  CHECK(default_scheme(m) == mbrt::Scheme::staggered_pcst);
  CHECK(default_scheme(parse_model(kTree + "tunable: [arm.mass, pin.coordinate]\n", "model.yaml")) ==
        mbrt::Scheme::rk4_tree);
  CHECK(default_scheme(parse_model(kTree + "tunable: [arm.velocity]\n", "model.yaml")) == mbrt::Scheme::staggered_pcst);
}
