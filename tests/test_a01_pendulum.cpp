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

namespace model = mbrt::models::a01_pendulum;

namespace {

struct Point {
  double x, y;
};

// RK4 on (phi, phi_dot); samples the bob position every `sample_dt`.
std::vector<Point> minimal_coordinate_reference(double t_end, double sample_dt, double h) {
  const double g = 9.81;
  double phi = M_PI, rate = 0.0;
  const auto acc = [&](double a) { return -g * std::cos(a); };
  std::vector<Point> out{{std::cos(phi), std::sin(phi)}};
  const long per_sample = std::lround(sample_dt / h);
  const long samples = std::lround(t_end / sample_dt);
  for (long s = 0; s < samples; ++s) {
    for (long i = 0; i < per_sample; ++i) {
      const double k1p = rate, k1v = acc(phi);
      const double k2p = rate + 0.5 * h * k1v, k2v = acc(phi + 0.5 * h * k1p);
      const double k3p = rate + 0.5 * h * k2v, k3v = acc(phi + 0.5 * h * k2p);
      const double k4p = rate + h * k3v, k4v = acc(phi + h * k3p);
      phi += h / 6.0 * (k1p + 2 * k2p + 2 * k3p + k4p);
      rate += h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
    }
    out.push_back({std::cos(phi), std::sin(phi)});
  }
  return out;
}

}  // namespace

TEST_CASE("A01 pendulum stays within 1e-3 m of the reference at every 0.5 s output up to 2000 s") {
  const double t_end = 2000.0, dt = 0.5;
  const std::vector<Point> ref = minimal_coordinate_reference(t_end, dt, model::kStep / 2.0);

  // Published benchmark values (t, x, y): the reference must reproduce them.
  const struct { double t, x, y; } published[] = {
      {0.5, -0.391049, -0.920370}, {10.0, -0.275087, -0.961419}, {100.0, -0.181513, -0.983388},
      {1000.0, 0.683230, -0.730203}, {2000.0, 0.814603, -0.580019}};
  for (const auto& p : published) {
    const Point& r = ref[static_cast<size_t>(std::lround(p.t / dt))];
    CHECK(std::abs(r.x - p.x) < 2e-6);
    CHECK(std::abs(r.y - p.y) < 2e-6);
  }

  model::State s = model::initial_state();
  const long per_sample = std::lround(dt / model::kStep);
  double worst = 0.0, worst_violation = 0.0, worst_tension = 0.0;
  for (size_t k = 1; k < ref.size(); ++k) {
    for (long i = 0; i < per_sample; ++i) REQUIRE(model::step(s) == mbrt::StepStatus::ok);
    const mbrt::Vec3& r = s.particle[0].r;
    worst = std::max(worst, std::max(std::abs(r.x() - ref[k].x), std::abs(r.y() - ref[k].y)));
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
