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
  vel[body::crank] = mbrt::velocity_of(s.rigid[rigid::crank]);
  vel[body::coupler] = mbrt::velocity_of(s.rigid[rigid::coupler]);
  vel[body::rocker] = mbrt::velocity_of(s.rigid[rigid::rocker]);
  return vel;
}

// (s) => (u): generalized velocities [v; w_body] per body.
static BodyVectors generalized_velocities(const State& s) noexcept {
  BodyVectors u;
  u[body::crank] << s.rigid[rigid::crank].v, s.rigid[rigid::crank].w;
  u[body::coupler] << s.rigid[rigid::coupler].v, s.rigid[rigid::coupler].w;
  u[body::rocker] << s.rigid[rigid::rocker].v, s.rigid[rigid::rocker].w;
  return u;
}

// (a) => (s): accelerations kept for the next step.
static void set_accelerations(const BodyVectors& a, State& s) noexcept {
  s.rigid_acceleration[rigid::crank] = {a[body::crank].head<3>(), a[body::crank].tail<3>()};
  s.rigid_acceleration[rigid::coupler] = {a[body::coupler].head<3>(), a[body::coupler].tail<3>()};
  s.rigid_acceleration[rigid::rocker] = {a[body::rocker].head<3>(), a[body::rocker].tail<3>()};
}

static BodyVectors accelerations_of(const State& s) noexcept {
  BodyVectors a;
  a[body::crank] << s.rigid_acceleration[rigid::crank].a, s.rigid_acceleration[rigid::crank].alpha;
  a[body::coupler] << s.rigid_acceleration[rigid::coupler].a, s.rigid_acceleration[rigid::coupler].alpha;
  a[body::rocker] << s.rigid_acceleration[rigid::rocker].a, s.rigid_acceleration[rigid::rocker].alpha;
  return a;
}

// (s) => (k): pose and velocity of every body.
static void kinematics(const State& s, Kinematics& k) noexcept {
  k.pose[body::crank] = mbrt::pose_of(s.rigid[rigid::crank]);
  k.pose[body::coupler] = mbrt::pose_of(s.rigid[rigid::coupler]);
  k.pose[body::rocker] = mbrt::pose_of(s.rigid[rigid::rocker]);
  k.vel = velocities_of(s);
}

// (k) => (l): applied forces (world) and torques (body axes) per body, and the elastic energy stored.
static void applied_loads([[maybe_unused]] const Kinematics& k, const State& s, Loads& l) noexcept {
  (void)s;
  l.w.fill(mbrt::Wrench{});
  l.elastic_energy = 0.0;
  l.w[body::crank].f += crank_weight;
  l.w[body::coupler].f += coupler_weight;
  l.w[body::rocker].f += rocker_weight;
}

// (k, s.t, s.params) => (c.*.rows): constraint values, Jacobians and acceleration terms.
static void constraint_rows(const Kinematics& k, [[maybe_unused]] const State& s, ConstraintSystem& c) noexcept {
  c.pin_o.rows = mbrt::revolute(pin_o_frame, mbrt::BodyMotion{kGroundPose, kGroundVelocity}, mbrt::BodyMotion{k.pose[body::crank], k.vel[body::crank]});
  c.pin_a.rows = mbrt::revolute(pin_a_frame, mbrt::BodyMotion{k.pose[body::crank], k.vel[body::crank]}, mbrt::BodyMotion{k.pose[body::coupler], k.vel[body::coupler]});
  c.pin_b.rows = mbrt::revolute(pin_b_frame, mbrt::BodyMotion{k.pose[body::coupler], k.vel[body::coupler]}, mbrt::BodyMotion{k.pose[body::rocker], k.vel[body::rocker]});
  c.pin_c.rows = mbrt::revolute(pin_c_frame, mbrt::BodyMotion{k.pose[body::rocker], k.vel[body::rocker]}, mbrt::BodyMotion{kGroundPose, kGroundVelocity});
}

// (c.*.rows) => (c.*.mbt_*): M^-1 B^T, the directions constraint forces move the bodies in.
// 300 flops: 90 mul, 60 add, 150 div.
static void constraint_directions(ConstraintSystem& c) noexcept {
  c.pin_o.mbt_crank = mbrt::inverse_mass_times_transpose(crank_mass, c.pin_o.rows.J2);
  c.pin_a.mbt_crank = mbrt::inverse_mass_times_transpose(crank_mass, c.pin_a.rows.J1);
  c.pin_a.mbt_coupler = mbrt::inverse_mass_times_transpose(coupler_mass, c.pin_a.rows.J2);
  c.pin_b.mbt_coupler = mbrt::inverse_mass_times_transpose(coupler_mass, c.pin_b.rows.J1);
  c.pin_b.mbt_rocker = mbrt::inverse_mass_times_transpose(rocker_mass, c.pin_b.rows.J2);
  c.pin_c.mbt_rocker = mbrt::inverse_mass_times_transpose(rocker_mass, c.pin_c.rows.J1);
}

// (c.*.rows) => (c.*.mbt_*, c.*.L*): M^-1 B^T, then S block by block in
// elimination order (0 fill blocks); false if a pivot is not positive.
// 4,190 flops: 2,045 mul, 1,860 add, 265 div, 20 sqrt.
static bool factorize(ConstraintSystem& c) noexcept {
  bool positive = true;
  constraint_directions(c);
  // pin_c
  c.pin_c.L = c.pin_c.rows.J1 * c.pin_c.mbt_rocker + kRegularization * Eigen::Matrix<double, 5, 5>::Identity();
  positive = mbrt::cholesky_in_place(c.pin_c.L) && positive;
  c.pin_b.L_pin_c = c.pin_b.rows.J2 * c.pin_c.mbt_rocker;
  mbrt::solve_right_lower_transposed(c.pin_c.L, c.pin_b.L_pin_c);
  // pin_b
  c.pin_b.L = c.pin_b.rows.J1 * c.pin_b.mbt_coupler + c.pin_b.rows.J2 * c.pin_b.mbt_rocker + kRegularization * Eigen::Matrix<double, 5, 5>::Identity()
      - c.pin_b.L_pin_c * c.pin_b.L_pin_c.transpose();
  positive = mbrt::cholesky_in_place(c.pin_b.L) && positive;
  c.pin_a.L_pin_b = c.pin_a.rows.J2 * c.pin_b.mbt_coupler;
  mbrt::solve_right_lower_transposed(c.pin_b.L, c.pin_a.L_pin_b);
  // pin_o
  c.pin_o.L = c.pin_o.rows.J2 * c.pin_o.mbt_crank + kRegularization * Eigen::Matrix<double, 5, 5>::Identity();
  positive = mbrt::cholesky_in_place(c.pin_o.L) && positive;
  c.pin_a.L_pin_o = c.pin_a.rows.J1 * c.pin_o.mbt_crank;
  mbrt::solve_right_lower_transposed(c.pin_o.L, c.pin_a.L_pin_o);
  // pin_a
  c.pin_a.L = c.pin_a.rows.J1 * c.pin_a.mbt_crank + c.pin_a.rows.J2 * c.pin_a.mbt_coupler + kRegularization * Eigen::Matrix<double, 5, 5>::Identity()
      - c.pin_a.L_pin_b * c.pin_a.L_pin_b.transpose()
      - c.pin_a.L_pin_o * c.pin_a.L_pin_o.transpose();
  positive = mbrt::cholesky_in_place(c.pin_a.L) && positive;
  return positive;
}

// (c.*.L*, x) => (x): x := S^-1 x by forward and backward substitution.
// 500 flops: 230 mul, 230 add, 40 div.
static void solve(const ConstraintSystem& c, Rows& x) noexcept {
  {  // pin_c
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(15);
    mbrt::solve_lower(c.pin_c.L, y);
    x.segment<5>(15) = y;
  }
  {  // pin_b
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(10);
    y -= c.pin_b.L_pin_c * x.segment<5>(15);
    mbrt::solve_lower(c.pin_b.L, y);
    x.segment<5>(10) = y;
  }
  {  // pin_o
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(0);
    mbrt::solve_lower(c.pin_o.L, y);
    x.segment<5>(0) = y;
  }
  {  // pin_a
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(5);
    y -= c.pin_a.L_pin_b * x.segment<5>(10);
    y -= c.pin_a.L_pin_o * x.segment<5>(0);
    mbrt::solve_lower(c.pin_a.L, y);
    x.segment<5>(5) = y;
  }
  {  // pin_a
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(5);
    mbrt::solve_lower_transposed(c.pin_a.L, y);
    x.segment<5>(5) = y;
  }
  {  // pin_o
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(0);
    y -= c.pin_a.L_pin_o.transpose() * x.segment<5>(5);
    mbrt::solve_lower_transposed(c.pin_o.L, y);
    x.segment<5>(0) = y;
  }
  {  // pin_b
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(10);
    y -= c.pin_a.L_pin_b.transpose() * x.segment<5>(5);
    mbrt::solve_lower_transposed(c.pin_b.L, y);
    x.segment<5>(10) = y;
  }
  {  // pin_c
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(15);
    y -= c.pin_b.L_pin_c.transpose() * x.segment<5>(10);
    mbrt::solve_lower_transposed(c.pin_c.L, y);
    x.segment<5>(15) = y;
  }
}

// (c, u) => (B u). 340 flops: 180 mul, 160 add.
static Rows jacobian_times(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  Rows y;
  y.segment<5>(0) = c.pin_o.rows.J2 * u[body::crank];
  y.segment<5>(5) = c.pin_a.rows.J1 * u[body::crank] + c.pin_a.rows.J2 * u[body::coupler];
  y.segment<5>(10) = c.pin_b.rows.J1 * u[body::coupler] + c.pin_b.rows.J2 * u[body::rocker];
  y.segment<5>(15) = c.pin_c.rows.J1 * u[body::rocker];
  return y;
}

// (c, lambda) => (u): u -= scale M^-1 B^T lambda. 396 flops: 216 mul, 180 add.
static void subtract_constraint_forces(const ConstraintSystem& c, const Rows& lambda, double scale,
                                BodyVectors& u) noexcept {
  u[body::crank] -= scale * (c.pin_o.mbt_crank * lambda.segment<5>(0));
  u[body::crank] -= scale * (c.pin_a.mbt_crank * lambda.segment<5>(5));
  u[body::coupler] -= scale * (c.pin_a.mbt_coupler * lambda.segment<5>(5));
  u[body::coupler] -= scale * (c.pin_b.mbt_coupler * lambda.segment<5>(10));
  u[body::rocker] -= scale * (c.pin_b.mbt_rocker * lambda.segment<5>(10));
  u[body::rocker] -= scale * (c.pin_c.mbt_rocker * lambda.segment<5>(15));
}

// (c) => (phi), (c) => (quad): stacked position residuals and acceleration terms.
static Rows stacked_phi(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<5>(0) = c.pin_o.rows.phi;
  y.segment<5>(5) = c.pin_a.rows.phi;
  y.segment<5>(10) = c.pin_b.rows.phi;
  y.segment<5>(15) = c.pin_c.rows.phi;
  return y;
}

static Rows stacked_quad(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<5>(0) = c.pin_o.rows.quad;
  y.segment<5>(5) = c.pin_a.rows.quad;
  y.segment<5>(10) = c.pin_b.rows.quad;
  y.segment<5>(15) = c.pin_c.rows.quad;
  return y;
}

// (c, u) => (phi_dot = B u + phi_t): velocity residuals.
static Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  return jacobian_times(c, u);  // no drivers: phi_t = 0
}

// (l) => (M^-1 F) per body.
static BodyVectors free_accelerations(const Loads& l) noexcept {
  BodyVectors a;
  a[body::crank] = mbrt::inverse_mass_times(crank_mass, l.w[body::crank]);
  a[body::coupler] = mbrt::inverse_mass_times(coupler_mass, l.w[body::coupler]);
  a[body::rocker] = mbrt::inverse_mass_times(rocker_mass, l.w[body::rocker]);
  return a;
}

// (s) => (J^-1 (-w x J w)) per body: the gyroscopic accelerations, which the
// explicit stage's free rotation applies and the multipliers must balance.
static BodyVectors gyroscopic_accelerations(const State& s) noexcept {
  BodyVectors g;
  g[body::crank] << mbrt::Vec3::Zero(), mbrt::inverse_inertia_times(crank_mass, mbrt::gyroscopic_torque(crank_mass, s.rigid[rigid::crank].w));
  g[body::coupler] << mbrt::Vec3::Zero(), mbrt::inverse_inertia_times(coupler_mass, mbrt::gyroscopic_torque(coupler_mass, s.rigid[rigid::coupler].w));
  g[body::rocker] << mbrt::Vec3::Zero(), mbrt::inverse_inertia_times(rocker_mass, mbrt::gyroscopic_torque(rocker_mass, s.rigid[rigid::rocker].w));
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
  s.rigid[rigid::crank] = {mbrt::Vec3(0.0, 0.5, 0.0), mbrt::Vec4(1.0, 0.0, 0.0, 0.0),
      mbrt::Vec3(0.5, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, -1.0)};
  s.rigid[rigid::coupler] = {mbrt::Vec3(1.5, 1.5, 0.0), mbrt::Vec4(1.0, 0.0, 0.0, 0.0),
      mbrt::Vec3(1.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0)};
  s.rigid[rigid::rocker] = {mbrt::Vec3(3.0, 1.0, 0.0), mbrt::Vec4(1.0, 0.0, 0.0, 0.0),
      mbrt::Vec3(0.5, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, -0.5)};
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s, c);
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
  e.kinetic += mbrt::kinetic_energy(crank_mass, u[body::crank]);
  e.potential -= crank_mass.m * kGravity.dot(k.pose[body::crank].r);
  e.kinetic += mbrt::kinetic_energy(coupler_mass, u[body::coupler]);
  e.potential -= coupler_mass.m * kGravity.dot(k.pose[body::coupler].r);
  e.kinetic += mbrt::kinetic_energy(rocker_mass, u[body::rocker]);
  e.potential -= rocker_mass.m * kGravity.dot(k.pose[body::rocker].r);
  return e;
}

static mbrt::ConstraintViolation constraint_violation(const State& s) noexcept {
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s, c);
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
  constraint_rows(k, s, c);
  r[constraint::pin_o] = mbrt::joint_reaction(-(c.pin_o.rows.J2.transpose() * s.lambda.segment<5>(0)), k.pose[body::crank],
      k.pose[body::crank].r + k.pose[body::crank].R * pin_o_frame.s2, 1.0, kGroundPose, pin_o_frame);
  r[constraint::pin_a] = mbrt::joint_reaction(-(c.pin_a.rows.J2.transpose() * s.lambda.segment<5>(5)), k.pose[body::coupler],
      k.pose[body::coupler].r + k.pose[body::coupler].R * pin_a_frame.s2, 1.0, k.pose[body::crank], pin_a_frame);
  r[constraint::pin_b] = mbrt::joint_reaction(-(c.pin_b.rows.J2.transpose() * s.lambda.segment<5>(10)), k.pose[body::rocker],
      k.pose[body::rocker].r + k.pose[body::rocker].R * pin_b_frame.s2, 1.0, k.pose[body::coupler], pin_b_frame);
  r[constraint::pin_c] = mbrt::joint_reaction(-(c.pin_c.rows.J1.transpose() * s.lambda.segment<5>(15)), k.pose[body::rocker],
      pin_c_frame.s2, -1.0, k.pose[body::rocker], pin_c_frame);
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
  vel[body::crank] = mbrt::planar_velocity_of<kNormal>(s.rigid[rigid::crank]);
  vel[body::coupler] = mbrt::planar_velocity_of<kNormal>(s.rigid[rigid::coupler]);
  vel[body::rocker] = mbrt::planar_velocity_of<kNormal>(s.rigid[rigid::rocker]);
  return vel;
}

// (s) => (u): (vx, vy, omega_z) per body.
static BodyVectors generalized_velocities(const State& s) noexcept {
  BodyVectors u;
  u[body::crank] = mbrt::planar_velocities<kNormal>(s.rigid[rigid::crank]);
  u[body::coupler] = mbrt::planar_velocities<kNormal>(s.rigid[rigid::coupler]);
  u[body::rocker] = mbrt::planar_velocities<kNormal>(s.rigid[rigid::rocker]);
  return u;
}

// (u) => (s): the in-plane velocities; the others stay zero.
static void set_velocities(const BodyVectors& u, State& s) noexcept {
  mbrt::set_planar_velocities<kNormal>(u[body::crank], s.rigid[rigid::crank]);
  mbrt::set_planar_velocities<kNormal>(u[body::coupler], s.rigid[rigid::coupler]);
  mbrt::set_planar_velocities<kNormal>(u[body::rocker], s.rigid[rigid::rocker]);
}

// (a) => (s): accelerations kept for the next step.
static void set_accelerations(const BodyVectors& a, State& s) noexcept {
  mbrt::set_planar_accelerations<kNormal>(a[body::crank], s.rigid_acceleration[rigid::crank]);
  mbrt::set_planar_accelerations<kNormal>(a[body::coupler], s.rigid_acceleration[rigid::coupler]);
  mbrt::set_planar_accelerations<kNormal>(a[body::rocker], s.rigid_acceleration[rigid::rocker]);
}

static BodyVectors accelerations_of(const State& s) noexcept {
  BodyVectors a;
  a[body::crank] = mbrt::planar_accelerations<kNormal>(s.rigid_acceleration[rigid::crank]);
  a[body::coupler] = mbrt::planar_accelerations<kNormal>(s.rigid_acceleration[rigid::coupler]);
  a[body::rocker] = mbrt::planar_accelerations<kNormal>(s.rigid_acceleration[rigid::rocker]);
  return a;
}

// (s) => (k): pose and velocity of every body.
static void kinematics(const State& s, Kinematics& k) noexcept {
  k.pose[body::crank] = mbrt::planar_pose_of<kNormal>(s.rigid[rigid::crank]);
  k.pose[body::coupler] = mbrt::planar_pose_of<kNormal>(s.rigid[rigid::coupler]);
  k.pose[body::rocker] = mbrt::planar_pose_of<kNormal>(s.rigid[rigid::rocker]);
  k.vel = velocities_of(s);
}

// (k) => (l): applied forces (world) and torques (body axes) per body, and the elastic energy stored.
static void applied_loads([[maybe_unused]] const Kinematics& k, const State& s, Loads& l) noexcept {
  (void)s;
  l.w.fill(mbrt::PlanarWrench{});
  l.elastic_energy = 0.0;
  l.w[body::crank].f += crank_weight;
  l.w[body::coupler].f += coupler_weight;
  l.w[body::rocker].f += rocker_weight;
}

// (k, s.t, s.params) => (c.*.rows): constraint values, Jacobians and acceleration terms.
static void constraint_rows(const Kinematics& k, [[maybe_unused]] const State& s, ConstraintSystem& c) noexcept {
  c.pin_o.rows = mbrt::planar_revolute(pin_o_frame, mbrt::PlanarMotion{kGroundPose, kGroundVelocity}, mbrt::PlanarMotion{k.pose[body::crank], k.vel[body::crank]});
  c.pin_a.rows = mbrt::planar_revolute(pin_a_frame, mbrt::PlanarMotion{k.pose[body::crank], k.vel[body::crank]}, mbrt::PlanarMotion{k.pose[body::coupler], k.vel[body::coupler]});
  c.pin_b.rows = mbrt::planar_revolute(pin_b_frame, mbrt::PlanarMotion{k.pose[body::coupler], k.vel[body::coupler]}, mbrt::PlanarMotion{k.pose[body::rocker], k.vel[body::rocker]});
  c.pin_c.rows = mbrt::planar_revolute(pin_c_frame, mbrt::PlanarMotion{k.pose[body::rocker], k.vel[body::rocker]}, mbrt::PlanarMotion{kGroundPose, kGroundVelocity});
}

// (c.*.rows) => (c.*.mbt_*): M^-1 B^T, the directions constraint forces move the bodies in.
// 36 flops: 0 mul, 0 add, 36 div.
static void constraint_directions(ConstraintSystem& c) noexcept {
  c.pin_o.mbt_crank = mbrt::inverse_mass_times_transpose(crank_mass, c.pin_o.rows.J2);
  c.pin_a.mbt_crank = mbrt::inverse_mass_times_transpose(crank_mass, c.pin_a.rows.J1);
  c.pin_a.mbt_coupler = mbrt::inverse_mass_times_transpose(coupler_mass, c.pin_a.rows.J2);
  c.pin_b.mbt_coupler = mbrt::inverse_mass_times_transpose(coupler_mass, c.pin_b.rows.J1);
  c.pin_b.mbt_rocker = mbrt::inverse_mass_times_transpose(rocker_mass, c.pin_b.rows.J2);
  c.pin_c.mbt_rocker = mbrt::inverse_mass_times_transpose(rocker_mass, c.pin_c.rows.J1);
}

// (c.*.rows) => (c.*.mbt_*, c.*.L*): M^-1 B^T, then S block by block in
// elimination order (0 fill blocks); false if a pivot is not positive.
// 324 flops: 142 mul, 122 add, 52 div, 8 sqrt.
static bool factorize(ConstraintSystem& c) noexcept {
  bool positive = true;
  constraint_directions(c);
  // pin_c
  c.pin_c.L = c.pin_c.rows.J1 * c.pin_c.mbt_rocker + kRegularization * Eigen::Matrix<double, 2, 2>::Identity();
  positive = mbrt::cholesky_in_place(c.pin_c.L) && positive;
  c.pin_b.L_pin_c = c.pin_b.rows.J2 * c.pin_c.mbt_rocker;
  mbrt::solve_right_lower_transposed(c.pin_c.L, c.pin_b.L_pin_c);
  // pin_b
  c.pin_b.L = c.pin_b.rows.J1 * c.pin_b.mbt_coupler + c.pin_b.rows.J2 * c.pin_b.mbt_rocker + kRegularization * Eigen::Matrix<double, 2, 2>::Identity()
      - c.pin_b.L_pin_c * c.pin_b.L_pin_c.transpose();
  positive = mbrt::cholesky_in_place(c.pin_b.L) && positive;
  c.pin_a.L_pin_b = c.pin_a.rows.J2 * c.pin_b.mbt_coupler;
  mbrt::solve_right_lower_transposed(c.pin_b.L, c.pin_a.L_pin_b);
  // pin_o
  c.pin_o.L = c.pin_o.rows.J2 * c.pin_o.mbt_crank + kRegularization * Eigen::Matrix<double, 2, 2>::Identity();
  positive = mbrt::cholesky_in_place(c.pin_o.L) && positive;
  c.pin_a.L_pin_o = c.pin_a.rows.J1 * c.pin_o.mbt_crank;
  mbrt::solve_right_lower_transposed(c.pin_o.L, c.pin_a.L_pin_o);
  // pin_a
  c.pin_a.L = c.pin_a.rows.J1 * c.pin_a.mbt_crank + c.pin_a.rows.J2 * c.pin_a.mbt_coupler + kRegularization * Eigen::Matrix<double, 2, 2>::Identity()
      - c.pin_a.L_pin_b * c.pin_a.L_pin_b.transpose()
      - c.pin_a.L_pin_o * c.pin_a.L_pin_o.transpose();
  positive = mbrt::cholesky_in_place(c.pin_a.L) && positive;
  return positive;
}

// (c.*.L*, x) => (x): x := S^-1 x by forward and backward substitution.
// 80 flops: 32 mul, 32 add, 16 div.
static void solve(const ConstraintSystem& c, Rows& x) noexcept {
  {  // pin_c
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(6);
    mbrt::solve_lower(c.pin_c.L, y);
    x.segment<2>(6) = y;
  }
  {  // pin_b
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(4);
    y -= c.pin_b.L_pin_c * x.segment<2>(6);
    mbrt::solve_lower(c.pin_b.L, y);
    x.segment<2>(4) = y;
  }
  {  // pin_o
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(0);
    mbrt::solve_lower(c.pin_o.L, y);
    x.segment<2>(0) = y;
  }
  {  // pin_a
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(2);
    y -= c.pin_a.L_pin_b * x.segment<2>(4);
    y -= c.pin_a.L_pin_o * x.segment<2>(0);
    mbrt::solve_lower(c.pin_a.L, y);
    x.segment<2>(2) = y;
  }
  {  // pin_a
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(2);
    mbrt::solve_lower_transposed(c.pin_a.L, y);
    x.segment<2>(2) = y;
  }
  {  // pin_o
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(0);
    y -= c.pin_a.L_pin_o.transpose() * x.segment<2>(2);
    mbrt::solve_lower_transposed(c.pin_o.L, y);
    x.segment<2>(0) = y;
  }
  {  // pin_b
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(4);
    y -= c.pin_a.L_pin_b.transpose() * x.segment<2>(2);
    mbrt::solve_lower_transposed(c.pin_b.L, y);
    x.segment<2>(4) = y;
  }
  {  // pin_c
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(6);
    y -= c.pin_b.L_pin_c.transpose() * x.segment<2>(4);
    mbrt::solve_lower_transposed(c.pin_c.L, y);
    x.segment<2>(6) = y;
  }
}

// (c, u) => (B u). 64 flops: 36 mul, 28 add.
static Rows jacobian_times(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  Rows y;
  y.segment<2>(0) = c.pin_o.rows.J2 * u[body::crank];
  y.segment<2>(2) = c.pin_a.rows.J1 * u[body::crank] + c.pin_a.rows.J2 * u[body::coupler];
  y.segment<2>(4) = c.pin_b.rows.J1 * u[body::coupler] + c.pin_b.rows.J2 * u[body::rocker];
  y.segment<2>(6) = c.pin_c.rows.J1 * u[body::rocker];
  return y;
}

// (c, lambda) => (u): u -= scale M^-1 B^T lambda. 90 flops: 54 mul, 36 add.
static void subtract_constraint_forces(const ConstraintSystem& c, const Rows& lambda, double scale,
                                BodyVectors& u) noexcept {
  u[body::crank] -= scale * (c.pin_o.mbt_crank * lambda.segment<2>(0));
  u[body::crank] -= scale * (c.pin_a.mbt_crank * lambda.segment<2>(2));
  u[body::coupler] -= scale * (c.pin_a.mbt_coupler * lambda.segment<2>(2));
  u[body::coupler] -= scale * (c.pin_b.mbt_coupler * lambda.segment<2>(4));
  u[body::rocker] -= scale * (c.pin_b.mbt_rocker * lambda.segment<2>(4));
  u[body::rocker] -= scale * (c.pin_c.mbt_rocker * lambda.segment<2>(6));
}

// (c) => (phi), (c) => (quad): stacked position residuals and acceleration terms.
static Rows stacked_phi(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<2>(0) = c.pin_o.rows.phi;
  y.segment<2>(2) = c.pin_a.rows.phi;
  y.segment<2>(4) = c.pin_b.rows.phi;
  y.segment<2>(6) = c.pin_c.rows.phi;
  return y;
}

static Rows stacked_quad(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<2>(0) = c.pin_o.rows.quad;
  y.segment<2>(2) = c.pin_a.rows.quad;
  y.segment<2>(4) = c.pin_b.rows.quad;
  y.segment<2>(6) = c.pin_c.rows.quad;
  return y;
}

// (c, u) => (phi_dot = B u + phi_t): velocity residuals.
static Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  return jacobian_times(c, u);  // no drivers: phi_t = 0
}

// (l) => (M^-1 F) per body.
static BodyVectors free_accelerations(const Loads& l) noexcept {
  BodyVectors a;
  a[body::crank] = mbrt::inverse_mass_times(crank_mass, l.w[body::crank]);
  a[body::coupler] = mbrt::inverse_mass_times(coupler_mass, l.w[body::coupler]);
  a[body::rocker] = mbrt::inverse_mass_times(rocker_mass, l.w[body::rocker]);
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

// (c0.*.mbt_*, c.*.rows) => (g): G block by block in S's elimination order.
// 400 flops: 212 mul, 168 add, 20 div.
static void factorize_newton(const ConstraintSystem& c0, const ConstraintSystem& c, NewtonMatrix& g) noexcept {
  // pin_c
  g.pin_c.D = c.pin_c.rows.J1 * c0.pin_c.mbt_rocker + kNewtonShift * Eigen::Matrix<double, 2, 2>::Identity();
  g.pin_b.L_pin_c = c.pin_b.rows.J2 * c0.pin_c.mbt_rocker;
  g.pin_c.U_pin_b = c.pin_c.rows.J1 * c0.pin_b.mbt_rocker;
  mbrt::invert_with_pivoting(g.pin_c.D);
  g.pin_b.L_pin_c = g.pin_b.L_pin_c * g.pin_c.D;
  // pin_b
  g.pin_b.D = c.pin_b.rows.J1 * c0.pin_b.mbt_coupler + c.pin_b.rows.J2 * c0.pin_b.mbt_rocker + kNewtonShift * Eigen::Matrix<double, 2, 2>::Identity()
      - g.pin_b.L_pin_c * g.pin_c.U_pin_b;
  g.pin_a.L_pin_b = c.pin_a.rows.J2 * c0.pin_b.mbt_coupler;
  g.pin_b.U_pin_a = c.pin_b.rows.J1 * c0.pin_a.mbt_coupler;
  mbrt::invert_with_pivoting(g.pin_b.D);
  g.pin_a.L_pin_b = g.pin_a.L_pin_b * g.pin_b.D;
  // pin_o
  g.pin_o.D = c.pin_o.rows.J2 * c0.pin_o.mbt_crank + kNewtonShift * Eigen::Matrix<double, 2, 2>::Identity();
  g.pin_a.L_pin_o = c.pin_a.rows.J1 * c0.pin_o.mbt_crank;
  g.pin_o.U_pin_a = c.pin_o.rows.J2 * c0.pin_a.mbt_crank;
  mbrt::invert_with_pivoting(g.pin_o.D);
  g.pin_a.L_pin_o = g.pin_a.L_pin_o * g.pin_o.D;
  // pin_a
  g.pin_a.D = c.pin_a.rows.J1 * c0.pin_a.mbt_crank + c.pin_a.rows.J2 * c0.pin_a.mbt_coupler + kNewtonShift * Eigen::Matrix<double, 2, 2>::Identity()
      - g.pin_a.L_pin_b * g.pin_b.U_pin_a
      - g.pin_a.L_pin_o * g.pin_o.U_pin_a;
  mbrt::invert_with_pivoting(g.pin_a.D);
}

// (g, x) => (x): x := G^-1 x by forward and backward substitution.
// 72 flops: 40 mul, 32 add.
static void solve_newton(const NewtonMatrix& g, Rows& x) noexcept {
  x.segment<2>(4) -= g.pin_b.L_pin_c * x.segment<2>(6);
  x.segment<2>(2) -= g.pin_a.L_pin_b * x.segment<2>(4);
  x.segment<2>(2) -= g.pin_a.L_pin_o * x.segment<2>(0);
  {  // pin_a
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(2);
    x.segment<2>(2) = g.pin_a.D * y;
  }
  {  // pin_o
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(0);
    y -= g.pin_o.U_pin_a * x.segment<2>(2);
    x.segment<2>(0) = g.pin_o.D * y;
  }
  {  // pin_b
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(4);
    y -= g.pin_b.U_pin_a * x.segment<2>(2);
    x.segment<2>(4) = g.pin_b.D * y;
  }
  {  // pin_c
    Eigen::Matrix<double, 2, 1> y = x.segment<2>(6);
    y -= g.pin_c.U_pin_b * x.segment<2>(4);
    x.segment<2>(6) = g.pin_c.D * y;
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

void refresh_bodies(State&) noexcept {}

mbrt::Energy energy(const State& s) noexcept { return Model::energy(s); }

mbrt::ConstraintViolation constraint_violation(const State& s) noexcept { return Model::constraint_violation(s); }

double quaternion_norm_error(const State& s) noexcept { return Model::quaternion_norm_error(s); }

void reactions(const State& s, Reactions& r) noexcept { Model::reactions(s, r); }

}  // namespace mbrt::models::four_bar
