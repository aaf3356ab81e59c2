// IFToMM / lim.ii.udc.es benchmark A01 (simple pendulum) over 2000 s.
//
// Reference: the minimal-coordinate equation phi'' = -g cos(phi) (phi: bar
// angle from +x, phi(0) = pi, g = 9.81, L = 1) integrated by classical RK4 at
// a step half the model's. A few values of the published table
// (A01_solution_data.txt of the benchmark, 6 significant digits) check that
// reference itself.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "a01_pendulum.hpp"
#include "reference_solutions.hpp"

namespace model = mbrt::models::a01_pendulum;


TEST_CASE("A01 pendulum stays within 1e-3 m of the reference at every 0.5 s output up to 2000 s") {
  const double t_end = 2000.0, dt = 0.5;
  const std::vector<mbrt::Vec3> ref = reference::a01_bob_positions(t_end, dt, model::kStep / 2.0);

  // Published benchmark values (t, x, y): the reference must reproduce them.
  const struct { double t, x, y; } published[] = {
      {0.5, -0.391049, -0.920370}, {10.0, -0.275087, -0.961419}, {100.0, -0.181513, -0.983388},
      {1000.0, 0.683230, -0.730203}, {2000.0, 0.814603, -0.580019}};
  for (const auto& p : published) {
    const mbrt::Vec3& r = ref[static_cast<size_t>(std::lround(p.t / dt))];
    CHECK(std::abs(r.x() - p.x) < 2e-6);
    CHECK(std::abs(r.y() - p.y) < 2e-6);
  }

  model::State s = model::initial_state();
  const long per_sample = std::lround(dt / model::kStep);
  double worst = 0.0, worst_violation = 0.0, worst_tension = 0.0;
  for (size_t k = 1; k < ref.size(); ++k) {
    for (long i = 0; i < per_sample; ++i) REQUIRE(model::step(s) == mbrt::StepStatus::ok);
    const mbrt::Vec3& r = s.particle[0].r;
    worst = std::max(worst, std::max(std::abs(r.x() - ref[k].x()), std::abs(r.y() - ref[k].y())));
    worst_violation = std::max(worst_violation, model::constraint_violation(s).position);
    // The multiplier of the distance row is the bar tension; from energy
    // conservation (v^2 = -2 g y) and the radial balance, T = -3 m g y.
    worst_tension = std::max(worst_tension, std::abs(s.lambda[0] - (-3.0 * 9.81 * r.y())));
  }
  MESSAGE("h = " << model::kStep << ": max position error " << worst << " m, max |phi| " << worst_violation
                 << ", max tension error " << worst_tension << " N (of up to 29.4 N)");
  CHECK(worst < 1e-3);
  CHECK(worst_violation < 1e-10);
  CHECK(worst_tension < 1e-2);
  CHECK(std::abs(model::energy(s).total()) < 1e-5);  // E = 0 with y = 0 at the pivot
}
