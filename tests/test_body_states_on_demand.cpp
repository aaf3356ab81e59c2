// solver.body_states: on_demand (docs/staggered-tree.md, "Body states on
// demand"): the tree step leaves the bodies' world states to refresh_bodies()
// and to the tools that read them. Each model here is generated twice from
// one file, once with the states formed by every step; the joint coordinates
// must agree to the bit, and the states, energies, reactions and outputs
// formed on demand must equal the every-step model's.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>

#include "allocation_counter.hpp"
#include "analysis.hpp"
#include "arm_7_rk4.hpp"
#include "arm_7_rk4_on_demand.hpp"
#include "arm3_friction.hpp"
#include "arm3_friction_on_demand.hpp"
#include "armature_pendulum_midpoint.hpp"
#include "armature_pendulum_midpoint_on_demand.hpp"
#include "model.hpp"
#include "spatial_chain_16_revolute_tree.hpp"
#include "spatial_chain_16_revolute_tree_on_demand.hpp"

using mbrt::codegen::analyse;
using mbrt::codegen::ModelError;
using mbrt::codegen::parse_model;

namespace {

template <class A, class B>
void check_same_bodies(const A& a, const B& b) {
  REQUIRE(a.rigid.size() == b.rigid.size());
  for (std::size_t i = 0; i < a.rigid.size(); ++i) {
    CHECK(a.rigid[i].r == b.rigid[i].r);
    CHECK(a.rigid[i].p == b.rigid[i].p);
    CHECK(a.rigid[i].v == b.rigid[i].v);
    CHECK(a.rigid[i].w == b.rigid[i].w);
  }
}

}  // namespace

namespace {

template <class State>
void no_inputs(State&) {}

template <class State>
void arm3_torques(State& s) {
  s.inputs[0] = 3.0;  // N m at the shoulder, elbow and wrist, above their friction
  s.inputs[1] = -1.5;
  s.inputs[2] = 0.4;
}

}  // namespace

// Both models step the same joint coordinates by the same code; only the
// final body_states differs. Without loads other than gravity, s.rigid of the
// on-demand model stays where the initial state put it until
// refresh_bodies() forms it; every tool forms it itself. Declares e, d (the
// two models' namespaces) and a, b (their states) in the enclosing block.
#define SAME_RUN(every, lazy, steps, set_inputs, untouched)                                  \
  namespace e = mbrt::models::every;                                                      \
  namespace d = mbrt::models::lazy;                                                       \
  e::State a = e::initial_state();                                                        \
  d::State b = d::initial_state();                                                        \
  set_inputs(a);                                                                          \
  set_inputs(b);                                                                          \
  const d::State start = b;                                                               \
  for (int k = 0; k < (steps); ++k) {                                                     \
    REQUIRE(e::step(a) == mbrt::StepStatus::ok);                                          \
    REQUIRE(d::step(b) == mbrt::StepStatus::ok);                                          \
  }                                                                                       \
  CHECK(a.q == b.q);                                                                      \
  CHECK(a.qd == b.qd);                                                                    \
  CHECK(a.qdd == b.qdd);                                                                  \
  if (untouched) check_same_bodies(start, b); /* the step did not form them */           \
  CHECK(e::energy(a).kinetic == d::energy(b).kinetic); /* energy() forms them itself */   \
  CHECK(e::energy(a).potential == d::energy(b).potential);                                \
  CHECK(e::quaternion_norm_error(a) == d::quaternion_norm_error(b));                      \
  e::Reactions ra;                                                                        \
  d::Reactions rb;                                                                        \
  e::reactions(a, ra);                                                                    \
  d::reactions(b, rb);                                                                    \
  for (std::size_t j = 0; j < ra.size(); ++j) CHECK(ra[j].force_joint == rb[j].force_joint); \
  e::State ma = a;                                                                        \
  d::State mb = b;                                                                        \
  e::set_multipliers(ma);                                                                 \
  d::set_multipliers(mb);                                                                 \
  CHECK(ma.lambda == mb.lambda)

// outputs() of the models SAME_RUN declared, before refresh_bodies.
#define SAME_OUTPUTS()         \
  e::Outputs ya{};             \
  d::Outputs yb{};             \
  e::outputs(a, ya);           \
  d::outputs(b, yb);           \
  CHECK(ya == yb)

// Then the states refresh_bodies() forms are the every-step model's.
#define SAME_BODIES()    \
  d::refresh_bodies(b);  \
  check_same_bodies(a, b)

TEST_CASE("on demand, the tree steps' joint coordinates are the every-step model's to the bit") {
  SUBCASE("staggered-tree, a 16-link chain whose axes meet at general angles") {
    SAME_RUN(spatial_chain_16_revolute_tree, spatial_chain_16_revolute_tree_on_demand, 500, no_inputs, true);
    SAME_BODIES();
  }
  SUBCASE("rk4-tree, the 7-link arm") {
    SAME_RUN(arm_7_rk4, arm_7_rk4_on_demand, 500, no_inputs, true);
    SAME_BODIES();
  }
  SUBCASE("midpoint-tree with an armature and an output") {
    SAME_RUN(armature_pendulum_midpoint, armature_pendulum_midpoint_on_demand, 700, no_inputs, true);
    MESSAGE("pin angle after 0.7 s: " << a.q[0] << " rad");
    CHECK(std::abs(a.q[0]) > 1e-4);  // a third of the 2.17 s period: far from its start
    SAME_OUTPUTS();
    SAME_BODIES();
  }
  // Inputs are loads: each stage forms the states they act on, so s.rigid
  // holds a stage's until refreshed.
  SUBCASE("rk4-tree with joint friction and input torques") {
    SAME_RUN(arm3_friction, arm3_friction_on_demand, 1000, arm3_torques, false);
    SAME_OUTPUTS();
    SAME_BODIES();
  }
}

TEST_CASE("on demand, a non-finite step restores the joint coordinates") {
  namespace d = mbrt::models::spatial_chain_16_revolute_tree_on_demand;
  d::State s = d::initial_state();
  REQUIRE(d::step(s) == mbrt::StepStatus::ok);
  s.qd[5] = std::numeric_limits<double>::infinity();
  const d::State before = s;
  CHECK(d::step(s) == mbrt::StepStatus::non_finite);
  CHECK(s.t == before.t);
  CHECK(s.q == before.q);
  CHECK(s.qd == before.qd);
  CHECK(s.qdd == before.qdd);
  // The restored state's bodies are formed (where they are: the rates hold the infinity).
  d::State fresh = before;
  d::refresh_bodies(fresh);
  for (std::size_t i = 0; i < s.rigid.size(); ++i) {
    CHECK(s.rigid[i].r == fresh.rigid[i].r);
    CHECK(s.rigid[i].p == fresh.rigid[i].p);
  }
}

TEST_CASE("on demand, stepping and refreshing allocate nothing") {
  namespace d = mbrt::models::arm_7_rk4_on_demand;
  static d::Workspace w;
  d::State s = d::initial_state();
  AllocationCounter counter;
  for (int k = 0; k < 100; ++k) {
    REQUIRE(d::step(s, w) == mbrt::StepStatus::ok);
    d::refresh_bodies(s);
  }
  CHECK(std::isfinite(d::energy(s).total()));  // energy() forms the states in a copy
  CHECK(counter.count() == 0);
}

TEST_CASE("solver.body_states: bad values and schemes without joint coordinates are refused") {
  const std::string pendulum =
      "name: p\ngravity: [0, 0, -9.81]\nbodies:\n  - {name: rod, mass: 1, inertia: [0.1, 0.1, 0.01], position: [0, 0, -0.5]}\n"
      "joints:\n  - {name: pin, type: revolute, body1: ground, body2: rod, point: [0, 0, 0], axis: [0, 1, 0]}\n";
  CHECK_THROWS_WITH_AS(parse_model(pendulum + "solver: {scheme: rk4-tree, body_states: lazily}\n", "p.yaml"),
                       doctest::Contains("p.yaml:7:"), ModelError);
  CHECK_THROWS_WITH_AS(parse_model(pendulum + "solver: {scheme: rk4-tree, body_states: lazily}\n", "p.yaml"),
                       doctest::Contains("each_step"), ModelError);
  CHECK_THROWS_WITH_AS(analyse(parse_model(pendulum + "solver: {scheme: staggered-pcst, body_states: on_demand}\n", "p.yaml")),
                       doctest::Contains("on_demand needs a tree scheme"), ModelError);
  CHECK_NOTHROW(analyse(parse_model(pendulum + "solver: {scheme: midpoint-tree, body_states: on_demand}\n", "p.yaml")));
}
