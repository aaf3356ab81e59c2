// Forces, springs and outputs at a modal body's nodes (docs/flexible.md):
// cantilevers under a tip force, alone and held by a tip spring, settle at
// the closed-form static deflections; a free modal body tied to a particle
// by a spring at its tip keeps the pair's energy, momentum and angular
// momentum, summed directly over the beam's mass (modal_momenta.hpp); the
// generator's checks of where such loads act.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "analysis.hpp"
#include "generator_error.hpp"
#include "modal_momenta.hpp"
#include "modal_spring_pair.hpp"
#include "modal_spring_pair_fine.hpp"
#include "modal_tip_loads.hpp"
#include "modal_tip_loads_blajer.hpp"
#include "model.hpp"

namespace {

using mbrt::Vec3;
namespace cg = mbrt::codegen;

// Deflections along y after 15 s: boom_a's tip and middle node, boom_b's tip.
struct Settled {
  double tip_a, middle_a, tip_b, largest_z;
};

template <class State, class Step, class Outputs, class OutputsOf>
Settled settle(State s, Step step, Outputs y, OutputsOf outputs, int tip_a, int middle_a, int tip_b, double h) {
  Settled r{0, 0, 0, 0};
  const int steps = static_cast<int>(std::lround(15.0 / h));
  for (int i = 0; i < steps; ++i) {
    REQUIRE(step(s) == mbrt::StepStatus::ok);
    outputs(s, y);
    r.largest_z = std::max({r.largest_z, std::abs(y[static_cast<size_t>(tip_a + 2)]), std::abs(y[static_cast<size_t>(tip_b + 2)] - 1.0)});
  }
  r.tip_a = y[static_cast<size_t>(tip_a + 1)], r.middle_a = y[static_cast<size_t>(middle_a + 1)], r.tip_b = y[static_cast<size_t>(tip_b + 1)];
  return r;
}


}  // namespace

TEST_CASE("modal cantilevers under a tip force settle at P L^3 / (3 EI), and with a tip spring at P / (3 EI / L^3 + k)") {
  namespace a = mbrt::models::modal_tip_loads;
  namespace b = mbrt::models::modal_tip_loads_blajer;
  const double P = 2.0, L = 1.0, EI = 100.0, k = 300.0;
  const double tip = P * L * L * L / (3 * EI), middle = 5 * P * L * L * L / (48 * EI), held = P / (3 * EI / (L * L * L) + k);
  const Settled pcst = settle(a::initial_state(), [](a::State& s) { return a::step(s); }, a::Outputs{},
                              [](const a::State& s, a::Outputs& y) { a::outputs(s, y); }, a::output::tip_a,
                              a::output::middle_a, a::output::tip_b, a::kStep);
  const Settled blajer = settle(b::initial_state(), [](b::State& s) { return b::step(s); }, b::Outputs{},
                                [](const b::State& s, b::Outputs& y) { b::outputs(s, y); }, b::output::tip_a,
                                b::output::middle_a, b::output::tip_b, b::kStep);
  for (const Settled& r : {pcst, blajer}) {
    MESSAGE("3 modes, 15 s: tip " << r.tip_a << " m (closed form " << tip << "), middle " << r.middle_a << " (" << middle
                                  << "), held tip " << r.tip_b << " (" << held << "), largest out of plane " << r.largest_z);
    // Three modes hold all but about 0.2 % of a tip load's static deflection.
    CHECK(r.tip_a == doctest::Approx(tip).epsilon(0.004).scale(0));
    CHECK(r.middle_a == doctest::Approx(middle).epsilon(0.004).scale(0));
    CHECK(r.tip_b == doctest::Approx(held).epsilon(0.004).scale(0));
    CHECK(r.largest_z < 1e-12);
  }
}

using modal_momenta::Conservation;

// The pair's drift from conservation: the rod's momenta summed over its beam
// (modal_momenta.hpp) and the particle's.
template <class State, class Step, class EnergyOf>
Conservation pair_errors(State s, Step step, EnergyOf energy, double h) {
  const modal_momenta::ModalBeamMass rod({1.5, 2.0e5, 400.0, 150.0, 250.0, 2.0, 0.01, 12}, 4);
  const double weight = 0.4;
  const auto momenta = [&](const State& x) {
    std::array<Vec3, 2> m = rod.momenta(x.rigid[0], x.modal_q[0].head(4), x.modal_p[0].head(4));
    const mbrt::ParticleState& w = x.particle[0];
    m[0] += weight * w.v;
    m[1] += weight * w.r.cross(w.v);
    return m;
  };
  return modal_momenta::conservation_errors(s, step, energy, momenta, h);
}

TEST_CASE("a free modal body tied to a particle by a spring at its tip keeps the pair's energy, momentum and angular momentum") {
  namespace m = mbrt::models::modal_spring_pair;
  namespace f = mbrt::models::modal_spring_pair_fine;
  const Conservation coarse = pair_errors(
      m::initial_state(), [](m::State& s) { return m::step(s); }, [](const m::State& s) { return m::energy(s).total(); },
      m::kStep);
  const Conservation fine = pair_errors(
      f::initial_state(), [](f::State& s) { return f::step(s); }, [](const f::State& s) { return f::energy(s).total(); },
      f::kStep);
  MESSAGE("10 s, relative errors at 1 ms: energy " << coarse.energy << ", momentum " << coarse.momentum
                                                   << ", angular momentum " << coarse.angular_momentum << "; at 0.25 ms: "
                                                   << fine.energy << ", " << fine.momentum << ", " << fine.angular_momentum
                                                   << "; largest modal coordinate " << coarse.largest_q);
  CHECK(coarse.largest_q > 1e-3);  // the spring does bend it
  CHECK(coarse.energy < 6e-3);
  CHECK(coarse.momentum < 6e-3);
  CHECK(coarse.angular_momentum < 1.5e-2);
  // A quarter of the step: 12 to 16 times less error down to 1/16 of the
  // step (the energy's, to 1/4: the geometric stiffness's energy is no
  // potential); a load at the wrong place or with the wrong share in the
  // modes would leave an error the step does not shrink.
  CHECK(fine.energy < coarse.energy / 6);
  CHECK(fine.momentum < coarse.momentum / 6);
  CHECK(fine.angular_momentum < coarse.angular_momentum / 6);
}

TEST_CASE("the generator places a force at a modal body's node, takes a planar joint there, and refuses a point off the node") {
  const std::string beam =
      "bodies:\n  - name: boom\n    flexible: {length: 2.0, elements: 10, modes: 4, EA: 1.0e6, GJ: 500.0, EI: 800.0, "
      "rho_A: 2.0, rho_J: 0.01}\n";
  const std::string pin = "joints:\n  - {name: pin, type: revolute, body1: ground, body2: boom, point: [0, 0, 0], axis: [0, 0, 1]}\n";
  CHECK(generator_error("name: ok\n" + beam + pin + "forces:\n  - {type: force, body: boom@7, vector: [0, 1, 0]}\n") == "");
  CHECK(generator_error("name: ok\n" + beam + pin + "forces:\n  - {type: force, body: boom@tip, point: [2, 0, 0], vector: [0, 1, 0]}\n") ==
        "");
  const std::string off = generator_error("name: off\n" + beam + pin +
                                          "forces:\n  - {type: force, body: boom@tip, point: [1.5, 0, 0], vector: [0, 1, 0]}\n");
  CHECK(off.find("forces[0].point") != std::string::npos);
  CHECK(off.find("node 10 of modal body 'boom', which is at (2.000000, 0.000000, 0.000000") != std::string::npos);
  const std::string spring = generator_error(
      "name: spring\n" + beam + pin +
      "forces:\n  - {type: spring_damper, body1: ground, body2: boom@5, point1: [1, 1, 0], stiffness: 10, rest_length: 1}\n");
  CHECK(spring == "");
  const std::string joint = generator_error("name: node\n" + beam +
                                            "joints:\n  - {name: pin, type: planar, body1: ground, body2: boom@tip, "
                                            "point: [2, 0, 0], axis: [0, 0, 1]}\n");
  CHECK(joint == "");  // a planar joint takes the node too
  CHECK(generator_error("name: far\n" + beam + pin + "forces:\n  - {type: force, body: boom@11, vector: [0, 1, 0]}\n")
            .find("unknown node '11' of modal body 'boom' (root, tip or 0 to 10)") != std::string::npos);
}
