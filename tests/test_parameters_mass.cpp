// Tunable masses and inertias (docs/parameters.md) in staggered-nps, ali3p and
// rk4-projected: a mass or inertia set at run time gives the closed-form
// period of the new value, at the defaults the same trajectory as the model
// generated with them folded, and neither setting nor stepping allocates.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <string_view>
#include <utility>
#include <vector>

#include "allocation_counter.hpp"
#include "physical_pendulum_ali3p.hpp"
#include "physical_pendulum_nps.hpp"
#include "physical_pendulum_rk4.hpp"
#include "tunable_physical_pendulum_ali3p.hpp"
#include "tunable_physical_pendulum_nps.hpp"
#include "tunable_physical_pendulum_rk4.hpp"

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.81;
constexpr double kArm = 0.5;  // d, pin to the link's centre

// One generated model's functions under one name, for the templates below.
#define MBRT_TUNABLE(NAME)                                                                                      \
  struct NAME##_model {                                                                                         \
    using State = mbrt::models::NAME::State;                                                                    \
    using Parameters = mbrt::models::NAME::Parameters;                                                          \
    using Workspace = mbrt::models::NAME::Workspace;                                                            \
    static Parameters defaults() { return mbrt::models::NAME::kDefaultParameters; }                             \
    static bool set(Parameters& p, std::string_view n, double v) { return mbrt::models::NAME::set_parameter(p, n, v); } \
    static State initial_state(const Parameters& p) { return mbrt::models::NAME::initial_state(p); }            \
    static mbrt::StepStatus step(State& s, Workspace& w) { return mbrt::models::NAME::step(s, w); }             \
    static double energy(const State& s) { return mbrt::models::NAME::energy(s).total(); }                      \
  }
#define MBRT_FOLDED(NAME)                                                                                       \
  struct NAME##_model {                                                                                         \
    using State = mbrt::models::NAME::State;                                                                    \
    using Workspace = mbrt::models::NAME::Workspace;                                                            \
    static State initial_state() { return mbrt::models::NAME::initial_state(); }                                \
    static mbrt::StepStatus step(State& s, Workspace& w) { return mbrt::models::NAME::step(s, w); }             \
    static double energy(const State& s) { return mbrt::models::NAME::energy(s).total(); }                      \
  }
MBRT_TUNABLE(tunable_physical_pendulum_nps);
MBRT_TUNABLE(tunable_physical_pendulum_ali3p);
MBRT_TUNABLE(tunable_physical_pendulum_rk4);
MBRT_FOLDED(physical_pendulum_nps);
MBRT_FOLDED(physical_pendulum_ali3p);
MBRT_FOLDED(physical_pendulum_rk4);

// The models of one scheme and the relative error its periods are held to
// at the step 1 ms (kStep) for the frequency w, as a function of w h. Order 2
// (staggered-nps, ali3p's trapezoidal rule): the trapezoidal rule's period
// error (w h)^2 / 12 (what ali3p shows; staggered-nps half of it), twice.
// Order 4 (rk4-projected): (w h)^4 <= 7e-9 at the largest w h below, 0.009
// (it shows 1e-9 and less).
struct Nps {
  static constexpr const char* kName = "staggered-nps";
  using Pendulum = tunable_physical_pendulum_nps_model;
  using Folded = physical_pendulum_nps_model;
  static double period_error(double wh) { return wh * wh / 6.0; }  // twice (w h)^2 / 12
};
struct Ali3p {
  static constexpr const char* kName = "ali3p";
  using Pendulum = tunable_physical_pendulum_ali3p_model;
  using Folded = physical_pendulum_ali3p_model;
  static double period_error(double wh) { return wh * wh / 6.0; }  // twice (w h)^2 / 12
};
struct Rk4 {
  static constexpr const char* kName = "rk4-projected";
  using Pendulum = tunable_physical_pendulum_rk4_model;
  using Folded = physical_pendulum_rk4_model;
  static double period_error(double) { return 1e-8; }  // (w h)^4 <= 7e-9
};

// The period of a sampled oscillation about c: twice the mean spacing of its
// crossings of c (linear interpolation), over the first n crossings.
template <class M, class Signal>
double period(typename M::State s, Signal f, double c, int n) {
  static typename M::Workspace w;
  std::vector<double> crossings;
  double t0 = s.t, f0 = f(s) - c;
  while (static_cast<int>(crossings.size()) < n && s.t < 100.0) {
    REQUIRE(M::step(s, w) == mbrt::StepStatus::ok);
    const double f1 = f(s) - c;
    if ((f0 < 0.0) != (f1 < 0.0)) crossings.push_back(t0 + (s.t - t0) * f0 / (f0 - f1));
    t0 = s.t;
    f0 = f1;
  }
  REQUIRE(static_cast<int>(crossings.size()) == n);
  return 2.0 * (crossings.back() - crossings.front()) / (n - 1);
}

double relative(double measured, double expected) { return std::abs(measured / expected - 1.0); }

}  // namespace

constexpr double kStep = 1.0e-3;  // the models' step

// Each mass or inertia below read as the file's value instead of the set one
// changes the period by 1.7 % or more, far beyond the bounds.
TEST_CASE_TEMPLATE("a physical pendulum's period follows 2 pi sqrt((J + m d^2) / (m g d)) for the mass and inertia set",
                   S, Nps, Ali3p, Rk4) {
  using M = typename S::Pendulum;
  INFO("scheme ", S::kName);
  const auto x = [](const typename M::State& s) { return s.rigid[0].r.x(); };
  for (const auto& [mass, jzz] : {std::pair{2.0, 0.03}, std::pair{2.0, 0.25}, std::pair{5.0, 0.03}, std::pair{0.7, 0.05}}) {
    typename M::Parameters p = M::defaults();
    REQUIRE(M::set(p, "link.mass", mass));
    REQUIRE(M::set(p, "link.inertia.zz", jzz));
    REQUIRE(M::set(p, "link.inertia.xx", jzz));  // a moment out of the swing's plane: no part in it
    // Small-angle period, and the amplitude theta0 the start's 0.1 rad/s reaches
    // (1 - cos theta0 = w0^2 / (2 W^2)), which lengthens the period by
    // theta0^2 / 16 + 11 theta0^4 / 3072 (the rest is below 1e-10).
    const double omega = std::sqrt(mass * kG * kArm / (jzz + mass * kArm * kArm));
    const double theta0 = std::acos(1.0 - 0.01 / (2.0 * omega * omega));
    const double expected = 2.0 * kPi / omega * (1.0 + theta0 * theta0 / 16.0 + 11.0 * std::pow(theta0, 4) / 3072.0);
    const double measured = period<M>(M::initial_state(p), x, 0.0, 7);
    CAPTURE(mass);
    CAPTURE(jzz);
    CHECK(relative(measured, expected) < S::period_error(omega * kStep));
  }
}

TEST_CASE_TEMPLATE("tunable mass and inertia at their defaults: the folded model's trajectory to round-off", S, Nps,
                   Ali3p, Rk4) {
  using T = typename S::Pendulum;
  using F = typename S::Folded;
  INFO("scheme ", S::kName);
  static typename T::Workspace wt;
  static typename F::Workspace wf;
  typename T::State a = T::initial_state(T::defaults());
  typename F::State b = F::initial_state();
  for (int i = 0; i < 2000; ++i) {
    REQUIRE(T::step(a, wt) == mbrt::StepStatus::ok);
    REQUIRE(F::step(b, wf) == mbrt::StepStatus::ok);
  }
  CHECK(std::abs(a.rigid[0].r.x()) > 1e-3);  // it swings
  CHECK((a.rigid[0].r - b.rigid[0].r).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((a.rigid[0].p - b.rigid[0].p).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((a.rigid[0].v - b.rigid[0].v).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((a.rigid[0].w - b.rigid[0].w).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(std::abs(T::energy(a) - F::energy(b)) < 1e-12);
}

TEST_CASE_TEMPLATE("setting masses and inertias and stepping allocate nothing", S, Nps, Ali3p, Rk4) {
  using M = typename S::Pendulum;
  INFO("scheme ", S::kName);
  static typename M::Workspace w;
  typename M::State s = M::initial_state(M::defaults());
  AllocationCounter counter;
  REQUIRE(M::set(s.params, "link.mass", 3.0));
  s = M::initial_state(s.params);
  for (int i = 0; i < 100; ++i) REQUIRE(M::step(s, w) == mbrt::StepStatus::ok);
  REQUIRE(M::set(s.params, "link.inertia.zz", 0.1));  // mid-run
  for (int i = 0; i < 100; ++i) REQUIRE(M::step(s, w) == mbrt::StepStatus::ok);
  CHECK(counter.count() == 0);
}
