// Model file parsing: a complete good model maps into the structs, and every
// kind of bad file is rejected with a ModelError naming file, line, key and
// what was expected.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "analysis.hpp"
#include "model.hpp"

using namespace mbrt::codegen;

namespace {

bool contains(const std::string& text, const std::string& phrase) {
  return text.find(phrase) != std::string::npos;
}

// The ModelError a model text produces; thrown == false if it parsed (or
// threw something else, recorded in what).
struct Failure {
  bool thrown = false;
  std::string what;
  std::string key;
  int line = 0;
};

Failure failure_of(const std::string& yaml) {
  Failure f;
  try {
    parse_model(yaml, "model.yaml");
    f.what = "(no exception)";
  } catch (const ModelError& e) {
    f = {true, e.what(), e.key(), e.where().line};
  } catch (const std::exception& e) {
    f.what = std::string("wrong exception type: ") + e.what();
  }
  return f;
}

}  // namespace

// The model must be rejected with a ModelError whose what() holds the file
// and 1-based line, the key path and a phrase of the expected-what.
#define CHECK_MODEL_ERROR(yaml, expected_key, expected_line, phrase)                    \
  do {                                                                                  \
    const Failure f_ = failure_of(yaml);                                                \
    INFO("what(): " << f_.what);                                                        \
    REQUIRE(f_.thrown);                                                                 \
    CHECK(f_.key == (expected_key));                                                    \
    CHECK(f_.line == (expected_line));                                                  \
    CHECK(contains(f_.what, "model.yaml:" + std::to_string(expected_line) + ":"));      \
    CHECK(contains(f_.what, std::string(expected_key)));                                \
    CHECK(contains(f_.what, phrase));                                                   \
  } while (false)

// ---- good models ------------------------------------------------------------

const char* const kFullModel = R"(name: four_bar
gravity: [0, -9.81, 0]
bodies:
  - name: crank
    mass: 2.0
    inertia: [0.1, 0.2, 0.3]
    position: [0, 0.5, 0]
    velocity: [0.5, 0, 0]
    angular_velocity: [0, 0, -1]
  - name: plate
    mass: 3
    particle: false
    inertia: [2, 3, 4, 0.1, 0.2, 0.3]
    orientation: [0, 1, 0, 0]
  - name: bob
    mass: 1.5
    particle: true
    position: [-1, 0, 0]
    velocity: [0, 1, 0]
  - name: free_body2
    mass: 1
    inertia: [1, 1, 1]
joints:
  - {name: pin_a, type: revolute, body1: ground, body2: crank, point: [0, 0, 0], axis: [0, 0, 2]}
  - {name: ball, type: spherical, body1: crank, body2: plate, point: [1, 2, 3]}
  - name: cardan
    type: universal
    body1: crank
    body2: plate
    point: [0, 1, 0]
    axis1: [3, 0, 0]
    axis2: [0, 0, -2]
  - {name: sleeve, type: cylindrical, body1: ground, body2: plate, point: [0, 0, 1], axis: [1, 1, 0]}
  - {name: rail, type: prismatic, body1: plate, body2: ground, point: [0, 0, 0], axis: [0, 3, 4]}
  - {name: weld, type: fixed, body1: ground, body2: plate, point: [5, 6, 7]}
  - {name: rod, type: distance, body1: crank, body2: bob, point1: [0, 1, 0], point2: [-1, 0, 0]}
  - {name: rope, type: distance, body1: ground, body2: bob, point1: [0, 0, 0], point2: [-1, 0, 0], length: 2.5}
forces:
  - {type: spring_damper, body1: ground, body2: bob, point1: [0, 0, 0], point2: [0, 0, 1], stiffness: 4530, damping: 12, rest_length: 0.07785}
  - {type: spring_damper, body1: crank, body2: plate, point1: [1, 0, 0], point2: [2, 0, 0], stiffness: 0, rest_length: 0}
  - {type: torque, body1: ground, body2: crank, axis: [0, 0, 5], value: 0.033}
  - {type: force, body: crank, point: [1, 1, 1], vector: [1, 0, 0]}
  - {type: force, body: bob, vector: [0, -2, 0]}
solver: {scheme: ali3p, step: 2.0e-3, euler_updates: 3, penalty: 1.0e-8, stabilization: 50,
         baumgarte_alpha: 7, baumgarte_beta: 8, corrections: 2}
)";

TEST_CASE("a model using every key, body, joint and force type parses into the structs") {
  const Model m = parse_model(kFullModel, "model.yaml");
  CHECK(m.name == "four_bar");
  CHECK(m.file == "model.yaml");
  REQUIRE(m.gravity.has_value());
  CHECK(m.gravity->isApprox(Eigen::Vector3d(0, -9.81, 0)));

  REQUIRE(m.bodies.size() == 4);
  const Body& crank = m.bodies[0];
  CHECK(crank.name == "crank");
  CHECK(crank.where.file == "model.yaml");
  CHECK(crank.where.line == 4);
  CHECK(crank.mass == 2.0);
  CHECK_FALSE(crank.particle);
  CHECK(crank.inertia == Eigen::Vector3d(0.1, 0.2, 0.3).asDiagonal().toDenseMatrix());
  CHECK(crank.position == Eigen::Vector3d(0, 0.5, 0));
  CHECK(crank.orientation == Eigen::Vector4d(1, 0, 0, 0));  // default identity
  CHECK(crank.velocity == Eigen::Vector3d(0.5, 0, 0));
  CHECK(crank.angular_velocity == Eigen::Vector3d(0, 0, -1));

  const Body& plate = m.bodies[1];
  CHECK(plate.position == Eigen::Vector3d::Zero());  // default
  CHECK(plate.orientation == Eigen::Vector4d(0, 1, 0, 0));
  // Products of inertia are the matrix entries themselves, symmetric.
  Eigen::Matrix3d j;
  j << 2, 0.1, 0.2,
       0.1, 3, 0.3,
       0.2, 0.3, 4;
  CHECK(plate.inertia == j);

  const Body& bob = m.bodies[2];
  CHECK(bob.particle);
  CHECK(bob.mass == 1.5);
  CHECK(bob.inertia == Eigen::Matrix3d::Zero());
  CHECK(bob.orientation == Eigen::Vector4d(1, 0, 0, 0));
  CHECK(bob.angular_velocity == Eigen::Vector3d::Zero());
  CHECK(bob.position == Eigen::Vector3d(-1, 0, 0));
  CHECK(bob.velocity == Eigen::Vector3d(0, 1, 0));
  CHECK(m.bodies[3].name == "free_body2");

  REQUIRE(m.joints.size() == 8);
  const Joint& pin = m.joints[0];
  CHECK(pin.name == "pin_a");
  CHECK(pin.type == JointType::revolute);
  CHECK(pin.body1 == kGround);
  CHECK(pin.body2 == 0);
  CHECK(pin.axis == Eigen::Vector3d(0, 0, 1));  // normalized
  CHECK(pin.where.line == 24);
  CHECK(m.joints[1].type == JointType::spherical);
  CHECK(m.joints[1].body1 == 0);
  CHECK(m.joints[1].body2 == 1);
  CHECK(m.joints[1].point == Eigen::Vector3d(1, 2, 3));
  const Joint& cardan = m.joints[2];
  CHECK(cardan.type == JointType::universal);
  CHECK(cardan.point == Eigen::Vector3d(0, 1, 0));
  CHECK(cardan.axis1 == Eigen::Vector3d(1, 0, 0));
  CHECK(cardan.axis2 == Eigen::Vector3d(0, 0, -1));
  CHECK(m.joints[3].type == JointType::cylindrical);
  CHECK(m.joints[3].axis.isApprox(Eigen::Vector3d(1, 1, 0) / std::sqrt(2.0)));
  CHECK(m.joints[3].point == Eigen::Vector3d(0, 0, 1));
  CHECK(m.joints[4].type == JointType::prismatic);
  CHECK(m.joints[4].body1 == 1);
  CHECK(m.joints[4].body2 == kGround);
  CHECK(m.joints[4].axis.isApprox(Eigen::Vector3d(0, 0.6, 0.8)));
  CHECK(m.joints[5].type == JointType::fixed);
  CHECK(m.joints[5].point == Eigen::Vector3d(5, 6, 7));
  const Joint& rod = m.joints[6];
  CHECK(rod.type == JointType::distance);
  CHECK(rod.point1 == Eigen::Vector3d(0, 1, 0));
  CHECK(rod.point2 == Eigen::Vector3d(-1, 0, 0));
  CHECK(rod.length == doctest::Approx(std::sqrt(2.0)));  // default |point2 - point1|
  CHECK(m.joints[7].length == 2.5);

  REQUIRE(m.forces.size() == 5);
  const Force& spring = m.forces[0];
  CHECK(spring.type == ForceType::spring_damper);
  CHECK(spring.body1 == kGround);
  CHECK(spring.body2 == 2);
  CHECK(spring.point2 == Eigen::Vector3d(0, 0, 1));
  CHECK(spring.stiffness == 4530);
  CHECK(spring.damping == 12);
  CHECK(spring.rest_length == 0.07785);
  CHECK(m.forces[1].damping == 0);  // default
  CHECK(m.forces[1].stiffness == 0);
  const Force& torque = m.forces[2];
  CHECK(torque.type == ForceType::torque);
  CHECK(torque.body2 == 0);
  CHECK(torque.axis == Eigen::Vector3d(0, 0, 1));
  CHECK(torque.value == 0.033);
  CHECK(m.forces[3].type == ForceType::force);
  CHECK(m.forces[3].body == 0);
  CHECK(m.forces[3].point == Eigen::Vector3d(1, 1, 1));
  CHECK(m.forces[3].vector == Eigen::Vector3d(1, 0, 0));
  CHECK(m.forces[4].body == 2);
  CHECK(m.forces[4].point == Eigen::Vector3d(-1, 0, 0));  // default: the body's position
  CHECK(m.forces[4].where.line == 43);

  CHECK(m.solver.scheme == mbrt::Scheme::ali3p);
  CHECK(m.solver.step == 2.0e-3);
  CHECK(m.solver.euler_updates == 3);
  CHECK(m.solver.penalty == 1.0e-8);
  CHECK(m.solver.stabilization == 50);
  CHECK(m.solver.baumgarte_alpha == 7);
  CHECK(m.solver.baumgarte_beta == 8);
  CHECK(m.solver.corrections == 2);
}

TEST_CASE("a minimal model keeps the defaults, and a free-floating body needs no joints") {
  const Model m = parse_model(R"(name: tumbler
bodies:
  - {name: brick, mass: 1, inertia: [1, 2, 3], angular_velocity: [0.1, 5, 0]}
joints:
forces: []
)",
                              "model.yaml");
  CHECK_FALSE(m.gravity.has_value());
  CHECK(m.joints.empty());
  CHECK(m.forces.empty());
  const SolverSettings defaults;
  CHECK(m.solver.scheme == defaults.scheme);
  CHECK(m.solver.step == defaults.step);
  CHECK(m.solver.euler_updates == defaults.euler_updates);
  CHECK(m.solver.penalty == defaults.penalty);
  CHECK(m.solver.stabilization == defaults.stabilization);
  CHECK(m.solver.baumgarte_alpha == defaults.baumgarte_alpha);
  CHECK(m.solver.corrections == defaults.corrections);
  CHECK(m.bodies[0].angular_velocity == Eigen::Vector3d(0.1, 5, 0));
}

TEST_CASE("Euler parameters within 1e-6 of unit norm are accepted and renormalized") {
  const Model m = parse_model(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1], orientation: [0.6, 0.8000004, 0, 0]}
)",
                              "model.yaml");
  CHECK(m.bodies[0].orientation.norm() == doctest::Approx(1.0).epsilon(1e-15));
}

TEST_CASE("load_model reads a file and records its path") {
  const std::string path =
      (std::filesystem::temp_directory_path() / "mbrt_test_model_parser.yaml").string();
  {
    std::ofstream out(path);
    out << "name: m\nbodies:\n  - {name: a, mass: 1, particle: true}\n";
  }
  const Model m = load_model(path);
  std::remove(path.c_str());
  CHECK(m.file == path);
  CHECK(m.bodies.size() == 1);
}

// ---- files that cannot be read ---------------------------------------------

TEST_CASE("a missing model file is rejected naming the path") {
  const std::string path = "no/such/dir/missing_model.yaml";
  try {
    load_model(path);
    FAIL("expected ModelError");
  } catch (const ModelError& e) {
    CHECK(e.where().file == path);
    CHECK(contains(e.what(), "cannot open the model file '" + path + "'"));
    CHECK(contains(e.what(), "No such file"));
  }
}

TEST_CASE("an empty file is rejected") {
  CHECK_MODEL_ERROR("", "", 1, "the model file is empty");
  CHECK_MODEL_ERROR("# only a comment\n\n", "", 1, "the model file is empty");
}

TEST_CASE("a top level that is not a map is rejected") {
  CHECK_MODEL_ERROR("- name: m\n- bodies: []\n", "", 1, "expected a map with keys name, gravity");
  CHECK_MODEL_ERROR("just words\n", "", 1, "got 'just words'");
}

TEST_CASE("malformed YAML is reported with its line, not as a raw yaml-cpp exception") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true
gravity: [0, 0, 0]
)",
                    "", 4, "invalid YAML");
  CHECK_MODEL_ERROR("name: m\nbodies: [1, 2\n", "", 3, "invalid YAML");
}

// ---- unknown and repeated keys ---------------------------------------------

TEST_CASE("an unknown top-level key is rejected with its line") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
gravty: [0, 0, -9.81]
)",
                    "gravty", 4,
                    "unknown key 'gravty' (expected one of: name, gravity, bodies, joints, forces, drivers, inputs, outputs, solver, tunable)");
}

TEST_CASE("an unknown key in a body is rejected with its line") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - name: crank
    mass: 1
    inertia: [1, 1, 1]
  - name: bob
    masss: 1
    particle: true
)",
                    "bodies[1].masss", 7,
                    "unknown key 'masss' (expected one of: name, mass, particle, inertia, position, "
                    "orientation, velocity, angular_velocity, flexible)");
}

TEST_CASE("an unknown key in a joint is rejected with its line") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
joints:
  - name: j
    type: spherical
    body1: ground
    body2: a
    piont: [0, 0, 0]
)",
                    "joints[0].piont", 9, "unknown key 'piont' (expected one of: name, type");
}

TEST_CASE("a key belonging to another joint type is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
joints:
  - name: j
    type: spherical
    body1: ground
    body2: a
    point: [0, 0, 0]
    axis: [0, 0, 1]
)",
                    "joints[0].axis", 10,
                    "'axis' does not apply to a spherical joint (it takes: name, type, body1, body2, point)");
}

TEST_CASE("an unknown key in a force is rejected with its line") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
forces:
  - {type: force, body: a, vector: [1, 0, 0]}
  - {type: force, body: a, vektor: [1, 0, 0]}
)",
                    "forces[1].vektor", 6, "unknown key 'vektor'");
}

TEST_CASE("a key belonging to another force type is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
forces:
  - {type: torque, body1: ground, body2: a, axis: [0, 0, 1], value: 1, point: [0, 0, 0]}
)",
                    "forces[0].point", 5, "'point' does not apply to a torque force");
}

TEST_CASE("an unknown key in the solver settings is rejected with its line") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
solver:
  scheme: blajer
  stepsize: 0.001
)",
                    "solver.stepsize", 6,
                    "unknown key 'stepsize' (expected one of: scheme, step, euler_updates, penalty, stabilization, baumgarte_alpha, baumgarte_beta, corrections, ali3p, parallel_parts, parallel_min_rows, parallel_interface, pcg_iterations, pcg_preconditioner, body_states)");
}

TEST_CASE("a key given twice in one map is rejected naming the first") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - name: a
    mass: 1
    particle: true
    mass: 2
)",
                    "bodies[0].mass", 6, "duplicate key 'mass' (first given at line 4)");
}

// ---- missing keys ----------------------------------------------------------

TEST_CASE("a missing required key is reported at the map that lacks it") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
  - name: b
    inertia: [1, 1, 1]
)",
                    "bodies[1].mass", 4, "missing required key 'mass'");
  CHECK_MODEL_ERROR(R"(gravity: [0, 0, -1]
name: m
)",
                    "bodies", 1, "missing required key 'bodies'");
  CHECK_MODEL_ERROR(R"(bodies:
  - {name: a, mass: 1, particle: true}
)",
                    "name", 1, "missing required key 'name'");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
forces:
  - {type: spring_damper, body1: ground, body2: a, point1: [0, 0, 0], point2: [0, 0, 1], stiffness: 1}
)",
                    "forces[0].rest_length", 5, "missing required key 'rest_length'");
}

TEST_CASE("a rigid body without inertia is rejected, suggesting particle: true") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - name: a
    mass: 1
)",
                    "bodies[0].inertia", 3, "set particle: true for a point mass");
}

TEST_CASE("a non-distance joint without a point is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1]}
joints:
  - name: j
    type: revolute
    body1: ground
    body2: a
    axis: [0, 0, 1]
)",
                    "joints[0].point", 5, "missing required key 'point'");
}

// ---- wrong types -----------------------------------------------------------

TEST_CASE("a string where a number belongs is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - name: a
    mass: heavy
    particle: true
)",
                    "bodies[0].mass", 4, "expected a number > 0, got 'heavy'");
  // Quoted scalars are strings even if they look like numbers.
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: "1", particle: true}
)",
                    "bodies[0].mass", 3, "expected a number > 0, got the string \"1\"");
}

TEST_CASE("an empty value where a number belongs is rejected at its key") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - name: a
    mass:
    particle: true
)",
                    "bodies[0].mass", 4, "expected a number > 0, got an empty value");
}

TEST_CASE("an infinite number is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: .inf, particle: true}
)",
                    "bodies[0].mass", 3, "expected a finite number");
}

TEST_CASE("a scalar where a list belongs is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - name: a
    mass: 1
    particle: true
    position: 5
)",
                    "bodies[0].position", 6, "expected a list of 3 numbers, got 5");
}

TEST_CASE("a list of the wrong length is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
gravity: [0, -9.81]
bodies:
  - {name: a, mass: 1, particle: true}
)",
                    "gravity", 2, "expected a list of 3 numbers, got a list of 2 items");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1, 0]}
)",
                    "bodies[0].inertia", 3, "expected a list of 3 or 6 numbers");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1], orientation: [1, 0, 0]}
)",
                    "bodies[0].orientation", 3, "expected a list of 4 numbers");
}

TEST_CASE("a non-number inside a list is rejected at the element") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - name: a
    mass: 1
    particle: true
    velocity:
      - 1
      - fast
      - 0
)",
                    "bodies[0].velocity[1]", 8, "expected a number, got 'fast'");
}

TEST_CASE("a non-bool particle flag is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: yes}
)",
                    "bodies[0].particle", 3, "expected true or false, got 'yes'");
}

TEST_CASE("parallel_parts takes 1 to 64 parts, parallel_min_rows a count >= 0") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
solver: {parallel_parts: 0}
)",
                    "solver.parallel_parts", 4, "expected an integer >= 1, got 0");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
solver: {parallel_parts: 65}
)",
                    "solver.parallel_parts", 4, "expected at most 64 parts, got 65");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
solver: {parallel_min_rows: -1}
)",
                    "solver.parallel_min_rows", 4, "expected an integer >= 0, got -1");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
solver: {parallel_interface: iterative}
)",
                    "solver.parallel_interface", 4, "expected one of: direct, pcg, got 'iterative'");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
solver: {pcg_preconditioner: jacobi}
)",
                    "solver.pcg_preconditioner", 4, "expected one of: block, diagonal, got 'jacobi'");
}

// A rod on a pin driven by the given function (for the driver-function cases).
std::string driven_pin(const std::string& function) {
  return "name: m\nbodies:\n  - {name: a, mass: 1, inertia: [1, 1, 1]}\njoints:\n"
         "  - {name: pin, type: revolute, body1: ground, body2: a, point: [0, 0, 0], axis: [0, 0, 1]}\n"
         "drivers:\n  - name: motor\n    type: joint_angle\n    joint: pin\n    function:\n" + function;
}

TEST_CASE("a piecewise driver function parses its pieces and is checked for continuity") {
  // t^2 up to 1 s, then 2 t - 1 plus harmonics whose value and rate vanish at t = 1.
  const Model m = parse_model(driven_pin(R"(      pieces:
        - {until: 1, polynomial: [0, 0, 1]}
        - polynomial: [-1, 2]
          harmonics: [{amplitude: 0.1, omega: 6.283185307179586}, {amplitude: -0.05, omega: 12.566370614359172}]
)"), "m.yaml");
  const TimeFunction& f = m.drivers.at(0).function;
  REQUIRE(f.pieces.size() == 2);
  CHECK(f.pieces[0].until == 1.0);
  CHECK(std::isinf(f.pieces[1].until));
  REQUIRE(f.pieces[1].harmonics.size() == 2);
  CHECK(f.pieces[1].harmonics[1].amplitude == -0.05);
  CHECK(f.pieces[1].harmonics[1].phase == 0.0);
  CHECK(evaluate(f, 0.5).f == doctest::Approx(0.25).scale(0));
  const double t = 1.3, w = 2 * M_PI;
  CHECK(evaluate(f, t).f == doctest::Approx(2 * t - 1 + 0.1 * std::sin(w * t) - 0.05 * std::sin(2 * w * t)));
  CHECK(evaluate(f, t).ddf == doctest::Approx(-0.1 * w * w * std::sin(w * t) + 0.2 * w * w * std::sin(2 * w * t)));
  CHECK_MODEL_ERROR(driven_pin("      pieces:\n        - {until: 1, polynomial: [0, 0, 1]}\n        - {polynomial: [0, 2]}\n"),
                    "drivers[0].function.pieces[1]", 13,
                    "pieces 0 and 1 give different values at t = 1 s (1 and 2): a driver's value and rate must be continuous");
  CHECK_MODEL_ERROR(driven_pin("      pieces:\n        - {until: 1, polynomial: [0, 0, 1]}\n        - {polynomial: [-2, 3]}\n"),
                    "drivers[0].function.pieces[1]", 13, "give different rates at t = 1 s (2 and 3)");
  CHECK_MODEL_ERROR(driven_pin("      pieces:\n        - {polynomial: [0]}\n        - {polynomial: [0]}\n"),
                    "drivers[0].function.pieces[0]", 12, "missing required key 'until'");
  CHECK_MODEL_ERROR(driven_pin("      pieces:\n        - {until: 2, polynomial: [0]}\n        - {until: 1, polynomial: [0]}\n"
                               "        - {polynomial: [0]}\n"),
                    "drivers[0].function.pieces[1].until", 13, "pieces must end in increasing time");
  CHECK_MODEL_ERROR(driven_pin("      pieces:\n        - {until: 1, polynomial: [0]}\n        - {until: 2, polynomial: [0]}\n"),
                    "drivers[0].function.pieces[1].until", 13, "the last piece runs to the end of time");
  CHECK_MODEL_ERROR(driven_pin("      pieces:\n        - {until: 1}\n        - {polynomial: [0]}\n"),
                    "drivers[0].function.pieces[0]", 12, "expected a piece with a polynomial, harmonics or both");
  CHECK_MODEL_ERROR(driven_pin("      pieces:\n        - {harmonics: [{amplitude: 1}]}\n"),
                    "drivers[0].function.pieces[0].harmonics[0].omega", 12, "missing required key 'omega'");
  CHECK_MODEL_ERROR(driven_pin("      {polynomial: [0], pieces: [{polynomial: [0]}]}\n"), "drivers[0].function", 10,
                    "expected exactly one of: polynomial, sine, pieces");
}

TEST_CASE("a flexible body becomes nodes with the beam's mass and elements between them") {
  const Model m = parse_model(R"(name: m
bodies:
  - {name: hub, mass: 1, inertia: [1, 1, 1]}
  - name: boom
    flexible: {length: 3, elements: 3, EA: 1.0e6, GJ: 50, EI: [100, 200], rho_A: 2, rho_J: 0.01}
    position: [1, 0, 0]
    orientation: [0.7071067811865476, 0, 0, 0.7071067811865476]
    angular_velocity: [0, 0, 2]
joints:
  - {name: clamp, type: fixed, body1: hub, body2: boom@root, point: [1, 0, 0]}
outputs:
  - {name: tip, type: body_pose, body: boom@tip}
  - {name: middle, type: body_pose, body: boom@2}
)", "m.yaml");
  REQUIRE(m.bodies.size() == 5);
  REQUIRE(m.flexible.size() == 1);
  REQUIRE(m.beam_elements.size() == 3);
  CHECK(m.bodies[1].name == "boom_n0");
  CHECK(m.bodies[4].name == "boom_n3");
  // Along the body x axis, turned 90 degrees about z: the nodes go up y.
  CHECK((m.bodies[4].position - Eigen::Vector3d(1, 3, 0)).norm() < 1e-12);
  CHECK(m.bodies[1].mass == doctest::Approx(1.0));  // half an element at each end
  CHECK(m.bodies[2].mass == doctest::Approx(2.0));
  CHECK((m.bodies[4].velocity - Eigen::Vector3d(-6, 0, 0)).norm() < 1e-12);  // w x r = 2 z x 3 y
  CHECK(m.beam_elements[0].section.EIy == 100);
  CHECK(m.beam_elements[0].section.EIz == 200);
  CHECK(m.beam_elements[0].section.GAy == doctest::Approx(1.0e6 / 3));
  CHECK(m.joints[0].body2 == 1);
  CHECK(m.outputs[0].body == 4);
  CHECK(m.outputs[1].body == 3);
}

TEST_CASE("bad flexible bodies and node references are rejected naming the key") {
  const std::string beam = "  - name: boom\n    flexible: {length: 2, elements: 4, EA: 1.0e6, GJ: 50, EI: 100, rho_A: 2, rho_J: 0.01}\n";
  CHECK_MODEL_ERROR("name: m\nbodies:\n" + beam + "    mass: 3\n", "bodies[0].mass", 5,
                    "key 'mass' does not apply to a flexible body (its mass and inertia come from the beam)");
  CHECK_MODEL_ERROR("name: m\nbodies:\n  - name: boom\n    flexible: {length: 2, elements: 0, EA: 1, GJ: 1, EI: 1, rho_A: 1, rho_J: 1}\n",
                    "bodies[0].flexible.elements", 4, "expected an integer >= 1");
  CHECK_MODEL_ERROR("name: m\nbodies:\n  - name: boom\n    flexible: {length: 2, elements: 2, EA: 1, GJ: 1, EI: [1, 2, 3], rho_A: 1, rho_J: 1}\n",
                    "bodies[0].flexible.EI", 4, "expected a number > 0 or a list [y, z] of two");
  CHECK_MODEL_ERROR("name: m\nbodies:\n  - name: boom\n    flexible: {length: 2, elements: 2, EA: 1, EI: 1, rho_A: 1, rho_J: 1}\n",
                    "bodies[0].flexible.GJ", 4, "missing required key 'GJ'");
  CHECK_MODEL_ERROR("name: m\nbodies:\n" + beam + "  - {name: boom_n2, mass: 1, particle: true}\n", "bodies[1].name", 5,
                    "duplicate body name 'boom_n2'");
  const std::string joint = "joints:\n  - {name: j, type: spherical, body1: ground, body2: ";
  CHECK_MODEL_ERROR("name: m\nbodies:\n" + beam + joint + "boom@7, point: [0, 0, 0]}\n", "joints[0].body2", 6,
                    "unknown node '7' of flexible body 'boom' (root, tip or 0 to 4)");
  CHECK_MODEL_ERROR("name: m\nbodies:\n" + beam + joint + "beam@tip, point: [0, 0, 0]}\n", "joints[0].body2", 6,
                    "'beam' is not a flexible body (flexible bodies: boom)");
  CHECK_MODEL_ERROR("name: m\nbodies:\n" + beam + joint + "boom, point: [0, 0, 0]}\n", "joints[0].body2", 6,
                    "'boom' is a flexible body: name one of its nodes, boom@root, boom@tip or boom@K");
}

TEST_CASE("a non-integer euler_updates is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
solver: {euler_updates: 2.5}
)",
                    "solver.euler_updates", 4, "expected an integer >= 1, got 2.5");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
solver: {euler_updates: 0}
)",
                    "solver.euler_updates", 4, "expected an integer >= 1, got 0");
}

TEST_CASE("bodies that are not a non-empty list are rejected") {
  CHECK_MODEL_ERROR("name: m\nbodies: []\n", "bodies", 2, "expected a non-empty list of bodies");
  CHECK_MODEL_ERROR("name: m\nbodies: {a: 1}\n", "bodies", 2, "expected a non-empty list of bodies, got a map");
}

TEST_CASE("joints that are not a list are rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
joints: pin
)",
                    "joints", 4, "expected a list of joints, got 'pin'");
}

// ---- names -----------------------------------------------------------------

TEST_CASE("names not matching [a-z][a-z0-9_]* are rejected") {
  CHECK_MODEL_ERROR(R"(name: 4bar
bodies:
  - {name: a, mass: 1, particle: true}
)",
                    "name", 1, "expected a name matching [a-z][a-z0-9_]*");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
  - {name: Crank-2, mass: 1, particle: true}
)",
                    "bodies[1].name", 4, "got 'Crank-2'");
}

TEST_CASE("a body may not use the reserved name ground") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: ground, mass: 1, particle: true}
)",
                    "bodies[0].name", 3, "'ground' is the reserved name");
}

TEST_CASE("a duplicate body name is rejected naming the first definition") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - name: bob
    mass: 1
    particle: true
  - name: crank
    mass: 1
    inertia: [1, 1, 1]
  - mass: 2
    name: crank
    inertia: [1, 1, 1]
)",
                    "bodies[2].name", 10, "duplicate body name 'crank' (first defined at line 6)");
}

TEST_CASE("a duplicate joint name is rejected naming the first definition") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
  - {name: b, mass: 1, particle: true}
joints:
  - {name: link, type: spherical, body1: ground, body2: a, point: [0, 0, 0]}
  - {name: link, type: spherical, body1: a, body2: b, point: [0, 0, 0]}
)",
                    "joints[1].name", 7, "duplicate joint name 'link' (first defined at line 6)");
}

// ---- bodies ----------------------------------------------------------------

TEST_CASE("zero or negative mass is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 0, particle: true}
)",
                    "bodies[0].mass", 3, "expected a number > 0, got 0");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - name: a
    mass: -1
    particle: true
)",
                    "bodies[0].mass", 4, "expected a number > 0, got -1");
}

TEST_CASE("an inertia that is not positive definite is rejected with its smallest eigenvalue") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - name: a
    mass: 1
    inertia: [1, 2, -0.5]
)",
                    "bodies[0].inertia", 5, "inertia is not positive definite (smallest eigenvalue -0.5)");
  // Positive diagonal, but the products make it indefinite: eigenvalues -1, 1, 3.
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1, 2, 0, 0]}
)",
                    "bodies[0].inertia", 3, "smallest eigenvalue -1");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 0, 1]}
)",
                    "bodies[0].inertia", 3, "smallest eigenvalue 0");
}

TEST_CASE("an inertia no rigid body can have (one principal moment above the sum of the others) is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - name: wrist
    mass: 0.3
    inertia: [0.1, 0.1, 5.0]
)",
                    "bodies[0].inertia", 5, "largest principal moment 5 exceeds the sum of the other two");
  // Rotated into products, the principal moments are the same: 0.1, 0.1 and 0.3.
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [0.2, 0.2, 0.1, 0.1, 0, 0]}
)",
                    "bodies[0].inertia", 3, "exceeds the sum of the other two");
  // A thin rod and a thin plate are at the limit, and accepted.
  CHECK_FALSE(failure_of("name: m\nbodies:\n  - {name: a, mass: 1, inertia: [0.5, 0.5, 1.0]}\n").thrown);
}

TEST_CASE("Euler parameters that are not unit are rejected saying the norm") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - name: a
    mass: 1
    inertia: [1, 1, 1]
    orientation: [1.2, 0, 0, 0]
)",
                    "bodies[0].orientation", 6, "Euler parameters must have unit norm (|p| = 1.2)");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1], orientation: [1.00001, 0, 0, 0]}
)",
                    "bodies[0].orientation", 3, "(|p| = 1.00001)");
}

TEST_CASE("a particle with rotational data is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - name: bob
    mass: 1
    particle: true
    inertia: [1, 1, 1]
)",
                    "bodies[0].inertia", 6, "a particle must not have inertia");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: bob, mass: 1, particle: true, orientation: [1, 0, 0, 0]}
)",
                    "bodies[0].orientation", 3, "a particle must not have orientation");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: bob, mass: 1, particle: true, angular_velocity: [0, 0, 1]}
)",
                    "bodies[0].angular_velocity", 3, "a particle must not have angular_velocity");
}

// ---- joints ----------------------------------------------------------------

TEST_CASE("a joint naming an unknown body is rejected listing the bodies") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: crank, mass: 1, inertia: [1, 1, 1]}
  - {name: bob, mass: 1, particle: true}
joints:
  - name: j
    type: spherical
    body1: crnk
    body2: bob
    point: [0, 0, 0]
)",
                    "joints[0].body1", 8, "unknown body 'crnk' (bodies: ground, crank, bob)");
}

TEST_CASE("a joint connecting a body to itself is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1]}
joints:
  - {name: j, type: fixed, body1: a, body2: a, point: [0, 0, 0]}
)",
                    "joints[0].body2", 5, "a joint must connect two different bodies");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1]}
joints:
  - name: j
    type: fixed
    body1: ground
    body2: ground
    point: [0, 0, 0]
)",
                    "joints[0].body2", 8, "a joint must connect two different bodies (both are 'ground')");
}

TEST_CASE("an unknown joint type is rejected listing the types") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1]}
joints:
  - name: j
    type: hinge
    body1: ground
    body2: a
)",
                    "joints[0].type", 6,
                    "expected one of: spherical, revolute, universal, cylindrical, prismatic, fixed, "
                    "distance, screw, planar, rolling_disk, rolling_ball, knife_edge, velocity_toward, point_contact, sphere_contact, got 'hinge'");
}

TEST_CASE("a zero-length axis is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1]}
joints:
  - name: j
    type: prismatic
    body1: ground
    body2: a
    point: [0, 0, 0]
    axis: [0, 0, 0]
)",
                    "joints[0].axis", 10, "zero-length axis");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1]}
forces:
  - {type: torque, body1: ground, body2: a, axis: [0, 0, 0], value: 1}
)",
                    "forces[0].axis", 5, "zero-length axis");
}

TEST_CASE("universal joint axes that are not perpendicular are rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1]}
joints:
  - name: u
    type: universal
    body1: ground
    body2: a
    point: [0, 0, 0]
    axis1: [1, 0, 0]
    axis2: [1, 1, 0]
)",
                    "joints[0].axis2", 11, "must be perpendicular");
}

TEST_CASE("a distance joint between coincident points without a length is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
joints:
  - name: rod
    type: distance
    body1: ground
    body2: a
    point1: [1, 2, 3]
    point2: [1, 2, 3]
)",
                    "joints[0].point2", 10, "zero-length distance");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
joints:
  - {name: rod, type: distance, body1: ground, body2: a, point1: [0, 0, 0], point2: [1, 0, 0], length: 0}
)",
                    "joints[0].length", 5, "expected a number > 0, got 0");
}

// ---- forces ----------------------------------------------------------------

TEST_CASE("an unknown force type is rejected listing the types") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
forces:
  - {type: gravity, body: a}
)",
                    "forces[0].type", 5, "expected one of: spring_damper, torque, force, joint_spring, got 'gravity'");
}

TEST_CASE("a negative spring stiffness is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
forces:
  - type: spring_damper
    body1: ground
    body2: a
    point1: [0, 0, 0]
    point2: [0, 0, 1]
    stiffness: -10
    rest_length: 1
)",
                    "forces[0].stiffness", 10, "expected a number >= 0, got -10");
}

TEST_CASE("a force on ground or a spring from a body to itself is rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
forces:
  - {type: force, body: ground, vector: [1, 0, 0]}
)",
                    "forces[0].body", 5, "a force must act on a body, not on ground");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
forces:
  - {type: spring_damper, body1: a, body2: a, point1: [0, 0, 0], point2: [0, 0, 1], stiffness: 1, rest_length: 1}
)",
                    "forces[0].body2", 5, "must connect two different bodies");
}

TEST_CASE("a joint_spring takes its joint's bodies; rest defaults to 0") {
  const Model m = parse_model(R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1]}
joints:
  - {name: pin, type: revolute, body1: ground, body2: a, point: [0, 0, 0], axis: [0, 0, 1]}
forces:
  - {type: joint_spring, joint: pin, stiffness: 2.0, damping: 0.05}
)",
                              "m.yaml");
  const Force& f = m.forces[0];
  CHECK(f.type == ForceType::joint_spring);
  CHECK(f.joint == 0);
  CHECK(f.body1 == kGround);
  CHECK(f.body2 == 0);
  CHECK(f.stiffness == 2.0);
  CHECK(f.damping == 0.05);
  CHECK(f.rest == 0.0);
}

TEST_CASE("a joint_spring needs a revolute or prismatic joint and a non-negative stiffness and damping") {
  const std::string head = R"(name: m
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1]}
joints:
  - {name: ball, type: spherical, body1: ground, body2: a, point: [0, 0, 0]}
  - {name: pin, type: revolute, body1: ground, body2: a, point: [0, 0, 0], axis: [0, 0, 1]}
forces:
)";
  CHECK_MODEL_ERROR(head + "  - {type: joint_spring, joint: ball, stiffness: 1}\n", "forces[0].joint", 8,
                    "a joint_spring force needs a revolute or prismatic joint; 'ball' is not one");
  CHECK_MODEL_ERROR(head + "  - {type: joint_spring, joint: pin, stiffness: -1}\n", "forces[0].stiffness", 8,
                    "expected a number >= 0, got -1");
  CHECK_MODEL_ERROR(head + "  - {type: joint_spring, joint: pin, stiffness: 1, damping: -0.5}\n", "forces[0].damping",
                    8, "expected a number >= 0, got -0.5");
}

// ---- solver ----------------------------------------------------------------

TEST_CASE("an unknown solver scheme is rejected listing the schemes") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
solver:
  scheme: rk4
)",
                    "solver.scheme", 5,
                    "expected one of: staggered-pcst, staggered-nps, ali3p, blajer, baumgarte, staggered-tree, midpoint-tree, rk4-tree, rk4-projected, staggered4, rk8-tree, got 'rk4'");
}

TEST_CASE("a non-positive step and a negative penalty are rejected") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
solver: {step: 0}
)",
                    "solver.step", 4, "expected a number > 0, got 0");
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: a, mass: 1, particle: true}
solver: {penalty: -1e-9}
)",
                    "solver.penalty", 4, "expected a number >= 0, got -1e-9");
}

// ---- inputs and outputs -----------------------------------------------------

const char* const kArm = R"(name: arm
bodies:
  - {name: link, mass: 1, inertia: [1, 1, 1]}
  - {name: cart, mass: 1, inertia: [1, 1, 1]}
joints:
  - {name: pin, type: revolute, body1: ground, body2: link, point: [0, 0, 0], axis: [0, 0, 1]}
  - {name: rail, type: prismatic, body1: ground, body2: cart, point: [0, 0, 0], axis: [1, 0, 0]}
)";

TEST_CASE("inputs and outputs parse into the structs") {
  const Model m = parse_model(std::string(kArm) + R"(inputs:
  - {name: tau_pin, type: joint_torque, joint: pin, min: -10, max: 10, safe: 0}
  - {name: push, type: joint_force, joint: rail, min: -5, max: 5, safe: 1}
  - {name: motor, type: motor_torque, body1: link, body2: cart, axis: [0, 0, 2], min: -1, max: 2, safe: 0}
outputs:
  - {name: q, type: joint_position, joint: pin}
  - {name: qd, type: joint_velocity, joint: rail}
  - {name: link_pose, type: body_pose, body: link}
  - {name: cart_velocity, type: body_velocity, body: cart}
)",
                              "model.yaml");
  REQUIRE(m.inputs.size() == 3);
  CHECK(m.inputs[0].type == InputType::joint_torque);
  CHECK(m.inputs[0].joint == 0);
  CHECK(m.inputs[1].safe == 1.0);
  CHECK(m.inputs[2].type == InputType::motor_torque);
  CHECK(m.inputs[2].body1 == 0);
  CHECK(m.inputs[2].axis.isApprox(Eigen::Vector3d::UnitZ()));
  REQUIRE(m.outputs.size() == 4);
  CHECK(m.outputs[1].joint == 1);
  CHECK(m.outputs[2].type == OutputType::body_pose);
  CHECK(m.outputs[3].body == 1);
}

TEST_CASE("a joint input on a joint of the wrong type is rejected naming the types it takes") {
  CHECK_MODEL_ERROR(std::string(kArm) + R"(inputs:
  - {name: push, type: joint_force, joint: pin, min: -5, max: 5, safe: 0}
)",
                    "inputs[0].joint", 9, "a joint_force input needs a prismatic or cylindrical joint; 'pin' is not one");
}

TEST_CASE("an input whose max is not above min, or whose safe value is outside, is rejected") {
  CHECK_MODEL_ERROR(std::string(kArm) + R"(inputs:
  - {name: tau, type: joint_torque, joint: pin, min: 3, max: 3, safe: 3}
)",
                    "inputs[0].max", 9, "expected a number > min (3)");
  CHECK_MODEL_ERROR(std::string(kArm) + R"(inputs:
  - {name: tau, type: joint_torque, joint: pin, min: -1, max: 1, safe: 2}
)",
                    "inputs[0].safe", 9, "expected a number within [min, max] = [-1, 1]");
}

TEST_CASE("an input without limits is rejected at the input") {
  CHECK_MODEL_ERROR(std::string(kArm) + R"(inputs:
  - {name: tau, type: joint_torque, joint: pin, min: -1, max: 1}
)",
                    "inputs[0].safe", 9, "missing required key 'safe'");
}

TEST_CASE("signal names are unique across inputs and outputs and exclude message fields") {
  CHECK_MODEL_ERROR(std::string(kArm) + R"(inputs:
  - {name: q, type: joint_torque, joint: pin, min: -1, max: 1, safe: 0}
outputs:
  - {name: q, type: joint_position, joint: pin}
)",
                    "outputs[0].name", 11, "duplicate input or output name 'q'");
  CHECK_MODEL_ERROR(std::string(kArm) + R"(outputs:
  - {name: utime, type: joint_position, joint: pin}
)",
                    "outputs[0].name", 9, "'utime' is a field of every message");
}

TEST_CASE("outputs of unknown joints, of ground or with keys of another type are rejected") {
  CHECK_MODEL_ERROR(std::string(kArm) + R"(outputs:
  - {name: q, type: joint_position, joint: elbow}
)",
                    "outputs[0].joint", 9, "unknown joint 'elbow'");
  CHECK_MODEL_ERROR(std::string(kArm) + R"(outputs:
  - {name: p, type: body_pose, body: ground}
)",
                    "outputs[0].body", 9, "ground does not move");
  CHECK_MODEL_ERROR(std::string(kArm) + R"(outputs:
  - {name: p, type: body_pose, body: link, joint: pin}
)",
                    "outputs[0].joint", 9, "key 'joint' does not apply to a body_pose output");
}

TEST_CASE("ground contacts parse as written in the contract, unnamed ones named after body and type") {
  const Model m = parse_model(R"(name: contacts
bodies:
  - {name: wheel, mass: 5, inertia: [0.625, 0.3125, 0.3125], position: [0, 0, 0.5]}
  - {name: ball, mass: 7, inertia: [0.03, 0.03, 0.03], position: [2, 0, 0.11]}
  - {name: b, mass: 1, inertia: [1, 1, 1], position: [4, 0, 0]}
joints:
  - {type: rolling_disk, body: wheel, radius: 0.5, axis: [1, 0, 0], plane_point: [0, 0, 0], plane_normal: [0, 0, 1]}
  - {type: rolling_ball, body: ball, radius: 0.11, center: [2.01, 0, 0.11], plane_point: [0, 0, 0], plane_normal: [0, 0, 1]}
  - {name: blade, type: knife_edge, body: b, point: [4, 0, 0], direction: [0, 2, 0], plane_normal: [0, 0, 1]}
  - {name: chase, type: velocity_toward, body1: ball, body2: b, point1: [2, 0, 0.11], point2: [4, 0, 0], plane_normal: [0, 0, 1]}
)",
                              "model.yaml");
  REQUIRE(m.joints.size() == 4);
  CHECK(m.joints[0].name == "wheel_rolling_disk");
  CHECK(m.joints[0].type == JointType::rolling_disk);
  CHECK(m.joints[0].body1 == kGround);
  CHECK(m.joints[0].radius == 0.5);
  CHECK(m.joints[1].name == "ball_rolling_ball");
  CHECK(m.joints[1].point == Eigen::Vector3d(2.01, 0, 0.11));
  CHECK(m.joints[2].direction == Eigen::Vector3d(0, 1, 0));
  CHECK(m.joints[3].type == JointType::velocity_toward);
  CHECK(m.joints[3].point2 == Eigen::Vector3d(4, 0, 0));
}

TEST_CASE("a knife edge whose direction leaves the plane is rejected with its line") {
  CHECK_MODEL_ERROR(R"(name: m
bodies:
  - {name: b, mass: 1, inertia: [1, 1, 1]}
joints:
  - {name: blade, type: knife_edge, body: b, point: [0, 0, 0], direction: [0, 1, 1],
     plane_normal: [0, 0, 1]}
)",
                    "joints[0].direction", 5, "the edge direction must lie in the plane");
}

// ---- element type tables ----------------------------------------------------

namespace {

// A model with bodies a and b, a cylindrical joint "slide" (ground - a) and a
// revolute joint "pin" (ground - b), plus `section` (e.g. "forces:\n  - {...}").
std::string scene_with(const std::string& section) {
  return "name: tables\nbodies:\n"
         "  - {name: a, mass: 1, inertia: [1, 1, 1]}\n"
         "  - {name: b, mass: 1, inertia: [1, 1, 1], position: [0, 0, 0.5]}\n"
         "joints:\n"
         "  - {name: slide, type: cylindrical, body1: ground, body2: a, point: [0, 0, 0], axis: [1, 0, 0]}\n"
         "  - {name: pin, type: revolute, body1: ground, body2: b, point: [0, 0, 0.5], axis: [0, 0, 1]}\n" +
         section;
}

// A list item giving exactly `keys`, each with a value every element type that
// takes it accepts but the joint, named by `joint`; a key without one here
// fails the test.
std::string item_with(const Keys& keys, const std::string& type_name, const std::string& joint = "slide") {
  static const std::map<std::string, std::string> kValues = {
      {"name", "item"},          {"body1", "ground"},      {"body2", "b"},            {"body", "b"},
      {"joint", "slide"},        {"point", "[0, 0, 0.5]"}, {"axis", "[0, 0, 1]"},     {"axis1", "[1, 0, 0]"},
      {"axis2", "[0, 1, 0]"},    {"point1", "[0, 0, 0]"},  {"point2", "[0, 0, 0.5]"}, {"length", "0.5"},
      {"lead", "0.1"},           {"radius", "0.5"},        {"center", "[0, 0, 0.5]"}, {"direction", "[1, 0, 0]"},
      {"plane_point", "[0, 0, 0]"}, {"plane_normal", "[0, 0, 1]"}, {"stiffness", "10"}, {"damping", "1"},
      {"rest_length", "0.5"},    {"value", "1"},           {"vector", "[1, 0, 0]"},   {"function", "{polynomial: [0]}"},
      {"min", "-1"},             {"max", "1"},             {"safe", "0"},             {"rest", "0.1"},
      {"armature", "0"},         {"contact", "touch"}};
  std::map<std::string, std::string> values = kValues;
  values["type"] = type_name;
  values["friction"] = type_name == "prismatic" ? "{force: 0}" : "{torque: 0}";  // none: any scheme takes it
  values["joint"] = joint;
  std::string item;
  for (const std::string& key : keys) {
    INFO("key: ", key);
    const auto value = values.find(key);
    REQUIRE(value != values.end());
    item += (item.empty() ? "" : ", ") + key + ": " + value->second;
  }
  return "  - {" + item + "}\n";
}

bool takes_all(const Keys& every, const Keys& keys) {
  return std::all_of(keys.begin(), keys.end(),
                     [&](const std::string& k) { return std::find(every.begin(), every.end(), k) != every.end(); });
}

}  // namespace

TEST_CASE("every joint type has a table row whose name and keys make a joint of that type") {
  for (std::size_t i = 0; i < kJointTypeCount; ++i) {
    const auto type = static_cast<JointType>(i);
    const JointTypeRow& row = type_row(type);
    INFO("joint type ", i, ": ", std::string(row.name));
    REQUIRE(row.type == type);
    CHECK(type_named(kJointTypeTable, row.name) == type);
    CHECK(0 <= row.holonomic_rows);
    CHECK(row.holonomic_rows <= row.rows);
    CHECK(row.rows <= 6);
    CHECK(std::string(row.kernel) != "");
    CHECK(takes_all(every_joint_key(), joint_keys(type)));
    const Model m = parse_model(scene_with(item_with(joint_keys(type), row.name)), "tables.yaml");
    REQUIRE(m.joints.size() == 3);
    CHECK(m.joints[2].type == type);
    const Analysis a = analyse(m);
    CHECK(a.constraints[2].joint_type == type);
    CHECK(a.constraints[2].rows == row.rows);
    CHECK(a.constraints[2].holonomic_rows == row.holonomic_rows);
    CHECK(a.constraints[2].kernel == row.kernel);
  }
}

TEST_CASE("every driver type has a table row whose name and keys make a driver of that type") {
  for (std::size_t i = 0; i < kDriverTypeCount; ++i) {
    const auto type = static_cast<DriverType>(i);
    const DriverTypeRow& row = type_row(type);
    INFO("driver type ", i, ": ", std::string(row.name));
    REQUIRE(row.type == type);
    CHECK(type_named(kDriverTypeTable, row.name) == type);
    CHECK(takes_all(every_driver_key(), driver_keys(type)));
    const Model m = parse_model(scene_with("drivers:\n" + item_with(driver_keys(type), row.name)), "tables.yaml");
    REQUIRE(m.drivers.size() == 1);
    CHECK(m.drivers[0].type == type);
    const Analysis a = analyse(m);
    CHECK(a.constraints[2].driver_type == type);
    CHECK(a.constraints[2].rows == row.rows);
    CHECK(a.constraints[2].kernel == row.kernel);
  }
}

TEST_CASE("every force type has a table row whose name and keys make a force of that type") {
  for (std::size_t i = 0; i < kForceTypeCount; ++i) {
    const auto type = static_cast<ForceType>(i);
    const ForceTypeRow& row = type_row(type);
    INFO("force type ", i, ": ", std::string(row.name));
    REQUIRE(row.type == type);
    CHECK(type_named(kForceTypeTable, row.name) == type);
    CHECK(takes_all(every_force_key(), force_keys(type)));
    // A joint_spring needs a revolute or prismatic joint.
    const std::string joint = type == ForceType::joint_spring ? "pin" : "slide";
    const Model m = parse_model(scene_with("forces:\n" + item_with(force_keys(type), row.name, joint)), "tables.yaml");
    REQUIRE(m.forces.size() == 1);
    CHECK(m.forces[0].type == type);
  }
}

TEST_CASE("every input type has a table row whose name and keys make an input of that type") {
  for (std::size_t i = 0; i < kInputTypeCount; ++i) {
    const auto type = static_cast<InputType>(i);
    const InputTypeRow& row = type_row(type);
    INFO("input type ", i, ": ", std::string(row.name));
    REQUIRE(row.type == type);
    CHECK(type_named(kInputTypeTable, row.name) == type);
    CHECK(takes_all(every_input_key(), input_keys(type)));
    const Model m = parse_model(scene_with("inputs:\n" + item_with(input_keys(type), row.name)), "tables.yaml");
    REQUIRE(m.inputs.size() == 1);
    CHECK(m.inputs[0].type == type);
  }
}

TEST_CASE("every output type has a table row whose name and keys make an output of that type") {
  for (std::size_t i = 0; i < kOutputTypeCount; ++i) {
    const auto type = static_cast<OutputType>(i);
    const OutputTypeRow& row = type_row(type);
    INFO("output type ", i, ": ", std::string(row.name));
    REQUIRE(row.type == type);
    CHECK(type_named(kOutputTypeTable, row.name) == type);
    CHECK(row.values >= 1);
    CHECK(takes_all(every_output_key(), output_keys(type)));
    // Joint outputs measure one coordinate: name the revolute joint.
    std::string item = item_with(output_keys(type), row.name);
    if (const std::size_t at = item.find("joint: slide"); at != std::string::npos) item.replace(at, 12, "joint: pin");
    std::string scene = scene_with("outputs:\n" + item);
    // Contact outputs name a contact (of a free body).
    if (type == OutputType::contact_force || type == OutputType::contact_stuck) {
      scene.replace(scene.find("joints:\n"), 8,
                    "  - {name: ball, mass: 1, inertia: [1, 1, 1], position: [2, 0, 0.1]}\njoints:\n"
                    "  - {name: touch, type: sphere_contact, body: ball, radius: 0.1, plane_point: [0, 0, 0], "
                    "plane_normal: [0, 0, 1]}\n");
    }
    // Friction outputs name a joint with friction.
    if (type == OutputType::joint_friction || type == OutputType::joint_stuck) {
      const std::string pin_end = "axis: [0, 0, 1]}";
      scene.replace(scene.find(pin_end), pin_end.size(), "axis: [0, 0, 1], friction: {torque: 0.1}}");
    }
    const Model m = parse_model(scene, "tables.yaml");
    REQUIRE(m.outputs.size() == 1);
    CHECK(m.outputs[0].type == type);
  }
}
