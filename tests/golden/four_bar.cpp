// mbrt generated model 'four_bar': 3 bodies (3 rigid, 0 particles), 4 joints, 0 drivers, 20 constraint rows.
// Scheme staggered-pcst: the step is mbrt::schemes::staggered_step (include/mbrt/schemes/staggered.hpp)
// over planar::Model, the model's types, constants and kernels below.
// Left out for this scene:
//   principal_axes: 2 principal-axis bodies: inertia products in M^-1 and the gyroscopic torques
//   single_stage: no velocity-dependent loads: the second implicit stage
//   folded_weights: gravity: the products m g, one constant weight per body
//   no_drivers: no drivers: the explicit time terms phi_t
//   sparse_factor: 3 of 6 off-diagonal blocks of S's factor: zero, never formed
//   planar: motion in the x-y plane: two coordinates and the angle about z per body, 8 of 20 constraint rows (the in-plane ones)
#include "four_bar.hpp"

#include <algorithm>
#include <cmath>

#include <mbrt/reactions.hpp>
#include <mbrt/schemes/staggered.hpp>

namespace mbrt::models::four_bar {

namespace {

constexpr double h = kStep;
constexpr double kRegularization = 2.2001079968800978e-06;  // added to diag(S)
constexpr double kNewtonShift = 220.0107996880098;  // added to diag(G) (3 redundant rows)
constexpr double kStabilization = 1000.0;  // alpha, 1/s
const mbrt::Vec3 kGravity = mbrt::Vec3(0.0, -9.8100000000000005, 0.0);
const mbrt::BodyPose kGroundPose = mbrt::ground_pose();
const mbrt::BodyVelocity kGroundVelocity = mbrt::ground_velocity();

// Mass properties (constant; M is block diagonal).
const mbrt::PrincipalInertia crank_mass{1.0, mbrt::Vec3(0.083358333333300005, 5.0000000000000002e-05, 0.083358333333300005)};
const mbrt::Vec3 crank_weight = mbrt::Vec3(0.0, -9.8100000000000005, 0.0);
const mbrt::FullInertia coupler_mass{1.0, (mbrt::Mat3() << 0.0833808333333, -0.24999250000000001, 0.0, -0.24999250000000001, 0.75002749999999996, 0.0, 0.0, 0.0, 0.83335833333300002).finished(), (mbrt::Mat3() << 18000.120007201596, 5999.6400143999317, -0.0, 5999.6400143999317, 2001.0799688009774, -0.0, -0.0, -0.0, 1.1999640010805883).finished(),
    mbrt::Vec3(4.999999997002022e-05, 0.83335833333300002, 0.83335833333332976), mbrt::Vec4(-0.11326595025589375, -0.11326595025589375, 0.69797623491966354, 0.69797623491966354)};
const mbrt::Vec3 coupler_weight = mbrt::Vec3(0.0, -9.8100000000000005, 0.0);
const mbrt::PrincipalInertia rocker_mass{1.0, mbrt::Vec3(0.33335833333300002, 5.0000000000000002e-05, 0.33335833333300002)};
const mbrt::Vec3 rocker_weight = mbrt::Vec3(0.0, -9.8100000000000005, 0.0);

// Joint and driver frames in body axes; drivers' functions of time.
const mbrt::JointFrame pin_o_frame{mbrt::Vec3(0.0, 0.0, 0.0), mbrt::Vec3(0.0, -0.5, 0.0),
    mbrt::Vec3(0.0, 0.0, 1.0), mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec3(-1.0, 0.0, 0.0),
    mbrt::Vec3(0.0, 0.0, 1.0), mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec3(-1.0, 0.0, 0.0), 0.0, 0.0};
const mbrt::JointFrame pin_a_frame{mbrt::Vec3(0.0, 0.5, 0.0), mbrt::Vec3(-1.5, -0.5, 0.0),
    mbrt::Vec3(0.0, 0.0, 1.0), mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec3(-1.0, 0.0, 0.0),
    mbrt::Vec3(0.0, 0.0, 1.0), mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec3(-1.0, 0.0, 0.0), 0.0, 0.0};
const mbrt::JointFrame pin_b_frame{mbrt::Vec3(1.5, 0.5, 0.0), mbrt::Vec3(0.0, 1.0, 0.0),
    mbrt::Vec3(0.0, 0.0, 1.0), mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec3(-1.0, 0.0, 0.0),
    mbrt::Vec3(0.0, 0.0, 1.0), mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec3(-1.0, 0.0, 0.0), 0.0, 0.0};
const mbrt::JointFrame pin_c_frame{mbrt::Vec3(0.0, -1.0, 0.0), mbrt::Vec3(3.0, 0.0, 0.0),
    mbrt::Vec3(0.0, 0.0, 1.0), mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec3(-1.0, 0.0, 0.0),
    mbrt::Vec3(0.0, 0.0, 1.0), mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec3(-1.0, 0.0, 0.0), 0.0, 0.0};

// Force elements in body axes.

// The model as the scheme's step (include/mbrt/schemes/) sees it: types,
// constants and kernels.
struct Model {
using State = mbrt::models::four_bar::State;
using Rows = detail::Rows;
using BodyVectors = detail::BodyVectors;
using Kinematics = detail::Kinematics;
using Loads = detail::Loads;
using ConstraintSystem = detail::ConstraintSystem;
// The spatial kernels serve initial_state() and the diagnostics.

static std::array<mbrt::BodyVelocity, kBodies> velocities_of(const State& s) noexcept {
  std::array<mbrt::BodyVelocity, kBodies> vel;
  vel[0] = mbrt::velocity_of(s.rigid[0]);
  vel[1] = mbrt::velocity_of(s.rigid[1]);
  vel[2] = mbrt::velocity_of(s.rigid[2]);
  return vel;
}

// (s) => (u): generalized velocities [v; w_body] per body.
static BodyVectors generalized_velocities(const State& s) noexcept {
  BodyVectors u;
  u[0] << s.rigid[0].v, s.rigid[0].w;
  u[1] << s.rigid[1].v, s.rigid[1].w;
  u[2] << s.rigid[2].v, s.rigid[2].w;
  return u;
}

// (a) => (s): accelerations kept for the next step.
static void set_accelerations(const BodyVectors& a, State& s) noexcept {
  s.rigid_acceleration[0] = {a[0].head<3>(), a[0].tail<3>()};
  s.rigid_acceleration[1] = {a[1].head<3>(), a[1].tail<3>()};
  s.rigid_acceleration[2] = {a[2].head<3>(), a[2].tail<3>()};
}

static BodyVectors accelerations_of(const State& s) noexcept {
  BodyVectors a;
  a[0] << s.rigid_acceleration[0].a, s.rigid_acceleration[0].alpha;
  a[1] << s.rigid_acceleration[1].a, s.rigid_acceleration[1].alpha;
  a[2] << s.rigid_acceleration[2].a, s.rigid_acceleration[2].alpha;
  return a;
}

// (s) => (k): pose and velocity of every body.
static void kinematics(const State& s, Kinematics& k) noexcept {
  k.pose[0] = mbrt::pose_of(s.rigid[0]);  // crank
  k.pose[1] = mbrt::pose_of(s.rigid[1]);  // coupler
  k.pose[2] = mbrt::pose_of(s.rigid[2]);  // rocker
  k.vel = velocities_of(s);
}

// (k) => (l): applied forces (world) and torques (body axes) per body, and the elastic energy stored.
static void applied_loads([[maybe_unused]] const Kinematics& k, const State& s, Loads& l) noexcept {
  (void)s;
  l.w.fill(mbrt::Wrench{});
  l.elastic_energy = 0.0;
  l.w[0].f += crank_weight;
  l.w[1].f += coupler_weight;
  l.w[2].f += rocker_weight;
}

// (k, t) => (c.rows_*): constraint values, Jacobians and acceleration terms.
static void constraint_rows(const Kinematics& k, [[maybe_unused]] double t, ConstraintSystem& c) noexcept {
  c.rows_pin_o = mbrt::revolute(pin_o_frame, mbrt::BodyMotion{kGroundPose, kGroundVelocity}, mbrt::BodyMotion{k.pose[0], k.vel[0]});
  c.rows_pin_a = mbrt::revolute(pin_a_frame, mbrt::BodyMotion{k.pose[0], k.vel[0]}, mbrt::BodyMotion{k.pose[1], k.vel[1]});
  c.rows_pin_b = mbrt::revolute(pin_b_frame, mbrt::BodyMotion{k.pose[1], k.vel[1]}, mbrt::BodyMotion{k.pose[2], k.vel[2]});
  c.rows_pin_c = mbrt::revolute(pin_c_frame, mbrt::BodyMotion{k.pose[2], k.vel[2]}, mbrt::BodyMotion{kGroundPose, kGroundVelocity});
}

// (c.rows_*) => (c.mbt_*): M^-1 B^T, the directions constraint forces move the bodies in.
static void constraint_directions(ConstraintSystem& c) noexcept {
  c.mbt_0_0 = mbrt::inverse_mass_times_transpose(crank_mass, c.rows_pin_o.J2);
  c.mbt_1_0 = mbrt::inverse_mass_times_transpose(crank_mass, c.rows_pin_a.J1);
  c.mbt_1_1 = mbrt::inverse_mass_times_transpose(coupler_mass, c.rows_pin_a.J2);
  c.mbt_2_1 = mbrt::inverse_mass_times_transpose(coupler_mass, c.rows_pin_b.J1);
  c.mbt_2_2 = mbrt::inverse_mass_times_transpose(rocker_mass, c.rows_pin_b.J2);
  c.mbt_3_2 = mbrt::inverse_mass_times_transpose(rocker_mass, c.rows_pin_c.J1);
}

// (c.rows_*) => (c.mbt_*, c.L_*): M^-1 B^T, then S block by block in
// elimination order (0 fill blocks); false if a pivot is not positive.
static bool factorize(ConstraintSystem& c) noexcept {
  bool positive = true;
  constraint_directions(c);
  // pin_c
  c.L_3_3 = c.rows_pin_c.J1 * c.mbt_3_2 + kRegularization * Eigen::Matrix<double, 5, 5>::Identity();
  positive = mbrt::cholesky_in_place(c.L_3_3) && positive;
  c.L_2_3 = c.rows_pin_b.J2 * c.mbt_3_2;
  mbrt::solve_right_lower_transposed(c.L_3_3, c.L_2_3);
  // pin_b
  c.L_2_2 = c.rows_pin_b.J1 * c.mbt_2_1 + c.rows_pin_b.J2 * c.mbt_2_2 + kRegularization * Eigen::Matrix<double, 5, 5>::Identity()
      - c.L_2_3 * c.L_2_3.transpose();
  positive = mbrt::cholesky_in_place(c.L_2_2) && positive;
  c.L_1_2 = c.rows_pin_a.J2 * c.mbt_2_1;
  mbrt::solve_right_lower_transposed(c.L_2_2, c.L_1_2);
  // pin_o
  c.L_0_0 = c.rows_pin_o.J2 * c.mbt_0_0 + kRegularization * Eigen::Matrix<double, 5, 5>::Identity();
  positive = mbrt::cholesky_in_place(c.L_0_0) && positive;
  c.L_1_0 = c.rows_pin_a.J1 * c.mbt_0_0;
  mbrt::solve_right_lower_transposed(c.L_0_0, c.L_1_0);
  // pin_a
  c.L_1_1 = c.rows_pin_a.J1 * c.mbt_1_0 + c.rows_pin_a.J2 * c.mbt_1_1 + kRegularization * Eigen::Matrix<double, 5, 5>::Identity()
      - c.L_1_2 * c.L_1_2.transpose()
      - c.L_1_0 * c.L_1_0.transpose();
  positive = mbrt::cholesky_in_place(c.L_1_1) && positive;
  return positive;
}

// (c.L_*, x) => (x): x := S^-1 x by forward and backward substitution.
static void solve(const ConstraintSystem& c, Rows& x) noexcept {
  {  // pin_c
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(15);
    mbrt::solve_lower(c.L_3_3, y);
    x.segment<5>(15) = y;
  }
  {  // pin_b
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(10);
    y -= c.L_2_3 * x.segment<5>(15);
    mbrt::solve_lower(c.L_2_2, y);
    x.segment<5>(10) = y;
  }
  {  // pin_o
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(0);
    mbrt::solve_lower(c.L_0_0, y);
    x.segment<5>(0) = y;
  }
  {  // pin_a
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(5);
    y -= c.L_1_2 * x.segment<5>(10);
    y -= c.L_1_0 * x.segment<5>(0);
    mbrt::solve_lower(c.L_1_1, y);
    x.segment<5>(5) = y;
  }
  {  // pin_a
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(5);
    mbrt::solve_lower_transposed(c.L_1_1, y);
    x.segment<5>(5) = y;
  }
  {  // pin_o
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(0);
    y -= c.L_1_0.transpose() * x.segment<5>(5);
    mbrt::solve_lower_transposed(c.L_0_0, y);
    x.segment<5>(0) = y;
  }
  {  // pin_b
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(10);
    y -= c.L_1_2.transpose() * x.segment<5>(5);
    mbrt::solve_lower_transposed(c.L_2_2, y);
    x.segment<5>(10) = y;
  }
  {  // pin_c
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(15);
    y -= c.L_2_3.transpose() * x.segment<5>(10);
    mbrt::solve_lower_transposed(c.L_3_3, y);
    x.segment<5>(15) = y;
  }
}

// (c, u) => (B u)
static Rows jacobian_times(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  Rows y;
  y.segment<5>(0) = c.rows_pin_o.J2 * u[0];
  y.segment<5>(5) = c.rows_pin_a.J1 * u[0] + c.rows_pin_a.J2 * u[1];
  y.segment<5>(10) = c.rows_pin_b.J1 * u[1] + c.rows_pin_b.J2 * u[2];
  y.segment<5>(15) = c.rows_pin_c.J1 * u[2];
  return y;
}

// (c, lambda) => (u): u -= scale M^-1 B^T lambda
static void subtract_constraint_forces(const ConstraintSystem& c, const Rows& lambda, double scale,
                                BodyVectors& u) noexcept {
  u[0] -= scale * (c.mbt_0_0 * lambda.segment<5>(0));
  u[0] -= scale * (c.mbt_1_0 * lambda.segment<5>(5));
  u[1] -= scale * (c.mbt_1_1 * lambda.segment<5>(5));
  u[1] -= scale * (c.mbt_2_1 * lambda.segment<5>(10));
  u[2] -= scale * (c.mbt_2_2 * lambda.segment<5>(10));
  u[2] -= scale * (c.mbt_3_2 * lambda.segment<5>(15));
}

// (c) => (phi), (c) => (quad): stacked position residuals and acceleration terms.
static Rows stacked_phi(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<5>(0) = c.rows_pin_o.phi;
  y.segment<5>(5) = c.rows_pin_a.phi;
  y.segment<5>(10) = c.rows_pin_b.phi;
  y.segment<5>(15) = c.rows_pin_c.phi;
  return y;
}

static Rows stacked_quad(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<5>(0) = c.rows_pin_o.quad;
  y.segment<5>(5) = c.rows_pin_a.quad;
  y.segment<5>(10) = c.rows_pin_b.quad;
  y.segment<5>(15) = c.rows_pin_c.quad;
  return y;
}

// (c, u) => (phi_dot = B u + phi_t): velocity residuals.
static Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  return jacobian_times(c, u);  // no drivers: phi_t = 0
}

// (l) => (M^-1 F) per body.
static BodyVectors free_accelerations(const Loads& l) noexcept {
  BodyVectors a;
  a[0] = mbrt::inverse_mass_times(crank_mass, l.w[0]);
  a[1] = mbrt::inverse_mass_times(coupler_mass, l.w[1]);
  a[2] = mbrt::inverse_mass_times(rocker_mass, l.w[2]);
  return a;
}

// (s) => (J^-1 (-w x J w)) per body: the gyroscopic accelerations, which the
// explicit stage's free rotation applies and the multipliers must balance.
static BodyVectors gyroscopic_accelerations(const State& s) noexcept {
  BodyVectors g;
  g[0] << mbrt::Vec3::Zero(), mbrt::inverse_inertia_times(crank_mass, mbrt::gyroscopic_torque(crank_mass, s.rigid[0].w));  // crank
  g[1] << mbrt::Vec3::Zero(), mbrt::inverse_inertia_times(coupler_mass, mbrt::gyroscopic_torque(coupler_mass, s.rigid[1].w));  // coupler
  g[2] << mbrt::Vec3::Zero(), mbrt::inverse_inertia_times(rocker_mass, mbrt::gyroscopic_torque(rocker_mass, s.rigid[2].w));  // rocker
  return g;
}

static void constraint_forces(const ConstraintSystem& c, const Loads& l, const Rows& phi, State& s) noexcept {
  BodyVectors a = free_accelerations(l);
  const BodyVectors g = gyroscopic_accelerations(s);
  for (int b = 0; b < kBodies; ++b) a[b] += g[b];
  s.lambda = jacobian_times(c, a) + stacked_quad(c) +
             (2.0 / h) * (velocity_residual(c, generalized_velocities(s)) + kStabilization * phi);
  solve(c, s.lambda);
  subtract_constraint_forces(c, s.lambda, 1.0, a);
  for (int b = 0; b < kBodies; ++b) a[b] -= g[b];
  set_accelerations(a, s);
}

static State initial_state() noexcept {
  State s;
  s.rigid[0] = {mbrt::Vec3(0.0, 0.5, 0.0), mbrt::Vec4(1.0, 0.0, 0.0, 0.0),
      mbrt::Vec3(0.5, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, -1.0)};  // crank
  s.rigid[1] = {mbrt::Vec3(1.5, 1.5, 0.0), mbrt::Vec4(1.0, 0.0, 0.0, 0.0),
      mbrt::Vec3(1.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0)};  // coupler
  s.rigid[2] = {mbrt::Vec3(3.0, 1.0, 0.0), mbrt::Vec4(1.0, 0.0, 0.0, 0.0),
      mbrt::Vec3(0.5, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, -0.5)};  // rocker
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s.t, c);
  factorize(c);
  Loads l;
  applied_loads(k, s, l);
  constraint_forces(c, l, stacked_phi(c), s);
  return s;
}

static mbrt::Energy energy(const State& s) noexcept {
  Kinematics k;
  kinematics(s, k);
  Loads l;
  applied_loads(k, s, l);
  const BodyVectors u = generalized_velocities(s);
  mbrt::Energy e{0.0, l.elastic_energy};
  e.kinetic += mbrt::kinetic_energy(crank_mass, u[0]);
  e.potential -= crank_mass.m * kGravity.dot(k.pose[0].r);
  e.kinetic += mbrt::kinetic_energy(coupler_mass, u[1]);
  e.potential -= coupler_mass.m * kGravity.dot(k.pose[1].r);
  e.kinetic += mbrt::kinetic_energy(rocker_mass, u[2]);
  e.potential -= rocker_mass.m * kGravity.dot(k.pose[2].r);
  return e;
}

static mbrt::ConstraintViolation constraint_violation(const State& s) noexcept {
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s.t, c);
  const Rows phi = stacked_phi(c);
  const Rows phi_dot = velocity_residual(c, generalized_velocities(s));
  BodyVectors a = accelerations_of(s);
  const BodyVectors g = gyroscopic_accelerations(s);  // the free rotation's part
  for (int b = 0; b < kBodies; ++b) a[b] += g[b];
  const Rows phi_ddot = jacobian_times(c, a) + stacked_quad(c);
  if (kConstraintRows == 0) return {0.0, 0.0, 0.0};
  return {phi.cwiseAbs().maxCoeff(), phi_dot.cwiseAbs().maxCoeff(), phi_ddot.cwiseAbs().maxCoeff()};
}

static double quaternion_norm_error(const State& s) noexcept {
  double e = 0.0;
  for (const mbrt::RigidState& x : s.rigid) e = std::max(e, std::abs(x.p.norm() - 1.0));
  return e;
}

static void reactions(const State& s, Reactions& r) noexcept {
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s.t, c);
  r[0] = mbrt::joint_reaction(-(c.rows_pin_o.J2.transpose() * s.lambda.segment<5>(0)), k.pose[0],
      k.pose[0].r + k.pose[0].R * pin_o_frame.s2, 1.0, kGroundPose, pin_o_frame);  // pin_o
  r[1] = mbrt::joint_reaction(-(c.rows_pin_a.J2.transpose() * s.lambda.segment<5>(5)), k.pose[1],
      k.pose[1].r + k.pose[1].R * pin_a_frame.s2, 1.0, k.pose[0], pin_a_frame);  // pin_a
  r[2] = mbrt::joint_reaction(-(c.rows_pin_b.J2.transpose() * s.lambda.segment<5>(10)), k.pose[2],
      k.pose[2].r + k.pose[2].R * pin_b_frame.s2, 1.0, k.pose[1], pin_b_frame);  // pin_b
  r[3] = mbrt::joint_reaction(-(c.rows_pin_c.J1.transpose() * s.lambda.segment<5>(15)), k.pose[2],
      pin_c_frame.s2, -1.0, k.pose[2], pin_c_frame);  // pin_c
}

};

// The step in planar coordinates: motion in one plane, per body two
// coordinates and the rotation about the normal, the in-plane constraint rows only.
namespace planar {

constexpr int kNormal = 2;  // the plane x-y, normal to world z
constexpr double kNewtonShift = 220.0107996880098;  // added to diag(G) (3 redundant rows)
const mbrt::PlanarPose kGroundPose = mbrt::planar_ground_pose();
const mbrt::PlanarVelocity kGroundVelocity = mbrt::planar_ground_velocity();

// Masses and the moments of inertia about the normal (particles keep their PointMass).
const mbrt::PlanarInertia crank_mass{1.0, 0.083358333333300005};
const mbrt::Vec2 crank_weight(0.0, -9.8100000000000005);
const mbrt::PlanarInertia coupler_mass{1.0, 0.83335833333300002};
const mbrt::Vec2 coupler_weight(0.0, -9.8100000000000005);
const mbrt::PlanarInertia rocker_mass{1.0, 0.33335833333300002};
const mbrt::Vec2 rocker_weight(0.0, -9.8100000000000005);

// The model as the scheme's step (include/mbrt/schemes/) sees it: types,
// constants and kernels.
struct Model {
using State = mbrt::models::four_bar::State;
using Workspace = mbrt::models::four_bar::Workspace;
using Rows = detail::planar::Rows;
using BodyVectors = detail::planar::BodyVectors;
using Kinematics = detail::planar::Kinematics;
using Loads = detail::planar::Loads;
using ConstraintSystem = detail::planar::ConstraintSystem;
using NewtonMatrix = detail::planar::NewtonMatrix;
static constexpr mbrt::Scheme kScheme = mbrt::Scheme::staggered_pcst;
static constexpr double kStep = h;
static constexpr int kStages = 1;  // implicit passes per step
static constexpr bool kPositionStage = true;
static constexpr int kPositionIterations = 2;  // Newton steps of the position stage

static std::array<mbrt::PlanarVelocity, kBodies> velocities_of(const State& s) noexcept {
  std::array<mbrt::PlanarVelocity, kBodies> vel;
  vel[0] = mbrt::planar_velocity_of<kNormal>(s.rigid[0]);
  vel[1] = mbrt::planar_velocity_of<kNormal>(s.rigid[1]);
  vel[2] = mbrt::planar_velocity_of<kNormal>(s.rigid[2]);
  return vel;
}

// (s) => (u): (vx, vy, omega_z) per body.
static BodyVectors generalized_velocities(const State& s) noexcept {
  BodyVectors u;
  u[0] = mbrt::planar_velocities<kNormal>(s.rigid[0]);
  u[1] = mbrt::planar_velocities<kNormal>(s.rigid[1]);
  u[2] = mbrt::planar_velocities<kNormal>(s.rigid[2]);
  return u;
}

// (u) => (s): the in-plane velocities; the others stay zero.
static void set_velocities(const BodyVectors& u, State& s) noexcept {
  mbrt::set_planar_velocities<kNormal>(u[0], s.rigid[0]);
  mbrt::set_planar_velocities<kNormal>(u[1], s.rigid[1]);
  mbrt::set_planar_velocities<kNormal>(u[2], s.rigid[2]);
}

// (a) => (s): accelerations kept for the next step.
static void set_accelerations(const BodyVectors& a, State& s) noexcept {
  mbrt::set_planar_accelerations<kNormal>(a[0], s.rigid_acceleration[0]);
  mbrt::set_planar_accelerations<kNormal>(a[1], s.rigid_acceleration[1]);
  mbrt::set_planar_accelerations<kNormal>(a[2], s.rigid_acceleration[2]);
}

static BodyVectors accelerations_of(const State& s) noexcept {
  BodyVectors a;
  a[0] = mbrt::planar_accelerations<kNormal>(s.rigid_acceleration[0]);
  a[1] = mbrt::planar_accelerations<kNormal>(s.rigid_acceleration[1]);
  a[2] = mbrt::planar_accelerations<kNormal>(s.rigid_acceleration[2]);
  return a;
}

// (s) => (k): pose and velocity of every body.
static void kinematics(const State& s, Kinematics& k) noexcept {
  k.pose[0] = mbrt::planar_pose_of<kNormal>(s.rigid[0]);  // crank
  k.pose[1] = mbrt::planar_pose_of<kNormal>(s.rigid[1]);  // coupler
  k.pose[2] = mbrt::planar_pose_of<kNormal>(s.rigid[2]);  // rocker
  k.vel = velocities_of(s);
}

// (k) => (l): applied forces (world) and torques (body axes) per body, and the elastic energy stored.
static void applied_loads([[maybe_unused]] const Kinematics& k, const State& s, Loads& l) noexcept {
  (void)s;
  l.w.fill(mbrt::PlanarWrench{});
  l.elastic_energy = 0.0;
  l.w[0].f += crank_weight;
  l.w[1].f += coupler_weight;
  l.w[2].f += rocker_weight;
}

// (k, t) => (c.rows_*): constraint values, Jacobians and acceleration terms.
static void constraint_rows(const Kinematics& k, [[maybe_unused]] double t, ConstraintSystem& c) noexcept {
  c.rows_pin_o = mbrt::planar_revolute(pin_o_frame, mbrt::PlanarMotion{kGroundPose, kGroundVelocity}, mbrt::PlanarMotion{k.pose[0], k.vel[0]});
  c.rows_pin_a = mbrt::planar_revolute(pin_a_frame, mbrt::PlanarMotion{k.pose[0], k.vel[0]}, mbrt::PlanarMotion{k.pose[1], k.vel[1]});
  c.rows_pin_b = mbrt::planar_revolute(pin_b_frame, mbrt::PlanarMotion{k.pose[1], k.vel[1]}, mbrt::PlanarMotion{k.pose[2], k.vel[2]});
  c.rows_pin_c = mbrt::planar_revolute(pin_c_frame, mbrt::PlanarMotion{k.pose[2], k.vel[2]}, mbrt::PlanarMotion{kGroundPose, kGroundVelocity});
}

// (c.rows_*) => (c.mbt_*): M^-1 B^T, the directions constraint forces move the bodies in.
static void constraint_directions(ConstraintSystem& c) noexcept {
  c.mbt_0_0 = mbrt::inverse_mass_times_transpose(crank_mass, c.rows_pin_o.J2);
  c.mbt_1_0 = mbrt::inverse_mass_times_transpose(crank_mass, c.rows_pin_a.J1);
  c.mbt_1_1 = mbrt::inverse_mass_times_transpose(coupler_mass, c.rows_pin_a.J2);
  c.mbt_2_1 = mbrt::inverse_mass_times_transpose(coupler_mass, c.rows_pin_b.J1);
  c.mbt_2_2 = mbrt::inverse_mass_times_transpose(rocker_mass, c.rows_pin_b.J2);
  c.mbt_3_2 = mbrt::inverse_mass_times_transpose(rocker_mass, c.rows_pin_c.J1);
}

// (c.rows_*) => (c.mbt_*, c.L_*): M^-1 B^T, then S block by block in
// elimination order (0 fill blocks); false if a pivot is not positive.
static bool factorize(ConstraintSystem& c) noexcept {
  bool positive = true;
  constraint_directions(c);
  // pin_c
  c.L_3_3 = c.rows_pin_c.J1 * c.mbt_3_2 + kRegularization * Eigen::Matrix<double, 2, 2>::Identity();
  positive = mbrt::cholesky_in_place(c.L_3_3) && positive;
  c.L_2_3 = c.rows_pin_b.J2 * c.mbt_3_2;
  mbrt::solve_right_lower_transposed(c.L_3_3, c.L_2_3);
  // pin_b
  c.L_2_2 = c.rows_pin_b.J1 * c.mbt_2_1 + c.rows_pin_b.J2 * c.mbt_2_2 + kRegularization * Eigen::Matrix<double, 2, 2>::Identity()
      - c.L_2_3 * c.L_2_3.transpose();
  positive = mbrt::cholesky_in_place(c.L_2_2) && positive;
  c.L_1_2 = c.rows_pin_a.J2 * c.mbt_2_1;
  mbrt::solve_right_lower_transposed(c.L_2_2, c.L_1_2);
  // pin_o
  c.L_0_0 = c.rows_pin_o.J2 * c.mbt_0_0 + kRegularization * Eigen::Matrix<double, 2, 2>::Identity();
  positive = mbrt::cholesky_in_place(c.L_0_0) && positive;
  c.L_1_0 = c.rows_pin_a.J1 * c.mbt_0_0;
  mbrt::solve_right_lower_transposed(c.L_0_0, c.L_1_0);
  // pin_a
  c.L_1_1 = c.rows_pin_a.J1 * c.mbt_1_0 + c.rows_pin_a.J2 * c.mbt_1_1 + kRegularization * Eigen::Matrix<double, 2, 2>::Identity()
      - c.L_1_2 * c.L_1_2.transpose()
      - c.L_1_0 * c.L_1_0.transpose();
  positive = mbrt::cholesky_in_place(c.L_1_1) && positive;
  return positive;
}

// (c.L_*, x) => (x): x := S^-1 x by forward and backward substitution.
static void solve(const ConstraintSystem& c, Rows& x) noexcept {
  {  // pin_c
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(6);
    mbrt::solve_lower(c.L_3_3, y);
    x.segment<2>(6) = y;
  }
  {  // pin_b
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(4);
    y -= c.L_2_3 * x.segment<2>(6);
    mbrt::solve_lower(c.L_2_2, y);
    x.segment<2>(4) = y;
  }
  {  // pin_o
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(0);
    mbrt::solve_lower(c.L_0_0, y);
    x.segment<2>(0) = y;
  }
  {  // pin_a
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(2);
    y -= c.L_1_2 * x.segment<2>(4);
    y -= c.L_1_0 * x.segment<2>(0);
    mbrt::solve_lower(c.L_1_1, y);
    x.segment<2>(2) = y;
  }
  {  // pin_a
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(2);
    mbrt::solve_lower_transposed(c.L_1_1, y);
    x.segment<2>(2) = y;
  }
  {  // pin_o
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(0);
    y -= c.L_1_0.transpose() * x.segment<2>(2);
    mbrt::solve_lower_transposed(c.L_0_0, y);
    x.segment<2>(0) = y;
  }
  {  // pin_b
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(4);
    y -= c.L_1_2.transpose() * x.segment<2>(2);
    mbrt::solve_lower_transposed(c.L_2_2, y);
    x.segment<2>(4) = y;
  }
  {  // pin_c
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(6);
    y -= c.L_2_3.transpose() * x.segment<2>(4);
    mbrt::solve_lower_transposed(c.L_3_3, y);
    x.segment<2>(6) = y;
  }
}

// (c, u) => (B u)
static Rows jacobian_times(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  Rows y;
  y.segment<2>(0) = c.rows_pin_o.J2 * u[0];
  y.segment<2>(2) = c.rows_pin_a.J1 * u[0] + c.rows_pin_a.J2 * u[1];
  y.segment<2>(4) = c.rows_pin_b.J1 * u[1] + c.rows_pin_b.J2 * u[2];
  y.segment<2>(6) = c.rows_pin_c.J1 * u[2];
  return y;
}

// (c, lambda) => (u): u -= scale M^-1 B^T lambda
static void subtract_constraint_forces(const ConstraintSystem& c, const Rows& lambda, double scale,
                                BodyVectors& u) noexcept {
  u[0] -= scale * (c.mbt_0_0 * lambda.segment<2>(0));
  u[0] -= scale * (c.mbt_1_0 * lambda.segment<2>(2));
  u[1] -= scale * (c.mbt_1_1 * lambda.segment<2>(2));
  u[1] -= scale * (c.mbt_2_1 * lambda.segment<2>(4));
  u[2] -= scale * (c.mbt_2_2 * lambda.segment<2>(4));
  u[2] -= scale * (c.mbt_3_2 * lambda.segment<2>(6));
}

// (c) => (phi), (c) => (quad): stacked position residuals and acceleration terms.
static Rows stacked_phi(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<2>(0) = c.rows_pin_o.phi;
  y.segment<2>(2) = c.rows_pin_a.phi;
  y.segment<2>(4) = c.rows_pin_b.phi;
  y.segment<2>(6) = c.rows_pin_c.phi;
  return y;
}

static Rows stacked_quad(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<2>(0) = c.rows_pin_o.quad;
  y.segment<2>(2) = c.rows_pin_a.quad;
  y.segment<2>(4) = c.rows_pin_b.quad;
  y.segment<2>(6) = c.rows_pin_c.quad;
  return y;
}

// (c, u) => (phi_dot = B u + phi_t): velocity residuals.
static Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  return jacobian_times(c, u);  // no drivers: phi_t = 0
}

// (l) => (M^-1 F) per body.
static BodyVectors free_accelerations(const Loads& l) noexcept {
  BodyVectors a;
  a[0] = mbrt::inverse_mass_times(crank_mass, l.w[0]);
  a[1] = mbrt::inverse_mass_times(coupler_mass, l.w[1]);
  a[2] = mbrt::inverse_mass_times(rocker_mass, l.w[2]);
  return a;
}

// (lambda) => (s.lambda): the in-plane rows of every spatial block.
static void store_multipliers(const Rows& lambda, State& s) noexcept {
  s.lambda.segment<2>(0) = lambda.segment<2>(0);  // pin_o
  s.lambda.segment<2>(5) = lambda.segment<2>(2);  // pin_a
  s.lambda.segment<2>(10) = lambda.segment<2>(4);  // pin_b
  s.lambda.segment<2>(15) = lambda.segment<2>(6);  // pin_c
}

// (s, accelerations at t) => (s): half kick of the velocities in the plane
// (docs/staggered-pcst.md, eq. 1).
static void kick(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) mbrt::planar_kick<kNormal>(s.rigid[b], s.rigid_acceleration[b], h);
  for (int b = 0; b < kParticles; ++b) mbrt::planar_kick<kNormal>(s.particle[b], s.particle_acceleration[b], h);
}

// (s) => (s): positions to t + h with the half-step velocities (eqs. 2-3); the
// rotation about the normal by the spatial step's Cayley updates.
static void drift(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) mbrt::planar_drift<kNormal>(s.rigid[b], h, kEulerUpdates);
  for (int b = 0; b < kParticles; ++b) mbrt::planar_drift<kNormal>(s.particle[b], h);
  s.t += h;
}

// (c0.mbt_*, c.rows_*) => (g): G block by block in S's elimination order.
static void factorize_newton(const ConstraintSystem& c0, const ConstraintSystem& c, NewtonMatrix& g) noexcept {
  // pin_c
  g.D_3 = c.rows_pin_c.J1 * c0.mbt_3_2 + kNewtonShift * Eigen::Matrix<double, 2, 2>::Identity();
  g.L_2_3 = c.rows_pin_b.J2 * c0.mbt_3_2;
  g.U_3_2 = c.rows_pin_c.J1 * c0.mbt_2_2;
  g.D_3 = g.D_3.partialPivLu().inverse();
  g.L_2_3 = g.L_2_3 * g.D_3;
  // pin_b
  g.D_2 = c.rows_pin_b.J1 * c0.mbt_2_1 + c.rows_pin_b.J2 * c0.mbt_2_2 + kNewtonShift * Eigen::Matrix<double, 2, 2>::Identity()
      - g.L_2_3 * g.U_3_2;
  g.L_1_2 = c.rows_pin_a.J2 * c0.mbt_2_1;
  g.U_2_1 = c.rows_pin_b.J1 * c0.mbt_1_1;
  g.D_2 = g.D_2.partialPivLu().inverse();
  g.L_1_2 = g.L_1_2 * g.D_2;
  // pin_o
  g.D_0 = c.rows_pin_o.J2 * c0.mbt_0_0 + kNewtonShift * Eigen::Matrix<double, 2, 2>::Identity();
  g.L_1_0 = c.rows_pin_a.J1 * c0.mbt_0_0;
  g.U_0_1 = c.rows_pin_o.J2 * c0.mbt_1_0;
  g.D_0 = g.D_0.partialPivLu().inverse();
  g.L_1_0 = g.L_1_0 * g.D_0;
  // pin_a
  g.D_1 = c.rows_pin_a.J1 * c0.mbt_1_0 + c.rows_pin_a.J2 * c0.mbt_1_1 + kNewtonShift * Eigen::Matrix<double, 2, 2>::Identity()
      - g.L_1_2 * g.U_2_1
      - g.L_1_0 * g.U_0_1;
  g.D_1 = g.D_1.partialPivLu().inverse();
}

// (g, x) => (x): x := G^-1 x by forward and backward substitution.
static void solve_newton(const NewtonMatrix& g, Rows& x) noexcept {
  x.segment<2>(4) -= g.L_2_3 * x.segment<2>(6);
  x.segment<2>(2) -= g.L_1_2 * x.segment<2>(4);
  x.segment<2>(2) -= g.L_1_0 * x.segment<2>(0);
  {  // pin_a
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(2);
    x.segment<2>(2) = g.D_1 * y;
  }
  {  // pin_o
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(0);
    y -= g.U_0_1 * x.segment<2>(2);
    x.segment<2>(0) = g.D_0 * y;
  }
  {  // pin_b
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(4);
    y -= g.U_2_1 * x.segment<2>(2);
    x.segment<2>(4) = g.D_2 * y;
  }
  {  // pin_c
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(6);
    y -= g.U_3_2 * x.segment<2>(4);
    x.segment<2>(6) = g.D_3 * y;
  }
}

// (c, l, phi, s) => (s.lambda, accelerations): multipliers of the stabilized
// companion equation (docs/staggered-pcst.md eq. 7)
//   (S + 2 eps/h I) lambda = B M^-1 F + quad + (2/h) (B u + alpha phi)
// which the next explicit stage applies: it steers phi at the next step to
// (1 - alpha h) phi. quad was evaluated at the predicted half-step velocity.
static void constraint_forces(const ConstraintSystem& c, const Loads& l, const Rows& phi, State& s) noexcept {
  BodyVectors a = free_accelerations(l);
  Rows lambda = jacobian_times(c, a) + stacked_quad(c) +
             (2.0 / h) * (velocity_residual(c, generalized_velocities(s)) + kStabilization * phi);
  solve(c, lambda);
  subtract_constraint_forces(c, lambda, 1.0, a);
  set_accelerations(a, s);
  store_multipliers(lambda, s);
}

};

}  // namespace planar

}  // namespace

State initial_state() noexcept { return Model::initial_state(); }

mbrt::StepStatus step(State& s, Workspace& w) noexcept {
  return mbrt::schemes::staggered_step<planar::Model>(s, w);
}

mbrt::StepStatus step(State& s) noexcept {
  Workspace w;
  return step(s, w);
}

mbrt::Energy energy(const State& s) noexcept { return Model::energy(s); }

mbrt::ConstraintViolation constraint_violation(const State& s) noexcept { return Model::constraint_violation(s); }

double quaternion_norm_error(const State& s) noexcept { return Model::quaternion_norm_error(s); }

void reactions(const State& s, Reactions& r) noexcept { Model::reactions(s, r); }

}  // namespace mbrt::models::four_bar
