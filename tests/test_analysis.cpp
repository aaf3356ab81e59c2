// The generator's analysis: body frames, row counts, the fixed block pattern
// of S = B M^-1 B^T and its fill-reducing elimination order, and what the
// scene lets the step leave out.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

#include "analysis.hpp"
#include "generate.hpp"

using namespace mbrt::codegen;

namespace {

// A chain of n rods hanging from ground, optionally closed by a joint from
// the last link back to the first (a loop of moving bodies; a loop through
// ground couples nothing, since ground has no velocity).
Model chain(int n, bool closed) {
  std::string y = "name: chain\ngravity: [0, -9.81, 0]\nbodies:\n";
  for (int i = 0; i < n; ++i) {
    y += "  - {name: link" + std::to_string(i) + ", mass: 1, inertia: [0.001, 0.08, 0.08], position: [" +
         std::to_string(i + 0.5) + ", 0, 0]}\n";
  }
  y += "joints:\n";
  for (int i = 0; i < n; ++i) {
    y += "  - {name: pin" + std::to_string(i) + ", type: revolute, body1: " +
         (i == 0 ? std::string("ground") : "link" + std::to_string(i - 1)) + ", body2: link" + std::to_string(i) +
         ", point: [" + std::to_string(i) + ", 0, 0], axis: [0, 0, 1]}\n";
  }
  if (closed) {
    y += "  - {name: close, type: spherical, body1: link" + std::to_string(n - 1) + ", body2: link0, point: [" +
         std::to_string(n) + ", 0, 0]}\n";
  }
  return parse_model(y, "chain.yaml");
}

bool is_permutation_of_joints(const std::vector<int>& order, size_t n) {
  std::set<int> s(order.begin(), order.end());
  return order.size() == n && s.size() == n && *s.begin() == 0 && *s.rbegin() == static_cast<int>(n) - 1;
}

}  // namespace

TEST_CASE("an open chain couples neighbouring joints only and factorizes without fill") {
  const Analysis a = analyse(chain(8, false));
  CHECK(a.constraint_rows == 8 * 5);
  REQUIRE(is_permutation_of_joints(a.pattern.order, 8));
  CHECK(a.pattern.fill_blocks == 0);
  for (size_t j = 0; j < 8; ++j) {
    const auto& c = a.pattern.coupled[j];
    CHECK(c.size() == (j == 0 || j == 7 ? 1u : 2u));  // the joints before and after
  }
}

TEST_CASE("a closed loop needs fill blocks, and each lower block refers to a later joint") {
  const Analysis a = analyse(chain(6, true));
  REQUIRE(is_permutation_of_joints(a.pattern.order, 7));
  CHECK(a.pattern.fill_blocks > 0);
  std::vector<int> position(7);
  for (size_t p = 0; p < 7; ++p) position[static_cast<size_t>(a.pattern.order[p])] = static_cast<int>(p);
  for (int k = 0; k < 7; ++k) {
    for (int i : a.pattern.lower[static_cast<size_t>(k)]) CHECK(position[static_cast<size_t>(i)] > position[static_cast<size_t>(k)]);
  }
  // A loop of 7 joints eliminated in any order leaves at most 2 blocks per column.
  for (const auto& col : a.pattern.lower) CHECK(col.size() <= 2);
}

TEST_CASE("joint frames put both joint points on the world point and keep triads orthonormal") {
  const Model m = parse_model(R"(
name: tilted
bodies:
  - {name: a, mass: 1, inertia: [1, 2, 3], position: [1, 2, 3], orientation: [0.5, 0.5, 0.5, 0.5]}
  - {name: b, mass: 1, inertia: [1, 2, 3], position: [2, 2, 3], orientation: [0.8, 0.6, 0, 0]}
joints:
  - {name: hinge, type: revolute, body1: a, body2: b, point: [1.5, 2.5, 3], axis: [1, 1, 0]}
)",
                              "tilted.yaml");
  const Analysis an = analyse(m);
  const mbrt::JointFrame& f = an.constraints[0].frame;
  const Eigen::Matrix3d R1 = mbrt::rotation_matrix(m.bodies[0].orientation);
  const Eigen::Matrix3d R2 = mbrt::rotation_matrix(m.bodies[1].orientation);
  const Eigen::Vector3d point(1.5, 2.5, 3);
  CHECK((m.bodies[0].position + R1 * f.s1 - point).norm() < 1e-14);
  CHECK((m.bodies[1].position + R2 * f.s2 - point).norm() < 1e-14);
  CHECK((R1 * f.a1 - Eigen::Vector3d(1, 1, 0).normalized()).norm() < 1e-14);
  CHECK((R2 * f.b2 - R1 * f.b1).norm() < 1e-14);  // the same world triad in both bodies at t = 0
  CHECK((R2 * f.c2 - R1 * f.c1).norm() < 1e-14);
  CHECK(std::abs(f.a1.dot(f.b1)) < 1e-14);
  CHECK(std::abs(f.b1.dot(f.c1)) < 1e-14);
  CHECK((f.a1.cross(f.b1) - f.c1).norm() < 1e-14);  // right-handed
}

TEST_CASE("the analysis records what the scene does not need") {
  const Model m = parse_model(R"(
name: bare
bodies:
  - {name: bob, mass: 1, particle: true}
  - {name: ball, mass: 1, inertia: [2, 2, 2], position: [1, 0, 0]}
)",
                              "bare.yaml");
  const Analysis a = analyse(m);
  CHECK(!a.gravity);
  CHECK(a.particle_count == 1);
  CHECK(a.rigid_count == 1);
  CHECK(a.bodies[1].principal_axes);
  CHECK(a.bodies[1].isotropic);
  CHECK(!a.velocity_dependent_forces);  // isotropic ball: no gyroscopic torque, one stage
}

TEST_CASE("joints and torques that need orientation are refused on particles") {
  const std::string base = "name: p\nbodies:\n  - {name: bob, mass: 1, particle: true}\n";
  CHECK_THROWS_WITH_AS(
      analyse(parse_model(base + "joints:\n  - {name: h, type: revolute, body1: ground, body2: bob, point: [0, 0, 0], "
                                 "axis: [0, 0, 1]}\n",
                          "p.yaml")),
      doctest::Contains("'bob' is a particle"), ModelError);
  CHECK_THROWS_WITH_AS(
      analyse(parse_model(base + "joints:\n  - {name: s, type: spherical, body1: ground, body2: bob, point: [1, 0, 0]}\n",
                          "p.yaml")),
      doctest::Contains("must be its position"), ModelError);
}

TEST_CASE("staggered-nps: the tree takes each link's pin, the closing joint becomes the cut rows") {
  Model m = chain(4, true);
  m.solver.scheme = mbrt::Scheme::staggered_nps;
  const Analysis a = analyse(m);
  REQUIRE(a.tree.order.size() == 4);
  for (int i = 0; i < 4; ++i) {
    const TreeBody& tb = a.tree.order[static_cast<size_t>(i)];
    CHECK(tb.body == i);
    CHECK(tb.parent == (i == 0 ? kGround : i - 1));
    CHECK(tb.joint == i);
    CHECK(tb.child_is_body2);
    CHECK(tb.dofs == 1);
    CHECK(tb.leaf == (i == 3));
  }
  CHECK(a.tree.cut_blocks == std::vector<int>{4});
  CHECK(a.tree.cut_rows == 3);
}

TEST_CASE("staggered-nps: a body reached from its joint's body2 side, and a body no tree joint reaches") {
  Model m = parse_model(R"(name: t
bodies:
  - {name: a, mass: 1, inertia: [1, 1, 1], position: [0, 0, 0]}
  - {name: b, mass: 1, inertia: [1, 1, 1], position: [1, 0, 0]}
  - {name: p, mass: 1, particle: true, position: [5, 0, 0]}
joints:
  - {name: hinge, type: revolute, body1: b, body2: a, point: [0.5, 0, 0], axis: [0, 0, 1]}
  - {name: rope, type: distance, body1: a, body2: p, point1: [0, 0, 0], point2: [5, 0, 0]}
solver: {scheme: staggered-nps}
)",
                        "t.yaml");
  const Analysis an = analyse(m);
  REQUIRE(an.tree.order.size() == 3);
  // No tree joint reaches ground: a is free, b hangs from it on the hinge
  // (as body1, the hinge's body2 being the parent), the particle p is free.
  CHECK(an.tree.order[0].body == 0);
  CHECK(an.tree.order[0].joint == -1);
  CHECK(an.tree.order[0].dofs == 6);
  CHECK_FALSE(an.tree.order[0].leaf);
  CHECK(an.tree.order[1].body == 1);
  CHECK(an.tree.order[1].parent == 0);
  CHECK_FALSE(an.tree.order[1].child_is_body2);
  CHECK(an.tree.order[1].leaf);
  // Tree joints join rigid bodies only, so a particle is a free leaf.
  CHECK(an.tree.order[2].body == 2);
  CHECK(an.tree.order[2].dofs == 3);
  CHECK(an.tree.order[2].leaf);
  CHECK(an.tree.cut_blocks == std::vector<int>{1});
}

TEST_CASE("staggered-nps refuses more cut rows than it solves densely, naming staggered-pcst") {
  Model m = chain(2, false);
  m.solver.scheme = mbrt::Scheme::staggered_nps;
  // Eleven extra spherical joints between the two links: 33 cut rows.
  for (int k = 0; k < 11; ++k) {
    Joint j = m.joints[1];
    j.name = "extra" + std::to_string(k);
    j.type = JointType::spherical;
    m.joints.push_back(j);
  }
  try {
    (void)analyse(m);
    FAIL("expected a ModelError");
  } catch (const ModelError& e) {
    CHECK(std::string(e.what()).find("at most 30; this model has 33 (use staggered-pcst)") != std::string::npos);
  }
}

TEST_CASE("a file that names no scheme gets rk4-tree for a tree of one-dof joints, else staggered-pcst") {
  const std::string bodies =
      "name: t\nbodies:\n  - {name: a, mass: 1, inertia: [1, 1, 1], position: [1, 0, 0]}\n"
      "  - {name: b, mass: 1, inertia: [1, 1, 1], position: [2, 0, 0]}\n";
  const std::string pin_a = "  - {name: pa, type: revolute, body1: ground, body2: a, point: [0, 0, 0], axis: [0, 0, 1]}\n";
  const Model tree = parse_model(bodies + "joints:\n" + pin_a +
                                     "  - {name: pb, type: prismatic, body1: a, body2: b, point: [1.5, 0, 0], axis: [1, 0, 0]}\n",
                                 "t.yaml");
  CHECK_FALSE(tree.solver.scheme_given);
  CHECK(default_scheme(tree) == mbrt::Scheme::rk4_tree);
  const Model ball = parse_model(
      bodies + "joints:\n" + pin_a + "  - {name: ball, type: spherical, body1: a, body2: b, point: [1.5, 0, 0]}\n", "t.yaml");
  CHECK(default_scheme(ball) == mbrt::Scheme::staggered_pcst);
  const Model loop = parse_model(bodies + "joints:\n" + pin_a +
                                     "  - {name: pb, type: revolute, body1: a, body2: b, point: [1.5, 0, 0], axis: [0, 0, 1]}\n"
                                     "  - {name: loop, type: revolute, body1: ground, body2: b, point: [2, 0, 0], axis: [0, 0, 1]}\n",
                                 "t.yaml");
  CHECK(default_scheme(loop) == mbrt::Scheme::staggered_pcst);
  const Model named = parse_model(bodies + "joints:\n" + pin_a + "solver: {scheme: staggered-pcst}\n", "t.yaml");
  CHECK(named.solver.scheme_given);
  // gen: the default where the file names none, --scheme over it.
  const std::string path = (std::filesystem::temp_directory_path() / "mbrt_default_scheme_tree.yaml").string();
  std::ofstream(path) << bodies << "joints:\n"
                      << pin_a << "  - {name: pb, type: revolute, body1: a, body2: b, point: [1.5, 0, 0], axis: [0, 1, 0]}\n";
  CHECK(generate(path, {}).model.solver.scheme == mbrt::Scheme::rk4_tree);
  GenerateOptions pcst;
  pcst.scheme = "staggered-pcst";
  CHECK(generate(path, pcst).model.solver.scheme == mbrt::Scheme::staggered_pcst);
  std::remove(path.c_str());
}

TEST_CASE("staggered-tree takes trees of revolute and prismatic joints; armature needs it") {
  const std::string bodies =
      "name: t\nbodies:\n  - {name: a, mass: 1, inertia: [1, 1, 1], position: [1, 0, 0]}\n"
      "  - {name: b, mass: 1, inertia: [1, 1, 1], position: [2, 0, 0]}\n";
  const std::string pin_a = "  - {name: pa, type: revolute, body1: ground, body2: a, point: [0, 0, 0], axis: [0, 0, 1]}\n";
  CHECK_THROWS_WITH_AS(
      analyse(parse_model(bodies + "joints:\n" + pin_a +
                              "  - {name: ball, type: spherical, body1: a, body2: b, point: [1.5, 0, 0]}\n"
                              "solver: {scheme: staggered-tree}\n",
                          "t.yaml")),
      doctest::Contains("joint ball is spherical; the tree step takes revolute and prismatic joints"), ModelError);
  CHECK_THROWS_WITH_AS(
      analyse(parse_model(bodies + "joints:\n" + pin_a +
                              "  - {name: pb, type: revolute, body1: a, body2: b, point: [1.5, 0, 0], axis: [0, 0, 1]}\n"
                              "  - {name: loop, type: revolute, body1: ground, body2: b, point: [2, 0, 0], axis: [0, 0, 1]}\n"
                              "solver: {scheme: staggered-tree}\n",
                          "t.yaml")),
      doctest::Contains("a joint closes a loop"), ModelError);
  CHECK_THROWS_WITH_AS(
      analyse(parse_model(bodies + "joints:\n" + pin_a +
                              "  - {name: pb, type: revolute, body1: a, body2: b, point: [1.5, 0, 0], axis: [0, 0, 1], "
                              "armature: 0.1}\n",
                          "t.yaml")),
      doctest::Contains("joints.pb.armature: armature needs solver.scheme midpoint-tree or staggered-tree"), ModelError);
  const Analysis a = analyse(parse_model(bodies + "joints:\n" + pin_a +
                                             "  - {name: pb, type: revolute, body1: a, body2: b, point: [1.5, 0, 0], "
                                             "axis: [0, 1, 0], armature: 0.1}\nsolver: {scheme: staggered-tree}\n",
                                         "t.yaml"));
  REQUIRE(a.tree_frames.frames.size() == 2);
  // Craig's convention: a's frame has x along z x y, so b's frame is a's
  // turned about x by a right angle, at 0.5 m along a's x.
  CHECK(a.tree_frames.frames[1].armature == 0.1);
  CHECK(std::abs(a.tree_frames.frames[1].r.norm() - 1.5) < 1e-12);
  CHECK(a.tree_frames.frames[1].Ex.cwiseAbs().sum() == 3.0);
}

namespace {

Model split(Model m, int parts, mbrt::Scheme scheme = mbrt::Scheme::staggered_pcst) {
  m.solver.scheme = scheme;
  m.solver.scheme_given = true;
  m.solver.parallel_parts = parts;
  return m;
}

// The parallel step's conditions on the partition and S's factor: blocks of
// different parts share no moving body, each part's factor column reaches
// only its own part and the interface, and the parts come before the
// interface in the elimination order.
void check_arrowhead(const Analysis& a) {
  const Partition& p = a.partition;
  const auto part = [&](int j) { return p.block_part[static_cast<size_t>(j)]; };
  const int n = static_cast<int>(a.constraints.size());
  for (int i = 0; i < n; ++i) {
    for (int k : a.pattern.coupled[static_cast<size_t>(i)]) {
      if (part(i) < p.parts && part(k) < p.parts) CHECK(part(i) == part(k));
    }
    for (int k : a.pattern.lower[static_cast<size_t>(i)]) {
      if (part(i) < p.parts) CHECK((part(k) == part(i) || part(k) == p.parts));
      else CHECK(part(k) == p.parts);
    }
  }
  for (size_t q = 1; q < a.pattern.order.size(); ++q) CHECK(part(a.pattern.order[q - 1]) <= part(a.pattern.order[q]));
}

}  // namespace

TEST_CASE("the parallel step's parts share no moving body and S keeps an arrowhead form") {
  SUBCASE("an open chain in two parts: one joint between them") {
    const Analysis a = analyse(split(chain(64, false), 2));
    REQUIRE(a.partition.parts == 2);
    CHECK(a.partition.interface_blocks == 1);
    CHECK(a.partition.part_rows[0] + a.partition.part_rows[1] + a.partition.interface_rows == a.constraint_rows);
    CHECK(std::abs(a.partition.part_rows[0] - a.partition.part_rows[1]) <= 10);
    CHECK(a.pattern.fill_blocks == 0);
    check_arrowhead(a);
  }
  SUBCASE("a closed loop in three parts") {
    const Analysis a = analyse(split(chain(90, true), 3));
    REQUIRE(a.partition.parts == 3);
    CHECK(a.partition.interface_blocks <= 4);
    check_arrowhead(a);
  }
}

TEST_CASE("a model too small for its parts keeps the serial step and says why") {
  const Analysis a = analyse(split(chain(8, false), 2));
  CHECK(a.partition.parts == 1);
  CHECK(a.partition.requested == 2);
  CHECK(a.partition.serial_reason.find("parallel_min_rows") != std::string::npos);
  Model forced = split(chain(8, false), 2);
  forced.solver.parallel_min_rows = 0;
  const Analysis f = analyse(forced);
  CHECK(f.partition.parts == 2);
  check_arrowhead(f);
}

TEST_CASE("the parallel step is refused for the schemes it is not built for") {
  for (mbrt::Scheme s : {mbrt::Scheme::ali3p, mbrt::Scheme::staggered_nps, mbrt::Scheme::staggered_tree}) {
    CAPTURE(mbrt::scheme_name(s));
    try {
      analyse(split(chain(64, false), 2, s));
      FAIL("no error");
    } catch (const ModelError& e) {
      CHECK(std::string(e.what()).find("solver.parallel_parts") != std::string::npos);
      CHECK(std::string(e.what()).find("staggered-pcst, baumgarte and blajer") != std::string::npos);
    }
  }
}
