// Screw and planar joints and drivers: their kernels against finite
// differences along exact motions, and generated models against closed-form
// mechanics.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Dense>
#include <mbrt/joints.hpp>
#include <mbrt/piecewise_function.hpp>

#include "breathing_rope.hpp"
#include "driven_rod.hpp"
#include "driven_slider.hpp"
#include "planar_slide.hpp"
#include "screw_nut.hpp"
#include "spin_up_rod.hpp"

namespace {

using mbrt::Vec3;

// Exact motion with constant v and constant body-axis w.
struct Motion {
  Vec3 r0, v;
  mbrt::EulerParameters p0;
  Vec3 w;
  mbrt::BodyPose pose(double t) const {
    const Eigen::Quaterniond q0(p0[0], p0[1], p0[2], p0[3]);
    const Eigen::Quaterniond q = q0 * Eigen::Quaterniond(Eigen::AngleAxisd(w.norm() * t, w.normalized()));
    return {r0 + v * t, q.toRotationMatrix()};
  }
  mbrt::BodyVelocity velocity() const { return {v, w}; }
};

mbrt::EulerParameters about(const Vec3& axis, double angle) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(angle, axis.normalized()));
  return {q.w(), q.x(), q.y(), q.z()};
}

template <class Kernel>
void check_against_finite_differences(const char* what, const Motion& m1, const Motion& m2, Kernel kernel) {
  INFO(what);
  const double t = 0.3, e = 1e-4;
  const auto phi = [&](double at) {
    const mbrt::BodyPose p1 = m1.pose(at), p2 = m2.pose(at);
    const mbrt::BodyVelocity v1 = m1.velocity(), v2 = m2.velocity();
    return kernel(mbrt::BodyMotion{p1, v1}, mbrt::BodyMotion{p2, v2}, at);
  };
  const auto rows = phi(t);
  const mbrt::BodyVelocity v1 = m1.velocity(), v2 = m2.velocity();
  mbrt::Vec6 u1, u2;
  u1 << v1.v, v1.w;
  u2 << v2.v, v2.w;
  const Eigen::VectorXd rate = rows.J1 * u1 + rows.J2 * u2 + rows.phi_t;
  const Eigen::VectorXd fd_rate = (phi(t + e).phi - phi(t - e).phi) / (2 * e);
  const Eigen::VectorXd fd_acc = (phi(t + e).phi - 2 * rows.phi + phi(t - e).phi) / (e * e);
  for (int i = 0; i < rows.phi.size(); ++i) {
    CHECK(rate[i] == doctest::Approx(fd_rate[i]).epsilon(1e-6).scale(1.0));
    CHECK(rows.quad[i] == doctest::Approx(fd_acc[i]).epsilon(1e-4).scale(1.0));  // u' = 0 here
  }
}

// Body 2 turns relative to body 1 about their common body z axis at rate
// theta_rate while body 1 tumbles with constant body-axis w1 (the manifold
// on which the angle rows are defined). Then w2 = Rz(-theta) w1 + theta_rate z
// changes in time, w2' = -theta_rate z x w2, and phi'' = J2 [0; w2'] + quad.
template <class Kernel>
void check_relative_rotation(const char* what, Kernel kernel) {
  INFO(what);
  const Vec3 w1(0.4, -0.9, 0.6), v1(0.3, -0.1, 0.2), v2(-0.2, 0.4, 0.6);
  const Vec3 r1(0.1, 0.2, 0.3), r2(0.5, -0.2, 0.1);
  const Eigen::Quaterniond q1_0(Eigen::AngleAxisd(0.8, Vec3(1, 2, 3).normalized()));
  const double theta0 = 0.7, theta_rate = -1.7;
  struct State {
    mbrt::BodyPose p1, p2;
    mbrt::BodyVelocity u1, u2;
  };
  const auto at = [&](double t) {
    const Eigen::Quaterniond q1 = q1_0 * Eigen::Quaterniond(Eigen::AngleAxisd(w1.norm() * t, w1.normalized()));
    const Eigen::Matrix3d Rz = Eigen::AngleAxisd(theta0 + theta_rate * t, Vec3::UnitZ()).toRotationMatrix();
    const Vec3 w2 = Rz.transpose() * w1 + theta_rate * Vec3::UnitZ();
    return State{{r1 + v1 * t, q1.toRotationMatrix()}, {r2 + v2 * t, q1.toRotationMatrix() * Rz}, {v1, w1}, {v2, w2}};
  };
  const auto phi = [&](double t) {
    const State x = at(t);
    return kernel(mbrt::BodyMotion{x.p1, x.u1}, mbrt::BodyMotion{x.p2, x.u2}, t);
  };
  const double t = 0.3, e = 1e-4;
  const State x = at(t);
  const auto rows = phi(t);
  mbrt::Vec6 u1, u2, u2_dot;
  u1 << x.u1.v, x.u1.w;
  u2 << x.u2.v, x.u2.w;
  u2_dot << Vec3::Zero(), -theta_rate * Vec3::UnitZ().cross(x.u2.w);
  const Eigen::VectorXd rate = rows.J1 * u1 + rows.J2 * u2 + rows.phi_t;
  const Eigen::VectorXd acc = rows.J2 * u2_dot + rows.quad;
  const Eigen::VectorXd fd_rate = (phi(t + e).phi - phi(t - e).phi) / (2 * e);
  const Eigen::VectorXd fd_acc = (phi(t + e).phi - 2 * rows.phi + phi(t - e).phi) / (e * e);
  for (int i = 0; i < rows.phi.size(); ++i) {
    CHECK(rate[i] == doctest::Approx(fd_rate[i]).epsilon(1e-6).scale(1.0));
    CHECK(acc[i] == doctest::Approx(fd_acc[i]).epsilon(1e-4).scale(1.0));
  }
}

// A frame on the z axis: triad (z, x, y) in both bodies at identity poses.
mbrt::JointFrame axis_frame(double pitch) {
  mbrt::JointFrame f{};
  f.s1 = Vec3(0.1, -0.2, 0.3);
  f.s2 = Vec3(-0.3, 0.2, 0.1);
  f.a1 = f.a2 = Vec3::UnitZ();
  f.b1 = f.b2 = Vec3::UnitX();
  f.c1 = f.c2 = Vec3::UnitY();
  f.pitch = pitch;
  return f;
}

}  // namespace

TEST_CASE("screw, planar and driver rows match finite differences of the motion") {
  const mbrt::JointFrame f = axis_frame(0.02);
  // Both bodies turn about the common z axis (the screw and angle rows are
  // defined on that manifold) and translate freely.
  const Motion m1{{0.1, 0.2, 0.3}, {0.3, -0.1, 0.2}, about(Vec3::UnitZ(), 0.4), {0, 0, 0.7}};
  const Motion m2{{0.5, -0.2, 0.1}, {-0.2, 0.4, 0.6}, about(Vec3::UnitZ(), 2.9), {0, 0, -1.3}};
  check_against_finite_differences("screw", m1, m2, [&](auto a, auto b, double) { return mbrt::screw(f, a, b); });
  const auto target = [](double t) { return mbrt::polynomial(std::array<double, 3>{0.2, -0.5, 0.7}, t); };
  check_against_finite_differences(
      "joint_angle_driver", m1, m2, [&](auto a, auto b, double t) { return mbrt::joint_angle_driver(f, a, b, target(t)); });
  check_relative_rotation("screw, tumbling", [&](auto a, auto b, double) { return mbrt::screw(f, a, b); });
  check_relative_rotation("joint_angle_driver, tumbling",
                          [&](auto a, auto b, double t) { return mbrt::joint_angle_driver(f, a, b, target(t)); });
  // Planar, slide and distance rows hold in any motion.
  const Motion g1{{0.1, 0.2, 0.3}, {0.3, -0.1, 0.2}, about(Vec3(1, 2, 3), 0.4), {0.2, -0.5, 0.7}};
  const Motion g2{{0.5, -0.2, 0.1}, {-0.2, 0.4, 0.6}, about(Vec3(-1, 0, 2), 1.1), {-0.4, 0.3, 0.9}};
  check_against_finite_differences("planar", g1, g2, [&](auto a, auto b, double) { return mbrt::planar(f, a, b); });
  const mbrt::Sine wave{0.3, 2.0, 0.1, 1.5};
  check_against_finite_differences("joint_distance_driver", g1, g2, [&](auto a, auto b, double t) {
    return mbrt::joint_distance_driver(f, a, b, mbrt::sine(wave, t));
  });
  check_against_finite_differences("distance_driver", g1, g2, [&](auto a, auto b, double t) {
    return mbrt::distance_driver(f, a, b, mbrt::sine(wave, t));
  });
}

TEST_CASE("time functions give their derivatives") {
  const mbrt::TimeValue p = mbrt::polynomial(std::array<double, 4>{1, 2, 3, 4}, 0.5);
  CHECK(p.f == doctest::Approx(1 + 2 * 0.5 + 3 * 0.25 + 4 * 0.125));
  CHECK(p.df == doctest::Approx(2 + 6 * 0.5 + 12 * 0.25));
  CHECK(p.ddf == doctest::Approx(6 + 24 * 0.5));
  const mbrt::TimeValue s = mbrt::sine({2.0, 3.0, 0.5, 1.0}, 0.7);
  CHECK(s.f == doctest::Approx(1.0 + 2.0 * std::sin(2.6)));
  CHECK(s.df == doctest::Approx(6.0 * std::cos(2.6)));
  CHECK(s.ddf == doctest::Approx(-18.0 * std::sin(2.6)));
  // A piece: 1 - t + 2 t^2 + 0.5 sin(3 t + 0.2) - 0.25 sin(7 t), derivatives by hand.
  const mbrt::TimeValue h = mbrt::polynomial_and_harmonics(std::array<double, 3>{1, -1, 2},
                                                           std::array<mbrt::Harmonic, 2>{{{0.5, 3, 0.2}, {-0.25, 7, 0}}}, 0.7);
  CHECK(h.f == doctest::Approx(1 - 0.7 + 2 * 0.49 + 0.5 * std::sin(2.3) - 0.25 * std::sin(4.9)));
  CHECK(h.df == doctest::Approx(-1 + 4 * 0.7 + 1.5 * std::cos(2.3) - 1.75 * std::cos(4.9)));
  CHECK(h.ddf == doctest::Approx(4 - 4.5 * std::sin(2.3) + 12.25 * std::sin(4.9)));
}

// The hub angle of Simo & Vu-Quoc's spin-up (1986), two pieces of one driver
// function, against its closed form: angle, rate, and the motor torque
// J theta'' (J = m L^2 / 3 = 400 kg m^2), before, across and after the hand-over at 15 s.
TEST_CASE("a piecewise driver with polynomial and harmonic terms follows the spin-up profile") {
  namespace m = mbrt::models::spin_up_rod;
  const auto theta = [](double t) {
    const double a = 15.0 / (2 * M_PI), w = 2 * M_PI / 15.0;
    if (t >= 15.0) return std::array<double, 3>{6 * t - 45, 6, 0};
    return std::array<double, 3>{0.4 * (t * t / 2 + a * a * (std::cos(w * t) - 1)), 0.4 * (t - a * std::sin(w * t)),
                                 0.4 * (1 - std::cos(w * t))};
  };
  m::State s = m::initial_state();
  double worst_angle = 0, worst_rate = 0, worst_torque = 0;
  for (int i = 0; i < 20000; ++i) {
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    const auto exact = theta(s.t);
    const mbrt::Vec3 com = s.rigid[0].r;
    worst_angle = std::max(worst_angle, std::abs(std::remainder(std::atan2(com.y(), com.x()) - exact[0], 2 * M_PI)));
    worst_rate = std::max(worst_rate, std::abs(s.rigid[0].w.z() - exact[1]));
    // The motor row's multiplier is the constraint torque along -J^T: -400 theta''.
    worst_torque = std::max(worst_torque, std::abs(s.lambda[m::kConstraintInfo[1].first_row] + 400.0 * exact[2]));
  }
  MESSAGE("20 s at h = 1e-3: angle error " << worst_angle << " rad, rate error " << worst_rate
                                           << " rad/s, motor torque error " << worst_torque << " N m");
  CHECK(s.rigid[0].w.z() == doctest::Approx(6.0).epsilon(1e-9));
  CHECK(worst_angle < 1e-8);
  CHECK(worst_rate < 1e-6);
  CHECK(worst_torque < 1e-2);  // of up to 320 N m
}

TEST_CASE("a rod driven at constant speed follows the driver, which carries the gravity torque") {
  namespace m = mbrt::models::driven_rod;
  m::State s = m::initial_state();
  double worst_angle = 0, worst_torque = 0;
  for (int i = 0; i < 3000; ++i) {
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    const double theta = 3.0 * s.t;
    const mbrt::Vec3 tip = s.rigid[0].r * 2.0;  // COM at L/2
    worst_angle = std::max(worst_angle, std::abs(std::remainder(std::atan2(tip.y(), tip.x()) - theta, 2 * M_PI)));
    // The motor supplies +m g (L/2) cos(theta) about +z; the multiplier is
    // the constraint force along -J^T, so lambda = -m g (L/2) cos(theta).
    const double lambda = s.lambda[m::kConstraintInfo[1].first_row];
    worst_torque = std::max(worst_torque, std::abs(lambda + 9.81 * 0.5 * std::cos(theta)));
  }
  MESSAGE("3 s at h = 1e-3: angle error " << worst_angle << " rad, motor torque error " << worst_torque << " N m");
  CHECK(worst_angle < 1e-8);
  CHECK(worst_torque < 2e-2);  // of up to 4.9 N m; the multiplier is O(h) accurate
}

TEST_CASE("a nut on a screw falls with the effective mass m + J/p^2 and turns with the thread") {
  namespace m = mbrt::models::screw_nut;
  const double mass = 0.2, J = 0.0005, pitch = 0.05 / (2 * M_PI);
  const double a = -9.81 * mass / (mass + J / (pitch * pitch));
  m::State s = m::initial_state();
  for (int i = 0; i < 1000; ++i) REQUIRE(m::step(s) == mbrt::StepStatus::ok);
  const double z = 1.0 + 0.5 * a * s.t * s.t;
  CHECK(s.rigid[0].r.z() == doctest::Approx(z).epsilon(1e-6));
  // Turned by (z - z0) / p about +z.
  const mbrt::Mat3 R = mbrt::rotation_matrix(s.rigid[0].p);
  const double turned = std::atan2(R(1, 0), R(0, 0));
  CHECK(std::abs(std::remainder(turned - (s.rigid[0].r.z() - 1.0) / pitch, 2 * M_PI)) < 1e-6);
  CHECK(std::abs(s.rigid[0].r.x()) < 1e-9);
}

TEST_CASE("a puck on a tilted plane slides down with g sin(30 deg) and keeps its spin") {
  namespace m = mbrt::models::planar_slide;
  m::State s = m::initial_state();
  for (int i = 0; i < 1000; ++i) REQUIRE(m::step(s) == mbrt::StepStatus::ok);
  // Down the slope: along the plane, the component of gravity -z with normal n.
  const Vec3 n(0, -0.5, std::sqrt(3.0) / 2);
  const Vec3 g(0, 0, -9.81);
  const Vec3 along = g - g.dot(n) * n;
  const Vec3 expected = Vec3(1, 0, 0) * s.t + 0.5 * along * s.t * s.t;
  CHECK((s.rigid[0].r - expected).norm() < 1e-9);
  CHECK(along.norm() == doctest::Approx(9.81 * 0.5));
  CHECK((s.rigid[0].w - Vec3(0, 0, 2)).norm() < 1e-9);
}

TEST_CASE("a particle on a driven rope follows L(t) and the rope pulls with -m L''") {
  namespace m = mbrt::models::breathing_rope;
  m::State s = m::initial_state();
  double worst_r = 0, worst_lambda = 0;
  for (int i = 0; i < 3000; ++i) {
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    const double L = 1.0 + 0.1 * std::sin(2 * s.t), L_dd = -0.4 * std::sin(2 * s.t);
    worst_r = std::max(worst_r, (s.particle[0].r - L * Vec3(0.6, 0.8, 0)).norm());
    worst_lambda = std::max(worst_lambda, std::abs(s.lambda[0] + 2.0 * L_dd));
  }
  MESSAGE("3 s: position error " << worst_r << " m, rope force error " << worst_lambda << " N");
  CHECK(worst_r < 1e-7);
  CHECK(worst_lambda < 1e-2);
}

TEST_CASE("a driven slider follows x = t^2 / 2 and the actuator pushes with m x''") {
  namespace m = mbrt::models::driven_slider;
  m::State s = m::initial_state();
  for (int i = 0; i < 2000; ++i) REQUIRE(m::step(s) == mbrt::StepStatus::ok);
  CHECK(s.rigid[0].r.x() == doctest::Approx(0.5 * s.t * s.t).epsilon(1e-9));
  CHECK(s.rigid[0].v.x() == doctest::Approx(s.t).epsilon(1e-9));
  const double lambda = s.lambda[m::kConstraintInfo[1].first_row];
  CHECK(lambda == doctest::Approx(-3.0).epsilon(1e-6));
}
