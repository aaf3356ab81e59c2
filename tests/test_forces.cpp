// Independent tests of forces.hpp and the inertia products of body_state.hpp.
// References: finite differences of the energy, moments computed in world axes,
// Euler's equations written out for principal axes, and Eigen's geometry module.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <random>

#include "mbrt/forces.hpp"

namespace {

using mbrt::BodyMotion;
using mbrt::BodyPose;
using mbrt::BodyVelocity;
using mbrt::Mat3;
using mbrt::Vec3;
using Quat = Eigen::Quaterniond;

class Random {
 public:
  explicit Random(unsigned seed) : gen_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(gen_); }
  Vec3 vec3(double scale) {
    Vec3 x;
    for (int i = 0; i < 3; ++i) x[i] = uniform(-scale, scale);
    return x;
  }
  Mat3 rotation() {
    Eigen::Vector4d c;
    do {
      for (int i = 0; i < 4; ++i) c[i] = std::normal_distribution<double>(0.0, 1.0)(gen_);
    } while (c.norm() < 1e-3);
    c.normalize();
    return Quat(c[0], c[1], c[2], c[3]).toRotationMatrix();
  }

 private:
  std::mt19937 gen_;
};

double max_abs(const Vec3& x) { return x.cwiseAbs().maxCoeff(); }

// A body of mass m whose principal moments J lie along the columns of Q (principal to body axes).
mbrt::FullInertia full_inertia(double m, const Vec3& J, const Mat3& Q) {
  const Mat3 J_body = Q * J.asDiagonal() * Q.transpose();
  const Quat axes(Q);
  return {m, J_body, J_body.inverse(), J, mbrt::EulerParameters(axes.w(), axes.x(), axes.y(), axes.z())};
}

struct Body {
  BodyPose pose;
  BodyVelocity vel;
};

Body random_body(Random& rnd) {
  Body b{BodyPose{rnd.vec3(1.0), rnd.rotation()}, BodyVelocity{rnd.vec3(1.0), rnd.vec3(2.0)}};
  return b;
}

// World position and velocity of body point s, from the rigid velocity field
// x_dot = v + omega_world x (x - r) with omega_world = R w.
Vec3 world_point(const Body& b, const Vec3& s) { return b.pose.r + b.pose.R * s; }
Vec3 world_point_velocity(const Body& b, const Vec3& s) {
  return b.vel.v + (b.pose.R * b.vel.w).cross(b.pose.R * s);
}

mbrt::SpringDamperForce evaluate(const mbrt::SpringDamper& e, const Body& b1, const Body& b2) {
  return mbrt::spring_damper(e, BodyMotion{b1.pose, b1.vel}, BodyMotion{b2.pose, b2.vel});
}

TEST_CASE("spring_damper: attachment points and energy 1/2 k (l - L)^2") {
  Random rnd(301);
  for (int trial = 0; trial < 20; ++trial) {
    const Body b1 = random_body(rnd), b2 = random_body(rnd);
    const mbrt::SpringDamper e{rnd.vec3(0.5), rnd.vec3(0.5), rnd.uniform(1, 100), rnd.uniform(0, 5),
                               rnd.uniform(0.2, 2)};
    const auto out = evaluate(e, b1, b2);
    CHECK(max_abs(out.x1 - world_point(b1, e.s1)) < 1e-14);
    CHECK(max_abs(out.x2 - world_point(b2, e.s2)) < 1e-14);
    const double stretch = (out.x2 - out.x1).norm() - e.rest_length;
    CHECK(out.energy == doctest::Approx(0.5 * e.stiffness * stretch * stretch).epsilon(1e-13));
  }
}

TEST_CASE("spring force on body 2 is minus the gradient of the energy with respect to x2 (no damping)") {
  Random rnd(302);
  const double eps = 1e-6;
  for (int trial = 0; trial < 20; ++trial) {
    const Body b1 = random_body(rnd), b2 = random_body(rnd);
    const mbrt::SpringDamper e{rnd.vec3(0.5), rnd.vec3(0.5), rnd.uniform(1, 100), 0.0, rnd.uniform(0.2, 2)};
    const Vec3 f2 = evaluate(e, b1, b2).f2;
    // Translating body 2 by delta moves x2 by delta.
    Vec3 gradient;
    for (int k = 0; k < 3; ++k) {
      Body plus = b2, minus = b2;
      plus.pose.r[k] += eps;
      minus.pose.r[k] -= eps;
      gradient[k] = (evaluate(e, b1, plus).energy - evaluate(e, b1, minus).energy) / (2 * eps);
    }
    CHECK(max_abs(f2 + gradient) < 1e-7 * std::max(1.0, gradient.norm()));
    CHECK(f2.norm() > 1e-3);
  }
}

TEST_CASE("damping force is -c (n . relative velocity) n and ignores sliding across the line") {
  Random rnd(303);
  for (int trial = 0; trial < 20; ++trial) {
    const Body b1 = random_body(rnd), b2 = random_body(rnd);
    const double c = rnd.uniform(0.5, 5);
    const mbrt::SpringDamper pure_damper{rnd.vec3(0.5), rnd.vec3(0.5), 0.0, c, rnd.uniform(0.2, 2)};
    const Vec3 x1 = world_point(b1, pure_damper.s1), x2 = world_point(b2, pure_damper.s2);
    const Vec3 n = (x2 - x1).normalized();
    const Vec3 relative = world_point_velocity(b2, pure_damper.s2) - world_point_velocity(b1, pure_damper.s1);
    const Vec3 expected = -c * n.dot(relative) * n;
    const Vec3 f2 = evaluate(pure_damper, b1, b2).f2;
    CHECK(max_abs(f2 - expected) < 1e-13 * std::max(1.0, expected.norm()));
    CHECK(expected.norm() > 1e-6);

    // Adding velocity perpendicular to the line leaves the force unchanged.
    Body sliding = b2;
    sliding.vel.v += n.cross(rnd.vec3(1.0));
    CHECK(max_abs(evaluate(pure_damper, b1, sliding).f2 - expected) < 1e-13 * std::max(1.0, expected.norm()));

    // Spring and damper superpose.
    mbrt::SpringDamper both = pure_damper;
    both.stiffness = rnd.uniform(1, 100);
    mbrt::SpringDamper spring = both;
    spring.damping = 0.0;
    const Vec3 sum = evaluate(spring, b1, b2).f2 + expected;
    CHECK(max_abs(evaluate(both, b1, b2).f2 - sum) < 1e-12 * std::max(1.0, sum.norm()));
  }
}

TEST_CASE("spring_damper pulls a stretched spring together and pushes a compressed one apart") {
  const Body b1{BodyPose{Vec3::Zero(), Mat3::Identity()}, BodyVelocity{Vec3::Zero(), Vec3::Zero()}};
  Body b2 = b1;
  b2.pose.r = Vec3(2, 0, 0);
  const mbrt::SpringDamper e{Vec3::Zero(), Vec3::Zero(), 10.0, 0.0, 1.0};
  CHECK(max_abs(evaluate(e, b1, b2).f2 - Vec3(-10, 0, 0)) < 1e-14);
  b2.pose.r = Vec3(0.5, 0, 0);
  CHECK(max_abs(evaluate(e, b1, b2).f2 - Vec3(5, 0, 0)) < 1e-14);
}

TEST_CASE("coincident attachment points give zero force and no NaN") {
  Random rnd(304);
  for (int trial = 0; trial < 10; ++trial) {
    const Body b1 = random_body(rnd);
    Body b2 = random_body(rnd);
    const mbrt::SpringDamper e{rnd.vec3(0.5), rnd.vec3(0.5), rnd.uniform(1, 100), rnd.uniform(0.5, 5),
                               rnd.uniform(0.2, 2)};
    b2.pose.r = world_point(b1, e.s1) - b2.pose.R * e.s2;  // x2 == x1 (to round-off)
    const auto out = evaluate(e, b1, b2);
    CHECK(out.f2.allFinite());
    CHECK(out.f2 == Vec3::Zero());
    CHECK(std::isfinite(out.energy));
    CHECK(out.energy == doctest::Approx(0.5 * e.stiffness * e.rest_length * e.rest_length).epsilon(1e-12));
  }
}

TEST_CASE("add_point_force: the torque is the world moment (R s) x f expressed in body axes, and accumulates") {
  Random rnd(305);
  for (int trial = 0; trial < 20; ++trial) {
    const BodyPose pose{rnd.vec3(1.0), rnd.rotation()};
    const Vec3 s = rnd.vec3(1.0), f = rnd.vec3(10.0);
    const mbrt::Wrench initial{rnd.vec3(1.0), rnd.vec3(1.0)};
    mbrt::Wrench w = initial;
    mbrt::add_point_force(w, pose, s, f);
    const Vec3 world_moment = (pose.R * s).cross(f);
    CHECK(max_abs(w.f - (initial.f + f)) < 1e-14 * 10);
    CHECK(max_abs(w.tau - (initial.tau + pose.R.transpose() * world_moment)) < 1e-13);

    // A force at the COM adds no torque.
    mbrt::Wrench at_com;
    mbrt::add_point_force(at_com, pose, Vec3::Zero(), f);
    CHECK(at_com.tau == Vec3::Zero());
    CHECK(at_com.f == f);
  }
  // A default wrench is zero.
  const mbrt::Wrench zero;
  CHECK(zero.f == Vec3::Zero());
  CHECK(zero.tau == Vec3::Zero());
}

TEST_CASE("axial_torque_world is value times the body-1 axis in world axes") {
  Random rnd(306);
  // Hand case: body 1 turned +90 degrees about z, axis along body x -> world y.
  const BodyPose turned{Vec3::Zero(), Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix()};
  CHECK(max_abs(mbrt::axial_torque_world(mbrt::AxialTorque{Vec3::UnitX(), 3.0}, turned) - Vec3(0, 3, 0)) < 1e-15);
  for (int trial = 0; trial < 10; ++trial) {
    const BodyPose pose{rnd.vec3(1.0), rnd.rotation()};
    const Vec3 world_axis = rnd.vec3(1.0).normalized();
    const double value = rnd.uniform(-5, 5);
    const Vec3 t = mbrt::axial_torque_world(mbrt::AxialTorque{pose.R.transpose() * world_axis, value}, pose);
    CHECK(max_abs(t - value * world_axis) < 1e-14);
  }
}

// A revolute or prismatic joint between two random bodies, body 2 turned by
// theta about, or slid by d along, the joint axis from its pose at t = 0.
struct JointPair {
  mbrt::JointFrame frame;
  Body b1, b2_at_zero;

  explicit JointPair(Random& rnd) : b1(random_body(rnd)), b2_at_zero(random_body(rnd)) {
    const Vec3 point = rnd.vec3(1.0);
    const Vec3 a = rnd.vec3(1.0).normalized();
    const Vec3 b = a.unitOrthogonal(), c = a.cross(b);
    const Mat3& R1 = b1.pose.R;
    const Mat3& R2 = b2_at_zero.pose.R;
    frame = {R1.transpose() * (point - b1.pose.r), R2.transpose() * (point - b2_at_zero.pose.r),
             R1.transpose() * a, R1.transpose() * b, R1.transpose() * c,
             R2.transpose() * a, R2.transpose() * b, R2.transpose() * c, 0.0, 0.0};
    b1.vel = {Vec3::Zero(), Vec3::Zero()};
  }
  Vec3 axis() const { return b1.pose.R * frame.a1; }
  // Turned by theta at rate theta_dot: the rotation about the axis through the joint point.
  Body turned(double theta, double theta_dot) const {
    const Mat3 turn = Eigen::AngleAxisd(theta, axis()).toRotationMatrix();
    const Vec3 point = world_point(b2_at_zero, frame.s2);
    const Vec3 omega = theta_dot * axis();
    Body b{BodyPose{point + turn * (b2_at_zero.pose.r - point), turn * b2_at_zero.pose.R}, {}};
    b.vel = {omega.cross(b.pose.r - point), b.pose.R.transpose() * omega};
    return b;
  }
  Body slid(double d, double d_dot) const {
    return Body{BodyPose{b2_at_zero.pose.r + d * axis(), b2_at_zero.pose.R}, BodyVelocity{d_dot * axis(), Vec3::Zero()}};
  }
  mbrt::JointCoordinate revolute(const Body& b2) const {
    return mbrt::revolute_coordinate(frame, BodyMotion{b1.pose, b1.vel}, BodyMotion{b2.pose, b2.vel});
  }
  mbrt::JointCoordinate prismatic(const Body& b2) const {
    return mbrt::prismatic_coordinate(frame, BodyMotion{b1.pose, b1.vel}, BodyMotion{b2.pose, b2.vel});
  }
};

TEST_CASE("joint_spring on a revolute joint: the torque is minus the derivative of the energy, the damper -c theta'") {
  Random rnd(311);
  const double eps = 1e-6;
  for (int trial = 0; trial < 20; ++trial) {
    const JointPair j(rnd);
    const mbrt::JointSpring e{rnd.uniform(0.1, 10), rnd.uniform(0, 1), rnd.uniform(-1, 1)};
    const double theta = rnd.uniform(-2, 2), theta_dot = rnd.uniform(-3, 3);
    const mbrt::JointCoordinate q = j.revolute(j.turned(theta, theta_dot));
    CHECK(q.position == doctest::Approx(theta).epsilon(1e-12));
    CHECK(q.velocity == doctest::Approx(theta_dot).epsilon(1e-12));
    const auto energy = [&](double angle) { return mbrt::joint_spring(e, j.revolute(j.turned(angle, 0.0))).energy; };
    const double derivative = (energy(theta + eps) - energy(theta - eps)) / (2 * eps);
    const mbrt::JointSpringLoad load = mbrt::joint_spring(e, q);
    CHECK(load.value + e.damping * theta_dot == doctest::Approx(-derivative).epsilon(1e-7).scale(1.0));
    CHECK(load.energy == doctest::Approx(0.5 * e.stiffness * (theta - e.rest) * (theta - e.rest)).epsilon(1e-12));
  }
}

TEST_CASE("joint_spring on a prismatic joint: the force is minus the derivative of the energy, the damper -c d'") {
  Random rnd(312);
  const double eps = 1e-6;
  for (int trial = 0; trial < 20; ++trial) {
    const JointPair j(rnd);
    const mbrt::JointSpring e{rnd.uniform(1, 100), rnd.uniform(0, 5), rnd.uniform(-0.5, 0.5)};
    const double d = rnd.uniform(-1, 1), d_dot = rnd.uniform(-2, 2);
    const mbrt::JointCoordinate q = j.prismatic(j.slid(d, d_dot));
    CHECK(q.position == doctest::Approx(d).epsilon(1e-12));
    CHECK(q.velocity == doctest::Approx(d_dot).epsilon(1e-12));
    const auto energy = [&](double slide) { return mbrt::joint_spring(e, j.prismatic(j.slid(slide, 0.0))).energy; };
    const double derivative = (energy(d + eps) - energy(d - eps)) / (2 * eps);
    const mbrt::JointSpringLoad load = mbrt::joint_spring(e, q);
    CHECK(load.value + e.damping * d_dot == doctest::Approx(-derivative).epsilon(1e-7).scale(1.0));
  }
}

TEST_CASE("gyroscopic_torque: Euler's equations for principal axes, equals FullInertia, perpendicular to w") {
  Random rnd(307);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 J(rnd.uniform(0.1, 3), rnd.uniform(0.1, 3), rnd.uniform(0.1, 3));
    const Vec3 w = rnd.vec3(5.0);
    const mbrt::PrincipalInertia principal{2.0, J};
    const mbrt::FullInertia full = full_inertia(2.0, J, Mat3::Identity());
    const Vec3 t = mbrt::gyroscopic_torque(principal, w);
    // -w x (J w) for diagonal J, component-wise.
    const Vec3 euler((J[1] - J[2]) * w[1] * w[2], (J[2] - J[0]) * w[2] * w[0], (J[0] - J[1]) * w[0] * w[1]);
    CHECK(max_abs(t - euler) < 1e-13 * std::max(1.0, euler.norm()));
    CHECK(max_abs(mbrt::gyroscopic_torque(full, w) - t) < 1e-13 * std::max(1.0, t.norm()));
    CHECK(std::abs(t.dot(w)) < 1e-12 * std::max(1.0, t.norm() * w.norm()));

    // A rotated inertia tensor: the torque transforms as a vector.
    const Mat3 Q = rnd.rotation();
    const mbrt::FullInertia rotated = full_inertia(2.0, J, Q);
    CHECK(max_abs(mbrt::gyroscopic_torque(rotated, Q * w) - Q * t) < 1e-12 * std::max(1.0, t.norm()));
    // Spinning about a principal axis produces no torque.
    CHECK(max_abs(mbrt::gyroscopic_torque(principal, Vec3(0, w[1], 0))) == 0.0);
  }
}

TEST_CASE("inertia_times and inverse_inertia_times are inverse, for principal and full inertia") {
  Random rnd(308);
  const Vec3 J(1.0, 2.0, 3.0);
  const Vec3 w = rnd.vec3(1.0);
  const mbrt::PrincipalInertia principal{1.0, J};
  CHECK(max_abs(mbrt::inertia_times(principal, w) - Vec3(w[0], 2 * w[1], 3 * w[2])) < 1e-15);
  CHECK(max_abs(mbrt::inverse_inertia_times(principal, mbrt::inertia_times(principal, w)) - w) < 1e-15);
  const Mat3 Q = rnd.rotation();
  const mbrt::FullInertia full = full_inertia(1.0, J, Q);
  const Mat3& Jr = full.J;
  CHECK(max_abs(mbrt::inertia_times(full, w) - Jr * w) < 1e-15);
  CHECK(max_abs(mbrt::inverse_inertia_times(full, mbrt::inertia_times(full, w)) - w) < 1e-14);
}

}  // namespace
