// mbrt generated model 'heavy_top': 1 bodies (1 rigid, 0 particles), 1 joints, 0 drivers, 3 constraint rows.
// Scheme staggered-pcst: the step is mbrt::schemes::staggered_step (include/mbrt/schemes/staggered.hpp)
// over Model, the model's types, constants and kernels below.
// Left out for this scene:
//   principal_axes: 1 principal-axis bodies: inertia products in M^-1 and the gyroscopic torques
//   single_stage: no velocity-dependent loads: the second implicit stage
//   folded_weights: gravity: the products m g, one constant weight per body
//   no_drivers: no drivers: the explicit time terms phi_t
// Kept: spatial coordinates, since gravity is not in the x-y plane; body top turns about an axis other than y; body top moves out of the y-z plane.
#include "heavy_top.hpp"

#include <algorithm>
#include <cmath>

#include <mbrt/reactions.hpp>
#include <mbrt/schemes/staggered.hpp>

namespace mbrt::models::heavy_top {

namespace {

constexpr double h = kStep;
constexpr double kRegularization = 4.3333333333333334e-10;  // added to diag(S)
constexpr double kNewtonShift = 4.3333333333333334e-10;  // added to diag(G)
constexpr double kStabilization = 10000.0;  // alpha, 1/s
const mbrt::Vec3 kGravity = mbrt::Vec3(0.0, 0.0, -9.8100000000000005);
const mbrt::BodyPose kGroundPose = mbrt::ground_pose();
const mbrt::BodyVelocity kGroundVelocity = mbrt::ground_velocity();

// Mass properties (constant; M is block diagonal).
const mbrt::PrincipalInertia top_mass{15.0, mbrt::Vec3(0.234375, 0.46875, 0.234375)};
const mbrt::Vec3 top_weight = mbrt::Vec3(0.0, 0.0, -147.15000000000001);

// Joint and driver frames in body axes; drivers' functions of time.
const mbrt::JointFrame tip_frame{mbrt::Vec3(0.0, 0.0, 0.0), mbrt::Vec3(0.0, -1.0, 0.0),
    mbrt::Vec3(0.0, 0.0, 1.0), mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec3(-1.0, 0.0, 0.0),
    mbrt::Vec3(0.0, 0.0, 1.0), mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec3(-1.0, 0.0, 0.0), 0.0, 0.0};

// Force elements in body axes.

// The model as the scheme's step (include/mbrt/schemes/) sees it: types,
// constants and kernels.
struct Model {
using State = mbrt::models::heavy_top::State;
using Workspace = mbrt::models::heavy_top::Workspace;
using Rows = detail::Rows;
using BodyVectors = detail::BodyVectors;
using Kinematics = detail::Kinematics;
using Loads = detail::Loads;
using ConstraintSystem = detail::ConstraintSystem;
using NewtonMatrix = detail::NewtonMatrix;
static constexpr mbrt::Scheme kScheme = mbrt::Scheme::staggered_pcst;
static constexpr double kStep = h;
static constexpr int kStages = 1;  // implicit passes per step
static constexpr bool kPositionStage = true;
static constexpr int kPositionIterations = 2;  // Newton steps of the position stage

static std::array<mbrt::BodyVelocity, kBodies> velocities_of(const State& s) noexcept {
  std::array<mbrt::BodyVelocity, kBodies> vel;
  vel[body::top] = mbrt::velocity_of(s.rigid[rigid::top]);
  return vel;
}

// (s) => (u): generalized velocities [v; w_body] per body.
static BodyVectors generalized_velocities(const State& s) noexcept {
  BodyVectors u;
  u[body::top] << s.rigid[rigid::top].v, s.rigid[rigid::top].w;
  return u;
}

// (u) => (s): write generalized velocities back.
static void set_velocities(const BodyVectors& u, State& s) noexcept {
  s.rigid[rigid::top].v = u[body::top].head<3>();
  s.rigid[rigid::top].w = u[body::top].tail<3>();
}

// (a) => (s): accelerations kept for the next step.
static void set_accelerations(const BodyVectors& a, State& s) noexcept {
  s.rigid_acceleration[rigid::top] = {a[body::top].head<3>(), a[body::top].tail<3>()};
}

static BodyVectors accelerations_of(const State& s) noexcept {
  BodyVectors a;
  a[body::top] << s.rigid_acceleration[rigid::top].a, s.rigid_acceleration[rigid::top].alpha;
  return a;
}

// (s) => (k): pose and velocity of every body.
static void kinematics(const State& s, Kinematics& k) noexcept {
  k.pose[body::top] = mbrt::pose_of(s.rigid[rigid::top]);
  k.vel = velocities_of(s);
}

// (k) => (l): applied forces (world) and torques (body axes) per body, and the elastic energy stored.
static void applied_loads([[maybe_unused]] const Kinematics& k, const State& s, Loads& l) noexcept {
  (void)s;
  l.w.fill(mbrt::Wrench{});
  l.elastic_energy = 0.0;
  l.w[body::top].f += top_weight;
}

// (k, s.t, s.params) => (c.*.rows): constraint values, Jacobians and acceleration terms.
static void constraint_rows(const Kinematics& k, [[maybe_unused]] const State& s, ConstraintSystem& c) noexcept {
  c.tip.rows = mbrt::spherical(tip_frame, mbrt::BodyMotion{kGroundPose, kGroundVelocity}, mbrt::BodyMotion{k.pose[body::top], k.vel[body::top]});
}

// (c.*.rows) => (c.*.mbt_*): M^-1 B^T, the directions constraint forces move the bodies in.
// 18 flops: 0 mul, 0 add, 18 div.
static void constraint_directions(ConstraintSystem& c) noexcept {
  c.tip.mbt_top = mbrt::inverse_mass_times_transpose(top_mass, c.tip.rows.J2);
}

// (c.*.rows) => (c.*.mbt_*, c.*.L*): M^-1 B^T, then S block by block in
// elimination order (0 fill blocks); false if a pivot is not positive.
// 134 flops: 58 mul, 52 add, 21 div, 3 sqrt.
static bool factorize(ConstraintSystem& c) noexcept {
  bool positive = true;
  constraint_directions(c);
  // tip
  c.tip.L = c.tip.rows.J2 * c.tip.mbt_top + kRegularization * Eigen::Matrix<double, 3, 3>::Identity();
  positive = mbrt::cholesky_in_place(c.tip.L) && positive;
  return positive;
}

// (c.*.L*, x) => (x): x := S^-1 x by forward and backward substitution.
// 18 flops: 6 mul, 6 add, 6 div.
static void solve(const ConstraintSystem& c, Rows& x) noexcept {
  {  // tip
    Eigen::Matrix<double, 3, 1> y = x.segment<3>(0);
    mbrt::solve_lower(c.tip.L, y);
    x.segment<3>(0) = y;
  }
  {  // tip
    Eigen::Matrix<double, 3, 1> y = x.segment<3>(0);
    mbrt::solve_lower_transposed(c.tip.L, y);
    x.segment<3>(0) = y;
  }
}

// (c, u) => (B u). 33 flops: 18 mul, 15 add.
static Rows jacobian_times(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  Rows y;
  y.segment<3>(0) = c.tip.rows.J2 * u[body::top];
  return y;
}

// (c, lambda) => (u): u -= scale M^-1 B^T lambda. 42 flops: 24 mul, 18 add.
static void subtract_constraint_forces(const ConstraintSystem& c, const Rows& lambda, double scale,
                                BodyVectors& u) noexcept {
  u[body::top] -= scale * (c.tip.mbt_top * lambda.segment<3>(0));
}

// (c) => (phi), (c) => (quad): stacked position residuals and acceleration terms.
static Rows stacked_phi(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<3>(0) = c.tip.rows.phi;
  return y;
}

static Rows stacked_quad(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<3>(0) = c.tip.rows.quad;
  return y;
}

// (c, u) => (phi_dot = B u + phi_t): velocity residuals.
static Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  return jacobian_times(c, u);  // no drivers: phi_t = 0
}

// (l) => (M^-1 F) per body.
static BodyVectors free_accelerations(const Loads& l) noexcept {
  BodyVectors a;
  a[body::top] = mbrt::inverse_mass_times(top_mass, l.w[body::top]);
  return a;
}

// (s, accelerations at t) => (s): half kick of the velocities (central
// difference, docs/staggered-pcst.md eq. 1).
static void kick(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) {
    s.rigid[b].v += (0.5 * h) * s.rigid_acceleration[b].a;
    s.rigid[b].w += (0.5 * h) * s.rigid_acceleration[b].alpha;
  }
  for (int b = 0; b < kParticles; ++b) s.particle[b].v += (0.5 * h) * s.particle_acceleration[b];
}

// (s) => (s): positions to t + h with the half-step velocities (eq. 2), and
// the Euler parameters (eq. 3): under staggered-pcst each body's torque-free
// rotation over h, which carries its gyroscopic torque (docs/stability.md).
static void drift(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) s.rigid[b].r += h * s.rigid[b].v;
  for (int b = 0; b < kParticles; ++b) s.particle[b].r += h * s.particle[b].v;
  mbrt::free_rotation(top_mass, s.rigid[rigid::top].p, s.rigid[rigid::top].w, h, kEulerUpdates);  // top
  s.t += h;
}

// (c0.*.mbt_*, c.*.rows) => (g): G block by block in S's elimination order.
// 160 flops: 77 mul, 71 add, 12 div.
static void factorize_newton(const ConstraintSystem& c0, const ConstraintSystem& c, NewtonMatrix& g) noexcept {
  // tip
  g.tip.D = c.tip.rows.J2 * c0.tip.mbt_top + kNewtonShift * Eigen::Matrix<double, 3, 3>::Identity();
  mbrt::invert_with_pivoting(g.tip.D);
}

// (g, x) => (x): x := G^-1 x by forward and backward substitution.
// 15 flops: 9 mul, 6 add.
static void solve_newton(const NewtonMatrix& g, Rows& x) noexcept {
  {  // tip
    Eigen::Matrix<double, 3, 1> y = x.segment<3>(0);
    x.segment<3>(0) = g.tip.D * y;
  }
}

// (c, l, phi, s) => (s.lambda, accelerations): multipliers of the stabilized
// companion equation (docs/staggered-pcst.md eq. 7)
//   (S + 2 eps/h I) lambda = B M^-1 F + quad + (2/h) (B u + alpha phi)
// which the next explicit stage applies: it steers phi at the next step to
// (1 - alpha h) phi. quad was evaluated at the predicted half-step velocity.
// (s) => (J^-1 (-w x J w)) per body: the gyroscopic accelerations, which the
// explicit stage's free rotation applies and the multipliers must balance.
static BodyVectors gyroscopic_accelerations(const State& s) noexcept {
  BodyVectors g;
  g[body::top] << mbrt::Vec3::Zero(), mbrt::inverse_inertia_times(top_mass, mbrt::gyroscopic_torque(top_mass, s.rigid[rigid::top].w));
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
  s.rigid[rigid::top] = {mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec4(1.0, 0.0, 0.0, 0.0),
      mbrt::Vec3(4.61538, 0.0, 0.0), mbrt::Vec3(0.0, 150.0, -4.61538)};
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
  e.kinetic += mbrt::kinetic_energy(top_mass, u[body::top]);
  e.potential -= top_mass.m * kGravity.dot(k.pose[body::top].r);
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
  r[constraint::tip] = mbrt::joint_reaction(-(c.tip.rows.J2.transpose() * s.lambda.segment<3>(0)), k.pose[body::top],
      k.pose[body::top].r + k.pose[body::top].R * tip_frame.s2, 1.0, kGroundPose, tip_frame);
}

};

}  // namespace

State initial_state() noexcept { return Model::initial_state(); }

mbrt::StepStatus step(State& s, Workspace& w) noexcept {
  return mbrt::schemes::staggered_step<Model>(s, w);
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

}  // namespace mbrt::models::heavy_top
