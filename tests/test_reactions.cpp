// Joint reactions from the multipliers against independent values: the A01
// bar tension from energy conservation and the radial balance, and a welded
// bracket whose reaction follows from statics, the same in every scheme.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "a01_moved_ali3p.hpp"
#include "a01_moved_baumgarte.hpp"
#include "a01_moved_blajer.hpp"
#include "a01_moved_nps.hpp"
#include "a01_moved_pcst.hpp"
#include "a01_pendulum.hpp"
#include "cantilever_ali3p.hpp"
#include "cantilever_baumgarte.hpp"
#include "cantilever_blajer.hpp"
#include "cantilever_nps.hpp"
#include "cantilever_pcst.hpp"

namespace {

#define CANTILEVER_REACTION(model)                                 \
  [] {                                                             \
    namespace m = mbrt::models::model;                             \
    m::State s = m::initial_state();                               \
    for (int i = 0; i < 1000; ++i) REQUIRE(m::step(s) == mbrt::StepStatus::ok); \
    m::Reactions r;                                                \
    m::reactions(s, r);                                            \
    return r[m::constraint::weld];                                 \
  }()

}  // namespace

TEST_CASE("the models' names index their state and tables") {
  namespace a = mbrt::models::a01_pendulum;
  CHECK(std::string(a::kBodyInfo[a::body::bob].name) == "bob");
  CHECK_FALSE(a::kBodyInfo[a::body::bob].rigid);
  CHECK(a::kBodyInfo[a::body::bob].slot == a::particle::bob);
  CHECK(std::string(a::kConstraintInfo[a::constraint::bar].name) == "bar");
  namespace c = mbrt::models::cantilever_nps;
  CHECK(std::string(c::kBodyInfo[c::body::bracket].name) == "bracket");
  CHECK(c::kBodyInfo[c::body::bracket].rigid);
  CHECK(c::kBodyInfo[c::body::bracket].slot == c::rigid::bracket);
  CHECK(std::string(c::kConstraintInfo[c::constraint::weld].name) == "weld");
}

TEST_CASE("A01: the bar's reaction on the bob is the tension -3 m g y along the bar, towards the pivot") {
  namespace m = mbrt::models::a01_pendulum;
  m::State s = m::initial_state();
  double worst = 0.0;
  for (int i = 1; i <= 40000; ++i) {  // 10 s at 2.5e-4
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    if (i % 100 != 0) continue;
    m::Reactions r;
    m::reactions(s, r);
    const mbrt::Vec3 bob = s.particle[m::particle::bob].r;
    const mbrt::Vec3 expected = -(-3.0 * 9.81 * bob.y()) * bob.normalized();
    const mbrt::JointReaction& bar = r[m::constraint::bar];
    worst = std::max(worst, (bar.force - expected).norm());
    CHECK(bar.torque.norm() < 1e-9);  // a point mass: the force passes through the bob
  }
  MESSAGE("A01 reaction force: max deviation from the tension " << worst << " N (of up to 29.4 N)");
  CHECK(worst < 1e-2);
}

// The moved A01 (pivot at (3, 5, 0)), h = 1e-4, 10 s: the largest deviation
// of the bar's force on the bob from the tension along the bar, -3 m g (y -
// 5) towards the pivot, in units of m g.
#define MOVED_A01_DEVIATION(model)                                                         \
  [] {                                                                                     \
    namespace m = mbrt::models::model;                                                     \
    const mbrt::Vec3 pivot(3, 5, 0);                                                       \
    m::State s = m::initial_state();                                                       \
    double worst = 0.0;                                                                    \
    for (int i = 1; i <= 100000; ++i) {                                                    \
      REQUIRE(m::step(s) == mbrt::StepStatus::ok);                                         \
      if (i % 100 != 0) continue;                                                          \
      m::Reactions r;                                                                      \
      m::reactions(s, r);                                                                  \
      const mbrt::Vec3 bob = s.particle[m::particle::bob].r;                               \
      const mbrt::Vec3 expected = -3.0 * 9.81 * (bob.y() - pivot.y()) * (pivot - bob).normalized(); \
      worst = std::max(worst, (r[m::constraint::bar].force - expected).norm() / 9.81);     \
    }                                                                                      \
    return worst;                                                                          \
  }()

// Friction takes its normal loads from these forces, so they must follow
// Newton's law wherever the model sits. ali3p's multipliers lambda* + alpha
// Phi + nu carried round-off in Phi times alpha = 6.4e13 (1.8e-2 m g here);
// it now takes the multipliers from Newton's law at the step's end (measured
// 1e-7 m g). The staggered schemes' multipliers include their penalty
// stabilization (measured 2.75e-4 m g), baumgarte 5e-8, blajer 4e-7.
TEST_CASE("moved A01: the bar's force is the tension along the bar in every scheme") {
  const double pcst = MOVED_A01_DEVIATION(a01_moved_pcst), nps = MOVED_A01_DEVIATION(a01_moved_nps);
  const double baumgarte = MOVED_A01_DEVIATION(a01_moved_baumgarte), blajer = MOVED_A01_DEVIATION(a01_moved_blajer);
  const double ali3p = MOVED_A01_DEVIATION(a01_moved_ali3p);
  MESSAGE("largest deviation (m g): staggered-pcst " << pcst << ", staggered-nps " << nps << ", baumgarte " << baumgarte
                                                     << ", blajer " << blajer << ", ali3p " << ali3p);
  CHECK(pcst < 5e-4);
  CHECK(nps < 5e-4);
  CHECK(baumgarte < 1e-5);
  CHECK(blajer < 1e-5);
  CHECK(ali3p < 1e-5);
}

TEST_CASE("welded bracket: f = -m g and t = -(c - p) x m g about the weld, in every scheme") {
  const double m = 2.0;
  const mbrt::Vec3 g(0, 0, -9.81), c(0.5, 0.2, -0.1), p(0, 0, 0);
  const mbrt::Vec3 force = -m * g, torque = -(c - p).cross(m * g);
  for (const mbrt::JointReaction& r : {CANTILEVER_REACTION(cantilever_pcst), CANTILEVER_REACTION(cantilever_baumgarte),
                                       CANTILEVER_REACTION(cantilever_blajer), CANTILEVER_REACTION(cantilever_ali3p),
                                       CANTILEVER_REACTION(cantilever_nps)}) {
    MESSAGE("force " << r.force.transpose() << ", torque " << r.torque.transpose());
    CHECK((r.force - force).norm() < 1e-6);
    CHECK((r.torque - torque).norm() < 1e-6);
    // The joint frame is a rotation of the world axes: lengths agree.
    CHECK(std::abs(r.force_joint.norm() - r.force.norm()) < 1e-9);
    CHECK(std::abs(r.torque_joint.norm() - r.torque.norm()) < 1e-9);
  }
}
