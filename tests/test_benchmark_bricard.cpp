// IFToMM / lim.ii.udc.es benchmark A04: Bricard's mechanism
// (tests/models/benchmarks/a04_bricard.yaml), five rods closed by six
// revolute joints, one redundant constraint row, released from rest under
// gravity. No reference solution has been published (docs/benchmarks.md),
// so each scheme is checked over 100 s at h = 1e-3 (1e5 steps) for:
//  - energy: the system is conservative, |E(t) - E(0)| stays small;
//  - constraints: |phi| and |phi'| stay bounded, no worse in the second half
//    of the run than allowed for the whole;
//  - motion: the mechanism swings (it is not locked by the redundant row):
//    the top of the third rod, P3, starts at (1, -1, 1) and, because the
//    mirror configuration (-1, -1, 1) has the same potential energy,
//    reaches x = -1 at its turning point and comes back.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>

#include <mbrt/rotation.hpp>

#include "bricard_ali3p.hpp"
#include "bricard_baumgarte.hpp"
#include "bricard_blajer.hpp"
#include "bricard_nps.hpp"
#include "bricard_pcst.hpp"
#include "model_adapter.hpp"

namespace {

BENCH_MODEL(Pcst, bricard_pcst);
BENCH_MODEL(Baumgarte, bricard_baumgarte);
BENCH_MODEL(Blajer, bricard_blajer);
BENCH_MODEL(Nps, bricard_nps);
BENCH_MODEL(Ali3p, bricard_ali3p);

struct Result {
  bool all_ok = true;
  double energy_error = 0.0;                        // max |E - E0|, J
  mbrt::ConstraintViolation first_half{0.0, 0.0, 0.0};   // max over 0..50 s
  mbrt::ConstraintViolation second_half{0.0, 0.0, 0.0};  // max over 50..100 s
  double p3_min_x = 1.0;                            // over the first 5 s
  double p3_max_x_later = -1.0;                     // over 2.5..7.5 s
};

template <class M>
Result run() {
  const double t_end = 100.0;
  Result res;
  typename M::State s = M::initial_state();
  const double e0 = M::energy(s).total();
  const int rod3 = M::slot("rod3");
  const long steps = std::lround(t_end / M::kStep), every = std::lround(0.01 / M::kStep);
  for (long n = 1; n <= steps; ++n) {
    if (M::step(s) != mbrt::StepStatus::ok) {
      res.all_ok = false;
      return res;
    }
    if (n % every != 0) continue;
    res.energy_error = std::max(res.energy_error, std::abs(M::energy(s).total() - e0));
    const mbrt::ConstraintViolation v = M::violation(s);
    mbrt::ConstraintViolation& half = s.t < 0.5 * t_end ? res.first_half : res.second_half;
    half.position = std::max(half.position, v.position);
    half.velocity = std::max(half.velocity, v.velocity);
    const double p3x = (s.rigid[rod3].r + mbrt::rotation_matrix(s.rigid[rod3].p) * mbrt::Vec3(0, 0, 0.5)).x();
    if (s.t <= 5.0) res.p3_min_x = std::min(res.p3_min_x, p3x);
    if (s.t >= 2.5 && s.t <= 7.5) res.p3_max_x_later = std::max(res.p3_max_x_later, p3x);
  }
  MESSAGE(std::string(M::kScheme) << ", h = " << M::kStep << ", 100 s: max |E - E0| " << res.energy_error
                                  << " J (E0 = " << e0 << "), max |phi| " << res.first_half.position << " / "
                                  << res.second_half.position << ", max |phi'| " << res.first_half.velocity << " / "
                                  << res.second_half.velocity << " (first / second half), P3.x min " << res.p3_min_x
                                  << " (0..5 s), max " << res.p3_max_x_later << " (2.5..7.5 s)");
  return res;
}

void check_common(const Result& r, double energy_tol, double phi_tol, double phi_dot_tol) {
  REQUIRE(r.all_ok);
  CHECK(r.energy_error < energy_tol);
  CHECK(r.first_half.position < phi_tol);
  CHECK(r.second_half.position < phi_tol);
  CHECK(r.first_half.velocity < phi_dot_tol);
  CHECK(r.second_half.velocity < phi_dot_tol);
  CHECK(r.p3_min_x < -0.999);       // reaches the mirror turning point
  CHECK(r.p3_max_x_later > 0.999);  // and swings back
}

}  // namespace

// Measured values and the commands that reproduce them: docs/benchmarks.md.
TEST_CASE("A04 Bricard, h = 1e-3, 100 s: energy conserved, violations bounded, the mechanism swings") {
  check_common(run<Pcst>(), 1e-5, 1e-8, 1e-8);
  check_common(run<Nps>(), 1e-5, 1e-8, 1e-8);
  check_common(run<Baumgarte>(), 1e-4, 1e-7, 1e-5);
  check_common(run<Blajer>(), 1e-5, 1e-13, 1e-8);
  check_common(run<Ali3p>(), 1e-5, 1e-13, 1e-12);
}
