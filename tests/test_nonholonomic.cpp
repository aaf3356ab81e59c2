// Nonholonomic contacts: the kernels against finite differences, and
// rolling disks and a knife edge in every scheme against closed forms
// (Dopico et al. 2014's pushed disk), Newton's second law with the contact
// reaction, and energy over a long conservative roll.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include <mbrt/runtime.hpp>

#include "disk_pushed_ali3p.hpp"
#include "disk_pushed_baumgarte.hpp"
#include "disk_pushed_blajer.hpp"
#include "disk_pushed_nps.hpp"
#include "disk_pushed_pcst.hpp"
#include "disk_rolling_ali3p.hpp"
#include "disk_rolling_pcst.hpp"
#include "ball_offset.hpp"
#include "knife_sled.hpp"
#include "two_masses.hpp"
#include "model_adapter.hpp"

namespace {

struct Sample {
  mbrt::Vec3 r;
  mbrt::Vec4 p;
  mbrt::Vec3 v, w;
};

// Moves a body with constant v (world) and w (body) for dt.
Sample moved(const Sample& s, double dt) {
  return {s.r + dt * s.v, mbrt::advance_euler_parameters(s.p, s.w, dt, 64), s.v, s.w};
}

template <class Kernel>
auto rows_at(Kernel kernel, const mbrt::JointFrame& f, const Sample& s) {
  const mbrt::BodyPose ground = mbrt::ground_pose(), pose{s.r, mbrt::rotation_matrix(s.p)};
  const mbrt::BodyVelocity still = mbrt::ground_velocity(), vel{s.v, s.w};
  return kernel(f, mbrt::BodyMotion{ground, still}, mbrt::BodyMotion{pose, vel});
}

template <class Kernel>
Eigen::VectorXd velocity_rows(Kernel kernel, const mbrt::JointFrame& f, const Sample& s) {
  mbrt::Vec6 u;
  u << s.v, s.w;
  return rows_at(kernel, f, s).J2 * u;
}

// quad is the derivative of J u along a motion with constant u; the
// holonomic rows' J u is also the derivative of phi.
template <class Kernel>
void check_against_finite_differences(Kernel kernel, const mbrt::JointFrame& f, int holonomic_rows) {
  const double eps = 1e-5;
  for (int k = 0; k < 5; ++k) {
    const double x = 0.3 * k;
    const Sample s{mbrt::Vec3(0.4 + x, -0.3, 0.7 - x), mbrt::Vec4(0.9, 0.2 + x, -0.3, 0.25 - x).normalized(),
                   mbrt::Vec3(0.3, -1.2 + x, 0.5), mbrt::Vec3(1.5, -0.7, 2.2 - 2 * x)};
    const auto rows = rows_at(kernel, f, s);
    const Eigen::VectorXd quad =
        (velocity_rows(kernel, f, moved(s, eps)) - velocity_rows(kernel, f, moved(s, -eps))) / (2 * eps);
    CHECK((quad - rows.quad).cwiseAbs().maxCoeff() < 1e-6);
    const Eigen::VectorXd phi_dot = (rows_at(kernel, f, moved(s, eps)).phi - rows_at(kernel, f, moved(s, -eps)).phi) / (2 * eps);
    const Eigen::VectorXd j_u = velocity_rows(kernel, f, s);
    for (int i = 0; i < rows.phi.size(); ++i) {
      if (i < holonomic_rows) CHECK(std::abs(phi_dot[i] - j_u[i]) < 1e-7);
      else CHECK(rows.phi[i] == 0.0);
    }
  }
}

#define PUSHED_DISK(model)                                                    \
  [] {                                                                        \
    namespace m = mbrt::models::model;                                        \
    m::State s = m::initial_state();                                          \
    while (s.t < 2.0 - 0.5 * m::kStep) REQUIRE(m::step(s) == mbrt::StepStatus::ok); \
    m::Reactions r;                                                           \
    m::reactions(s, r);                                                       \
    return std::vector<double>{s.rigid[0].r.y(), r[0].force.x(), r[0].force.y(), r[0].force.z()}; \
  }()

}  // namespace

TEST_CASE("rolling_disk, rolling_ball and knife_edge rows against finite differences") {
  mbrt::JointFrame f{};
  f.c1 = mbrt::Vec3(0.1, -0.2, 1).normalized();
  f.a1 = f.c1.cross(mbrt::Vec3::UnitX()).normalized();
  f.b1 = f.c1.cross(f.a1);
  f.s1 = mbrt::Vec3(0.3, 0.1, -0.2);
  f.a2 = mbrt::Vec3(0.2, 0.9, -0.3).normalized();
  f.s2 = mbrt::Vec3(0.1, 0.2, 0.3);
  f.length = 0.5;
  check_against_finite_differences([](const auto&... a) { return mbrt::rolling_disk(a...); }, f, 1);
  check_against_finite_differences([](const auto&... a) { return mbrt::knife_edge(a...); }, f, 0);
  check_against_finite_differences([](const auto&... a) { return mbrt::rolling_ball(a...); }, f, 1);
}

TEST_CASE("disk pushed by 3 N (m = 5 kg, rho = 0.5 m): a = 0.4 m/s^2, friction -1 N, normal m g, every scheme") {
  for (const std::vector<double>& r : {PUSHED_DISK(disk_pushed_pcst), PUSHED_DISK(disk_pushed_baumgarte),
                                       PUSHED_DISK(disk_pushed_blajer), PUSHED_DISK(disk_pushed_ali3p),
                                       PUSHED_DISK(disk_pushed_nps)}) {
    MESSAGE("y(2) = " << r[0] << " m, contact force (" << r[1] << ", " << r[2] << ", " << r[3] << ") N");
    CHECK(std::abs(r[0] - 0.5 * 0.4 * 4.0) < 1e-9);
    CHECK(std::abs(r[1]) < 1e-9);
    CHECK(std::abs(r[2] - (-1.0)) < 1e-6);
    CHECK(std::abs(r[3] - 5.0 * 9.81) < 1e-6);
  }
}

TEST_CASE("rolling disk, vP = (0.05, 1.3, 0): contact force plus weight is m times the COM acceleration") {
  namespace m = mbrt::models::disk_rolling_pcst;
  m::State s = m::initial_state();
  mbrt::Vec3 v_before = s.rigid[0].v;  // one step before the state whose reaction is taken
  REQUIRE(m::step(s) == mbrt::StepStatus::ok);
  double worst = 0.0, largest = 0.0;
  for (int i = 0; i < 8000; ++i) {  // 4 s
    m::Reactions r;
    m::reactions(s, r);
    const mbrt::Vec3 f = r[0].force + 5.0 * mbrt::Vec3(0, 0, -9.81);
    const mbrt::Vec3 v_now = s.rigid[0].v;
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    // Central difference of the velocity around the state the reaction belongs to.
    const mbrt::Vec3 ma = 5.0 * (s.rigid[0].v - v_before) / (2.0 * m::kStep);
    worst = std::max(worst, (ma - f).norm());
    largest = std::max(largest, f.norm());
    v_before = v_now;
  }
  MESSAGE("max |m a - (f + m g)| " << worst << " N, largest |f + m g| " << largest << " N");
  CHECK(worst < 1e-3 * largest);
  CHECK(largest > 0.1);  // the disk really turns and leans
}

TEST_CASE("rolling disk over 20 s: ideal contact does no work; ali3p's projections lose a bounded amount") {
  const auto drift = [](auto initial, auto step, auto energy, double dt) {
    auto s = initial();
    const double e0 = energy(s);
    double worst = 0.0;
    for (long i = 0; i < std::lround(20.0 / dt); ++i) {
      REQUIRE(step(s) == mbrt::StepStatus::ok);
      worst = std::max(worst, std::abs(energy(s) - e0));
    }
    return worst;
  };
  namespace pcst = mbrt::models::disk_rolling_pcst;
  namespace ali3p = mbrt::models::disk_rolling_ali3p;
  const double pcst_drift = drift(pcst::initial_state, STEP_OF(pcst),
                                  [](const pcst::State& s) { return pcst::energy(s).total(); }, pcst::kStep);
  const double ali3p_drift = drift(ali3p::initial_state, STEP_OF(ali3p),
                                   [](const ali3p::State& s) { return ali3p::energy(s).total(); }, ali3p::kStep);
  MESSAGE("max |E - E0| over 20 s (E0 = 30.87 J): staggered-pcst " << pcst_drift << " J, ali3p " << ali3p_drift << " J");
  CHECK(pcst_drift < 1e-6);
  CHECK(ali3p_drift < 0.05);
}

TEST_CASE("knife edge: pushed by (1, 1, 0) N, the sled moves along the edge only; the edge holds -1 N") {
  namespace m = mbrt::models::knife_sled;
  m::State s = m::initial_state();
  while (s.t < 1.0 - 0.5 * m::kStep) REQUIRE(m::step(s) == mbrt::StepStatus::ok);
  m::Reactions r;
  m::reactions(s, r);
  CHECK(std::abs(s.rigid[0].r.x() - 0.5 * 0.5 * 1.0) < 1e-9);  // a = 1 N / 2 kg
  CHECK(std::abs(s.rigid[0].r.y()) < 1e-12);
  CHECK(std::abs(r[0].force.y() - (-1.0)) < 1e-9);
  CHECK(std::abs(r[0].force.x()) < 1e-9);
}

TEST_CASE("two masses, A's velocity towards B: B moves freely, A pursues at constant speed") {
  namespace m = mbrt::models::two_masses;
  // Reference: A's pursuit curve x_A' = |v_A| (x_B - x_A) / |x_B - x_A| with
  // the free motion x_B = (1 + t, t^2), by RK4 at 1e-4 s.
  const auto rate = [](double t, const mbrt::Vec3& a) {
    const mbrt::Vec3 b(1.0 + t, t * t, 0.0);
    return mbrt::Vec3((b - a).normalized());
  };
  mbrt::Vec3 a_ref(0, 0, 0);
  const double dt = 1e-4;
  m::State s = m::initial_state();
  double worst_a = 0.0, worst_b = 0.0, worst_speed = 0.0;
  for (int k = 1; k <= 5000; ++k) {  // 5 s
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    for (int i = 0; i < 10; ++i) {
      const double t = (k - 1) * m::kStep + i * dt;
      const mbrt::Vec3 k1 = rate(t, a_ref), k2 = rate(t + dt / 2, a_ref + dt / 2 * k1);
      const mbrt::Vec3 k3 = rate(t + dt / 2, a_ref + dt / 2 * k2), k4 = rate(t + dt, a_ref + dt * k3);
      a_ref += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    const double t = s.t;
    worst_b = std::max(worst_b, (s.particle[1].r - mbrt::Vec3(1.0 + t, t * t, 0.0)).norm());
    worst_a = std::max(worst_a, (s.particle[0].r - a_ref).norm());
    worst_speed = std::max(worst_speed, std::abs(s.particle[0].v.norm() - 1.0));
  }
  MESSAGE("max error: A " << worst_a << " m, B " << worst_b << " m, A's speed " << worst_speed << " m/s");
  CHECK(worst_b < 1e-9);
  CHECK(worst_a < 1e-4);
  CHECK(worst_speed < 1e-5);
}

TEST_CASE("bowling ball with its centre of mass off the centre: energy kept, Newton's law with the contact force") {
  namespace m = mbrt::models::ball_offset;
  m::State s = m::initial_state();
  const double e0 = m::energy(s).total();
  mbrt::Vec3 v_before = s.rigid[0].v;
  REQUIRE(m::step(s) == mbrt::StepStatus::ok);
  double worst = 0.0, largest = 0.0, drift = 0.0;
  for (int i = 0; i < 20000; ++i) {  // 10 s
    m::Reactions r;
    m::reactions(s, r);
    const mbrt::Vec3 f = r[0].force + 7.0 * mbrt::Vec3(0, 0, -9.81);
    const mbrt::Vec3 v_now = s.rigid[0].v;
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    const mbrt::Vec3 ma = 7.0 * (s.rigid[0].v - v_before) / (2.0 * m::kStep);
    worst = std::max(worst, (ma - f).norm());
    largest = std::max(largest, f.norm());
    v_before = v_now;
    drift = std::max(drift, std::abs(m::energy(s).total() - e0));
  }
  MESSAGE("bowling ball: max |m a - (f + m g)| " << worst << " N of " << largest << " N, max |E - E0| " << drift << " J");
  CHECK(worst < 3e-3 * largest);  // O(h^2) of the central difference at 10 rad/s
  CHECK(largest > 1.0);            // the offset mass makes it wobble
  CHECK(drift < 1e-5);             // of 13.9 J
}
