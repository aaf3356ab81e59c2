// Every specialization the generator makes gives the general code's results:
// each scene below is generated twice in this build, as the generator
// specializes it and with --no-specialize, and both run side by side. The
// analysis cases check that the specializations named do apply to the scene
// (else the comparison would prove nothing).
#include <doctest/doctest.h>

#include <algorithm>
#include <initializer_list>
#include <string>

#include "a01_general.hpp"
#include "a01_special.hpp"
#include "analysis.hpp"
#include "driven_slider_general.hpp"
#include "driven_slider_special.hpp"
#include "four_bar_ali3p_general.hpp"
#include "four_bar_ali3p_special.hpp"
#include "four_bar_general.hpp"
#include "four_bar_special.hpp"
#include "two_masses_general.hpp"
#include "two_masses_special.hpp"

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

// Whether every specialization named applies to the model file.
bool applies(const std::string& model, std::initializer_list<const char*> names) {
  const mbrt::codegen::Analysis a = mbrt::codegen::analyse(mbrt::codegen::load_model(std::string(MBRT_TEST_MODELS) + "/" + model));
  return std::all_of(names.begin(), names.end(), [&](const char* name) {
    return std::any_of(a.skipped.begin(), a.skipped.end(),
                       [&](const mbrt::codegen::Skipped& s) { return s.specialization == name; });
  });
}

}  // namespace

// Largest difference between the models <tag>_special and <tag>_general.
#define DIFFERENCE_FROM_GENERAL(tag)                                                                         \
  max_difference(mbrt::models::tag##_special::initial_state(), mbrt::models::tag##_general::initial_state(), \
                 mbrt::models::tag##_special::step, mbrt::models::tag##_general::step, kSteps)

TEST_CASE("single stage, folded weights, no drivers: the A01 pendulum equals the general code") {
  CHECK(applies("a01_pendulum.yaml", {"single_stage", "folded_weights", "no_drivers"}));
  CHECK(DIFFERENCE_FROM_GENERAL(a01) < kRoundOff);
}

TEST_CASE("principal axes and the sparse factor: the four-bar equals the general code") {
  CHECK(applies("four_bar.yaml", {"principal_axes", "sparse_factor"}));
  CHECK(DIFFERENCE_FROM_GENERAL(four_bar) < kRoundOff);
  CHECK(DIFFERENCE_FROM_GENERAL(four_bar_ali3p) < kRoundOff);
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
