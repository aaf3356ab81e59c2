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
#include <vector>

#include "allocation_counter.hpp"
#include "analysis.hpp"
#include "model.hpp"
#include "parameters.hpp"
#include "torsion_rotor_spatial.hpp"
#include "tunable_pendulum.hpp"
#include "tunable_rotor.hpp"
#include "tunable_slider.hpp"

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

TEST_CASE("tunable keys: names, and errors naming file, line and key") {
  Model m = parse_model(kPendulum + "tunable: [gravity, bob.mass, arm.angular_velocity.z]\n", "model.yaml");
  CHECK(tunable_names(m) ==
        std::vector<std::string>{"gravity.x", "gravity.y", "gravity.z", "bob.mass", "arm.angular_velocity.z"});
  const std::string unknown = what_of(kPendulum + "tunable:\n  - bob.mass\n  - bob.colour\n");
  CHECK(unknown.find("model.yaml:10:5: tunable[1]: 'bob.colour' is not a tunable key") == 0);
  CHECK(what_of(kPendulum + "tunable: [bob.inertia]\n").find("is not a tunable key") != std::string::npos);  // a particle
  CHECK(what_of(kPendulum + "tunable: [arm.inertia]\n").find("has products") != std::string::npos);
  CHECK(what_of(kPendulum + "tunable: [bob.mass, bob]\n").find("marked tunable twice") != std::string::npos);
  CHECK(what_of(kPendulum + "tunable: [gravity]\n", mbrt::Scheme::rk4_tree).find("scheme rk4-tree folds gravity.x") !=
        std::string::npos);
  CHECK(what_of(kPendulum + "tunable: [bob.mass]\n", mbrt::Scheme::staggered_tree)
            .find("scheme staggered-tree folds bob.mass") != std::string::npos);
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
  // A file that names no scheme gets staggered-pcst, not a tree scheme that would fold them.
  CHECK(default_scheme(m) == mbrt::Scheme::staggered_pcst);
}
