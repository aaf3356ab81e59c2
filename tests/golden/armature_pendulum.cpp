// mbrt generated model 'armature_pendulum': 1 bodies (1 rigid, 0 particles), 1 joints, 0 drivers, 5 constraint rows.
// Scheme staggered-tree: the step is mbrt::schemes::tree_step (include/mbrt/schemes/tree.hpp)
// over Model, the model's types, constants and kernels below.
// Left out for this scene:
//   principal_axes: 1 principal-axis bodies: inertia products in M^-1 and the gyroscopic torques
//   folded_weights: gravity: the products m g, one constant weight per body
//   no_drivers: no drivers: the explicit time terms phi_t
// Kept: spatial coordinates, since not for scheme staggered-tree.
#include "armature_pendulum.hpp"

#include <algorithm>
#include <cmath>

#include <mbrt/reactions.hpp>
#include <mbrt/schemes/tree.hpp>

namespace mbrt::models::armature_pendulum {

namespace {

constexpr double h = kStep;
constexpr double kRegularization = 1.0000000000000001e-07;  // added to diag(S)
const mbrt::Vec3 kGravity = mbrt::Vec3(0.0, 0.0, -9.8100000000000005);
const mbrt::BodyPose kGroundPose = mbrt::ground_pose();
const mbrt::BodyVelocity kGroundVelocity = mbrt::ground_velocity();

// Mass properties (constant; M is block diagonal).
const mbrt::PrincipalInertia rod_mass{2.0, mbrt::Vec3(0.16666666666666666, 0.16666666666666666, 0.001)};
const mbrt::Vec3 rod_weight = mbrt::Vec3(0.0, 0.0, -19.620000000000001);

// Joint and driver frames in body axes; drivers' functions of time.
const mbrt::JointFrame pin_frame{mbrt::Vec3(0.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.5),
    mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec3(0.0, 0.0, -1.0), mbrt::Vec3(-1.0, 0.0, 0.0),
    mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec3(0.0, 0.0, -1.0), mbrt::Vec3(-1.0, 0.0, 0.0), 0.0, 0.0};

// Force elements in body axes.

// The model as the scheme's step (include/mbrt/schemes/) sees it: types,
// constants and kernels.
struct Model {
using State = mbrt::models::armature_pendulum::State;
using Workspace = mbrt::models::armature_pendulum::Workspace;
using Rows = detail::Rows;
using BodyVectors = detail::BodyVectors;
using Kinematics = detail::Kinematics;
using Loads = detail::Loads;
using ConstraintSystem = detail::ConstraintSystem;
static constexpr mbrt::Scheme kScheme = mbrt::Scheme::staggered_tree;
static constexpr double kStep = h;
using Dofs = mbrt::models::armature_pendulum::Dofs;
using HalfAngles = mbrt::models::armature_pendulum::HalfAngles;
static constexpr int kStages = 1;  // recursions per step
static constexpr bool kExternalLoads = false;  // loads other than gravity
static constexpr bool kBodyStatesEachStep = true;  // s.rigid formed by every step, else by refresh_bodies()

static std::array<mbrt::BodyVelocity, kBodies> velocities_of(const State& s) noexcept {
  std::array<mbrt::BodyVelocity, kBodies> vel;
  vel[body::rod] = mbrt::velocity_of(s.rigid[rigid::rod]);
  return vel;
}

// (s) => (u): generalized velocities [v; w_body] per body.
static BodyVectors generalized_velocities(const State& s) noexcept {
  BodyVectors u;
  u[body::rod] << s.rigid[rigid::rod].v, s.rigid[rigid::rod].w;
  return u;
}

// (u) => (s): write generalized velocities back.
static void set_velocities(const BodyVectors& u, State& s) noexcept {
  s.rigid[rigid::rod].v = u[body::rod].head<3>();
  s.rigid[rigid::rod].w = u[body::rod].tail<3>();
}

// (a) => (s): accelerations kept for the next step.
static void set_accelerations(const BodyVectors& a, State& s) noexcept {
  s.rigid_acceleration[rigid::rod] = {a[body::rod].head<3>(), a[body::rod].tail<3>()};
}

static BodyVectors accelerations_of(const State& s) noexcept {
  BodyVectors a;
  a[body::rod] << s.rigid_acceleration[rigid::rod].a, s.rigid_acceleration[rigid::rod].alpha;
  return a;
}

// (s) => (k): pose and velocity of every body.
static void kinematics(const State& s, Kinematics& k) noexcept {
  k.pose[body::rod] = mbrt::pose_of(s.rigid[rigid::rod]);
  k.vel = velocities_of(s);
}

// (k) => (l): applied forces (world) and torques (body axes) per body,
// gyroscopic torques included, and the elastic energy stored.
static void applied_loads([[maybe_unused]] const Kinematics& k, const State& s, Loads& l) noexcept {
  (void)s;
  l.w.fill(mbrt::Wrench{});
  l.elastic_energy = 0.0;
  l.w[body::rod].f += rod_weight;
  l.w[body::rod].tau += mbrt::gyroscopic_torque(rod_mass, k.vel[body::rod].w);
}

// (k, s.t, s.params) => (c.*.rows): constraint values, Jacobians and acceleration terms.
static void constraint_rows(const Kinematics& k, [[maybe_unused]] const State& s, ConstraintSystem& c) noexcept {
  c.pin.rows = mbrt::revolute(pin_frame, mbrt::BodyMotion{kGroundPose, kGroundVelocity}, mbrt::BodyMotion{k.pose[body::rod], k.vel[body::rod]});
}

// (c.*.rows) => (c.*.mbt_*): M^-1 B^T, the directions constraint forces move the bodies in.
// 30 flops: 0 mul, 0 add, 30 div.
static void constraint_directions(ConstraintSystem& c) noexcept {
  c.pin.mbt_rod = mbrt::inverse_mass_times_transpose(rod_mass, c.pin.rows.J2);
}

// (c.*.rows) => (c.*.mbt_*, c.*.L*): M^-1 B^T, then S block by block in
// elimination order (0 fill blocks); false if a pivot is not positive.
// 365 flops: 170 mul, 150 add, 40 div, 5 sqrt.
static bool factorize(ConstraintSystem& c) noexcept {
  bool positive = true;
  constraint_directions(c);
  // pin
  c.pin.L = c.pin.rows.J2 * c.pin.mbt_rod + kRegularization * Eigen::Matrix<double, 5, 5>::Identity();
  positive = mbrt::cholesky_in_place(c.pin.L) && positive;
  return positive;
}

// (c.*.L*, x) => (x): x := S^-1 x by forward and backward substitution.
// 50 flops: 20 mul, 20 add, 10 div.
static void solve(const ConstraintSystem& c, Rows& x) noexcept {
  {  // pin
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(0);
    mbrt::solve_lower(c.pin.L, y);
    x.segment<5>(0) = y;
  }
  {  // pin
    Eigen::Matrix<double, 5, 1> y = x.segment<5>(0);
    mbrt::solve_lower_transposed(c.pin.L, y);
    x.segment<5>(0) = y;
  }
}

// (c, u) => (B u). 55 flops: 30 mul, 25 add.
static Rows jacobian_times(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  Rows y;
  y.segment<5>(0) = c.pin.rows.J2 * u[body::rod];
  return y;
}

// (c, lambda) => (u): u -= scale M^-1 B^T lambda. 66 flops: 36 mul, 30 add.
static void subtract_constraint_forces(const ConstraintSystem& c, const Rows& lambda, double scale,
                                BodyVectors& u) noexcept {
  u[body::rod] -= scale * (c.pin.mbt_rod * lambda.segment<5>(0));
}

// (c) => (phi), (c) => (quad): stacked position residuals and acceleration terms.
static Rows stacked_phi(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<5>(0) = c.pin.rows.phi;
  return y;
}

static Rows stacked_quad(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<5>(0) = c.pin.rows.quad;
  return y;
}

// (c, u) => (phi_dot = B u + phi_t): velocity residuals.
static Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  return jacobian_times(c, u);  // no drivers: phi_t = 0
}

// (l) => (M^-1 F) per body.
static BodyVectors free_accelerations(const Loads& l) noexcept {
  BodyVectors a;
  a[body::rod] = mbrt::inverse_mass_times(rod_mass, l.w[body::rod]);
  return a;
}

// The loads the recursion takes from outside: all but gravity and the
// gyroscopic torques, which it holds itself.
// (k) => (l): applied forces (world) and torques (body axes) per body, and the elastic energy stored.
static void tree_loads([[maybe_unused]] const Kinematics& k, const State& s, Loads& l) noexcept {
  (void)s;
  l.w.fill(mbrt::Wrench{});
  l.elastic_energy = 0.0;
}

static void constraint_forces(const ConstraintSystem& c, const Loads& l, const Rows& phi, State& s) noexcept {
  (void)phi;
  BodyVectors a = free_accelerations(l);
  s.lambda = jacobian_times(c, a) + stacked_quad(c);
  solve(c, s.lambda);
  subtract_constraint_forces(c, s.lambda, 1.0, a);
  set_accelerations(a, s);
}

// (q) => (ha): the half angles every kernel below turns frames by.
static void half_angles([[maybe_unused]] const Dofs& q, [[maybe_unused]] HalfAngles& ha) noexcept {
  ha[body::rod] = mbrt::sin_cos(0.5 * (q[body::rod] + 1.5707963267948966));  // rod
}

// (s.q, qd) => (qdd): the articulated-body recursion, this model's nonzero terms only.
// 4 flops: 2 mul, 0 add, 1 fma
static void joint_accelerations([[maybe_unused]] const State& s, [[maybe_unused]] const HalfAngles& ha, [[maybe_unused]] const Dofs& qd, [[maybe_unused]] const Kinematics& k, [[maybe_unused]] const Loads& l, Dofs& qdd) noexcept {
  const double t0 = ha[body::rod].c * ha[body::rod].c;
  const double t1 = mbrt::mul_add(-ha[body::rod].s, ha[body::rod].s, t0);
  const double t2 = t1 * 8.4085714285714293;
  qdd[body::rod] = t2;
}

// (q, qd) => (s.rigid): where every body is and how it moves.
// 12 flops: 8 mul, 2 add, 1 fma
static void body_states([[maybe_unused]] const Dofs& q, [[maybe_unused]] const HalfAngles& ha, [[maybe_unused]] const Dofs& qd, State& s) noexcept {
  const double t0 = ha[body::rod].s * 0.70710678118654746;
  const double t1 = ha[body::rod].c * 0.70710678118654746;
  const double t2 = t0 + t1;
  const double t3 = t0 - t1;
  const double t4 = t3 * 2.0;
  const double t5 = t2 * t4;
  const double t6 = mbrt::mul_add(t3, t4, (-1.0));
  const double t7 = t5 * 0.5;
  const double t8 = t6 * 0.5;
  const double t9 = qd[body::rod] * t8;
  const double t10 = qd[body::rod] * t7;
  s.rigid[rigid::rod].r[0] = -t7;
  s.rigid[rigid::rod].v[0] = t9;
  s.rigid[rigid::rod].w[0] = 0.0;
  s.rigid[rigid::rod].r[1] = 0.0;
  s.rigid[rigid::rod].v[1] = 0.0;
  s.rigid[rigid::rod].w[1] = qd[body::rod];
  s.rigid[rigid::rod].r[2] = t8;
  s.rigid[rigid::rod].v[2] = t10;
  s.rigid[rigid::rod].w[2] = 0.0;
  s.rigid[rigid::rod].p[0] = t2;
  s.rigid[rigid::rod].p[1] = 0.0;
  s.rigid[rigid::rod].p[2] = t3;
  s.rigid[rigid::rod].p[3] = 0.0;
}

static State initial_state() noexcept {
  State s;
  s.rigid[rigid::rod] = {mbrt::Vec3(0.0, 0.0, -0.5), mbrt::Vec4(1.0, 0.0, 0.0, 0.0),
      mbrt::Vec3(-0.001, 0.0, 0.0), mbrt::Vec3(0.0, 0.002, 0.0)};
  s.q.fill(0.0);
  s.qd = {0.002};
  HalfAngles ha;
  half_angles(s.q, ha);
  body_states(s.q, ha, s.qd, s);
  Kinematics k;
  kinematics(s, k);
  Loads l;
  tree_loads(k, s, l);
  joint_accelerations(s, ha, s.qd, k, l, s.qdd);
  set_multipliers(s);
  return s;
}

static mbrt::Energy energy(const State& s) noexcept {
  Kinematics k;
  kinematics(s, k);
  Loads l;
  applied_loads(k, s, l);
  const BodyVectors u = generalized_velocities(s);
  mbrt::Energy e{0.0, l.elastic_energy};
  e.kinetic += mbrt::kinetic_energy(rod_mass, u[body::rod]);
  e.potential -= rod_mass.m * kGravity.dot(k.pose[body::rod].r);
  e.kinetic += 0.25 * s.qd[body::rod] * s.qd[body::rod];  // armature of pin
  return e;
}

static mbrt::ConstraintViolation constraint_violation(const State& given) noexcept {
  State s = given;
  set_multipliers(s);
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s, c);
  const Rows phi = stacked_phi(c);
  const Rows phi_dot = velocity_residual(c, generalized_velocities(s));
  BodyVectors a = accelerations_of(s);
  const Rows phi_ddot = jacobian_times(c, a) + stacked_quad(c);
  if (kConstraintRows == 0) return {0.0, 0.0, 0.0};
  return {phi.cwiseAbs().maxCoeff(), phi_dot.cwiseAbs().maxCoeff(), phi_ddot.cwiseAbs().maxCoeff()};
}

static double quaternion_norm_error(const State& s) noexcept {
  double e = 0.0;
  for (const mbrt::RigidState& x : s.rigid) e = std::max(e, std::abs(x.p.norm() - 1.0));
  return e;
}

// (s) => (s.rigid_acceleration, s.lambda): what the joint coordinates imply,
// from the index-1 multipliers S lambda = B M^-1 F + quad.
static void set_multipliers(State& s) noexcept {
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s, c);
  factorize(c);
  Loads l;
  applied_loads(k, s, l);
  constraint_forces(c, l, stacked_phi(c), s);
}

static void reactions(const State& given, Reactions& r) noexcept {
  State s = given;
  set_multipliers(s);
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s, c);
  r[constraint::pin] = mbrt::joint_reaction(-(c.pin.rows.J2.transpose() * s.lambda.segment<5>(0)), k.pose[body::rod],
      k.pose[body::rod].r + k.pose[body::rod].R * pin_frame.s2, 1.0, kGroundPose, pin_frame);
}

static void outputs(const State& s, Outputs& y) noexcept {
  Kinematics k;
  kinematics(s, k);
  y[output::pin_angle] = mbrt::revolute_coordinate(pin_frame, mbrt::BodyMotion{kGroundPose, kGroundVelocity}, mbrt::BodyMotion{k.pose[body::rod], k.vel[body::rod]}).position;
}

};

}  // namespace

State initial_state() noexcept { return Model::initial_state(); }

mbrt::StepStatus step(State& s, Workspace& w) noexcept {
  return mbrt::schemes::tree_step<Model>(s, w);
}

mbrt::StepStatus step(State& s) noexcept {
  Workspace w;
  return step(s, w);
}

void refresh_bodies(State& s) noexcept {
  HalfAngles ha;
  Model::half_angles(s.q, ha);
  Model::body_states(s.q, ha, s.qd, s);
}

void set_multipliers(State& s) noexcept {
  Model::set_multipliers(s);
}

mbrt::Energy energy(const State& s) noexcept { return Model::energy(s); }

mbrt::ConstraintViolation constraint_violation(const State& s) noexcept { return Model::constraint_violation(s); }

double quaternion_norm_error(const State& s) noexcept { return Model::quaternion_norm_error(s); }

void reactions(const State& s, Reactions& r) noexcept { Model::reactions(s, r); }

void outputs(const State& s, Outputs& y) noexcept { Model::outputs(s, y); }

}  // namespace mbrt::models::armature_pendulum
