// Every specialization the generator makes gives the general code's results:
// each scene below is generated twice in this build, as the generator
// specializes it and with --no-specialize, and both run side by side. The
// analysis cases check that the specializations named do apply to the scene
// (else the comparison would prove nothing).
#include <doctest/doctest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>

#include "a01_general.hpp"
#include "a01_planar.hpp"
#include "a01_spatial.hpp"
#include "a01_special.hpp"
#include "analysis.hpp"
#include "boom_cylinder_planar.hpp"
#include "boom_cylinder_spatial.hpp"
#include "chain_10_planar.hpp"
#include "chain_10_spatial.hpp"
#include "driven_slider_general.hpp"
#include "driven_slider_planar.hpp"
#include "driven_slider_spatial.hpp"
#include "driven_slider_special.hpp"
#include "four_bar_ali3p_general.hpp"
#include "four_bar_ali3p_special.hpp"
#include "four_bar_general.hpp"
#include "four_bar_planar.hpp"
#include "four_bar_spatial.hpp"
#include "four_bar_special.hpp"
#include "loaded_four_bar_planar.hpp"
#include "loaded_four_bar_planar_general.hpp"
#include "loaded_four_bar_spatial.hpp"
#include "loaded_four_bar_baumgarte_planar.hpp"
#include "loaded_four_bar_baumgarte_spatial.hpp"
#include "loaded_four_bar_blajer_planar.hpp"
#include "loaded_four_bar_blajer_spatial.hpp"
#include "loaded_four_bar_xz_planar.hpp"
#include "loaded_four_bar_xz_spatial.hpp"
#include "loaded_four_bar_yz_planar.hpp"
#include "loaded_four_bar_yz_spatial.hpp"
#include "slider_crank_planar.hpp"
#include "slider_crank_spatial.hpp"
#include "two_masses_general.hpp"
#include "two_masses_special.hpp"
#include "model_adapter.hpp"

namespace {

template <class A, class B>
double state_difference(const A& a, const B& b) {
  double d = 0.0;
  for (size_t i = 0; i < a.rigid.size(); ++i) {
    const auto& x = a.rigid[i];
    const auto& y = b.rigid[i];
    d = std::max({d, (x.r - y.r).cwiseAbs().maxCoeff(), (x.p - y.p).cwiseAbs().maxCoeff(),
                  (x.v - y.v).cwiseAbs().maxCoeff(), (x.w - y.w).cwiseAbs().maxCoeff()});
  }
  for (size_t i = 0; i < a.particle.size(); ++i) {
    d = std::max({d, (a.particle[i].r - b.particle[i].r).cwiseAbs().maxCoeff(),
                  (a.particle[i].v - b.particle[i].v).cwiseAbs().maxCoeff()});
  }
  return d;
}

// Largest difference of positions, Euler parameters and velocities over the run.
template <class A, class B, class StepA, class StepB>
double max_difference(A a, B b, StepA step_a, StepB step_b, int steps) {
  double d = state_difference(a, b);
  for (int i = 0; i < steps; ++i) {
    REQUIRE(step_a(a) == mbrt::StepStatus::ok);
    REQUIRE(step_b(b) == mbrt::StepStatus::ok);
    d = std::max(d, state_difference(a, b));
  }
  return d;
}

constexpr int kSteps = 2000;
constexpr double kRoundOff = 1e-10;  // m, m/s, rad/s: states are of order 1
// staggered-pcst's position stage on a loop with redundant rows solves a
// shifted Newton system (docs/stability.md) whose residual the two codes reach
// by different sums: measured 1.4e-10 on the four-bar over the run.
constexpr double kRedundantRoundOff = 1e-9;

// Whether every specialization named applies to the model file (in tests/models, or a path).
bool applies(const std::string& model, std::initializer_list<const char*> names) {
  const std::string file = model.find('/') == std::string::npos ? std::string(MBRT_TEST_MODELS) + "/" + model : model;
  const mbrt::codegen::Analysis a = mbrt::codegen::analyse(mbrt::codegen::load_model(file));
  return std::all_of(names.begin(), names.end(), [&](const char* name) {
    return std::any_of(a.skipped.begin(), a.skipped.end(),
                       [&](const mbrt::codegen::Skipped& s) { return s.specialization == name; });
  });
}

}  // namespace

// Largest difference between the models <tag>_special and <tag>_general.
#define DIFFERENCE_FROM_GENERAL(tag)                                                                         \
  max_difference(mbrt::models::tag##_special::initial_state(), mbrt::models::tag##_general::initial_state(), \
                 STEP_OF(mbrt::models::tag##_special), STEP_OF(mbrt::models::tag##_general), kSteps)

TEST_CASE("single stage, folded weights, no drivers: the A01 pendulum equals the general code") {
  CHECK(applies("a01_pendulum.yaml", {"single_stage", "folded_weights", "no_drivers"}));
  CHECK(DIFFERENCE_FROM_GENERAL(a01) < kRoundOff);
}

TEST_CASE("principal axes and the sparse factor: the four-bar equals the general code") {
  CHECK(applies("four_bar.yaml", {"principal_axes", "sparse_factor"}));
  CHECK(DIFFERENCE_FROM_GENERAL(four_bar) < kRedundantRoundOff);
  CHECK(DIFFERENCE_FROM_GENERAL(four_bar_ali3p) < kRoundOff);
}

// Largest difference between the models <tag>_planar and <tag>_spatial
// (--no-specialize=planar), of the states and of the multipliers.
#define DIFFERENCE_FROM_SPATIAL(tag)                                                                         \
  max_difference(mbrt::models::tag##_planar::initial_state(), mbrt::models::tag##_spatial::initial_state(), \
                 STEP_OF(mbrt::models::tag##_planar), STEP_OF(mbrt::models::tag##_spatial), kSteps)

template <class A, class B, class StepA, class StepB>
double multiplier_difference(A a, B b, StepA step_a, StepB step_b) {
  double d = 0.0;
  for (int i = 0; i < kSteps; ++i) {
    REQUIRE(step_a(a) == mbrt::StepStatus::ok);
    REQUIRE(step_b(b) == mbrt::StepStatus::ok);
    d = std::max(d, (a.lambda - b.lambda).cwiseAbs().maxCoeff());
  }
  return d;
}

#define MULTIPLIER_DIFFERENCE_FROM_SPATIAL(tag)                                                            \
  multiplier_difference(mbrt::models::tag##_planar::initial_state(), mbrt::models::tag##_spatial::initial_state(), \
                        STEP_OF(mbrt::models::tag##_planar), STEP_OF(mbrt::models::tag##_spatial))

constexpr double kMultiplierRoundOff = 1e-7;  // N: the multipliers are of order 10 and see 2/h^2 times phi
// The same for staggered-pcst on the loops with redundant rows: the spatial
// code's shifted Newton system leaves a residual of order 1e-12 m that the
// planar code (rows independent) does not, and the multipliers see it times 2/h^2.
constexpr double kRedundantMultiplierRoundOff = 2e-5;

TEST_CASE("planar coordinates: the A01 pendulum, the four-bar and a 10-link chain equal the spatial code") {
  CHECK(applies("a01_pendulum.yaml", {"planar"}));
  CHECK(applies("four_bar.yaml", {"planar"}));
  CHECK(applies(std::string(MBRT_TIMING_MODELS) + "/chain_10.yaml", {"planar"}));
  CHECK(DIFFERENCE_FROM_SPATIAL(a01) < kRoundOff);
  CHECK(DIFFERENCE_FROM_SPATIAL(four_bar) < kRedundantRoundOff);
  CHECK(DIFFERENCE_FROM_SPATIAL(chain_10) < kRoundOff);
  // The in-plane multipliers land on their spatial rows; the others are zero in both.
  CHECK(MULTIPLIER_DIFFERENCE_FROM_SPATIAL(a01) < kMultiplierRoundOff);
  CHECK(MULTIPLIER_DIFFERENCE_FROM_SPATIAL(four_bar) < kRedundantMultiplierRoundOff);
  CHECK(MULTIPLIER_DIFFERENCE_FROM_SPATIAL(chain_10) < kMultiplierRoundOff);
}

TEST_CASE("planar coordinates: a four-bar under a damped spring, torques, a point force and an input equals the spatial code") {
  CHECK(applies("loaded_four_bar.yaml", {"planar"}));
  CHECK(DIFFERENCE_FROM_SPATIAL(loaded_four_bar) < kRedundantRoundOff);
  CHECK(MULTIPLIER_DIFFERENCE_FROM_SPATIAL(loaded_four_bar) < kRedundantMultiplierRoundOff);
}

TEST_CASE("planar coordinates in baumgarte and blajer: the loaded four-bar equals the spatial code") {
  const auto four_bar_in = [](const char* scheme) {
    mbrt::codegen::Model m = mbrt::codegen::load_model(std::string(MBRT_TEST_MODELS) + "/loaded_four_bar.yaml");
    m.solver.scheme = *mbrt::scheme_from_name(scheme);
    return m;
  };
  CHECK(mbrt::codegen::analyse(four_bar_in("baumgarte")).planar.applies);
  CHECK(mbrt::codegen::analyse(four_bar_in("blajer")).planar.applies);
  CHECK(DIFFERENCE_FROM_SPATIAL(loaded_four_bar_baumgarte) < kRoundOff);
  CHECK(MULTIPLIER_DIFFERENCE_FROM_SPATIAL(loaded_four_bar_baumgarte) < kMultiplierRoundOff);
  // Blajer's corrections take a body's rotation through the same increments.
  CHECK(DIFFERENCE_FROM_SPATIAL(loaded_four_bar_blajer) < kRoundOff);
  CHECK(MULTIPLIER_DIFFERENCE_FROM_SPATIAL(loaded_four_bar_blajer) < kMultiplierRoundOff);
}

TEST_CASE("planar coordinates in the x-z and y-z planes: the loaded four-bar turned into them equals the spatial code") {
  using namespace mbrt::codegen;
  const Analysis xz = analyse(load_model(std::string(MBRT_TEST_MODELS) + "/loaded_four_bar_xz.yaml"));
  CHECK(xz.planar.applies);
  CHECK(xz.planar.normal == 1);
  const Analysis yz = analyse(load_model(std::string(MBRT_TEST_MODELS) + "/loaded_four_bar_yz.yaml"));
  CHECK(yz.planar.applies);
  CHECK(yz.planar.normal == 0);
  CHECK(DIFFERENCE_FROM_SPATIAL(loaded_four_bar_xz) < kRoundOff);
  CHECK(MULTIPLIER_DIFFERENCE_FROM_SPATIAL(loaded_four_bar_xz) < kRedundantMultiplierRoundOff);
  CHECK(DIFFERENCE_FROM_SPATIAL(loaded_four_bar_yz) < kRoundOff);
  CHECK(MULTIPLIER_DIFFERENCE_FROM_SPATIAL(loaded_four_bar_yz) < kRedundantMultiplierRoundOff);
}

TEST_CASE("planar coordinates: the loaded four-bar in the x-z plane moves as the x-y one turned about x") {
  auto xy = mbrt::models::loaded_four_bar_planar::initial_state();
  auto xz = mbrt::models::loaded_four_bar_xz_planar::initial_state();
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.5 * M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  double moved = 0.0, difference = 0.0;
  for (int i = 0; i < kSteps; ++i) {
    REQUIRE(mbrt::models::loaded_four_bar_planar::step(xy) == mbrt::StepStatus::ok);
    REQUIRE(mbrt::models::loaded_four_bar_xz_planar::step(xz) == mbrt::StepStatus::ok);
  }
  for (size_t b = 0; b < xy.rigid.size(); ++b) {
    moved = std::max(moved, (xy.rigid[b].r - mbrt::models::loaded_four_bar_planar::initial_state().rigid[b].r).norm());
    difference = std::max(difference, (xz.rigid[b].r - turn * xy.rigid[b].r).norm());
  }
  CHECK(moved > 0.1);
  CHECK(difference < kRoundOff);
}

// The state after the comparison's run: the scene must have moved for the comparison to mean anything.
template <class State, class Step>
State after_run(State s, Step step) {
  for (int i = 0; i < kSteps; ++i) REQUIRE(step(s) == mbrt::StepStatus::ok);
  return s;
}

TEST_CASE("planar coordinates: a slider-crank driven at the crank (joint_angle driver, prismatic joint) equals the spatial code") {
  CHECK(applies("slider_crank.yaml", {"planar"}));
  CHECK(DIFFERENCE_FROM_SPATIAL(slider_crank) < kRoundOff);
  CHECK(MULTIPLIER_DIFFERENCE_FROM_SPATIAL(slider_crank) < kMultiplierRoundOff);
  // The crank has turned 8 rad, more than a turn: the slider has reached
  // both dead centres, x = 0.2 and 0.8.
  namespace m = mbrt::models::slider_crank_planar;
  double x_min = 1.0, x_max = 0.0;
  m::State s = m::initial_state();
  for (int i = 0; i < kSteps; ++i) {
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    x_min = std::min(x_min, s.rigid[2].r.x());
    x_max = std::max(x_max, s.rigid[2].r.x());
  }
  CHECK(x_min < 0.201);
  CHECK(x_max > 0.799);
}

TEST_CASE("planar coordinates: the driven slider (joint_distance driver, prismatic joint along x) equals the spatial code") {
  CHECK(applies("driven_slider.yaml", {"planar"}));
  CHECK(DIFFERENCE_FROM_SPATIAL(driven_slider) < kRoundOff);
  CHECK(MULTIPLIER_DIFFERENCE_FROM_SPATIAL(driven_slider) < kMultiplierRoundOff);
  namespace m = mbrt::models::driven_slider_planar;
  const m::State s = after_run(m::initial_state(), STEP_OF(m));
  CHECK(s.rigid[0].r.x() == doctest::Approx(2.0).epsilon(1e-6));  // x = t^2 / 2 at t = 2 s
}

TEST_CASE("planar coordinates: a boom on a distance driver, a carriage pushed by a joint_force input along it, equal the spatial code") {
  CHECK(applies("boom_cylinder.yaml", {"planar"}));
  CHECK(DIFFERENCE_FROM_SPATIAL(boom_cylinder) < kRoundOff);
  CHECK(MULTIPLIER_DIFFERENCE_FROM_SPATIAL(boom_cylinder) < kMultiplierRoundOff);
  // The boom has turned (from e3 = 0), and the carriage has moved along it,
  // on the boom's line through the pivot at the origin.
  namespace m = mbrt::models::boom_cylinder_planar;
  const m::State s0 = m::initial_state();
  const m::State s = after_run(s0, STEP_OF(m));
  CHECK(std::abs(s.rigid[0].p[3]) > 0.05);
  CHECK(std::abs(s.rigid[1].r.norm() - s0.rigid[1].r.norm()) > 0.1);
}

TEST_CASE("planar coordinates refuse a prismatic axis out of the plane and a distance driver across planes") {
  using namespace mbrt::codegen;
  Model tilted = load_model(std::string(MBRT_TEST_MODELS) + "/slider_crank.yaml");
  tilted.joints[3].axis = Eigen::Vector3d(0.6, 0.0, 0.8);
  // The x-y plane's reason comes first, then the other planes'.
  CHECK(analyse(tilted).planar.refusal.rfind("the axis of joint rail is not in the x-y plane; ", 0) == 0);
  Model across = load_model(std::string(MBRT_TEST_MODELS) + "/boom_cylinder.yaml");
  across.drivers[0].point1.z() = 0.1;
  CHECK(analyse(across).planar.refusal.rfind("the points of distance driver cylinder are not in one x-y plane; ", 0) == 0);
}

TEST_CASE("planar coordinates with every other specialization turned off equal the planar step") {
  mbrt::codegen::Specializations planar_only = mbrt::codegen::Specializations::none();
  planar_only.planar = true;
  const mbrt::codegen::Analysis a =
      mbrt::codegen::analyse(mbrt::codegen::load_model(std::string(MBRT_TEST_MODELS) + "/loaded_four_bar.yaml"), planar_only);
  CHECK(a.planar.applies);
  CHECK(max_difference(mbrt::models::loaded_four_bar_planar::initial_state(),
                       mbrt::models::loaded_four_bar_planar_general::initial_state(),
                       STEP_OF(mbrt::models::loaded_four_bar_planar), STEP_OF(mbrt::models::loaded_four_bar_planar_general),
                       kSteps) < kRoundOff);
}

TEST_CASE("planar coordinates: the four-bar keeps 8 of its 20 rows; --no-specialize=planar keeps all") {
  using namespace mbrt::codegen;
  const Model four_bar = load_model(std::string(MBRT_TEST_MODELS) + "/four_bar.yaml");
  const Analysis a = analyse(four_bar);
  CHECK(a.planar.applies);
  CHECK(a.planar.constraint_rows == 8);
  CHECK(a.constraint_rows == 20);
  Specializations no_planar;
  no_planar.planar = false;
  const Analysis b = analyse(four_bar, no_planar);
  CHECK_FALSE(b.planar.applies);
  CHECK(std::none_of(b.skipped.begin(), b.skipped.end(), [](const Skipped& s) { return s.specialization == "planar"; }));
}

TEST_CASE("planar coordinates do not apply to the heavy top, nor to the four-bar in another scheme") {
  using namespace mbrt::codegen;
  const Analysis top = analyse(load_model(std::string(MBRT_TEST_MODELS) + "/heavy_top.yaml"));
  CHECK_FALSE(top.planar.applies);
  CHECK_FALSE(top.planar.refusal.empty());
  Model four_bar = load_model(std::string(MBRT_TEST_MODELS) + "/four_bar.yaml");
  four_bar.solver.scheme = mbrt::Scheme::ali3p;
  const Analysis ali3p = analyse(four_bar);
  CHECK_FALSE(ali3p.planar.applies);
  CHECK(ali3p.planar.refusal == "not for scheme ali3p");
}

TEST_CASE("isotropic bodies: the driven slider equals the general code") {
  CHECK(applies("driven_slider.yaml", {"isotropic"}));
  CHECK(DIFFERENCE_FROM_GENERAL(driven_slider) < kRoundOff);
}

TEST_CASE("gravity-free, unloaded bodies: the pursuit of two masses equals the general code") {
  CHECK(applies("two_masses.yaml", {"gravity_free", "unloaded_bodies"}));
  CHECK(DIFFERENCE_FROM_GENERAL(two_masses) < kRoundOff);
}

TEST_CASE("without specializations nothing is left out but the particles' rotations") {
  using namespace mbrt::codegen;
  for (const char* model : {"a01_pendulum.yaml", "four_bar.yaml", "driven_slider.yaml", "two_masses.yaml"}) {
    const Analysis a = analyse(load_model(std::string(MBRT_TEST_MODELS) + "/" + model), Specializations::none());
    for (const Skipped& s : a.skipped) CHECK_MESSAGE(s.specialization == "particles", model << ": " << s.removed);
  }
}
