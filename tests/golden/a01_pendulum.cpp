// mbrt generated model 'a01_pendulum': 1 bodies (0 rigid, 1 particles), 1 joints, 0 drivers, 1 constraint rows.
// Scheme staggered-pcst. Stage order per step: explicit_stage -> kinematics ->
// constraint_rows -> factorize -> (applied_loads -> implicit stage) x kStages.
// Left out for this scene:
//   particles: 1 particle(s): no rotational state (the model's contract, also without specializations)
//   single_stage: no velocity-dependent loads: the second implicit stage
//   folded_weights: gravity: the products m g, one constant weight per body
//   no_drivers: no drivers: the explicit time terms phi_t
//   planar: motion in the x-y plane: two coordinates and the angle about z per body, 1 of 1 constraint rows (the in-plane ones)
#include "a01_pendulum.hpp"

#include <algorithm>
#include <cmath>

#include <mbrt/natural_partitioning.hpp>
#include <mbrt/reactions.hpp>
#include <mbrt/runtime.hpp>

namespace mbrt::models::a01_pendulum {

namespace {

constexpr double h = kStep;
constexpr int kStages = 1;  // implicit stages per step
constexpr double kRegularization = 1e-10;  // added to diag(S)
constexpr int kPositionIterations = 2;  // Newton steps of the position stage
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
// included, and the elastic energy stored.
void applied_loads(const Kinematics& k, Loads& l) noexcept {
  l.w.fill(mbrt::Wrench{});
  l.elastic_energy = 0.0;
  l.w[0].f += bob_weight;
}

// (k, t) => (c.rows_*): constraint values, Jacobians and acceleration terms.
void constraint_rows(const Kinematics& k, double t, ConstraintSystem& c) noexcept {
  (void)t;
  c.rows_bar = mbrt::distance(bar_frame, mbrt::BodyMotion{kGroundPose, kGroundVelocity}, mbrt::BodyMotion{k.pose[0], k.vel[0]});
}

// (c.rows_*) => (c.mbt_*): M^-1 B^T, the directions constraint forces move the bodies in.
void constraint_directions(ConstraintSystem& c) noexcept {
  c.mbt_0_0 = mbrt::inverse_mass_times_transpose(bob_mass, c.rows_bar.J2);
}

// (c.rows_*) => (c.mbt_*, c.L_*): M^-1 B^T, then S block by block in
// elimination order (0 fill blocks); false if a pivot is not positive.
bool factorize(ConstraintSystem& c) noexcept {
  bool positive = true;
  constraint_directions(c);
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

// (c) => (phi), (c) => (quad): stacked position residuals and acceleration terms.
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

// (c, u) => (phi_dot = B u + phi_t): velocity residuals.
Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  return jacobian_times(c, u);  // no drivers: phi_t = 0
}

// (l) => (M^-1 F) per body.
BodyVectors free_accelerations(const Loads& l) noexcept {
  BodyVectors a;
  a[0] = mbrt::inverse_mass_times(bob_mass, l.w[0]);
  return a;
}

void constraint_forces(const ConstraintSystem& c, const Loads& l, const Rows& phi, State& s) noexcept {
  BodyVectors a = free_accelerations(l);
  s.lambda = jacobian_times(c, a) + stacked_quad(c) +
             (2.0 / h) * (velocity_residual(c, generalized_velocities(s)) + kStabilization * phi);
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

// The step in planar coordinates: motion in one plane, per body two
// coordinates and the rotation about the normal, the in-plane constraint rows only.
namespace planar {

constexpr int kNormal = 2;  // the plane x-y, normal to world z
constexpr int kPlanarRows = 1;  // of kConstraintRows
constexpr int kStages = 1;  // implicit stages per step
constexpr int kPositionIterations = 2;  // Newton steps of the position stage
constexpr double kNewtonShift = 1e-10;  // added to diag(G)
const mbrt::PlanarPose kGroundPose = mbrt::planar_ground_pose();
const mbrt::PlanarVelocity kGroundVelocity = mbrt::planar_ground_velocity();

// Masses and the moments of inertia about the normal (particles keep their PointMass).
const mbrt::Vec2 bob_weight(0.0, -9.8100000000000005);

using Rows = Eigen::Matrix<double, kPlanarRows, 1>;
using BodyVectors = std::array<mbrt::Vec3, kBodies>;  // [v_i; v_j; omega_k], plane coordinates per body

struct Kinematics {
  std::array<mbrt::PlanarPose, kBodies> pose;
  std::array<mbrt::PlanarVelocity, kBodies> vel;
};

struct Loads {
  std::array<mbrt::PlanarWrench, kBodies> w;
  double elastic_energy;
};

// Constraint rows, M^-1 B^T blocks and the block Cholesky factor of
// S = B M^-1 B^T + kRegularization I over the model's fixed pattern.
struct ConstraintSystem {
  mbrt::PlanarRows<1> rows_bar;  // planar_distance ground - bob, rows 0..0
  Eigen::Matrix<double, 3, 1> mbt_0_0;  // M^-1 B^T: bar, bob
  Eigen::Matrix<double, 1, 1> L_0_0;  // bar
};

std::array<mbrt::PlanarVelocity, kBodies> velocities_of(const State& s) noexcept {
  std::array<mbrt::PlanarVelocity, kBodies> vel;
  vel[0] = mbrt::planar_velocity_of<kNormal>(s.particle[0]);
  return vel;
}

// (s) => (u): (vx, vy, omega_z) per body.
BodyVectors generalized_velocities(const State& s) noexcept {
  BodyVectors u;
  u[0] = mbrt::planar_velocities<kNormal>(s.particle[0]);
  return u;
}

// (u) => (s): the in-plane velocities; the others stay zero.
void set_velocities(const BodyVectors& u, State& s) noexcept {
  mbrt::set_planar_velocities<kNormal>(u[0], s.particle[0]);
}

// (a) => (s): accelerations kept for the next step.
void set_accelerations(const BodyVectors& a, State& s) noexcept {
  mbrt::set_planar_accelerations<kNormal>(a[0], s.particle_acceleration[0]);
}

BodyVectors accelerations_of(const State& s) noexcept {
  BodyVectors a;
  a[0] = mbrt::planar_accelerations<kNormal>(s.particle_acceleration[0]);
  return a;
}

// (s) => (k): pose and velocity of every body.
void kinematics(const State& s, Kinematics& k) noexcept {
  k.pose[0] = mbrt::planar_pose_of<kNormal>(s.particle[0]);  // bob
  k.vel = velocities_of(s);
}

// (k) => (l): applied forces (world) and torques (body axes) per body,
// included, and the elastic energy stored.
void applied_loads(const Kinematics& k, Loads& l) noexcept {
  l.w.fill(mbrt::PlanarWrench{});
  l.elastic_energy = 0.0;
  l.w[0].f += bob_weight;
}

// (k, t) => (c.rows_*): constraint values, Jacobians and acceleration terms.
void constraint_rows(const Kinematics& k, double t, ConstraintSystem& c) noexcept {
  (void)t;
  c.rows_bar = mbrt::planar_distance(bar_frame, mbrt::PlanarMotion{kGroundPose, kGroundVelocity}, mbrt::PlanarMotion{k.pose[0], k.vel[0]});
}

// (c.rows_*) => (c.mbt_*): M^-1 B^T, the directions constraint forces move the bodies in.
void constraint_directions(ConstraintSystem& c) noexcept {
  c.mbt_0_0 = mbrt::inverse_mass_times_transpose(bob_mass, c.rows_bar.J2);
}

// (c.rows_*) => (c.mbt_*, c.L_*): M^-1 B^T, then S block by block in
// elimination order (0 fill blocks); false if a pivot is not positive.
bool factorize(ConstraintSystem& c) noexcept {
  bool positive = true;
  constraint_directions(c);
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

// (c) => (phi), (c) => (quad): stacked position residuals and acceleration terms.
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

// (c, u) => (phi_dot = B u + phi_t): velocity residuals.
Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept {
  return jacobian_times(c, u);  // no drivers: phi_t = 0
}

// (l) => (M^-1 F) per body.
BodyVectors free_accelerations(const Loads& l) noexcept {
  BodyVectors a;
  a[0] = mbrt::inverse_mass_times(bob_mass, l.w[0]);
  return a;
}

// (lambda) => (s.lambda): the in-plane rows of every spatial block.
void store_multipliers(const Rows& lambda, State& s) noexcept {
  s.lambda.segment<1>(0) = lambda.segment<1>(0);  // bar
}

// (s, accelerations at t) => (s): half kick of the velocities in the plane
// (docs/staggered-pcst.md, eq. 1).
void kick(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) mbrt::planar_kick<kNormal>(s.rigid[b], s.rigid_acceleration[b], h);
  for (int b = 0; b < kParticles; ++b) mbrt::planar_kick<kNormal>(s.particle[b], s.particle_acceleration[b], h);
}

// (s) => (s): positions to t + h with the half-step velocities (eqs. 2-3); the
// rotation about the normal by the spatial step's Cayley updates.
void drift(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) mbrt::planar_drift<kNormal>(s.rigid[b], h, kEulerUpdates);
  for (int b = 0; b < kParticles; ++b) mbrt::planar_drift<kNormal>(s.particle[b], h);
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
  Eigen::Matrix<double, 1, 1> D_0;  // bar, inverted
};

// (c0.mbt_*, c.rows_*) => (g): G block by block in S's elimination order.
void factorize_newton(const ConstraintSystem& c0, const ConstraintSystem& c, NewtonMatrix& g) noexcept {
  // bar
  g.D_0 = c.rows_bar.J2 * c0.mbt_0_0 + kNewtonShift * Eigen::Matrix<double, 1, 1>::Identity();
  g.D_0 = g.D_0.partialPivLu().inverse();
}

// (g, x) => (x): x := G^-1 x by forward and backward substitution.
void solve_newton(const NewtonMatrix& g, Rows& x) noexcept {
  {  // bar
    Eigen::Matrix<double, 1, 1> y = x.segment<1>(0);
    x.segment<1>(0) = g.D_0 * y;
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
void constraint_forces(const ConstraintSystem& c, const Loads& l, const Rows& phi, State& s) noexcept {
  BodyVectors a = free_accelerations(l);
  Rows lambda = jacobian_times(c, a) + stacked_quad(c) +
             (2.0 / h) * (velocity_residual(c, generalized_velocities(s)) + kStabilization * phi);
  solve(c, lambda);
  subtract_constraint_forces(c, lambda, 1.0, a);
  set_accelerations(a, s);
  store_multipliers(lambda, s);
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

}  // namespace planar

}  // namespace

State initial_state() noexcept {
  State s;
  s.particle[0] = {mbrt::Vec3(-1.0, 0.0, 0.0), mbrt::Vec3(0.0, 0.0, 0.0)};  // bob
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

mbrt::StepStatus step(State& s) noexcept { return planar::step(s); }

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
  constraint_rows(k, s.t, c);
  const Rows phi = stacked_phi(c);
  const Rows phi_dot = velocity_residual(c, generalized_velocities(s));
  BodyVectors a = accelerations_of(s);
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
  r[0] = mbrt::joint_reaction(-(c.rows_bar.J2.transpose() * s.lambda.segment<1>(0)), k.pose[0],
      k.pose[0].r + k.pose[0].R * bar_frame.s2, 1.0, kGroundPose, bar_frame);  // bar
}

}  // namespace mbrt::models::a01_pendulum
