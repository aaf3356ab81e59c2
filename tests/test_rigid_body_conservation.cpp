// Conservation laws of the staggered step on spinning rigid bodies over 1e6
// steps: energy, angular momentum and the Euler-parameter norm, plus the
// heavy top's closed-form nutation (Lagrange top, integrable).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "free_body.hpp"
#include "heavy_top.hpp"
#include "reference_solutions.hpp"

namespace top = mbrt::models::heavy_top;
namespace free_body = mbrt::models::free_body;

namespace {

// World angular momentum about the origin: m r x v + R J w.
mbrt::Vec3 angular_momentum(const mbrt::RigidState& b, double m, const mbrt::Vec3& J) {
  return m * b.r.cross(b.v) + mbrt::rotation_matrix(b.p) * J.cwiseProduct(b.w);
}

}  // namespace

TEST_CASE("heavy top: energy, vertical angular momentum, spin and |p| are held over 1e6 steps") {
  const double m = 15.0;
  const mbrt::Vec3 J(0.234375, 0.46875, 0.234375);
  // Closed-form invariants of the initial state (see models/heavy_top.yaml).
  const double E0 = 5435.696790865547, Lz0 = -70.3124296875;
  top::State s = top::initial_state();
  CHECK(top::energy(s).total() == doctest::Approx(E0).epsilon(1e-9));
  double max_dE = 0, max_dLz = 0, max_dspin = 0, max_quat = 0, max_phi = 0;
  for (long i = 1; i <= 1000000; ++i) {
    REQUIRE(top::step(s) == mbrt::StepStatus::ok);
    if (i % 1000 == 0) {
      max_dE = std::max(max_dE, std::abs(top::energy(s).total() - E0) / E0);
      max_dLz = std::max(max_dLz, std::abs(angular_momentum(s.rigid[0], m, J).z() - Lz0));
      max_dspin = std::max(max_dspin, std::abs(s.rigid[0].w.y() - 150.0));
      max_quat = std::max(max_quat, top::quaternion_norm_error(s));
      max_phi = std::max(max_phi, top::constraint_violation(s).position);
    }
  }
  MESSAGE("t = " << s.t << " s: |dE|/E " << max_dE << ", |dLz| " << max_dLz << ", |d spin| " << max_dspin
                 << ", | |p|-1 | " << max_quat << ", |phi| " << max_phi);
  CHECK(max_dE < 2e-6);
  CHECK(max_dLz < 1e-3);  // of |Lz0| = 70.3
  CHECK(max_dspin < 1e-3);
  CHECK(max_quat < 1e-12);
  CHECK(max_phi < 1e-7);
}

TEST_CASE("heavy top follows the closed-form height of its centre of mass") {
  top::State s = top::initial_state();
  long done = 0;
  for (const reference::TimedValue& c : reference::kHeavyTopHeight) {
    for (; done < std::lround(c.t / top::kStep); ++done) top::step(s);
    // 7.6e-6 at h = 1e-4 (second order, test_convergence_order): the error of
    // splitting the gravity torque's kicks from the spin's free rotation.
    CHECK(std::abs(s.rigid[0].r.z() - c.value) < 1e-5);
  }
}

TEST_CASE("free asymmetric body: energy, angular momentum and |p| are held over 1e6 steps through spin flips") {
  const double m = 2.0;
  const mbrt::Vec3 J(1.0, 2.0, 3.0);
  free_body::State s = free_body::initial_state();
  const double E0 = free_body::energy(s).total();
  const mbrt::Vec3 L0 = angular_momentum(s.rigid[0], m, J);
  double max_dE = 0, max_dL = 0, max_quat = 0;
  bool flipped = false;
  for (long i = 1; i <= 1000000; ++i) {
    REQUIRE(free_body::step(s) == mbrt::StepStatus::ok);
    flipped = flipped || s.rigid[0].w.y() < -4.0;
    if (i % 100 == 0) {
      max_dE = std::max(max_dE, std::abs(free_body::energy(s).total() - E0) / E0);
      max_dL = std::max(max_dL, (angular_momentum(s.rigid[0], m, J) - L0).norm() / L0.norm());
      max_quat = std::max(max_quat, free_body::quaternion_norm_error(s));
    }
  }
  MESSAGE("t = " << s.t << " s: |dE|/E " << max_dE << ", |dL|/|L| " << max_dL << ", | |p|-1 | " << max_quat);
  CHECK(flipped);  // the intermediate-axis instability is reproduced
  CHECK(max_dE < 1e-4);
  CHECK(max_dL < 1e-2);
  CHECK(max_quat < 1e-12);
}
