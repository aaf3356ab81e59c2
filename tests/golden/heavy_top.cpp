// mbrt generated model 'heavy_top': 1 bodies (1 rigid, 0 particles), 1 joints, 0 drivers, 3 constraint rows.
// Scheme staggered-pcst. Stage order per step: explicit_stage -> kinematics ->
// constraint_rows -> factorize -> (applied_loads -> implicit stage) x kStages.
// Left out for this scene:
//   principal_axes: 1 principal-axis bodies: inertia products in M^-1 and the gyroscopic torques
//   single_stage: no velocity-dependent loads: the second implicit stage
//   folded_weights: gravity: the products m g, one constant weight per body
//   no_drivers: no drivers: the explicit time terms phi_t
// Kept: spatial coordinates, since gravity is not in the x-y plane; body top turns about an axis other than y; body top moves out of the y-z plane.
#include "heavy_top.hpp"

#include <algorithm>
#include <cmath>

#include <mbrt/natural_partitioning.hpp>
#include <mbrt/reactions.hpp>
#include <mbrt/runtime.hpp>

namespace mbrt::models::heavy_top {

namespace {

constexpr double h = kStep;
constexpr int kStages = 1;  // implicit stages per step
constexpr double kRegularization = 4.3333333333333334e-10;  // added to diag(S)
constexpr int kPositionIterations = 2;  // Newton steps of the position stage
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

using Rows = Eigen::Matrix<double, kConstraintRows, 1>;
using BodyVectors = std::array<mbrt::Vec6, kBodies>;  // [v; w_body] per body

struct Kinematics {
  std::array<mbrt::BodyPose, kBodies> pose;
  std::array<mbrt::BodyVelocity, kBodies> vel;
};

struct Loads {
  std::array<mbrt::Wrench, kBodies> w;
  double elastic_energy;
};

// Constraint rows, M^-1 B^T blocks and the block Cholesky factor of
// S = B M^-1 B^T + kRegularization I over the model's fixed pattern.
struct ConstraintSystem {
  mbrt::ConstraintRows<3> rows_tip;  // spherical ground - top, rows 0..2
  Eigen::Matrix<double, 6, 3> mbt_0_0;  // M^-1 B^T: tip, top
  Eigen::Matrix<double, 3, 3> L_0_0;  // tip
};

std::array<mbrt::BodyVelocity, kBodies> velocities_of(const State& s) noexcept {
  std::array<mbrt::BodyVelocity, kBodies> vel;
  vel[0] = mbrt::velocity_of(s.rigid[0]);
  return vel;
}

// (s) => (u): generalized velocities [v; w_body] per body.
BodyVectors generalized_velocities(const State& s) noexcept {
  BodyVectors u;
  u[0] << s.rigid[0].v, s.rigid[0].w;
  return u;
}

// (u) => (s): write generalized velocities back.
void set_velocities(const BodyVectors& u, State& s) noexcept {
  s.rigid[0].v = u[0].head<3>();
  s.rigid[0].w = u[0].tail<3>();
}

// (a) => (s): accelerations kept for the next step.
void set_accelerations(const BodyVectors& a, State& s) noexcept {
  s.rigid_acceleration[0] = {a[0].head<3>(), a[0].tail<3>()};
}

BodyVectors accelerations_of(const State& s) noexcept {
  BodyVectors a;
  a[0] << s.rigid_acceleration[0].a, s.rigid_acceleration[0].alpha;
  return a;
}

// (s) => (k): pose and velocity of every body.
void kinematics(const State& s, Kinematics& k) noexcept {
  k.pose[0] = mbrt::pose_of(s.rigid[0]);  // top
  k.vel = velocities_of(s);
}

// (k) => (l): applied forces (world) and torques (body axes) per body,
// included, and the elastic energy stored.
void applied_loads(const Kinematics& k, Loads& l) noexcept {
  l.w.fill(mbrt::Wrench{});
  l.elastic_energy = 0.0;
  l.w[0].f += top_weight;
}

// (k, t) => (c.rows_*): constraint values, Jacobians and acceleration terms.
void constraint_rows(const Kinematics& k, double t, ConstraintSystem& c) noexcept {
  (void)t;
  c.rows_tip = mbrt::spherical(tip_frame, mbrt::BodyMotion{kGroundPose, kGroundVelocity}, mbrt::BodyMotion{k.pose[0], k.vel[0]});
}

// (c.rows_*) => (c.mbt_*): M^-1 B^T, the directions constraint forces move the bodies in.
void constraint_directions(ConstraintSystem& c) noexcept {
  c.mbt_0_0 = mbrt::inverse_mass_times_transpose(top_mass, c.rows_tip.J2);
}

// (c.rows_*) => (c.mbt_*, c.L_*): M^-1 B^T, then S block by block in
// elimination order (0 fill blocks); false if a pivot is not positive.
bool factorize(ConstraintSystem& c) noexcept {
  bool positive = true;
  constraint_directions(c);
  // tip
  c.L_0_0 = c.rows_tip.J2 * c.mbt_0_0 + kRegularization * Eigen::Matrix<double, 3, 3>::Identity();
  positive = mbrt::cholesky_in_place(c.L_0_0) && positive;
  return positive;
}

// (c.L_*, x) => (x): x := S^-1 x by forward and backward substitution.
void solve(const ConstraintSystem& c, Rows& x) noexcept {
  {  // tip
    Eigen::Matrix<double, 3, 1> y = x.segment<3>(0);
    mbrt::solve_lower(c.L_0_0, y);
    x.segment<3>(0) = y;
  }
  {  // tip
    Eigen::Matrix<double, 3, 1> y = x.segment<3>(0);
    mbrt::solve_lower_transposed(c.L_0_0, y);
    x.segment<3>(0) = y;
  }
}

// (c, u) => (B u)
Rows jacobian_times(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  Rows y;
  y.segment<3>(0) = c.rows_tip.J2 * u[0];
  return y;
}

// (c, lambda) => (u): u -= scale M^-1 B^T lambda
void subtract_constraint_forces(const ConstraintSystem& c, const Rows& lambda, double scale,
                                BodyVectors& u) noexcept {
  u[0] -= scale * (c.mbt_0_0 * lambda.segment<3>(0));
}

// (c) => (phi), (c) => (quad): stacked position residuals and acceleration terms.
Rows stacked_phi(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<3>(0) = c.rows_tip.phi;
  return y;
}

Rows stacked_quad(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<3>(0) = c.rows_tip.quad;
  return y;
}

// (c, u) => (phi_dot = B u + phi_t): velocity residuals.
Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  return jacobian_times(c, u);  // no drivers: phi_t = 0
}

// (l) => (M^-1 F) per body.
BodyVectors free_accelerations(const Loads& l) noexcept {
  BodyVectors a;
  a[0] = mbrt::inverse_mass_times(top_mass, l.w[0]);
  return a;
}

// (s, accelerations at t) => (s): half kick of the velocities (central
// difference, docs/staggered-pcst.md eq. 1).
void kick(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) {
    s.rigid[b].v += (0.5 * h) * s.rigid_acceleration[b].a;
    s.rigid[b].w += (0.5 * h) * s.rigid_acceleration[b].alpha;
  }
  for (int b = 0; b < kParticles; ++b) s.particle[b].v += (0.5 * h) * s.particle_acceleration[b];
}

// (s) => (s): positions to t + h with the half-step velocities (eq. 2), and
// the Euler parameters (eq. 3): under staggered-pcst each body's torque-free
// rotation over h, which carries its gyroscopic torque (docs/stability.md).
void drift(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) s.rigid[b].r += h * s.rigid[b].v;
  for (int b = 0; b < kParticles; ++b) s.particle[b].r += h * s.particle[b].v;
  mbrt::free_rotation(top_mass, s.rigid[0].p, s.rigid[0].w, h, kEulerUpdates);
  s.t += h;
}

// (from) => (s): positions and time of another state.
void set_positions(const State& from, State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) {
    s.rigid[b].r = from.rigid[b].r;
    s.rigid[b].p = from.rigid[b].p;
  }
  for (int b = 0; b < kParticles; ++b) s.particle[b].r = from.particle[b].r;
  s.t = from.t;
}

// Block LU factors of the position stage's Newton matrix G = B(q*) M^-1 B(q(t))^T:
// G = L U with unit-diagonal L, U's diagonal blocks kept inverted.
struct NewtonMatrix {
  Eigen::Matrix<double, 3, 3> D_0;  // tip, inverted
};

// (c0.mbt_*, c.rows_*) => (g): G block by block in S's elimination order.
void factorize_newton(const ConstraintSystem& c0, const ConstraintSystem& c, NewtonMatrix& g) noexcept {
  // tip
  g.D_0 = c.rows_tip.J2 * c0.mbt_0_0 + kNewtonShift * Eigen::Matrix<double, 3, 3>::Identity();
  g.D_0 = g.D_0.partialPivLu().inverse();
}

// (g, x) => (x): x := G^-1 x by forward and backward substitution.
void solve_newton(const NewtonMatrix& g, Rows& x) noexcept {
  {  // tip
    Eigen::Matrix<double, 3, 1> y = x.segment<3>(0);
    x.segment<3>(0) = g.D_0 * y;
  }
}

// (c0, c, u_kick, last_good) => (s, k, c.rows_*): the position stage. The
// first half kick's constraint forces act along M^-1 B(q(t))^T; their
// multipliers are corrected so that the drift lands on Phi(q(t + h)) = 0
// (RATTLE's position step: Andersen 1983, "Rattle: a velocity version of the
// Shake algorithm", J. Comput. Phys. 52, eqs. 2.6-2.9), by Newton steps with
// the matrix G = B(q*) M^-1 B(q(t))^T of the first drift q*. Correcting along
// B(q(t))^T rather than B(q(t + h))^T is what keeps the energy of
// fast-turning bodies bounded (docs/stability.md).
void position_stage(const ConstraintSystem& c0, ConstraintSystem& c, BodyVectors& u_kick, const State& last_good,
                    Kinematics& k, State& s) noexcept {
  NewtonMatrix g;
  factorize_newton(c0, c, g);
  for (int i = 0; i < kPositionIterations; ++i) {
    Rows x = stacked_phi(c);
    Rows y = x;
    solve_newton(g, x);
    // G is close to singular where a long chain turns by more than its softest
    // modes allow; a Newton step larger than S(q*)'s is then not trusted.
    solve(c, y);
    if (!(x.squaredNorm() <= 4.0 * y.squaredNorm())) x = y;
    subtract_constraint_forces(c0, x, 1.0 / h, u_kick);
    set_positions(last_good, s);
    set_velocities(u_kick, s);
    drift(s);
    kinematics(s, k);
    if (i + 1 < kPositionIterations) constraint_rows(k, s.t, c);
  }
}

// (c, l, u_half) => (u): implicit stage. The end-of-step velocities satisfy
// the velocity constraints, regularized by the penalty eps (eq. 5):
//   (h/2) (S + 2 eps/h I) mu = B u_hat,  u = u_hat - h/2 M^-1 B^T mu.
void implicit_stage(const ConstraintSystem& c, const Loads& l, const BodyVectors& u_half, BodyVectors& u) noexcept {
  const BodyVectors a_free = free_accelerations(l);
  for (int b = 0; b < kBodies; ++b) u[b] = u_half[b] + (0.5 * h) * a_free[b];
  Rows mu = (2.0 / h) * velocity_residual(c, u);
  solve(c, mu);
  subtract_constraint_forces(c, mu, 0.5 * h, u);
}

// (c, l, phi, s) => (s.lambda, accelerations): multipliers of the stabilized
// companion equation (eq. 7)
//   (S + 2 eps/h I) lambda = B M^-1 F + quad + (2/h) (B u + alpha phi)
// which the next explicit stage applies: it steers phi at the next step to
// (1 - alpha h) phi. quad was evaluated at the predicted half-step velocity.
// (s) => (J^-1 (-w x J w)) per body: the gyroscopic accelerations, which the
// explicit stage's free rotation applies and the multipliers must balance.
BodyVectors gyroscopic_accelerations(const State& s) noexcept {
  BodyVectors g;
  g[0] << mbrt::Vec3::Zero(), mbrt::inverse_inertia_times(top_mass, mbrt::gyroscopic_torque(top_mass, s.rigid[0].w));  // top
  return g;
}

void constraint_forces(const ConstraintSystem& c, const Loads& l, const Rows& phi, State& s) noexcept {
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

bool finite(const State& s) noexcept {
  bool ok = std::isfinite(s.lambda.sum());
  for (const mbrt::RigidState& x : s.rigid) {
    ok = ok && mbrt::all_finite(x.r) && mbrt::all_finite(x.p) && mbrt::all_finite(x.v) && mbrt::all_finite(x.w);
  }
  for (const mbrt::ParticleState& x : s.particle) ok = ok && mbrt::all_finite(x.r) && mbrt::all_finite(x.v);
  return ok;
}

}  // namespace

State initial_state() noexcept {
  State s;
  s.rigid[0] = {mbrt::Vec3(0.0, 1.0, 0.0), mbrt::Vec4(1.0, 0.0, 0.0, 0.0),
      mbrt::Vec3(4.61538, 0.0, 0.0), mbrt::Vec3(0.0, 150.0, -4.61538)};  // top
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s.t, c);
  factorize(c);
  Loads l;
  applied_loads(k, l);
  constraint_forces(c, l, stacked_phi(c), s);
  return s;
}

mbrt::StepStatus step(State& s) noexcept {
  const State last_good = s;
  const BodyVectors a_old = accelerations_of(s);
  // Directions of the first half kick's constraint forces, at q(t).
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c0;
  constraint_rows(k, s.t, c0);
  constraint_directions(c0);
  kick(s);
  BodyVectors u_kick = generalized_velocities(s);
  drift(s);

  // Constraint terms at the drifted positions, factorized once per step; the
  // position stage moves the positions onto the constraints and keeps the factor.
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s.t, c);
  bool positive = factorize(c);
  position_stage(c0, c, u_kick, last_good, k, s);
  const BodyVectors u_half = generalized_velocities(s);

  // Constraint terms at the new positions. The quadratic terms are taken at
  // the predicted next half-step velocity u_half + h a_old, which the next
  // explicit stage will drift with.
  BodyVectors u = u_half;
  for (int b = 0; b < kBodies; ++b) u[b] += h * a_old[b];
  set_velocities(u, s);
  k.vel = velocities_of(s);
  constraint_rows(k, s.t, c);
  constraint_directions(c);  // the factor stays that of the first drift

  // Implicit stages: the first evaluates velocity-dependent loads at the
  // predicted end-of-step velocities u_half + h/2 a_old, the next ones at the
  // last result.
  for (int b = 0; b < kBodies; ++b) u[b] = u_half[b] + (0.5 * h) * a_old[b];
  Loads l;
  for (int stage = 0; stage < kStages; ++stage) {
    set_velocities(u, s);
    k.vel = velocities_of(s);
    applied_loads(k, l);
    implicit_stage(c, l, u_half, u);
  }
  set_velocities(u, s);
  constraint_forces(c, l, stacked_phi(c), s);

  if (!finite(s)) {
    s = last_good;
    return mbrt::StepStatus::non_finite;
  }
  if (!positive) {
    s = last_good;
    return mbrt::StepStatus::not_positive;
  }
  return mbrt::StepStatus::ok;
}

mbrt::Energy energy(const State& s) noexcept {
  Kinematics k;
  kinematics(s, k);
  Loads l;
  applied_loads(k, l);
  const BodyVectors u = generalized_velocities(s);
  mbrt::Energy e{0.0, l.elastic_energy};
  e.kinetic += mbrt::kinetic_energy(top_mass, u[0]);
  e.potential -= top_mass.m * kGravity.dot(k.pose[0].r);
  return e;
}

mbrt::ConstraintViolation constraint_violation(const State& s) noexcept {
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

double quaternion_norm_error(const State& s) noexcept {
  double e = 0.0;
  for (const mbrt::RigidState& x : s.rigid) e = std::max(e, std::abs(x.p.norm() - 1.0));
  return e;
}

void reactions(const State& s, Reactions& r) noexcept {
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s.t, c);
  r[0] = mbrt::joint_reaction(-(c.rows_tip.J2.transpose() * s.lambda.segment<3>(0)), k.pose[0],
      k.pose[0].r + k.pose[0].R * tip_frame.s2, 1.0, kGroundPose, tip_frame);  // tip
}

}  // namespace mbrt::models::heavy_top
