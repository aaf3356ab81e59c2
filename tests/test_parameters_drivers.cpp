// Drivers' coefficients as runtime parameters (docs/parameters.md): the
// coefficients set at run time give the closed-form prescribed motion and
// driving torque and force, at the defaults the same trajectory as the model
// folded, setting and stepping allocate nothing, a coefficient that moves
// f(0) or f'(0) off the initial state is reported, and bad entries name
// themselves.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "allocation_counter.hpp"
#include "analysis.hpp"
#include "driven_pair_folded.hpp"
#include "model.hpp"
#include "parameters.hpp"
#include "tunable_driven_pair.hpp"
#include "tunable_driven_pair_ali3p.hpp"

using namespace mbrt::codegen;

// A generated model of tunable_driven_pair.yaml, for the function templates below.
#define DRIVEN_MODEL(Tag, ns)                                                                             \
  struct Tag {                                                                                            \
    using State = mbrt::models::ns::State;                                                                \
    using Parameters = mbrt::models::ns::Parameters;                                                      \
    static constexpr Parameters kDefaultParameters = mbrt::models::ns::kDefaultParameters;               \
    static int first_row(int block) { return mbrt::models::ns::kConstraintInfo[block].first_row; }        \
    static bool set_parameter(Parameters& p, std::string_view name, double value) {                       \
      return mbrt::models::ns::set_parameter(p, name, value);                                             \
    }                                                                                                     \
    static State initial_state(const Parameters& p) { return mbrt::models::ns::initial_state(p); }        \
    static mbrt::ConstraintViolation violation(const State& s) { return mbrt::models::ns::constraint_violation(s); } \
    static mbrt::StepStatus step(State& s) { return mbrt::models::ns::step(s); }                          \
  }

namespace {

DRIVEN_MODEL(DrivenPcst, tunable_driven_pair);
DRIVEN_MODEL(DrivenAli3p, tunable_driven_pair_ali3p);

constexpr double kPi = std::numbers::pi;
constexpr double kJzz = 0.25;        // the rotor's moment of inertia about the shaft, kg m^2
constexpr double kSliderMass = 3.0;  // kg

// theta(t) = c1 t + c2 t^2 and x(t) = a sin(omega t + phase) + offset, with
// the initial rates that keep the initial state on the drivers.
struct Coefficients {
  double c1, c2;
  double amplitude, omega, phase, offset;
};

// Different rates, accelerations, amplitudes and frequencies; the last moves
// the phase and puts the offset where x(0) = 0.
const Coefficients kCases[] = {{1.0, 0.5, 0.2, 3.0, 0.0, 0.0},
                               {2.0, -0.3, 0.1, 5.0, 0.0, 0.0},
                               {0.0, 1.5, 0.3, 1.5, 0.7, -0.3 * std::sin(0.7)}};

template <class M>
typename M::Parameters parameters(const Coefficients& c) {
  typename M::Parameters p = M::kDefaultParameters;
  REQUIRE(M::set_parameter(p, "spin.function.c1", c.c1));
  REQUIRE(M::set_parameter(p, "spin.function.c2", c.c2));
  REQUIRE(M::set_parameter(p, "rotor.angular_velocity.z", c.c1));
  REQUIRE(M::set_parameter(p, "stroke.function.amplitude", c.amplitude));
  REQUIRE(M::set_parameter(p, "stroke.function.omega", c.omega));
  REQUIRE(M::set_parameter(p, "stroke.function.phase", c.phase));
  REQUIRE(M::set_parameter(p, "stroke.function.offset", c.offset));
  REQUIRE(M::set_parameter(p, "slider.velocity.x", c.amplitude * c.omega * std::cos(c.phase)));
  return p;
}

struct Errors {
  double angle = 0, rate = 0, slide = 0, speed = 0, torque = 0, force = 0;
};

// Steps a model of tunable_driven_pair.yaml for 2 s at the coefficients c and
// returns the largest differences from the closed forms: the rotor's angle
// and rate, the slider's travel and speed, and the drivers' multipliers
// against minus the torque J theta'' = 2 J c2 and force m x''.
template <class M>
Errors run(const Coefficients& c) {
  typename M::State s = M::initial_state(parameters<M>(c));
  const mbrt::ConstraintViolation v = M::violation(s);
  CHECK(v.position < 1e-12);
  CHECK(v.velocity < 1e-12);
  const double x0 = s.rigid[1].r.x();
  Errors e;
  for (int i = 0; i < 2000; ++i) {
    REQUIRE(M::step(s) == mbrt::StepStatus::ok);
    const double t = s.t;
    const double theta = c.c1 * t + c.c2 * t * t;
    const double x = c.amplitude * std::sin(c.omega * t + c.phase) + c.offset;
    const double x_dot = c.amplitude * c.omega * std::cos(c.omega * t + c.phase);
    const double x_ddot = -c.omega * c.omega * (x - c.offset);
    const double angle = 2.0 * std::atan2(s.rigid[0].p[3], s.rigid[0].p[0]);
    e.angle = std::max(e.angle, std::abs(std::remainder(angle - theta, 2.0 * kPi)));
    e.rate = std::max(e.rate, std::abs(s.rigid[0].w.z() - (c.c1 + 2.0 * c.c2 * t)));
    e.slide = std::max(e.slide, std::abs(s.rigid[1].r.x() - x0 - x));
    e.speed = std::max(e.speed, std::abs(s.rigid[1].v.x() - x_dot));
    e.torque = std::max(e.torque, std::abs(s.lambda[M::first_row(2)] + kJzz * 2.0 * c.c2));
    e.force = std::max(e.force, std::abs(s.lambda[M::first_row(3)] + kSliderMass * x_ddot));
  }
  return e;
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

const std::string kDriven = R"(name: d
bodies:
  - {name: rotor, mass: 1.0, inertia: [1, 1, 1], angular_velocity: [0, 0, 1]}
joints:
  - {name: shaft, type: revolute, body1: ground, body2: rotor, point: [0, 0, 0], axis: [0, 0, 1]}
drivers:
  - {name: spin, type: joint_angle, joint: shaft, function: {polynomial: [0, 1, 0.5]}}
)";

}  // namespace

TEST_CASE("drivers' coefficients set at run time: the prescribed motion and driving loads of the values set") {
  for (const Coefficients& c : kCases) {
    INFO("c1 " << c.c1 << ", c2 " << c.c2 << ", amplitude " << c.amplitude << ", omega " << c.omega << ", phase "
               << c.phase);
    const Errors pcst = run<DrivenPcst>(c);
    const Errors ali3p = run<DrivenAli3p>(c);
    for (const Errors& e : {pcst, ali3p}) {
      MESSAGE("angle " << e.angle << " rad, rate " << e.rate << " rad/s, slide " << e.slide << " m, speed " << e.speed
                       << " m/s, torque " << e.torque << " N m, force " << e.force << " N");
      // Both schemes keep the positions on the drivers to round-off; the
      // driving torque is the constant 2 J c2 = -0.15 to 0.75 N m, the force
      // m x'' up to m a omega^2 = 2.0 to 7.5 N.
      CHECK(e.angle < 1e-12);
      CHECK(e.slide < 1e-12);
      CHECK(e.rate < 1e-9);
      CHECK(e.speed < 1e-9);
      CHECK(e.torque < 1e-8);
      CHECK(e.force < 1e-8);
    }
  }
}

TEST_CASE("drivers' coefficients at their defaults: the same trajectory as the model folded") {
  namespace t = mbrt::models::tunable_driven_pair;
  namespace f = mbrt::models::driven_pair_folded;  // the file without its tunable line, --no-specialize=planar
  t::State a = t::initial_state();
  f::State b = f::initial_state();
  for (int i = 0; i < 3000; ++i) {
    REQUIRE(t::step(a) == mbrt::StepStatus::ok);
    REQUIRE(f::step(b) == mbrt::StepStatus::ok);
  }
  for (int k = 0; k < 2; ++k) {
    CHECK((a.rigid[k].r - b.rigid[k].r).cwiseAbs().maxCoeff() < 1e-12);
    CHECK((a.rigid[k].p - b.rigid[k].p).cwiseAbs().maxCoeff() < 1e-12);
    CHECK((a.rigid[k].v - b.rigid[k].v).cwiseAbs().maxCoeff() < 1e-12);
    CHECK((a.rigid[k].w - b.rigid[k].w).cwiseAbs().maxCoeff() < 1e-12);
  }
  CHECK((a.lambda - b.lambda).cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("a coefficient that moves f(0) or f'(0) leaves the initial state off the driver, and says by how much") {
  namespace m = mbrt::models::tunable_driven_pair;
  m::Parameters p = m::kDefaultParameters;
  p.value[m::parameter::spin_function_c0] = 0.2;  // theta(0) = 0.2 rad, the rotor at 0
  CHECK(m::constraint_violation(m::initial_state(p)).position == doctest::Approx(0.2).epsilon(1e-12).scale(0));
  p = m::kDefaultParameters;
  REQUIRE(m::set_parameter(p, "stroke.function.omega", 5.0));  // x'(0) = 1 m/s, the slider at 0.6 m/s
  const mbrt::ConstraintViolation v = m::constraint_violation(m::initial_state(p));
  CHECK(v.position < 1e-12);
  CHECK(v.velocity == doctest::Approx(0.4).epsilon(1e-12));
  REQUIRE(m::set_parameter(p, "slider.velocity.x", 1.0));  // the rate that keeps it
  CHECK(m::constraint_violation(m::initial_state(p)).velocity < 1e-12);
}

TEST_CASE("setting drivers' coefficients and stepping allocate nothing") {
  namespace m = mbrt::models::tunable_driven_pair;
  static m::Workspace w;
  m::State s = m::initial_state();
  AllocationCounter counter;
  REQUIRE(m::set_parameter(s.params, "spin.function.c2", 2.0));
  s = m::initial_state(s.params);
  for (int i = 0; i < 100; ++i) REQUIRE(m::step(s, w) == mbrt::StepStatus::ok);
  REQUIRE(m::set_parameter(s.params, "stroke.function.amplitude", 0.25));  // mid-run
  for (int i = 0; i < 100; ++i) REQUIRE(m::step(s, w) == mbrt::StepStatus::ok);
  CHECK(counter.count() == 0);
}

TEST_CASE("drivers' tunable keys: names, and errors naming file, line and key") {
  Model m = parse_model(kDriven + "tunable: [spin.function]\n", "model.yaml");
  CHECK(tunable_names(m) == std::vector<std::string>{"spin.function.c0", "spin.function.c1", "spin.function.c2"});
  m = parse_model(kDriven + "tunable: [spin.function.c2]\n", "model.yaml");
  CHECK(tunable_names(m) == std::vector<std::string>{"spin.function.c2"});
  const std::string beyond = what_of(kDriven + "tunable:\n  - spin.function.c3\n");
  CHECK(beyond.find("model.yaml:9:5: tunable[0]: 'spin.function.c3' is not a tunable key") == 0);
  CHECK(beyond.find("DRIVER.function") != std::string::npos);
  CHECK(what_of(kDriven + "tunable: [spin.function.omega]\n").find("is not a tunable key") != std::string::npos);
  CHECK(what_of(kDriven + "tunable: [spin, spin.function.c1]\n").find("marked tunable twice") != std::string::npos);
  // The tree schemes take no drivers, tunable or not; a file that names no
  // scheme gets staggered-pcst.
  CHECK(what_of(kDriven + "tunable: [spin.function]\n", mbrt::Scheme::rk4_tree).find("drivers are constraints outside") !=
        std::string::npos);
  CHECK(default_scheme(m) == mbrt::Scheme::staggered_pcst);
  for (const mbrt::Scheme s : {mbrt::Scheme::staggered_pcst, mbrt::Scheme::staggered_nps, mbrt::Scheme::baumgarte,
                               mbrt::Scheme::blajer, mbrt::Scheme::ali3p, mbrt::Scheme::rk4_projected}) {
    CHECK(what_of(kDriven + "tunable: [spin.function]\n", s) == "(no error)");
  }
}
