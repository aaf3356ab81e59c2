// Applied loads in generated steps, checked by mechanics rather than by the
// kernels: internal loads (spring-damper, torque with its reaction) leave the
// total momentum and angular momentum unchanged; a constant force changes
// the momentum by F t exactly.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "pushed_body.hpp"
#include "spring_pair.hpp"

namespace pair = mbrt::models::spring_pair;
namespace pushed = mbrt::models::pushed_body;

namespace {

struct Body {
  double m;
  mbrt::Vec3 J;
};

mbrt::Vec3 momentum(const mbrt::RigidState& s, const Body& b) { return b.m * s.v; }
mbrt::Vec3 angular_momentum(const mbrt::RigidState& s, const Body& b) {
  return b.m * s.r.cross(s.v) + mbrt::rotation_matrix(s.p) * b.J.cwiseProduct(s.w);
}

}  // namespace

TEST_CASE("internal spring-damper and torque conserve momentum and angular momentum") {
  const Body a{2.0, {0.3, 0.2, 0.1}}, b{1.0, {0.1, 0.1, 0.05}};
  pair::State s = pair::initial_state();
  const mbrt::Vec3 P0 = momentum(s.rigid[0], a) + momentum(s.rigid[1], b);
  const mbrt::Vec3 L0 = angular_momentum(s.rigid[0], a) + angular_momentum(s.rigid[1], b);
  const double E0 = pair::energy(s).total();
  double max_dP = 0, max_dL = 0;
  for (int i = 1; i <= 20000; ++i) {
    REQUIRE(pair::step(s) == mbrt::StepStatus::ok);
    max_dP = std::max(max_dP, (momentum(s.rigid[0], a) + momentum(s.rigid[1], b) - P0).norm());
    max_dL = std::max(max_dL, (angular_momentum(s.rigid[0], a) + angular_momentum(s.rigid[1], b) - L0).norm());
  }
  MESSAGE("20 s: |dP| " << max_dP << ", |dL| " << max_dL << ", energy " << E0 << " -> " << pair::energy(s).total());
  CHECK(max_dP < 1e-12);  // internal forces cancel exactly in every half kick
  CHECK(max_dL < 1e-3 * L0.norm());
  CHECK(std::abs(pair::energy(s).total() - E0) > 0.1);  // the loads act: the torque does work
  CHECK((s.rigid[1].r - s.rigid[0].r).norm() < 3.0);  // the spring holds them together
}

TEST_CASE("a constant force changes the momentum by F t and its moment spins the body") {
  const Body box{3.0, {0.2, 0.3, 0.4}};
  pushed::State s = pushed::initial_state();
  for (int i = 0; i < 2000; ++i) REQUIRE(pushed::step(s) == mbrt::StepStatus::ok);
  const mbrt::Vec3 P = momentum(s.rigid[0], box);
  CHECK(std::abs(P.x() - 1.5 * s.t) < 1e-12);
  CHECK(std::abs(P.y()) < 1e-12);
  CHECK(std::abs(P.z()) < 1e-12);
  // At t = 0 the moment of 1.5 N at (0, 0.1, 0) is -0.15 about z.
  pushed::State s0 = pushed::initial_state();
  pushed::step(s0);
  CHECK(s0.rigid_acceleration[0].alpha.z() == doctest::Approx(-0.15 / 0.4).epsilon(1e-3));
}
