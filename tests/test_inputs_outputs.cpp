// Model inputs act as the loads they name and outputs measure what they name,
// checked against closed-form motion under constant inputs (no gravity):
//   rod pinned at its end:  theta = tau t^2 / (2 (I_zz + m (L/2)^2))
//   cart on a rail:         x = F t^2 / (2 m)
//   free wheel, motor:      w_z = tau t / J_zz, turning about z by w_z t / 2
// An input changed before step() acts from the middle of that step: the
// step's first half-kick uses the accelerations the previous step left
// (docs/hil.md), so a change at t = 0 is a constant load from t0 = h / 2.
#include <doctest/doctest.h>

#include <cmath>

#include "actuated.hpp"

namespace model = mbrt::models::actuated;

namespace {

constexpr double kRodInertiaAboutPivot = 0.06 + 2.0 * 0.3 * 0.3;
constexpr double kCartMass = 3.0;
constexpr double kWheelJzz = 0.08;

constexpr double kOnset = 0.5 * model::kStep;

model::State run(const model::Inputs& u, double t_end) {
  model::State s = model::initial_state();
  s.inputs = u;
  const long steps = std::lround(t_end / model::kStep);
  for (long i = 0; i < steps; ++i) REQUIRE(model::step(s) == mbrt::StepStatus::ok);
  return s;
}

}  // namespace

TEST_CASE("initial_state applies the safe input values") {
  const model::State s = model::initial_state();
  CHECK(s.inputs[model::input::tau_pivot] == 0.0);
  CHECK(s.inputs[model::input::spin] == 0.25);
  CHECK(s.rigid_acceleration[2].alpha.z() == doctest::Approx(0.25 / kWheelJzz).epsilon(1e-12));
  CHECK(s.rigid_acceleration[0].alpha.norm() < 1e-12);
}

TEST_CASE("a joint torque turns a pinned rod with alpha = tau / I_pivot") {
  const double tau = 1.2, t = 0.5;
  model::Inputs u{};
  u[model::input::tau_pivot] = tau;
  const model::State s = run(u, t);
  const double alpha = tau / kRodInertiaAboutPivot;
  const double theta = 0.5 * alpha * (t - kOnset) * (t - kOnset);
  model::Outputs y;
  model::outputs(s, y);
  CHECK(s.rigid_acceleration[0].alpha.z() == doctest::Approx(alpha).epsilon(1e-3));
  CHECK(y[model::output::pivot_angle] == doctest::Approx(theta).epsilon(1e-5));
  CHECK(y[model::output::pivot_rate] == doctest::Approx(alpha * (t - kOnset)).epsilon(1e-5));
  // The COM of the rod lies at angle theta on a circle of radius L / 2 around the pivot.
  CHECK(s.rigid[0].r.x() == doctest::Approx(0.3 * std::cos(theta)).epsilon(1e-5).scale(0));
  CHECK(s.rigid[0].r.y() == doctest::Approx(0.3 * std::sin(theta)).epsilon(1e-5).scale(0));
}

TEST_CASE("a joint force moves a cart along its rail with a = F / m") {
  const double force = 6.0, t = 0.5;
  model::Inputs u{};
  u[model::input::push] = force;
  const model::State s = run(u, t);
  const double a = force / kCartMass;
  const double x = 0.5 * a * (t - kOnset) * (t - kOnset);
  model::Outputs y;
  model::outputs(s, y);
  CHECK(y[model::output::rail_position] == doctest::Approx(x).epsilon(1e-5).scale(0));  // O(h^2): central differences
  CHECK(y[model::output::rail_speed] == doctest::Approx(a * (t - kOnset)).epsilon(1e-9));
  const double along = x / std::sqrt(2.0);  // the rail runs along (1, 1, 0)
  CHECK(s.rigid[1].r.x() == doctest::Approx(along).epsilon(1e-5).scale(0));
  CHECK(s.rigid[1].r.y() == doctest::Approx(2.0 + along).epsilon(1e-5));
  CHECK(s.rigid[1].w.norm() < 1e-9);  // the force passes through the rail: no turning
}

TEST_CASE("a motor torque held at its safe value from t = 0 spins a free wheel with w_z = tau t / J") {
  const double tau = 0.25, t = 0.5;  // the safe value: acting from the start, no onset
  model::Inputs u{};
  u[model::input::spin] = tau;
  const model::State s = run(u, t);
  const double w = tau * t / kWheelJzz;
  const double angle = 0.5 * w * t;
  model::Outputs y;
  model::outputs(s, y);
  const int pose = model::output::wheel_pose, vel = model::output::wheel_velocity;
  CHECK(y[vel + 5] == doctest::Approx(w).epsilon(1e-9));
  CHECK(std::abs(y[vel + 3]) + std::abs(y[vel + 4]) < 1e-9);
  CHECK(y[pose + 1] == doctest::Approx(-2.0));  // y of the COM: the wheel does not move
  CHECK(y[pose + 3] == doctest::Approx(std::cos(0.5 * angle)).epsilon(1e-6));
  CHECK(y[pose + 6] == doctest::Approx(std::sin(0.5 * angle)).epsilon(1e-5).scale(0));
}

TEST_CASE("a non-finite input is refused by the step and the state stays as it was") {
  model::State s = model::initial_state();
  model::step(s);
  const model::State before = s;
  s.inputs[model::input::push] = std::nan("");
  CHECK(model::step(s) == mbrt::StepStatus::non_finite);
  CHECK(s.t == before.t);
  CHECK(s.rigid[1].r == before.rigid[1].r);
}
