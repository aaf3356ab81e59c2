// mbrt generated model 'a01_pendulum': 1 bodies (0 rigid, 1 particles), 1 joints, 0 drivers, 1 constraint rows.
// Scheme staggered-pcst: the step is mbrt::schemes::staggered_step (include/mbrt/schemes/staggered.hpp)
// over planar::Model, the model's types, constants and kernels below.
// Left out for this scene:
//   particles: 1 particle(s): no rotational state (the model's contract, also without specializations)
//   single_stage: no velocity-dependent loads: the second implicit stage
//   folded_weights: gravity: the products m g, one constant weight per body
//   no_drivers: no drivers: the explicit time terms phi_t
//   planar: motion in the x-y plane: two coordinates and the angle about z per body, 1 of 1 constraint rows (the in-plane ones)
#include "a01_pendulum.hpp"

#include <algorithm>
#include <cmath>

#include <mbrt/reactions.hpp>
#include <mbrt/schemes/staggered.hpp>

namespace mbrt::models::a01_pendulum {

namespace {

constexpr double h = kStep;
constexpr double kRegularization = 1e-10;  // added to diag(S)
constexpr double kNewtonShift = 1e-10;  // added to diag(G)
constexpr double kStabilization = 2000.0;  // alpha, 1/s
const mbrt::Vec3 kGravity = mbrt::Vec3(0.0, -9.8100000000000005, 0.0);
const mbrt::BodyPose kGroundPose = mbrt::ground_pose();
const mbrt::BodyVelocity kGroundVelocity = mbrt::ground_velocity();

// Mass properties (constant; M is block diagonal).
constexpr mbrt::PointMass bob_mass{1.0};
const mbrt::Vec3 bob_weight = mbrt::Vec3(0.0, -9.8100000000000005, 0.0);

// Joint and driver frames in body axes; drivers' functions of time.
const mbrt::JointFrame bar_frame{mbrt::Vec3(0.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0),
    mbrt::Vec3(0.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0),
    mbrt::Vec3(0.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0), 1.0, 0.0};

// Force elements in body axes.

// The model as the scheme's step (include/mbrt/schemes/) sees it: types,
// constants and kernels.
struct Model {
using State = mbrt::models::a01_pendulum::State;
using Rows = detail::Rows;
using BodyVectors = detail::BodyVectors;
using Kinematics = detail::Kinematics;
using Loads = detail::Loads;
using ConstraintSystem = detail::ConstraintSystem;
// The spatial kernels serve initial_state() and the diagnostics.

static std::array<mbrt::BodyVelocity, kBodies> velocities_of(const State& s) noexcept {
  std::array<mbrt::BodyVelocity, kBodies> vel;
  vel[body::bob] = mbrt::velocity_of(s.particle[particle::bob]);
  return vel;
}

// (s) => (u): generalized velocities [v; w_body] per body.
static BodyVectors generalized_velocities(const State& s) noexcept {
  BodyVectors u;
  u[body::bob] << s.particle[particle::bob].v, mbrt::Vec3::Zero();
  return u;
}

// (a) => (s): accelerations kept for the next step.
static void set_accelerations(const BodyVectors& a, State& s) noexcept {
  s.particle_acceleration[particle::bob] = a[body::bob].head<3>();
}

static BodyVectors accelerations_of(const State& s) noexcept {
  BodyVectors a;
  a[body::bob] << s.particle_acceleration[particle::bob], mbrt::Vec3::Zero();
  return a;
}

// (s) => (k): pose and velocity of every body.
static void kinematics(const State& s, Kinematics& k) noexcept {
  k.pose[body::bob] = mbrt::pose_of(s.particle[particle::bob]);
  k.vel = velocities_of(s);
}

// (k) => (l): applied forces (world) and torques (body axes) per body, and the elastic energy stored.
static void applied_loads([[maybe_unused]] const Kinematics& k, const State& s, Loads& l) noexcept {
  (void)s;
  l.w.fill(mbrt::Wrench{});
  l.elastic_energy = 0.0;
  l.w[body::bob].f += bob_weight;
}

// (k, s.t, s.params) => (c.*.rows): constraint values, Jacobians and acceleration terms.
static void constraint_rows(const Kinematics& k, [[maybe_unused]] const State& s, ConstraintSystem& c) noexcept {
  c.bar.rows = mbrt::distance(bar_frame, mbrt::BodyMotion{kGroundPose, kGroundVelocity}, mbrt::BodyMotion{k.pose[body::bob], k.vel[body::bob]});
}

// (c.*.rows) => (c.*.mbt_*): M^-1 B^T, the directions constraint forces move the bodies in.
// 3 flops: 0 mul, 0 add, 3 div.
static void constraint_directions(ConstraintSystem& c) noexcept {
  c.bar.mbt_bob = mbrt::inverse_mass_times_transpose(bob_mass, c.bar.rows.J2);
}

// (c.*.rows) => (c.*.mbt_*, c.*.L*): M^-1 B^T, then S block by block in
// elimination order (0 fill blocks); false if a pivot is not positive.
// 16 flops: 6 mul, 6 add, 3 div, 1 sqrt.
static bool factorize(ConstraintSystem& c) noexcept {
  bool positive = true;
  constraint_directions(c);
  // bar
  c.bar.L = c.bar.rows.J2 * c.bar.mbt_bob + kRegularization * Eigen::Matrix<double, 1, 1>::Identity();
  positive = mbrt::cholesky_in_place(c.bar.L) && positive;
  return positive;
}

// (c.*.L*, x) => (x): x := S^-1 x by forward and backward substitution.
// 2 flops: 0 mul, 0 add, 2 div.
static void solve(const ConstraintSystem& c, Rows& x) noexcept {
  {  // bar
    Eigen::Matrix<double, 1, 1> y = x.segment<1>(0);
    mbrt::solve_lower(c.bar.L, y);
    x.segment<1>(0) = y;
  }
  {  // bar
    Eigen::Matrix<double, 1, 1> y = x.segment<1>(0);
    mbrt::solve_lower_transposed(c.bar.L, y);
    x.segment<1>(0) = y;
  }
}

// (c, u) => (B u). 11 flops: 6 mul, 5 add.
static Rows jacobian_times(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  Rows y;
  y.segment<1>(0) = c.bar.rows.J2 * u[body::bob];
  return y;
}

// (c, lambda) => (u): u -= scale M^-1 B^T lambda. 18 flops: 12 mul, 6 add.
static void subtract_constraint_forces(const ConstraintSystem& c, const Rows& lambda, double scale,
                                BodyVectors& u) noexcept {
  u[body::bob] -= scale * (c.bar.mbt_bob * lambda.segment<1>(0));
}

// (c) => (phi), (c) => (quad): stacked position residuals and acceleration terms.
static Rows stacked_phi(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<1>(0) = c.bar.rows.phi;
  return y;
}

static Rows stacked_quad(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<1>(0) = c.bar.rows.quad;
  return y;
}

// (c, u) => (phi_dot = B u + phi_t): velocity residuals.
static Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  return jacobian_times(c, u);  // no drivers: phi_t = 0
}

// (l) => (M^-1 F) per body.
static BodyVectors free_accelerations(const Loads& l) noexcept {
  BodyVectors a;
  a[body::bob] = mbrt::inverse_mass_times(bob_mass, l.w[body::bob]);
  return a;
}

static void constraint_forces(const ConstraintSystem& c, const Loads& l, const Rows& phi, State& s) noexcept {
  BodyVectors a = free_accelerations(l);
  s.lambda = jacobian_times(c, a) + stacked_quad(c) +
             (2.0 / h) * (velocity_residual(c, generalized_velocities(s)) + kStabilization * phi);
  solve(c, s.lambda);
  subtract_constraint_forces(c, s.lambda, 1.0, a);
  set_accelerations(a, s);
}

static State initial_state() noexcept {
  State s;
  s.particle[particle::bob] = {mbrt::Vec3(-1.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0)};
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
  e.kinetic += mbrt::kinetic_energy(bob_mass, u[body::bob]);
  e.potential -= bob_mass.m * kGravity.dot(k.pose[body::bob].r);
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
  r[constraint::bar] = mbrt::joint_reaction(-(c.bar.rows.J2.transpose() * s.lambda.segment<1>(0)), k.pose[body::bob],
      k.pose[body::bob].r + k.pose[body::bob].R * bar_frame.s2, 1.0, kGroundPose, bar_frame);
}

};

// The step in planar coordinates: motion in one plane, per body two
// coordinates and the rotation about the normal, the in-plane constraint rows only.
namespace planar {

constexpr int kNormal = 2;  // the plane x-y, normal to world z
constexpr double kNewtonShift = 1e-10;  // added to diag(G)
const mbrt::PlanarPose kGroundPose = mbrt::planar_ground_pose();
const mbrt::PlanarVelocity kGroundVelocity = mbrt::planar_ground_velocity();

// Masses and the moments of inertia about the normal (particles keep their PointMass).
const mbrt::Vec2 bob_weight(0.0, -9.8100000000000005);

// The model as the scheme's step (include/mbrt/schemes/) sees it: types,
// constants and kernels.
struct Model {
using State = mbrt::models::a01_pendulum::State;
using Workspace = mbrt::models::a01_pendulum::Workspace;
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
  vel[body::bob] = mbrt::planar_velocity_of<kNormal>(s.particle[particle::bob]);
  return vel;
}

// (s) => (u): (vx, vy, omega_z) per body.
static BodyVectors generalized_velocities(const State& s) noexcept {
  BodyVectors u;
  u[body::bob] = mbrt::planar_velocities<kNormal>(s.particle[particle::bob]);
  return u;
}

// (u) => (s): the in-plane velocities; the others stay zero.
static void set_velocities(const BodyVectors& u, State& s) noexcept {
  mbrt::set_planar_velocities<kNormal>(u[body::bob], s.particle[particle::bob]);
}

// (a) => (s): accelerations kept for the next step.
static void set_accelerations(const BodyVectors& a, State& s) noexcept {
  mbrt::set_planar_accelerations<kNormal>(a[body::bob], s.particle_acceleration[particle::bob]);
}

static BodyVectors accelerations_of(const State& s) noexcept {
  BodyVectors a;
  a[body::bob] = mbrt::planar_accelerations<kNormal>(s.particle_acceleration[particle::bob]);
  return a;
}

// (s) => (k): pose and velocity of every body.
static void kinematics(const State& s, Kinematics& k) noexcept {
  k.pose[body::bob] = mbrt::planar_pose_of<kNormal>(s.particle[particle::bob]);
  k.vel = velocities_of(s);
}

// (k) => (l): applied forces (world) and torques (body axes) per body, and the elastic energy stored.
static void applied_loads([[maybe_unused]] const Kinematics& k, const State& s, Loads& l) noexcept {
  (void)s;
  l.w.fill(mbrt::PlanarWrench{});
  l.elastic_energy = 0.0;
  l.w[body::bob].f += bob_weight;
}

// (k, s.t, s.params) => (c.*.rows): constraint values, Jacobians and acceleration terms.
static void constraint_rows(const Kinematics& k, [[maybe_unused]] const State& s, ConstraintSystem& c) noexcept {
  c.bar.rows = mbrt::planar_distance(bar_frame, mbrt::PlanarMotion{kGroundPose, kGroundVelocity}, mbrt::PlanarMotion{k.pose[body::bob], k.vel[body::bob]});
}

// (c.*.rows) => (c.*.mbt_*): M^-1 B^T, the directions constraint forces move the bodies in.
// 2 flops: 0 mul, 0 add, 2 div.
static void constraint_directions(ConstraintSystem& c) noexcept {
  c.bar.mbt_bob = mbrt::inverse_mass_times_transpose(bob_mass, c.bar.rows.J2);
}

// (c.*.rows) => (c.*.mbt_*, c.*.L*): M^-1 B^T, then S block by block in
// elimination order (0 fill blocks); false if a pivot is not positive.
// 9 flops: 3 mul, 3 add, 2 div, 1 sqrt.
static bool factorize(ConstraintSystem& c) noexcept {
  bool positive = true;
  constraint_directions(c);
  // bar
  c.bar.L = c.bar.rows.J2 * c.bar.mbt_bob + kRegularization * Eigen::Matrix<double, 1, 1>::Identity();
  positive = mbrt::cholesky_in_place(c.bar.L) && positive;
  return positive;
}

// (c.*.L*, x) => (x): x := S^-1 x by forward and backward substitution.
// 2 flops: 0 mul, 0 add, 2 div.
static void solve(const ConstraintSystem& c, Rows& x) noexcept {
  {  // bar
    Eigen::Matrix<double, 1, 1> y = x.segment<1>(0);
    mbrt::solve_lower(c.bar.L, y);
    x.segment<1>(0) = y;
  }
  {  // bar
    Eigen::Matrix<double, 1, 1> y = x.segment<1>(0);
    mbrt::solve_lower_transposed(c.bar.L, y);
    x.segment<1>(0) = y;
  }
}

// (c, u) => (B u). 5 flops: 3 mul, 2 add.
static Rows jacobian_times(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  Rows y;
  y.segment<1>(0) = c.bar.rows.J2 * u[body::bob];
  return y;
}

// (c, lambda) => (u): u -= scale M^-1 B^T lambda. 9 flops: 6 mul, 3 add.
static void subtract_constraint_forces(const ConstraintSystem& c, const Rows& lambda, double scale,
                                BodyVectors& u) noexcept {
  u[body::bob] -= scale * (c.bar.mbt_bob * lambda.segment<1>(0));
}

// (c) => (phi), (c) => (quad): stacked position residuals and acceleration terms.
static Rows stacked_phi(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<1>(0) = c.bar.rows.phi;
  return y;
}

static Rows stacked_quad(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<1>(0) = c.bar.rows.quad;
  return y;
}

// (c, u) => (phi_dot = B u + phi_t): velocity residuals.
static Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  return jacobian_times(c, u);  // no drivers: phi_t = 0
}

// (l) => (M^-1 F) per body.
static BodyVectors free_accelerations(const Loads& l) noexcept {
  BodyVectors a;
  a[body::bob] = mbrt::inverse_mass_times(bob_mass, l.w[body::bob]);
  return a;
}

// (lambda) => (s.lambda): the in-plane rows of every spatial block.
static void store_multipliers(const Rows& lambda, State& s) noexcept {
  s.lambda.segment<1>(0) = lambda.segment<1>(0);  // bar
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
// 7 flops: 3 mul, 3 add, 1 div.
static void factorize_newton(const ConstraintSystem& c0, const ConstraintSystem& c, NewtonMatrix& g) noexcept {
  // bar
  g.bar.D = c.bar.rows.J2 * c0.bar.mbt_bob + kNewtonShift * Eigen::Matrix<double, 1, 1>::Identity();
  mbrt::invert_with_pivoting(g.bar.D);
}

// (g, x) => (x): x := G^-1 x by forward and backward substitution.
// 1 flops: 1 mul, 0 add.
static void solve_newton(const NewtonMatrix& g, Rows& x) noexcept {
  {  // bar
    Eigen::Matrix<double, 1, 1> y = x.segment<1>(0);
    x.segment<1>(0) = g.bar.D * y;
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

}  // namespace mbrt::models::a01_pendulum
