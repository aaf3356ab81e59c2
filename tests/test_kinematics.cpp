// Independent tests of rotation.hpp, constraint_kernels.hpp, joints.hpp and the
// pose helpers of body_state.hpp. References come from Eigen's geometry module,
// definitions written out by hand, and finite differences of the motion
// (translation integrated exactly, rotation by the exact exponential map or RK4).
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "mbrt/joints.hpp"

namespace {

using mbrt::BodyMotion;
using mbrt::BodyPose;
using mbrt::BodyVelocity;
using mbrt::EulerParameters;
using mbrt::JointFrame;
using mbrt::Mat3;
using mbrt::Vec3;
using mbrt::Vec4;
using Quat = Eigen::Quaterniond;
using Eigen::MatrixXd;
using Eigen::VectorXd;

// ---------------------------------------------------------------------------
// Random data (fixed seeds: every test case seeds its own generator)

class Random {
 public:
  explicit Random(unsigned seed) : gen_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(gen_); }
  double normal() { return std::normal_distribution<double>(0.0, 1.0)(gen_); }
  Vec3 vec3(double scale) {
    Vec3 x;
    for (int i = 0; i < 3; ++i) x[i] = uniform(-scale, scale);
    return x;
  }
  Vec3 unit_vec3() {
    Vec3 x;
    do {
      for (int i = 0; i < 3; ++i) x[i] = normal();
    } while (x.norm() < 1e-3);
    return x.normalized();
  }

 private:
  std::mt19937 gen_;
};

Quat random_unit_quaternion(Random& rnd) {
  Vec4 c;
  do {
    for (int i = 0; i < 4; ++i) c[i] = rnd.normal();
  } while (c.norm() < 1e-3);
  c.normalize();
  return Quat(c[0], c[1], c[2], c[3]);  // Eigen's constructor order is (w, x, y, z)
}

EulerParameters to_euler_parameters(const Quat& q) { return EulerParameters(q.w(), q.x(), q.y(), q.z()); }
Quat to_quat(const EulerParameters& p) { return Quat(p[0], p[1], p[2], p[3]); }

// exp(theta / 2) as a unit quaternion: rotation by |theta| about theta.
Quat rotation_exp(const Vec3& theta) {
  const double angle = theta.norm();
  if (angle == 0.0) return Quat::Identity();
  return Quat(Eigen::AngleAxisd(angle, theta / angle));
}

// Distance between two unit quaternions as rotations (sign-insensitive).
double quaternion_distance(const EulerParameters& a, const EulerParameters& b) {
  return std::min((a - b).norm(), (a + b).norm());
}

// Random orthonormal right-handed triad, as the columns of a rotation matrix.
Mat3 random_triad(Random& rnd) { return random_unit_quaternion(rnd).toRotationMatrix(); }

double scale_of(const VectorXd& x) { return std::max(1.0, x.cwiseAbs().maxCoeff()); }
double max_abs(const MatrixXd& x) { return x.size() == 0 ? 0.0 : x.cwiseAbs().maxCoeff(); }

// ---------------------------------------------------------------------------
// 1. rotation.hpp

TEST_CASE("rotation_matrix is orthonormal with determinant +1 and equals Eigen's") {
  Random rnd(101);
  for (int trial = 0; trial < 200; ++trial) {
    const Quat q = random_unit_quaternion(rnd);
    const Mat3 R = mbrt::rotation_matrix(to_euler_parameters(q));
    CHECK(max_abs(R.transpose() * R - Mat3::Identity()) < 1e-14);
    CHECK(R.determinant() == doctest::Approx(1.0).epsilon(1e-14));
    CHECK(max_abs(R - q.toRotationMatrix()) < 1e-14);
  }
}

TEST_CASE("rotation_matrix of an axis-angle quaternion matches Eigen::AngleAxisd (body to world)") {
  Random rnd(102);
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 n = rnd.unit_vec3();
    const double angle = rnd.uniform(-3.0, 3.0);
    const EulerParameters p(std::cos(angle / 2), std::sin(angle / 2) * n.x(), std::sin(angle / 2) * n.y(),
                            std::sin(angle / 2) * n.z());
    CHECK(max_abs(mbrt::rotation_matrix(p) - Eigen::AngleAxisd(angle, n).toRotationMatrix()) < 1e-14);
  }
  // A hand case: +90 degrees about z maps body x to world y.
  const double h = std::sqrt(0.5);
  const Vec3 y = mbrt::rotation_matrix(EulerParameters(h, 0, 0, h)) * Vec3::UnitX();
  CHECK(max_abs(y - Vec3::UnitY()) < 1e-15);
}

TEST_CASE("quaternion_product is the Hamilton product (matches Eigen, also for non-unit factors)") {
  Random rnd(103);
  for (int trial = 0; trial < 100; ++trial) {
    EulerParameters a, b;
    for (int i = 0; i < 4; ++i) a[i] = rnd.uniform(-2, 2);
    for (int i = 0; i < 4; ++i) b[i] = rnd.uniform(-2, 2);
    const Quat expected = to_quat(a) * to_quat(b);
    CHECK((mbrt::quaternion_product(a, b) - to_euler_parameters(expected)).norm() < 1e-14);
  }
  // Composition: R(a * b) = R(a) R(b) for unit factors.
  const EulerParameters a = to_euler_parameters(random_unit_quaternion(rnd));
  const EulerParameters b = to_euler_parameters(random_unit_quaternion(rnd));
  CHECK(max_abs(mbrt::rotation_matrix(mbrt::quaternion_product(a, b)) -
                mbrt::rotation_matrix(a) * mbrt::rotation_matrix(b)) < 1e-14);
  // Hand case: i * j = k.
  CHECK((mbrt::quaternion_product(EulerParameters(0, 1, 0, 0), EulerParameters(0, 0, 1, 0)) -
         EulerParameters(0, 0, 0, 1)).norm() == 0.0);
}

TEST_CASE("cayley_increment has unit norm, points along theta and solves the implicit midpoint rule") {
  Random rnd(104);
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 theta = rnd.vec3(trial < 50 ? 1.0 : 10.0);
    const EulerParameters c = mbrt::cayley_increment(theta);
    CHECK(c.norm() == doctest::Approx(1.0).epsilon(1e-15));
    CHECK(c.tail<3>().cross(theta).norm() < 1e-14 * theta.norm());
    CHECK(c.tail<3>().dot(theta) >= 0.0);
    // (p+ - p) = 1/2 * ((p + p+)/2) * (0, theta), with p+ = p * c.
    const Quat p = random_unit_quaternion(rnd);
    const Quat p_next = p * to_quat(c);
    const Vec4 mid = 0.5 * (p.coeffs() + p_next.coeffs());
    Quat mid_q;
    mid_q.coeffs() = mid;
    const Vec4 rhs = 0.5 * (mid_q * Quat(0, theta.x(), theta.y(), theta.z())).coeffs();
    CHECK((p_next.coeffs() - p.coeffs() - rhs).norm() < 1e-14 * (1 + theta.norm()));
  }
  CHECK((mbrt::cayley_increment(Vec3::Zero()) - EulerParameters(1, 0, 0, 0)).norm() == 0.0);
}

TEST_CASE("cayley_increment matches exp(theta/2) to third order in theta") {
  Random rnd(105);
  for (int trial = 0; trial < 10; ++trial) {
    const Vec3 direction = rnd.unit_vec3();
    double previous = 0.0;
    for (int k = 0; k < 6; ++k) {
      const double angle = 0.2 / (1 << k);
      const Vec3 theta = angle * direction;
      const double err =
          quaternion_distance(mbrt::cayley_increment(theta), to_euler_parameters(rotation_exp(theta)));
      // Leading term: half-angle error |theta|/2 - 2 atan(|theta|/4) = |theta|^3 / 96.
      CHECK(err == doctest::Approx(std::pow(angle, 3) / 96).epsilon(0.02).scale(0));
      if (k > 0) CHECK(previous / err == doctest::Approx(8.0).epsilon(0.02));
      previous = err;
    }
  }
}

TEST_CASE("advance_euler_parameters converges to exp(h w) with error ~ K^-2 and keeps unit norm") {
  Random rnd(106);
  for (int trial = 0; trial < 5; ++trial) {
    const Quat p = random_unit_quaternion(rnd);
    const Vec3 w = 2.0 * rnd.unit_vec3();
    const double h = 0.5;
    const EulerParameters exact = to_euler_parameters(p * rotation_exp(h * w));  // constant body w
    double previous = 0.0;
    for (int K = 1; K <= 128; K *= 2) {
      const EulerParameters q = mbrt::advance_euler_parameters(to_euler_parameters(p), w, h, K);
      CHECK(q.norm() == doctest::Approx(1.0).epsilon(1e-14));
      const double err = quaternion_distance(q, exact);
      // Total angle error (h|w|)^3 / (48 K^2): quaternion distance is half of it.
      CHECK(err == doctest::Approx(std::pow(h * w.norm(), 3) / (96.0 * K * K)).epsilon(0.05).scale(0));
      if (K > 1) CHECK(previous / err == doctest::Approx(4.0).epsilon(0.05));
      previous = err;
    }
  }
}

TEST_CASE("pose_of and velocity_of: rigid bodies use R(p), particles and ground use R = I, w = 0") {
  Random rnd(107);
  const Quat q = random_unit_quaternion(rnd);
  const mbrt::RigidState rigid{rnd.vec3(1), to_euler_parameters(q), rnd.vec3(1), rnd.vec3(1)};
  const BodyPose pose = mbrt::pose_of(rigid);
  const BodyVelocity vel = mbrt::velocity_of(rigid);
  CHECK(pose.r == rigid.r);
  CHECK(max_abs(pose.R - q.toRotationMatrix()) < 1e-14);
  CHECK(vel.v == rigid.v);
  CHECK(vel.w == rigid.w);
  const mbrt::ParticleState particle{rnd.vec3(1), rnd.vec3(1)};
  CHECK(mbrt::pose_of(particle).r == particle.r);
  CHECK(mbrt::pose_of(particle).R == Mat3::Identity());
  CHECK(mbrt::velocity_of(particle).v == particle.v);
  CHECK(mbrt::velocity_of(particle).w == Vec3::Zero());
  CHECK(mbrt::ground_pose().r == Vec3::Zero());
  CHECK(mbrt::ground_pose().R == Mat3::Identity());
  CHECK(mbrt::ground_velocity().v == Vec3::Zero());
  CHECK(mbrt::ground_velocity().w == Vec3::Zero());
}

// ---------------------------------------------------------------------------
// Bodies and their motion

enum class Kind { rigid, particle, ground };

const char* kind_name(Kind k) { return k == Kind::rigid ? "rigid" : k == Kind::particle ? "particle" : "ground"; }

struct TestBody {
  Kind kind = Kind::rigid;
  Vec3 r = Vec3::Zero(), v = Vec3::Zero(), a = Vec3::Zero();  // COM, world
  Quat q = Quat::Identity();                                  // body to world
  Vec3 w = Vec3::Zero(), alpha = Vec3::Zero();                // body axes
};

Mat3 rotation_of(const TestBody& b) { return b.kind == Kind::rigid ? b.q.toRotationMatrix() : Mat3::Identity(); }

// R^T x: world vector in body components.
Vec3 body_components(const TestBody& b, const Vec3& world) { return rotation_of(b).transpose() * world; }

TestBody random_body(Random& rnd, Kind kind) {
  TestBody b;
  b.kind = kind;
  if (kind == Kind::ground) return b;
  b.r = rnd.vec3(1.0);
  b.v = rnd.vec3(1.0);
  if (kind == Kind::particle) return b;
  b.q = random_unit_quaternion(rnd);
  b.w = rnd.vec3(2.0);
  return b;
}

void set_random_accelerations(Random& rnd, TestBody& b) {
  if (b.kind == Kind::ground) return;
  b.a = rnd.vec3(2.0);
  if (b.kind == Kind::rigid) b.alpha = rnd.vec3(3.0);
}

// Body state at time t under constant a (world) and constant alpha (body):
// translation exactly; rotation p' = 1/2 p * (0, w0 + alpha t) by the exact
// exponential map when alpha = 0, else by RK4 with many small steps.
TestBody advance_pose(const TestBody& b, double t) {
  TestBody out = b;
  if (b.kind == Kind::ground) return out;
  out.r = b.r + t * b.v + 0.5 * t * t * b.a;
  out.v = b.v + t * b.a;
  if (b.kind == Kind::particle) return out;
  out.w = b.w + t * b.alpha;
  if (b.alpha.isZero(0.0)) {
    out.q = b.q * rotation_exp(t * b.w);
    return out;
  }
  const auto rate = [&](const Vec4& coeffs, double tau) {
    Quat q;
    q.coeffs() = coeffs;
    const Vec3 w = b.w + tau * b.alpha;
    return Vec4(0.5 * (q * Quat(0.0, w.x(), w.y(), w.z())).coeffs());
  };
  const int steps = 64;
  const double h = t / steps;
  Vec4 y = b.q.coeffs();
  for (int i = 0; i < steps; ++i) {
    const double tau = i * h;
    const Vec4 k1 = rate(y, tau);
    const Vec4 k2 = rate(y + 0.5 * h * k1, tau + 0.5 * h);
    const Vec4 k3 = rate(y + 0.5 * h * k2, tau + 0.5 * h);
    const Vec4 k4 = rate(y + h * k3, tau + h);
    y += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  out.q.coeffs() = y;
  return out;
}

// Rigid displacement x -> center + Q (x - center) + shift applied to a body.
TestBody displaced(const TestBody& b, const Quat& Q, const Vec3& center, const Vec3& shift) {
  TestBody out = b;
  if (b.kind == Kind::ground) return out;
  out.r = center + Q * (b.r - center) + shift;
  if (b.kind == Kind::rigid) out.q = Q * b.q;
  return out;
}

// The kernels' view of a body: rigid poses built from Eigen's rotation matrix,
// particles and ground through the library's own helpers.
struct Snapshot {
  BodyPose pose;
  BodyVelocity vel;
};

Snapshot snapshot(const TestBody& b) {
  switch (b.kind) {
    case Kind::ground:
      return {mbrt::ground_pose(), mbrt::ground_velocity()};
    case Kind::particle: {
      const mbrt::ParticleState s{b.r, b.v};
      return {mbrt::pose_of(s), mbrt::velocity_of(s)};
    }
    case Kind::rigid:
      break;
  }
  return {BodyPose{b.r, b.q.toRotationMatrix()}, BodyVelocity{b.v, b.w}};
}

// ---------------------------------------------------------------------------
// Joints

struct Rows {
  VectorXd phi, quad;
  MatrixXd J1, J2;
};

template <int N>
Rows dynamic_rows(const mbrt::ConstraintRows<N>& c) {
  return {c.phi, c.quad, c.J1, c.J2};
}

enum class JointKind { spherical, revolute, universal, cylindrical, prismatic, fixed, distance };

struct JointType {
  JointKind kind;
  const char* name;
  int rows;                  // from the joint definitions, not from the code
  std::vector<int> allowed;  // relative twists at the joint point that keep it: 0..2 rotation about A, B, C;
                             // 3..5 translation along A, B, C (A is the axis; along x2 - x1 for distance)
  std::function<Rows(const JointFrame&, const BodyMotion&, const BodyMotion&)> evaluate;
};

const std::vector<JointType>& joint_types() {
  using F = const JointFrame&;
  using M = const BodyMotion&;
  static const std::vector<JointType> types = {
      {JointKind::spherical, "spherical", 3, {0, 1, 2},
       [](F f, M m1, M m2) { return dynamic_rows(mbrt::spherical(f, m1, m2)); }},
      {JointKind::revolute, "revolute", 5, {0},
       [](F f, M m1, M m2) { return dynamic_rows(mbrt::revolute(f, m1, m2)); }},
      {JointKind::universal, "universal", 4, {0, 1},
       [](F f, M m1, M m2) { return dynamic_rows(mbrt::universal(f, m1, m2)); }},
      {JointKind::cylindrical, "cylindrical", 4, {0, 3},
       [](F f, M m1, M m2) { return dynamic_rows(mbrt::cylindrical(f, m1, m2)); }},
      {JointKind::prismatic, "prismatic", 5, {3},
       [](F f, M m1, M m2) { return dynamic_rows(mbrt::prismatic(f, m1, m2)); }},
      {JointKind::fixed, "fixed", 6, {},
       [](F f, M m1, M m2) { return dynamic_rows(mbrt::fixed(f, m1, m2)); }},
      {JointKind::distance, "distance", 1, {0, 1, 2, 4, 5},
       [](F f, M m1, M m2) { return dynamic_rows(mbrt::distance(f, m1, m2)); }},
  };
  return types;
}

Rows evaluate(const JointType& joint, const JointFrame& f, const TestBody& b1, const TestBody& b2) {
  const Snapshot s1 = snapshot(b1);
  const Snapshot s2 = snapshot(b2);
  return joint.evaluate(f, BodyMotion{s1.pose, s1.vel}, BodyMotion{s2.pose, s2.vel});
}

VectorXd velocity_vector(const TestBody& b) {
  VectorXd u(6);
  u << b.v, b.w;
  return u;
}

VectorXd acceleration_vector(const TestBody& b) {
  VectorXd u(6);
  u << b.a, b.alpha;
  return u;
}

// The rows written out from the joint definitions (independent of the kernels).
VectorXd reference_phi(JointKind kind, const JointFrame& f, const TestBody& b1, const TestBody& b2) {
  const Mat3 R1 = rotation_of(b1), R2 = rotation_of(b2);
  const Vec3 d = (b2.r + R2 * f.s2) - (b1.r + R1 * f.s1);
  const Vec3 A1 = R1 * f.a1, B1 = R1 * f.b1, C1 = R1 * f.c1;
  const Vec3 A2 = R2 * f.a2, B2 = R2 * f.b2, C2 = R2 * f.c2;
  VectorXd phi;
  switch (kind) {
    case JointKind::spherical:
      phi = d;
      break;
    case JointKind::revolute:
      phi.resize(5);
      phi << d, A1.dot(B2), A1.dot(C2);
      break;
    case JointKind::universal:
      phi.resize(4);
      phi << d, A1.dot(A2);
      break;
    case JointKind::cylindrical:
      phi.resize(4);
      phi << A1.dot(B2), A1.dot(C2), B1.dot(d), C1.dot(d);
      break;
    case JointKind::prismatic:
      phi.resize(5);
      phi << A1.dot(B2), A1.dot(C2), B1.dot(d), C1.dot(d), B1.dot(C2);
      break;
    case JointKind::fixed:
      phi.resize(6);
      phi << d, A1.dot(B2), A1.dot(C2), B1.dot(C2);
      break;
    case JointKind::distance:
      phi.resize(1);
      phi << (d.squaredNorm() - f.length * f.length) / (2.0 * f.length);
      break;
  }
  return phi;
}

// Number of leading rows that are the world vector x2 - x1.
int coincidence_rows(JointKind kind) {
  return kind == JointKind::spherical || kind == JointKind::revolute || kind == JointKind::universal ||
                 kind == JointKind::fixed
             ? 3
             : 0;
}

// Two bodies and a joint frame built from a world description, so that the
// joint is satisfied: joint points x1 (body 1) and x2 (body 2) coincide except
// for distance joints; the world triad (A, B, C) is expressed in both bodies.
struct Scenario {
  TestBody b1, b2;
  JointFrame frame;
  Vec3 x1, x2;
  Vec3 A, B, C;
};

Scenario satisfied_scenario(Random& rnd, const JointType& joint, Kind k1, Kind k2) {
  Scenario s;
  s.b1 = random_body(rnd, k1);
  s.b2 = random_body(rnd, k2);
  const Mat3 triad = random_triad(rnd);
  s.A = triad.col(0);
  s.B = triad.col(1);
  s.C = triad.col(2);
  // A particle's joint point is the particle itself.
  s.x1 = k1 == Kind::particle ? s.b1.r : rnd.vec3(1.0);
  const double length = rnd.uniform(0.5, 1.5);
  s.x2 = joint.kind == JointKind::distance ? Vec3(s.x1 + length * s.A) : s.x1;
  if (k2 == Kind::particle) s.b2.r = s.x2;

  JointFrame& f = s.frame;
  f.s1 = body_components(s.b1, s.x1 - s.b1.r);
  f.s2 = body_components(s.b2, s.x2 - s.b2.r);
  f.a1 = body_components(s.b1, s.A);
  f.b1 = body_components(s.b1, s.B);
  f.c1 = body_components(s.b1, s.C);
  f.a2 = body_components(s.b2, joint.kind == JointKind::universal ? s.B : s.A);
  f.b2 = body_components(s.b2, s.B);
  f.c2 = body_components(s.b2, s.C);
  f.length = joint.kind == JointKind::distance ? length : 0.0;
  return s;
}

// Moves the bodies off the constraint manifold; the frame stays.
void violate(Random& rnd, Scenario& s) {
  for (TestBody* b : {&s.b1, &s.b2}) {
    if (b->kind == Kind::ground) continue;
    b->r += rnd.vec3(0.4);
    if (b->kind == Kind::rigid) b->q = b->q * rotation_exp(rnd.vec3(0.5));
  }
}

std::vector<std::pair<Kind, Kind>> pairings(const JointType& joint) {
  std::vector<std::pair<Kind, Kind>> p = {{Kind::rigid, Kind::rigid}, {Kind::ground, Kind::rigid},
                                          {Kind::rigid, Kind::ground}};
  if (joint.kind == JointKind::spherical || joint.kind == JointKind::distance) {
    p.insert(p.end(), {{Kind::rigid, Kind::particle},
                       {Kind::particle, Kind::rigid},
                       {Kind::ground, Kind::particle},
                       {Kind::particle, Kind::particle}});
  }
  return p;
}

std::string case_name(const JointType& joint, Kind k1, Kind k2, int trial) {
  return std::string(joint.name) + " (" + kind_name(k1) + ", " + kind_name(k2) + ") trial " + std::to_string(trial);
}

// Runs `body` over every joint type, its body pairings and a few random trials.
void for_each_case(unsigned seed, int trials, const std::function<void(const JointType&, Kind, Kind, Random&)>& body) {
  Random rnd(seed);
  for (const JointType& joint : joint_types()) {
    for (const auto& [k1, k2] : pairings(joint)) {
      for (int trial = 0; trial < trials; ++trial) {
        INFO(case_name(joint, k1, k2, trial));
        body(joint, k1, k2, rnd);
      }
    }
  }
}

VectorXd phi_at(const JointType& joint, const Scenario& s, double t) {
  return evaluate(joint, s.frame, advance_pose(s.b1, t), advance_pose(s.b2, t)).phi;
}

// Central differences of phi along the motion: first and second derivative at t = 0.
VectorXd finite_difference_phi_dot(const JointType& joint, const Scenario& s, double eps) {
  return (phi_at(joint, s, eps) - phi_at(joint, s, -eps)) / (2.0 * eps);
}

VectorXd finite_difference_phi_ddot(const JointType& joint, const Scenario& s, double eps) {
  return (phi_at(joint, s, eps) - 2.0 * phi_at(joint, s, 0.0) + phi_at(joint, s, -eps)) / (eps * eps);
}

TEST_CASE("every joint has the row count of its definition and 6 Jacobian columns per body") {
  const std::vector<std::pair<std::string, int>> expected = {{"spherical", 3}, {"revolute", 5}, {"universal", 4},
                                                             {"cylindrical", 4}, {"prismatic", 5}, {"fixed", 6},
                                                             {"distance", 1}};
  REQUIRE(joint_types().size() == expected.size());
  for_each_case(201, 1, [&](const JointType& joint, Kind k1, Kind k2, Random& rnd) {
    const Scenario s = satisfied_scenario(rnd, joint, k1, k2);
    const Rows rows = evaluate(joint, s.frame, s.b1, s.b2);
    const auto it = std::find_if(expected.begin(), expected.end(), [&](const auto& e) { return e.first == joint.name; });
    REQUIRE(it != expected.end());
    CHECK(rows.phi.size() == it->second);
    CHECK(rows.quad.size() == it->second);
    CHECK(rows.J1.rows() == it->second);
    CHECK(rows.J2.rows() == it->second);
    CHECK(rows.J1.cols() == 6);
    CHECK(rows.J2.cols() == 6);
  });
}

TEST_CASE("phi vanishes in the configuration the joint frame was built from") {
  for_each_case(202, 4, [](const JointType& joint, Kind k1, Kind k2, Random& rnd) {
    const Scenario s = satisfied_scenario(rnd, joint, k1, k2);
    CHECK(max_abs(evaluate(joint, s.frame, s.b1, s.b2).phi) < 1e-12);
  });
}

TEST_CASE("phi equals the joint definition in violated configurations") {
  for_each_case(203, 4, [](const JointType& joint, Kind k1, Kind k2, Random& rnd) {
    Scenario s = satisfied_scenario(rnd, joint, k1, k2);
    violate(rnd, s);
    const VectorXd phi = evaluate(joint, s.frame, s.b1, s.b2).phi;
    const VectorXd expected = reference_phi(joint.kind, s.frame, s.b1, s.b2);
    REQUIRE(phi.size() == expected.size());
    CHECK(max_abs(phi - expected) < 1e-13);
    CHECK(max_abs(expected) > 1e-3);  // the configuration really is violated
  });
}

TEST_CASE("finite allowed relative displacements keep phi zero") {
  // Moves whichever body is not ground by a finite allowed motion about the joint.
  for_each_case(204, 4, [](const JointType& joint, Kind k1, Kind k2, Random& rnd) {
    const Scenario s = satisfied_scenario(rnd, joint, k1, k2);
    const bool move_second = k2 != Kind::ground;
    const auto check_zero = [&](const Quat& Q, const Vec3& center, const Vec3& shift) {
      const TestBody b1 = move_second ? s.b1 : displaced(s.b1, Q, center, shift);
      const TestBody b2 = move_second ? displaced(s.b2, Q, center, shift) : s.b2;
      CHECK(max_abs(evaluate(joint, s.frame, b1, b2).phi) < 1e-12);
    };
    const double angle = rnd.uniform(0.3, 2.5);
    const double slide = rnd.uniform(-1.5, 1.5);
    const Vec3 none = Vec3::Zero();
    switch (joint.kind) {
      case JointKind::spherical:
        check_zero(random_unit_quaternion(rnd), s.x1, none);
        break;
      case JointKind::revolute:
        check_zero(Quat(Eigen::AngleAxisd(angle, s.A)), s.x1, none);
        break;
      case JointKind::universal:
        check_zero(Quat(Eigen::AngleAxisd(angle, s.A)), s.x1, none);
        check_zero(Quat(Eigen::AngleAxisd(angle, s.B)), s.x1, none);
        break;
      case JointKind::cylindrical:
        check_zero(Quat(Eigen::AngleAxisd(angle, s.A)), s.x1, slide * s.A);
        break;
      case JointKind::prismatic:
        check_zero(Quat::Identity(), s.x1, slide * s.A);
        break;
      case JointKind::fixed:
        check_zero(Quat::Identity(), s.x1, none);
        break;
      case JointKind::distance:
        // About the fixed end (moving the point on the sphere) and about the moving end.
        check_zero(random_unit_quaternion(rnd), move_second ? s.x1 : s.x2, none);
        check_zero(random_unit_quaternion(rnd), move_second ? s.x2 : s.x1, none);
        break;
    }
  });
}

TEST_CASE("moving both bodies rigidly together keeps phi zero; violated rows transform as vectors and scalars") {
  for_each_case(205, 4, [](const JointType& joint, Kind k1, Kind k2, Random& rnd) {
    if (k1 == Kind::ground || k2 == Kind::ground) return;  // ground cannot be moved
    Scenario s = satisfied_scenario(rnd, joint, k1, k2);
    const Quat Q = random_unit_quaternion(rnd);
    const Vec3 shift = rnd.vec3(1.0);
    CHECK(max_abs(evaluate(joint, s.frame, displaced(s.b1, Q, s.x1, shift), displaced(s.b2, Q, s.x1, shift)).phi) <
          1e-12);

    violate(rnd, s);
    const Vec3 center = rnd.vec3(1.0);
    const VectorXd before = evaluate(joint, s.frame, s.b1, s.b2).phi;
    const VectorXd after =
        evaluate(joint, s.frame, displaced(s.b1, Q, center, shift), displaced(s.b2, Q, center, shift)).phi;
    VectorXd expected = before;
    const int n = coincidence_rows(joint.kind);
    if (n == 3) expected.head<3>() = Q * Vec3(before.head<3>());
    CHECK(max_abs(after - expected) < 1e-12);
  });
}

TEST_CASE("phi_dot = J1 u1 + J2 u2 matches the central difference of phi along the motion") {
  for_each_case(206, 4, [](const JointType& joint, Kind k1, Kind k2, Random& rnd) {
    for (const bool violated : {false, true}) {
      INFO("violated = " << violated);
      Scenario s = satisfied_scenario(rnd, joint, k1, k2);
      if (violated) violate(rnd, s);
      const Rows rows = evaluate(joint, s.frame, s.b1, s.b2);
      const VectorXd phi_dot = rows.J1 * velocity_vector(s.b1) + rows.J2 * velocity_vector(s.b2);
      const VectorXd reference = finite_difference_phi_dot(joint, s, 1e-6);
      CHECK(max_abs(phi_dot - reference) < 1e-7 * scale_of(reference));
    }
  });
}

TEST_CASE("quad is phi_ddot when velocities are constant (u' = 0)") {
  for_each_case(207, 4, [](const JointType& joint, Kind k1, Kind k2, Random& rnd) {
    for (const bool violated : {false, true}) {
      INFO("violated = " << violated);
      Scenario s = satisfied_scenario(rnd, joint, k1, k2);
      if (violated) violate(rnd, s);
      const Rows rows = evaluate(joint, s.frame, s.b1, s.b2);
      const VectorXd reference = finite_difference_phi_ddot(joint, s, 1e-4);
      CHECK(max_abs(rows.quad - reference) < 1e-5 * scale_of(reference));
      // The check has something to see (spherical joints between particles and ground have quad = 0).
      if (k1 == Kind::rigid || k2 == Kind::rigid) CHECK(max_abs(reference) > 1e-2);
    }
  });
}

TEST_CASE("phi_ddot = J1 u1' + J2 u2' + quad under constant linear and body angular accelerations") {
  for_each_case(208, 4, [](const JointType& joint, Kind k1, Kind k2, Random& rnd) {
    for (const bool violated : {false, true}) {
      INFO("violated = " << violated);
      Scenario s = satisfied_scenario(rnd, joint, k1, k2);
      if (violated) violate(rnd, s);
      set_random_accelerations(rnd, s.b1);
      set_random_accelerations(rnd, s.b2);
      const Rows rows = evaluate(joint, s.frame, s.b1, s.b2);
      const VectorXd phi_ddot =
          rows.J1 * acceleration_vector(s.b1) + rows.J2 * acceleration_vector(s.b2) + rows.quad;
      const VectorXd reference = finite_difference_phi_ddot(joint, s, 1e-4);
      CHECK(max_abs(phi_ddot - reference) < 1e-5 * scale_of(reference));
    }
  });
}

TEST_CASE("J columns: linear part is d phi / d r, angular part is d phi / d(body-frame rotation)") {
  const double eps = 1e-6;
  for_each_case(209, 3, [&](const JointType& joint, Kind k1, Kind k2, Random& rnd) {
    Scenario s = satisfied_scenario(rnd, joint, k1, k2);
    violate(rnd, s);
    const Rows rows = evaluate(joint, s.frame, s.b1, s.b2);
    for (int body = 0; body < 2; ++body) {
      const TestBody& b = body == 0 ? s.b1 : s.b2;
      const MatrixXd& J = body == 0 ? rows.J1 : rows.J2;
      if (b.kind == Kind::ground) continue;
      const auto phi_with = [&](const TestBody& moved) {
        return evaluate(joint, s.frame, body == 0 ? moved : s.b1, body == 0 ? s.b2 : moved).phi;
      };
      for (int k = 0; k < 3; ++k) {
        INFO("body " << body + 1 << ", component " << k);
        TestBody plus = b, minus = b;
        plus.r[k] += eps;
        minus.r[k] -= eps;
        const VectorXd dphi_dr = (phi_with(plus) - phi_with(minus)) / (2 * eps);
        CHECK(max_abs(J.col(k) - dphi_dr) < 1e-7 * scale_of(dphi_dr));
        if (b.kind != Kind::rigid) continue;
        plus = b;
        minus = b;
        plus.q = b.q * rotation_exp(eps * Vec3::Unit(k));
        minus.q = b.q * rotation_exp(-eps * Vec3::Unit(k));
        const VectorXd dphi_dtheta = (phi_with(plus) - phi_with(minus)) / (2 * eps);
        CHECK(max_abs(J.col(3 + k) - dphi_dtheta) < 1e-7 * scale_of(dphi_dtheta));
      }
    }
  });
}

TEST_CASE("allowed relative motions give phi_dot = 0; the forbidden ones are independent") {
  Random rnd(210);
  for (const JointType& joint : joint_types()) {
    for (const Kind k1 : {Kind::rigid, Kind::ground}) {
      for (int trial = 0; trial < 4; ++trial) {
        INFO(case_name(joint, k1, Kind::rigid, trial));
        const Scenario s = satisfied_scenario(rnd, joint, k1, Kind::rigid);
        const Rows rows = evaluate(joint, s.frame, s.b1, s.b2);
        const Mat3 R1 = rotation_of(s.b1), R2 = rotation_of(s.b2);
        TestBody b1 = s.b1;
        if (k1 == Kind::rigid) {
          b1.v = rnd.vec3(1.0);
          b1.w = rnd.vec3(2.0);
        }
        const Vec3 omega1 = R1 * b1.w;  // world
        // Body 2 carried along with body 1 plus a relative twist (omega_rel, v_rel) at its joint point x2.
        const auto phi_dot = [&](const Vec3& omega_rel, const Vec3& v_rel) {
          TestBody b2 = s.b2;
          b2.v = b1.v + omega1.cross(s.b2.r - b1.r) + omega_rel.cross(s.b2.r - s.x2) + v_rel;
          b2.w = R2.transpose() * (omega1 + omega_rel);
          return VectorXd(rows.J1 * velocity_vector(b1) + rows.J2 * velocity_vector(b2));
        };
        CHECK(max_abs(phi_dot(Vec3::Zero(), Vec3::Zero())) < 1e-12);  // moving together

        const Vec3 axes[3] = {s.A, s.B, s.C};
        MatrixXd forbidden(joint.rows, 0);
        for (int twist = 0; twist < 6; ++twist) {
          INFO("twist " << twist);
          const Vec3 e = axes[twist % 3];
          const VectorXd response = twist < 3 ? phi_dot(e, Vec3::Zero()) : phi_dot(Vec3::Zero(), e);
          REQUIRE(response.size() == joint.rows);
          if (std::find(joint.allowed.begin(), joint.allowed.end(), twist) != joint.allowed.end()) {
            CHECK(max_abs(response) < 1e-12);
          } else {
            forbidden.conservativeResize(Eigen::NoChange, forbidden.cols() + 1);
            forbidden.col(forbidden.cols() - 1) = response;
          }
        }
        // One independent row per forbidden relative motion.
        REQUIRE(forbidden.cols() == joint.rows);
        const VectorXd sigma = Eigen::JacobiSVD<MatrixXd>(forbidden).singularValues();
        CHECK(sigma.minCoeff() > 0.5);
      }
    }
  }
}

}  // namespace
