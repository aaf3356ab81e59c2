// mbrt generated model 'a01_pendulum': 1 bodies (0 rigid, 1 particles), 1 joints, 1 constraint rows.
// Scheme staggered-pcst. Stage order per step: explicit_stage -> kinematics ->
// constraint_rows -> factorize -> (applied_loads -> implicit stage) x kStages.
// Left out for this scene:
//   1 particle(s): no rotational state
//   no velocity-dependent forces: one stage per step
#include "a01_pendulum.hpp"

#include <algorithm>
#include <cmath>

#include <mbrt/runtime.hpp>

namespace mbrt::models::a01_pendulum {

namespace {

constexpr double h = kStep;
constexpr int kStages = 1;  // implicit stages per step
constexpr double kRegularization = 1e-10;  // added to diag(S)
constexpr double kStabilization = 4000.0;  // alpha, 1/s
const mbrt::Vec3 kGravity = mbrt::Vec3(0.0, -9.8100000000000005, 0.0);
const mbrt::BodyPose kGroundPose = mbrt::ground_pose();
const mbrt::BodyVelocity kGroundVelocity = mbrt::ground_velocity();

// Mass properties (constant; M is block diagonal).
constexpr mbrt::PointMass bob_mass{1.0};

// Joint frames in body axes.
const mbrt::JointFrame bar_frame{mbrt::Vec3(0.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0),
    mbrt::Vec3(0.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0),
    mbrt::Vec3(0.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0), 1.0};

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
  mbrt::ConstraintRows<1> rows_bar;  // distance ground - bob, rows 0..0
  Eigen::Matrix<double, 6, 1> mbt_0_0;  // M^-1 B^T: bar, bob
  Eigen::Matrix<double, 1, 1> L_0_0;  // bar
};

std::array<mbrt::BodyVelocity, kBodies> velocities_of(const State& s) noexcept {
  std::array<mbrt::BodyVelocity, kBodies> vel;
  vel[0] = mbrt::velocity_of(s.particle[0]);
  return vel;
}

// (s) => (u): generalized velocities [v; w_body] per body.
BodyVectors generalized_velocities(const State& s) noexcept {
  BodyVectors u;
  u[0] << s.particle[0].v, mbrt::Vec3::Zero();
  return u;
}

// (u) => (s): write generalized velocities back.
void set_velocities(const BodyVectors& u, State& s) noexcept {
  s.particle[0].v = u[0].head<3>();
}

// (a) => (s): accelerations kept for the next step.
void set_accelerations(const BodyVectors& a, State& s) noexcept {
  s.particle_acceleration[0] = a[0].head<3>();
}

BodyVectors accelerations_of(const State& s) noexcept {
  BodyVectors a;
  a[0] << s.particle_acceleration[0], mbrt::Vec3::Zero();
  return a;
}

// (s) => (k): pose and velocity of every body.
void kinematics(const State& s, Kinematics& k) noexcept {
  k.pose[0] = mbrt::pose_of(s.particle[0]);  // bob
  k.vel = velocities_of(s);
}

// (k) => (l): applied forces (world) and torques (body axes) per body,
// gyroscopic torques included, and the elastic energy stored.
void applied_loads(const Kinematics& k, Loads& l) noexcept {
  l.w.fill(mbrt::Wrench{});
  l.elastic_energy = 0.0;
  l.w[0].f += bob_mass.m * kGravity;
}

// (k) => (c.rows_*): constraint values, Jacobians and quadratic terms.
void constraint_rows(const Kinematics& k, ConstraintSystem& c) noexcept {
  c.rows_bar = mbrt::distance(bar_frame, mbrt::BodyMotion{kGroundPose, kGroundVelocity}, mbrt::BodyMotion{k.pose[0], k.vel[0]});
}

// (c.rows_*) => (c.mbt_*, c.L_*): M^-1 B^T, then S block by block in
// elimination order (0 fill blocks); false if a pivot is not positive.
bool factorize(ConstraintSystem& c) noexcept {
  bool positive = true;
  c.mbt_0_0 = mbrt::inverse_mass_times_transpose(bob_mass, c.rows_bar.J2);
  // bar
  c.L_0_0 = c.rows_bar.J2 * c.mbt_0_0 + kRegularization * Eigen::Matrix<double, 1, 1>::Identity();
  positive = mbrt::cholesky_in_place(c.L_0_0) && positive;
  return positive;
}

// (c.L_*, x) => (x): x := S^-1 x by forward and backward substitution.
void solve(const ConstraintSystem& c, Rows& x) noexcept {
  {  // bar
    Eigen::Matrix<double, 1, 1> y = x.segment<1>(0);
    mbrt::solve_lower(c.L_0_0, y);
    x.segment<1>(0) = y;
  }
  {  // bar
    Eigen::Matrix<double, 1, 1> y = x.segment<1>(0);
    mbrt::solve_lower_transposed(c.L_0_0, y);
    x.segment<1>(0) = y;
  }
}

// (c, u) => (B u)
Rows jacobian_times(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  Rows y;
  y.segment<1>(0) = c.rows_bar.J2 * u[0];
  return y;
}

// (c, lambda) => (u): u -= scale M^-1 B^T lambda
void subtract_constraint_forces(const ConstraintSystem& c, const Rows& lambda, double scale,
                                BodyVectors& u) noexcept {
  u[0] -= scale * (c.mbt_0_0 * lambda.segment<1>(0));
}

// (c) => (phi), (c) => (quad): stacked position residuals and quadratic terms.
Rows stacked_phi(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<1>(0) = c.rows_bar.phi;
  return y;
}

Rows stacked_quad(const ConstraintSystem& c) noexcept {
  Rows y;
  y.segment<1>(0) = c.rows_bar.quad;
  return y;
}

// (l) => (M^-1 F) per body.
BodyVectors free_accelerations(const Loads& l) noexcept {
  BodyVectors a;
  a[0] = mbrt::inverse_mass_times(bob_mass, l.w[0]);
  return a;
}

// (s, accelerations at t) => (s): explicit stage, central difference.
// Half kick of the velocities, then positions and Euler parameters to t + h
// with the half-step velocities (docs/staggered-pcst.md, eqs. 1-3).
void explicit_stage(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) {
    mbrt::RigidState& x = s.rigid[b];
    x.v += (0.5 * h) * s.rigid_acceleration[b].a;
    x.w += (0.5 * h) * s.rigid_acceleration[b].alpha;
    x.r += h * x.v;
    x.p = mbrt::advance_euler_parameters(x.p, x.w, h, kEulerUpdates);
  }
  for (int b = 0; b < kParticles; ++b) {
    mbrt::ParticleState& x = s.particle[b];
    x.v += (0.5 * h) * s.particle_acceleration[b];
    x.r += h * x.v;
  }
  s.t += h;
}

// (c, l, u_half) => (u): implicit stage. The end-of-step velocities satisfy
// the velocity constraints, regularized by the penalty eps (eq. 5):
//   (h/2) (S + 2 eps/h I) mu = B u_hat,  u = u_hat - h/2 M^-1 B^T mu.
void implicit_stage(const ConstraintSystem& c, const Loads& l, const BodyVectors& u_half, BodyVectors& u) noexcept {
  const BodyVectors a_free = free_accelerations(l);
  for (int b = 0; b < kBodies; ++b) u[b] = u_half[b] + (0.5 * h) * a_free[b];
  Rows mu = (2.0 / h) * jacobian_times(c, u);
  solve(c, mu);
  subtract_constraint_forces(c, mu, 0.5 * h, u);
}

// (c, l, phi, s) => (s.lambda, accelerations): multipliers of the stabilized
// companion equation (eq. 7)
//   (S + 2 eps/h I) lambda = B M^-1 F + quad + (2/h) (B u + alpha phi)
// which the next explicit stage applies: it steers phi at the next step to
// (1 - alpha h) phi. quad was evaluated at the predicted half-step velocity.
void constraint_forces(const ConstraintSystem& c, const Loads& l, const Rows& phi, State& s) noexcept {
  BodyVectors a = free_accelerations(l);
  s.lambda = jacobian_times(c, a) + stacked_quad(c) +
             (2.0 / h) * (jacobian_times(c, generalized_velocities(s)) + kStabilization * phi);
  solve(c, s.lambda);
  subtract_constraint_forces(c, s.lambda, 1.0, a);
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
  s.particle[0] = {mbrt::Vec3(-1.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0)};  // bob
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, c);
  factorize(c);
  Loads l;
  applied_loads(k, l);
  constraint_forces(c, l, stacked_phi(c), s);
  return s;
}

mbrt::StepStatus step(State& s) noexcept {
  const State last_good = s;
  const BodyVectors a_old = accelerations_of(s);
  explicit_stage(s);
  const BodyVectors u_half = generalized_velocities(s);

  // Constraint terms at the new positions, factorized once per step. The
  // quadratic terms are taken at the predicted next half-step velocity
  // u_half + h a_old, which the next explicit stage will drift with.
  Kinematics k;
  kinematics(s, k);
  BodyVectors u = u_half;
  for (int b = 0; b < kBodies; ++b) u[b] += h * a_old[b];
  set_velocities(u, s);
  k.vel = velocities_of(s);
  ConstraintSystem c;
  constraint_rows(k, c);
  bool positive = factorize(c);

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
  e.kinetic += mbrt::kinetic_energy(bob_mass, u[0]);
  e.potential -= bob_mass.m * kGravity.dot(k.pose[0].r);
  return e;
}

mbrt::ConstraintViolation constraint_violation(const State& s) noexcept {
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, c);
  const Rows phi = stacked_phi(c);
  const Rows phi_dot = jacobian_times(c, generalized_velocities(s));
  if (kConstraintRows == 0) return {0.0, 0.0};
  return {phi.cwiseAbs().maxCoeff(), phi_dot.cwiseAbs().maxCoeff()};
}

double quaternion_norm_error(const State& s) noexcept {
  double e = 0.0;
  for (const mbrt::RigidState& x : s.rigid) e = std::max(e, std::abs(x.p.norm() - 1.0));
  return e;
}

}  // namespace mbrt::models::a01_pendulum
