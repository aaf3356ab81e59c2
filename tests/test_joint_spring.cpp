// joint_spring against closed forms: a rotor on a torsional spring, the same
// with a damper, and a block on a linear spring along a prismatic joint, each
// under staggered-pcst (in plane coordinates), ali3p (spatial) and
// staggered-tree and midpoint-tree (joint coordinates); and the armature of a
// geared joint, on the rotor and on a pendulum, under both tree schemes.
//
// Tolerances follow from the leading errors of second-order methods on the
// linear oscillator x'' + 2 zeta x' + w^2 x = 0 at step h, a mode
// exp(lambda t). The trapezoidal rule (ali3p; Newmark's average
// acceleration) turns lambda into (2 / h) atanh(lambda h / 2) = lambda (1 +
// (lambda h)^2 / 12 + ...): the period lengthens by (w h)^2 / 12 and, with
// lambda = -zeta + i w_d, the decay rate drops by (w h)^2 / 4. Stormer-Verlet
// (the staggered kick-drift-kick) shortens the period by (w h)^2 / 24 and
// keeps x^2 w^2 + v^2 (1 - (w h / 2)^2), so the energy at the steps swings by
// (w h)^2 / 4 (Hughes 1987, "The Finite Element Method: Linear Static and
// Dynamic Finite Element Analysis", ch. 9; Hairer, Lubich and Wanner 2006,
// "Geometric Numerical Integration", ch. I.5). With w h = 6.3e-3 (rotor) or
// 5e-3 (slider), every relative check allows (w h)^2 / 2, twice the largest
// of these.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "armature_pendulum.hpp"
#include "armature_rotor.hpp"
#include "armature_pendulum_midpoint.hpp"
#include "armature_rotor_midpoint.hpp"
#include "damped_rotor_ali3p.hpp"
#include "damped_rotor_midpoint.hpp"
#include "damped_rotor_pcst.hpp"
#include "damped_rotor_tree.hpp"
#include "spring_slider_ali3p.hpp"
#include "spring_slider_midpoint.hpp"
#include "spring_slider_pcst.hpp"
#include "spring_slider_tree.hpp"
#include "torsion_rotor_ali3p.hpp"
#include "torsion_rotor_midpoint.hpp"
#include "torsion_rotor_pcst.hpp"
#include "torsion_rotor_tree.hpp"

// A generated model with one output, its joint coordinate.
#define SPRING_MODEL(Tag, ns)                                                     \
  struct Tag {                                                                    \
    static constexpr const char* kName = #ns;                                     \
    static constexpr double kStep = mbrt::models::ns::kStep;                      \
    using State = mbrt::models::ns::State;                                        \
    static State initial_state() { return mbrt::models::ns::initial_state(); }    \
    static mbrt::StepStatus step(State& s) { return mbrt::models::ns::step(s); }  \
    static double energy(const State& s) { return mbrt::models::ns::energy(s).total(); } \
    static double coordinate(const State& s) {                                    \
      mbrt::models::ns::Outputs y;                                                \
      mbrt::models::ns::outputs(s, y);                                            \
      return y[0];                                                                \
    }                                                                             \
  }

namespace {

SPRING_MODEL(TorsionPcst, torsion_rotor_pcst);
SPRING_MODEL(TorsionAli3p, torsion_rotor_ali3p);
SPRING_MODEL(DampedPcst, damped_rotor_pcst);
SPRING_MODEL(DampedAli3p, damped_rotor_ali3p);
SPRING_MODEL(SliderPcst, spring_slider_pcst);
SPRING_MODEL(SliderAli3p, spring_slider_ali3p);
SPRING_MODEL(TorsionTree, torsion_rotor_tree);
SPRING_MODEL(DampedTree, damped_rotor_tree);
SPRING_MODEL(SliderTree, spring_slider_tree);
SPRING_MODEL(TorsionMidpoint, torsion_rotor_midpoint);
SPRING_MODEL(DampedMidpoint, damped_rotor_midpoint);
SPRING_MODEL(SliderMidpoint, spring_slider_midpoint);
SPRING_MODEL(ArmatureRotor, armature_rotor);
SPRING_MODEL(ArmaturePendulum, armature_pendulum);
SPRING_MODEL(ArmatureRotorMidpoint, armature_rotor_midpoint);
SPRING_MODEL(ArmaturePendulumMidpoint, armature_pendulum_midpoint);

// The models' data (tests/models/*.yaml).
constexpr double kRotorInertia = 0.05, kRotorStiffness = 2.0, kRotorDamping = 0.05, kRotorRest = 0.1;
constexpr double kSliderMass = 2.0, kSliderStiffness = 50.0, kSliderRest = 0.05;

// The joint coordinate minus its rest value, and the energy, at every step.
struct Trace {
  double h;
  std::vector<double> x;
  std::vector<double> energy;
  double t(size_t k) const { return static_cast<double>(k) * h; }
};

template <class M>
Trace run(double t_end, double rest) {
  Trace trace{M::kStep, {}, {}};
  typename M::State s = M::initial_state();
  const long steps = std::lround(t_end / M::kStep);
  for (long k = 0; k <= steps; ++k) {
    if (k > 0) REQUIRE(M::step(s) == mbrt::StepStatus::ok);
    trace.x.push_back(M::coordinate(s) - rest);
    trace.energy.push_back(M::energy(s));
  }
  return trace;
}

// Times where x crosses zero upwards, linearly interpolated between steps.
std::vector<double> upward_zeros(const Trace& tr) {
  std::vector<double> out;
  for (size_t k = 1; k < tr.x.size(); ++k) {
    if (tr.x[k - 1] < 0.0 && tr.x[k] >= 0.0) out.push_back(tr.t(k - 1) + tr.h * tr.x[k - 1] / (tr.x[k - 1] - tr.x[k]));
  }
  return out;
}

double mean_period(const std::vector<double>& zeros) {
  REQUIRE(zeros.size() >= 3);
  return (zeros.back() - zeros.front()) / static_cast<double>(zeros.size() - 1);
}

// Extrema of x (time, |x|), each from the parabola through three steps.
struct Extremum {
  double t, magnitude;
};
std::vector<Extremum> extrema(const Trace& tr) {
  std::vector<Extremum> out;
  for (size_t k = 1; k + 1 < tr.x.size(); ++k) {
    const double a = tr.x[k - 1], b = tr.x[k], c = tr.x[k + 1];
    if ((b - a) * (c - b) >= 0.0) continue;
    const double offset = 0.5 * (a - c) / (a - 2.0 * b + c);  // in steps from k
    out.push_back({tr.t(k) + offset * tr.h, std::abs(b - 0.25 * (a - c) * offset)});
  }
  return out;
}

double max_relative_energy_drift(const Trace& tr) {
  double worst = 0.0;
  for (double e : tr.energy) worst = std::max(worst, std::abs(e - tr.energy.front()) / tr.energy.front());
  return worst;
}

// Undamped: x = rest - amplitude cos(w t - phase); period, amplitude over
// the last period and energy.
template <class M>
void check_undamped(double omega, double amplitude, double t_end, double rest) {
  const Trace tr = run<M>(t_end, rest);
  const double w_h = omega * M::kStep;
  const double period = mean_period(upward_zeros(tr));
  const double period_error = period / (2.0 * M_PI / omega) - 1.0;
  const auto last_period = tr.x.end() - std::lround(2.0 * M_PI / omega / M::kStep);
  const auto [low, high] = std::minmax_element(last_period, tr.x.end());
  const double amplitude_error = 0.5 * (*high - *low) / amplitude - 1.0;
  const double mean = 0.5 * (*high + *low);  // of x: the equilibrium is at rest
  const double drift = max_relative_energy_drift(tr);
  MESSAGE(std::string(M::kName) << ": period error " << period_error << ", amplitude error " << amplitude_error
                   << ", equilibrium offset " << mean << ", energy drift " << drift << " (w h = " << w_h << ")");
  const double tolerance = w_h * w_h / 2.0;
  CHECK(std::abs(period_error) < tolerance);
  // The sampled peak misses the true one by at most h / 2: (w h)^2 / 8 relative.
  CHECK(std::abs(amplitude_error) < tolerance);
  CHECK(std::abs(mean) < amplitude * tolerance);
  CHECK(drift < tolerance);
}

}  // namespace

TEST_CASE_TEMPLATE("torsion rotor: period 2 pi sqrt(J / k), amplitude and energy kept", M, TorsionPcst, TorsionAli3p,
                   TorsionTree, TorsionMidpoint) {
  check_undamped<M>(std::sqrt(kRotorStiffness / kRotorInertia), kRotorRest, 10.0, kRotorRest);
}

TEST_CASE_TEMPLATE("spring slider: period 2 pi sqrt(m / k) about d = rest, energy kept", M, SliderPcst, SliderAli3p,
                   SliderTree, SliderMidpoint) {
  check_undamped<M>(std::sqrt(kSliderStiffness / kSliderMass), kSliderRest, 12.0, kSliderRest);
}

// tests/models/armature_rotor.yaml: the torsion rotor with an armature of
// 0.05 kg m^2, which the joint coordinate alone feels.
TEST_CASE_TEMPLATE("armature: the rotor's period is 2 pi sqrt((J + armature) / k)", M, ArmatureRotor,
                   ArmatureRotorMidpoint) {
  check_undamped<M>(std::sqrt(kRotorStiffness / (kRotorInertia + 0.05)), kRotorRest, 10.0, kRotorRest);
}

// tests/models/armature_pendulum.yaml: m = 2 kg, L = 1 m, armature 0.5 kg m^2,
// pushed at 0.002 rad/s from the bottom: amplitude 0.002 / w, whose
// finite-amplitude period correction (amplitude^2 / 16 = 3e-8) is far below
// the tolerance.
TEST_CASE_TEMPLATE("armature: a pendulum's period is 2 pi sqrt((m L^2 / 3 + armature) / (m g L / 2))", M,
                   ArmaturePendulum, ArmaturePendulumMidpoint) {
  const double m = 2.0, length = 1.0, g = 9.81, armature = 0.5;
  const double omega = std::sqrt(m * g * length / 2.0 / (m * length * length / 3.0 + armature));
  check_undamped<M>(omega, 0.002 / omega, 12.0, 0.0);
}

// Underdamped: x = -rest exp(-zeta t) (cos(w_d t) + zeta / w_d sin(w_d t)),
// zeta = c / (2 J): its extrema fall at t = n pi / w_d with |x| = rest
// exp(-zeta t), its zeros pi / w_d apart.
TEST_CASE_TEMPLATE("damped rotor: decay exp(-c t / (2 J)) at sqrt(k / J - (c / 2 J)^2)", M, DampedPcst, DampedAli3p,
                   DampedTree, DampedMidpoint) {
  const double zeta = kRotorDamping / (2.0 * kRotorInertia);
  const double omega = std::sqrt(kRotorStiffness / kRotorInertia);
  const double omega_d = std::sqrt(omega * omega - zeta * zeta);
  const Trace tr = run<M>(8.0, kRotorRest);
  const double w_h = omega * M::kStep;

  const double omega_error = 2.0 * M_PI / mean_period(upward_zeros(tr)) / omega_d - 1.0;
  const std::vector<Extremum> peaks = extrema(tr);
  REQUIRE(peaks.size() >= 10);
  const double decay = -std::log(peaks.back().magnitude / peaks.front().magnitude) / (peaks.back().t - peaks.front().t);
  const double decay_error = decay / zeta - 1.0;
  double worst = 0.0;  // against the closed form, relative to the initial offset
  for (size_t k = 0; k < tr.x.size(); ++k) {
    const double t = tr.t(k);
    const double exact = -kRotorRest * std::exp(-zeta * t) * (std::cos(omega_d * t) + zeta / omega_d * std::sin(omega_d * t));
    worst = std::max(worst, std::abs(tr.x[k] - exact) / kRotorRest);
  }
  MESSAGE(std::string(M::kName) << ": damped frequency error " << omega_error << ", decay rate error " << decay_error
                   << ", max trajectory error " << worst << " of the offset (w h = " << w_h << ")");
  const double tolerance = w_h * w_h / 2.0;
  CHECK(std::abs(omega_error) < tolerance);
  CHECK(std::abs(decay_error) < tolerance);
  // A phase error of (w h)^2 / 12 per radian on an amplitude exp(-zeta t):
  // w t exp(-zeta t) (w h)^2 / 12 is largest at t = 1 / zeta; twice that.
  CHECK(worst < 2.0 * omega / (M_E * zeta) * w_h * w_h / 12.0);
}
