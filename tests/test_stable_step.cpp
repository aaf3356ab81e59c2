// The stable-step estimate of gen --report (codegen/plan/stable_step.hpp): the
// energy bound on the fastest rotation against closed forms, the spring
// limit, and the warning a scheme's limit gives before the run.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "model.hpp"
#include "stable_step.hpp"

using mbrt::codegen::estimate_stable_step;
using mbrt::codegen::parse_model;

namespace {

// A uniform 1 kg, 1 m rod pinned at the origin, released at rest horizontally.
const char* kRodPendulum = R"(name: rod
gravity: [0, 0, -9.81]
bodies:
  - {name: rod, mass: 1, inertia: [1.0e-4, 0.08333333333333333, 0.08333333333333333], position: [0.5, 0, 0]}
joints:
  - {name: pin, type: revolute, body1: ground, body2: rod, point: [0, 0, 0], axis: [0, 1, 0]}
solver: {scheme: staggered-pcst, step: 1.0e-3}
)";

}  // namespace

TEST_CASE("the fastest rotation of a rod pendulum released horizontally is its closed-form rate at the bottom") {
  const auto s = estimate_stable_step(parse_model(kRodPendulum, "rod.yaml"));
  // Falls m g L/2 = 4.905 J; 1/2 (m L^2 / 3) w^2 = m g L / 2 gives w = sqrt(3 g / L).
  CHECK(s.energy_bound == doctest::Approx(4.905).epsilon(1e-12));
  CHECK(s.fastest_rotation == doctest::Approx(std::sqrt(3.0 * 9.81)).epsilon(1e-6));
  CHECK(s.fastest_body == "rod");
  CHECK_FALSE(s.exceeded);
}

TEST_CASE("bodies on prismatic joints do not turn, however much energy the scene holds") {
  // A 1e8 kg sled at 0.1 m/s (5e5 J) carrying a 1 kg block on a second joint.
  const auto sleds = [](const std::string& rail) {
    return estimate_stable_step(parse_model(R"(name: sleds
bodies:
  - {name: sled, mass: 1.0e8, inertia: [1.0e8, 1.0e8, 1.0e8], velocity: [0.1, 0, 0]}
  - {name: block, mass: 1, inertia: [0.01, 0.01, 0.01], position: [0, 0, 1], velocity: [0.1, 0, 0]}
joints:
  - {name: guide, type: prismatic, body1: ground, body2: sled, point: [0, 0, 0], axis: [1, 0, 0]}
  - {name: rail, type: )" + rail + R"(, body1: sled, body2: block, point: [0, 0, 1], axis: [1, 0, 0]}
solver: {scheme: rk4-tree, step: 1.0e-3}
)", "sleds.yaml"));
  };
  // On a prismatic rail neither can turn, so no rotation limits the step.
  const auto s = sleds("prismatic");
  CHECK(s.energy_bound == doctest::Approx(0.5 * (1.0e8 + 1.0) * 0.01));
  CHECK(s.fastest_rotation == 0.0);
  CHECK_FALSE(s.exceeded);
  // The same block on a pin instead turns with that energy.
  const auto pinned = sleds("revolute");
  CHECK(pinned.fastest_body == "block");
  CHECK(pinned.exceeded);
}

TEST_CASE("a stiff spring limits the step to 2 / omega and is named") {
  const auto s = estimate_stable_step(parse_model(R"(name: stiff
bodies:
  - {name: bob, mass: 0.01, particle: true, position: [1, 0, 0]}
forces:
  - {type: spring_damper, body1: ground, body2: bob, point1: [0, 0, 0], point2: [1, 0, 0], stiffness: 1.0e5, rest_length: 1}
solver: {scheme: staggered-pcst, step: 1.0e-3}
)",
                                                  "stiff.yaml"));
  CHECK(s.stiffest_frequency == doctest::Approx(std::sqrt(1e5 / 0.01)));
  CHECK(s.stable_step == doctest::Approx(2.0 / std::sqrt(1e7)).scale(0));
  CHECK(s.exceeded);
  CHECK(s.stiffest_element == "spring_damper ground - bob");
  CHECK(mbrt::codegen::stable_step_warning(parse_model(kRodPendulum, "rod.yaml"), estimate_stable_step(parse_model(kRodPendulum, "rod.yaml"))).empty());
}

TEST_CASE("a stiff joint spring limits the step to 2 / sqrt(k / J) about its axis and is named") {
  // A rotor with J = 0.05 kg m^2 about the joint axis z (tilted in the world by
  // its orientation: 90 degrees about x puts body y on world z) and k = 5e6
  // N m/rad, at rest at its rest angle (no energy to release).
  const auto s = estimate_stable_step(parse_model(R"(name: stiff_rotor
bodies:
  - {name: rotor, mass: 1.5, inertia: [0.03, 0.05, 0.04], orientation: [0.7071067811865476, 0.7071067811865476, 0, 0]}
joints:
  - {name: shaft, type: revolute, body1: ground, body2: rotor, point: [0, 0, 0], axis: [0, 0, 1]}
forces:
  - {type: joint_spring, joint: shaft, stiffness: 5.0e6}
solver: {scheme: staggered-pcst, step: 1.0e-3}
)",
                                                  "stiff_rotor.yaml"));
  CHECK(s.stiffest_frequency == doctest::Approx(std::sqrt(5e6 / 0.05)).epsilon(1e-9));
  CHECK(s.stiffest_element == "joint_spring shaft");
  CHECK(s.stable_step == doctest::Approx(2.0 / std::sqrt(1e8)).scale(0));
  CHECK(s.exceeded);
}

TEST_CASE("a joint spring at a modal body's node stiffens its modes in the estimate") {
  // tests/models/modal_node_spring.yaml undamped, its hinge's spring at
  // 5e4 N m/rad: the generated step (mbrt sim, 5 s) runs at 1.6e-4 s and
  // goes non-finite at 1.9e-4 s; without the spring's share the modes'
  // estimate would be 2.05e-4 s.
  const auto model = [](const std::string& spring) {
    return "name: sprung\nbodies:\n  - name: boom\n    flexible: {length: 1.0, elements: 12, modes: 6, EA: 1.0e8, GJ: 500.0, "
           "EI: [1.0e8, 100.0], rho_A: 1.0, rho_J: 0.01}\n  - {name: arm, mass: 0.2, inertia: [1.0e-4, 0.005, 0.005], "
           "position: [1.25, 0, 0]}\njoints:\n  - {name: clamp, type: fixed, body1: ground, body2: boom, point: [0, 0, 0]}\n"
           "  - {name: hinge, type: revolute, body1: boom@tip, body2: arm, axis: [0, 0, 1]}\n" +
           spring + "solver: {scheme: staggered-pcst, step: 1.0e-4}\n";
  };
  const auto free = estimate_stable_step(parse_model(model(""), "free.yaml"));
  const auto sprung =
      estimate_stable_step(parse_model(model("forces:\n  - {type: joint_spring, joint: hinge, stiffness: 5.0e4}\n"), "sprung.yaml"));
  MESSAGE("stable step " << sprung.stable_step << " s with the spring, " << free.stable_step << " s without");
  CHECK(sprung.stiffest_element.rfind("modal body boom", 0) == 0);
  CHECK(sprung.stable_step < 1.9e-4);
  CHECK(sprung.stable_step < 0.8 * free.stable_step);
}

TEST_CASE("a body spinning fast on a pivot is beyond the schemes with explicit constraint forces, and they say so") {
  const std::string spinner = std::string(MBRT_STRESS_MODELS) + "/spinner.yaml";
  mbrt::codegen::Model m = mbrt::codegen::load_model(spinner);
  CHECK_FALSE(estimate_stable_step(m).exceeded);  // staggered-pcst at 1 ms: 0.3 rad per step
  for (const char* scheme : {"staggered-nps", "baumgarte", "blajer"}) {
    m.solver.scheme = *mbrt::scheme_from_name(scheme);
    const auto s = estimate_stable_step(m);
    CHECK(s.exceeded);
    const std::string w = mbrt::codegen::stable_step_warning(m, s);
    CHECK(w.find("body box could turn at") != std::string::npos);
    CHECK(w.find(scheme) != std::string::npos);
  }
}

TEST_CASE("staggered-tree warns of its energy on trees of several links above 1e-4 s, not on one joint") {
  mbrt::codegen::Model arm = mbrt::codegen::load_model(std::string(MBRT_STRESS_MODELS) + "/arm_7.yaml");
  arm.solver.scheme = mbrt::Scheme::staggered_tree;
  arm.solver.step = 1e-3;
  const std::string w = mbrt::codegen::tree_energy_warning(arm);
  CHECK(w.find("arm_7: staggered-tree at step 0.001 s") != std::string::npos);
  CHECK(w.find("not symplectic") != std::string::npos);
  arm.solver.step = 1e-4;
  CHECK(mbrt::codegen::tree_energy_warning(arm).empty());
  arm.solver.step = 1e-3;
  arm.solver.scheme = mbrt::Scheme::staggered_pcst;
  CHECK(mbrt::codegen::tree_energy_warning(arm).empty());
  arm.solver.scheme = mbrt::Scheme::midpoint_tree;
  CHECK(mbrt::codegen::tree_energy_warning(arm).empty());
  // One revolute joint: M is constant and kick-drift-kick is the Stormer-Verlet step.
  mbrt::codegen::Model rod = parse_model(kRodPendulum, "rod.yaml");
  rod.solver.scheme = mbrt::Scheme::staggered_tree;
  CHECK(mbrt::codegen::tree_energy_warning(rod).empty());
}

TEST_CASE("a free ball's spin does not bound the step; a free body that can tumble does") {
  // A 10 g, 1 cm ball at 1000 rad/s on a contact and a 2 kg ball launched at
  // 2 m/s: the scene's energy would turn the small ball at 4580 rad/s, but a
  // free body with equal moments has no gyroscopic torque and moves no joint.
  const std::string balls = R"(name: balls
gravity: [0, 0, -9.81]
bodies:
  - {name: spinner, mass: 0.01, inertia: [4.0e-7, 4.0e-7, 4.0e-7], position: [0, 1, 0.01], angular_velocity: [0, 1000, 0]}
  - {name: slider, mass: 2.0, inertia: [0.008, 0.008, 0.008], position: [0, 0, 0.1], velocity: [2, 0, 0]}
joints:
  - {type: sphere_contact, body: spinner, radius: 0.01, plane_point: [0, 0, 0], plane_normal: [0, 0, 1]}
  - {type: sphere_contact, body: slider, radius: 0.1, plane_point: [0, 0, 0], plane_normal: [0, 0, 1]}
solver: {scheme: staggered-pcst, step: 1.0e-3}
)";
  const auto free = estimate_stable_step(parse_model(balls, "balls.yaml"));
  CHECK(free.fastest_rotation == 0.0);
  CHECK_FALSE(free.exceeded);
  // The same small body with unequal moments tumbles: its rate bounds the step.
  std::string tumbling = balls;
  tumbling.replace(tumbling.find("[4.0e-7, 4.0e-7, 4.0e-7]"), 24, "[4.0e-7, 5.0e-7, 3.0e-7]");
  const auto s = estimate_stable_step(parse_model(tumbling, "balls.yaml"));
  CHECK(s.fastest_body == "spinner");
  CHECK(s.exceeded);
}

TEST_CASE("bodies welded together turn as one: their bound takes the group's inertia about the joint it hangs from") {
  // A light hub on an axle along z at the origin with a plate welded to it at
  // x = 0.2, both turning at 10 rad/s about z. About the axle the group's
  // inertia is hub + plate + m d^2: diag(0.501, 2.901, 3.351); the energy
  // 1/2 3.351 w^2 could turn it at most w sqrt(3.351 / 2.901) about its middle axis.
  const auto s = estimate_stable_step(parse_model(R"(name: hub_plate
bodies:
  - {name: hub, mass: 1, inertia: [0.001, 0.001, 0.001], angular_velocity: [0, 0, 10]}
  - {name: plate, mass: 10, inertia: [0.5, 0.4, 0.85], position: [0.5, 0, 0], velocity: [0, 5, 0], angular_velocity: [0, 0, 10]}
joints:
  - {name: axle, type: revolute, body1: ground, body2: hub, point: [0, 0, 0], axis: [0, 0, 1]}
  - {name: weld, type: fixed, body1: hub, body2: plate, point: [0.2, 0, 0]}
solver: {scheme: staggered-pcst, step: 1.0e-3}
)",
                                                  "hub_plate.yaml"));
  CHECK(s.energy_bound == doctest::Approx(0.5 * 3.351 * 100).epsilon(1e-12));
  const double bound = 10 * std::sqrt(3.351 / 2.901);
  CHECK(s.rotation_bound[0] == doctest::Approx(bound).epsilon(1e-12));
  CHECK(s.rotation_bound[1] == doctest::Approx(bound).epsilon(1e-12));
  CHECK(s.fastest_rotation == doctest::Approx(bound).epsilon(1e-12));
}
