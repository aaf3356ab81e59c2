// Andrews' squeezing mechanism (tests/models/benchmarks/a03_andrews_squeezer.yaml;
// IFToMM / lim.ii.udc.es A03 and the Test Set for IVP Solvers problem
// "andrews"), over the Test Set's interval [0, 0.03] s, in each scheme at
// h = 1e-5 (3000 steps; the crank turns 2.5 times and reaches 1140 rad/s).
//
// Reference: the Test Set's solution at t = 0.03 (deTestSet Ex_andrews.f
// `andsoln`, the same in MEBDFI's andrewi.f; PSIDE at rtol = atol = 1e-14),
// the seven angles y(1..7) = (beta, Theta, gamma, Phi, delta, Omega,
// epsilon) and their rates y(8..14), embedded below. They are recovered from
// the bodies' rotations about z: each body's absolute angle is its initial
// angle (from q0) plus its rotation since t = 0, unwrapped step by step;
// Theta, Phi and Omega are relative angles (rod_fe - crank, rod_ge - link_ag,
// rod_he - link_ah).
// Also checked: the A03 energy balance T + V - E0 - mom (beta - beta0) = 0.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <string_view>

#include "andrews_ali3p.hpp"
#include "andrews_baumgarte.hpp"
#include "andrews_blajer.hpp"
#include "andrews_nps.hpp"
#include "andrews_pcst.hpp"
#include "model_adapter.hpp"

namespace {

BENCH_MODEL(Pcst, andrews_pcst);
BENCH_MODEL(Baumgarte, andrews_baumgarte);
BENCH_MODEL(Blajer, andrews_blajer);
BENCH_MODEL(Nps, andrews_nps);
BENCH_MODEL(Ali3p, andrews_ali3p);

// Consistent initial angles q0 of the Test Set (beta, Theta, gamma, Phi, delta, Omega, epsilon).
constexpr std::array<double, 7> kQ0 = {-0.0617138900142764496358948458001, 0.0,
                                       0.455279819163070380255912382449,   0.222668390165885884674473185609,
                                       0.487364979543842550225598953530,   -0.222668390165885884674473185609,
                                       1.23054744454982119249735015568};
// Test Set reference solution at t = 0.03: y(1..7) angles, y(8..14) rates.
constexpr std::array<double, 7> kQRef = {0.1581077119629904e+2,  -0.1575637105984298e+2, 0.4082224013073101e-1,
                                         -0.5347301163226948e+0, 0.5244099658805304e+0,  0.5347301163226948e+0,
                                         0.1048080741042263e+1};
constexpr std::array<double, 7> kRateRef = {0.1139920302151208e+4, -0.1424379294994111e+4, 0.1103291221937134e+2,
                                            0.1929337464421385e+2, 0.5735699284790808e+0,  -0.1929337464421385e+2,
                                            0.3231791658026955e+0};
constexpr double kTorque = 0.033;  // N m on the crank
// Bodies in the order whose angles make up the coordinates.
constexpr std::array<const char*, 7> kNames = {"crank", "rod_fe", "triangle", "rod_ge", "link_ag", "rod_he", "link_ah"};

struct Result {
  bool all_ok = true;
  double angle_error = 0.0;    // max over the 7 coordinates, rad
  double rate_error = 0.0;     // max over the 7 rates of |error| / max(1, |reference|)
  double balance_error = 0.0;  // max over the run of |T + V - E0 - mom (beta - beta0)|, J
  double violation = 0.0;
};

template <class M>
Result run() {
  Result res;
  typename M::State s = M::initial_state();
  std::array<int, 7> slot{};
  for (size_t i = 0; i < kNames.size(); ++i) slot[i] = M::slot(kNames[i]);
  const auto rotation_about_z = [&](int i) {
    const mbrt::EulerParameters& p = s.rigid[slot[i]].p;
    return 2.0 * std::atan2(p[3], p[0]);  // the bodies only turn about z
  };
  std::array<double, 7> turned{}, last{};  // rotation since t = 0, unwrapped
  const double e0 = M::energy(s).total();
  const long steps = std::lround(0.03 / M::kStep);
  for (long n = 1; n <= steps; ++n) {
    if (M::step(s) != mbrt::StepStatus::ok) {
      res.all_ok = false;
      return res;
    }
    for (int i = 0; i < 7; ++i) {
      const double a = rotation_about_z(i);
      turned[i] += std::remainder(a - last[i], 2.0 * M_PI);
      last[i] = a;
    }
    const double beta_change = turned[0];
    res.balance_error = std::max(res.balance_error, std::abs(M::energy(s).total() - e0 - kTorque * beta_change));
    if (n % 10 == 0) res.violation = std::max(res.violation, M::violation(s).position);
  }
  // Absolute angle of body i = its initial absolute angle + turned[i].
  const std::array<double, 7> q = {
      kQ0[0] + turned[0], kQ0[1] + turned[1] - turned[0], kQ0[2] + turned[2], kQ0[3] + turned[3] - turned[4],
      kQ0[4] + turned[4], kQ0[5] + turned[5] - turned[6], kQ0[6] + turned[6]};
  std::array<double, 7> w{};
  for (int i = 0; i < 7; ++i) w[i] = s.rigid[slot[i]].w.z();
  const std::array<double, 7> rate = {w[0], w[1] - w[0], w[2], w[3] - w[4], w[4], w[5] - w[6], w[6]};
  for (int i = 0; i < 7; ++i) {
    res.angle_error = std::max(res.angle_error, std::abs(q[i] - kQRef[i]));
    res.rate_error = std::max(res.rate_error, std::abs(rate[i] - kRateRef[i]) / std::max(1.0, std::abs(kRateRef[i])));
  }
  MESSAGE(std::string(M::kScheme) << ", h = " << M::kStep << ", t = " << s.t << ": beta = " << q[0] << " (reference "
                                  << kQRef[0] << "), max angle error " << res.angle_error
                                  << " rad, max relative rate error " << res.rate_error << ", max energy balance error "
                                  << res.balance_error << " J (E0 = " << e0 << "), max |phi| " << res.violation);
  return res;
}

}  // namespace

// Measured values and the commands that reproduce them: docs/benchmarks.md.
TEST_CASE("Andrews' squeezer, h = 1e-5: the Test Set solution at t = 0.03 in every scheme") {
  const Result pcst = run<Pcst>();
  REQUIRE(pcst.all_ok);
  CHECK(pcst.angle_error < 1e-4);
  CHECK(pcst.rate_error < 2e-3);
  CHECK(pcst.balance_error < 3e-5);
  CHECK(pcst.violation < 1e-8);

  const Result nps = run<Nps>();
  REQUIRE(nps.all_ok);
  CHECK(nps.angle_error < 1e-4);
  CHECK(nps.rate_error < 2e-3);
  CHECK(nps.balance_error < 3e-5);
  CHECK(nps.violation < 1e-8);

  const Result baumgarte = run<Baumgarte>();
  REQUIRE(baumgarte.all_ok);
  CHECK(baumgarte.angle_error < 1e-3);
  CHECK(baumgarte.rate_error < 2e-2);
  CHECK(baumgarte.balance_error < 1e-4);
  CHECK(baumgarte.violation < 1e-6);

  const Result blajer = run<Blajer>();
  REQUIRE(blajer.all_ok);
  CHECK(blajer.angle_error < 1e-4);
  CHECK(blajer.rate_error < 2e-3);
  CHECK(blajer.balance_error < 1e-4);
  CHECK(blajer.violation < 1e-12);

  const Result ali3p = run<Ali3p>();
  REQUIRE(ali3p.all_ok);
  CHECK(ali3p.angle_error < 2e-4);
  CHECK(ali3p.rate_error < 4e-3);
  CHECK(ali3p.balance_error < 1e-4);
  CHECK(ali3p.violation < 2e-10);
}
