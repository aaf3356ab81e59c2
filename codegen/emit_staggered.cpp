// Step emission for the schemes built on the staggered explicit stage:
// staggered-pcst (docs/staggered-pcst.md), baumgarte and blajer
// (docs/schemes.md).
#include "emitter.hpp"

namespace mbrt::codegen {

std::string Emitter::stabilization_term() const {
  switch (scheme_kind()) {
    case Scheme::pcst:
    case Scheme::nps:
      return "(2.0 / h) * (velocity_residual(c, generalized_velocities(s)) + kStabilization * phi)";
    case Scheme::baumgarte:
      return "(2.0 * kBaumgarteAlpha) * velocity_residual(c, generalized_velocities(s)) + "
             "(kBaumgarteBeta * kBaumgarteBeta) * phi";
    case Scheme::blajer:
    case Scheme::ali3p: return "";
  }
  return "";
}

void Emitter::explicit_stage_function(std::ostringstream& o) const {
  o << R"(// (s, accelerations at t) => (s): half kick of the velocities (central
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
)";
  for (int i = 0; i < static_cast<int>(m_.bodies.size()); ++i) {
    if (!plan(i).rigid) continue;
    const std::string st = state_of(i);
    if (!free_rotation() || spherical_inertia(i)) {  // w constant over the step
      o << "  " << st << ".p = mbrt::advance_euler_parameters(" << st << ".p, " << st << ".w, h, kEulerUpdates);\n";
    } else {
      o << "  mbrt::free_rotation(" << mass_of(i) << ", " << st << ".p, " << st << ".w, h, kEulerUpdates);\n";
    }
  }
  o << "  s.t += h;\n}\n\n";
  if (rattle()) {
    set_positions_function(o);
  } else {
    o << "// (s, accelerations at t) => (s): the explicit stage.\nvoid explicit_stage(State& s) noexcept {\n"
      << "  kick(s);\n  drift(s);\n}\n\n";
  }
}

void Emitter::staggered_stages(std::ostringstream& o) const {
  if (planar_) planar_explicit_stage(o);
  else explicit_stage_function(o);
  if (rattle()) position_stage(o);
  if (scheme_kind() == Scheme::nps) {
    nps_stages(o);
    return;
  }
  const std::string stab = stabilization_term();
  switch (scheme_kind()) {
    case Scheme::pcst:
      o << R"(// (c, l, u_half) => (u): implicit stage. The end-of-step velocities satisfy
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
)";
      break;
    case Scheme::nps:
    case Scheme::ali3p: break;
    case Scheme::baumgarte:
      o << R"(// (c, l, phi, s) => (s.lambda, accelerations): index-1 multipliers with
// Baumgarte's terms, phi'' + 2 alpha phi' + beta^2 phi = 0:
//   S lambda = B M^-1 F + quad + 2 alpha B u + beta^2 phi
)";
      break;
    case Scheme::blajer:
      o << R"(// (c, l, phi, s) => (s.lambda, accelerations): the projective (index-1)
// multipliers, S lambda = B M^-1 F + quad (Blajer 1997, eq. 26). Drift is
// removed after the step by mass-orthogonal corrections.
)";
      break;
  }
  constraint_forces_function(o, stab);
  if (scheme_kind() == Scheme::blajer) {
    o << R"(// (c, s) => (s): mass-orthogonal position correction (Blajer eq. 38),
// dq = -M^-1 B^T S^-1 phi, rotations applied as body-frame increments.
void correct_positions(const ConstraintSystem& c, State& s) noexcept {
  Rows x = stacked_phi(c);
  solve(c, x);
  BodyVectors dq;
  for (auto& d : dq) d.setZero();
  subtract_constraint_forces(c, x, 1.0, dq);
)";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      const std::string st = state_of(static_cast<int>(i));
      if (planar_) {
        o << "  mbrt::correct_planar_position<kNormal>(" << st << ", dq[" << i << "]);\n";
        continue;
      }
      o << "  " << st << ".r += dq[" << i << "].head<3>();\n";
      if (a_.bodies[i].rigid) {
        o << "  " << st << ".p = mbrt::quaternion_product(" << st << ".p, mbrt::cayley_increment(dq[" << i
          << "].tail<3>())).normalized();\n";
      }
    }
    o << R"(}

// (c, s) => (s): mass-orthogonal velocity correction (Blajer eq. 40),
// du = -M^-1 B^T S^-1 B u.
void correct_velocities(const ConstraintSystem& c, State& s) noexcept {
  BodyVectors u = generalized_velocities(s);
  Rows x = velocity_residual(c, u);
  solve(c, x);
  subtract_constraint_forces(c, x, 1.0, u);
  set_velocities(u, s);
}

)";
  }
}

void Emitter::position_stage_constants(std::ostringstream& o) const {
  o << "constexpr int kPositionIterations = 2;  // Newton steps of the position stage\n"
    << "constexpr double kNewtonShift = " << num(a_.newton_shift) << ";  // added to diag(G)"
    << (a_.redundant_rows > 0 ? " (" + std::to_string(a_.redundant_rows) + " redundant rows)" : "") << "\n";
}

void Emitter::set_positions_function(std::ostringstream& o) const {
  o << R"(// (from) => (s): positions and time of another state.
void set_positions(const State& from, State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) {
    s.rigid[b].r = from.rigid[b].r;
    s.rigid[b].p = from.rigid[b].p;
  }
  for (int b = 0; b < kParticles; ++b) s.particle[b].r = from.particle[b].r;
  s.t = from.t;
}

)";
}

void Emitter::position_stage(std::ostringstream& o) const {
  newton_matrix(o);
  o << R"(// (c0, c, u_kick, last_good) => (s, k, c.rows_*): the position stage. The
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

)";
}

void Emitter::staggered_step(std::ostringstream& o) const {
  const bool rattle = this->rattle();
  o << R"(mbrt::StepStatus step(State& s) noexcept {
  const State last_good = s;
  const BodyVectors a_old = accelerations_of(s);
)";
  if (rattle) {
    o << R"(  // Directions of the first half kick's constraint forces, at q(t).
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

)";
  } else {
    o << "  explicit_stage(s);\n  const BodyVectors u_half = generalized_velocities(s);\n\n";
  }
  if (scheme_kind() == Scheme::pcst || scheme_kind() == Scheme::nps) {
    // staggered-nps eliminates the tree's rows and factorizes the cut rows
    // where staggered-pcst factorizes S; the stages are the same.
    const bool nps = scheme_kind() == Scheme::nps;
    const std::string factorize =
        nps ? std::string("TreeSystem t;\n  bool positive = factorize_tree(k, c, t)") +
                  (nps_cuts() ? ";\n  positive = factorize_cut(c, t) && positive" : "")
            : "bool positive = factorize(c)";
    const std::string system = nps ? "c, t" : "c";
    o << R"(  // Constraint terms at the new positions. The quadratic terms are taken at
  // the predicted next half-step velocity u_half + h a_old, which the next
  // explicit stage will drift with.
)" << (rattle ? "" : "  Kinematics k;\n  kinematics(s, k);\n") << R"(  BodyVectors u = u_half;
  for (int b = 0; b < kBodies; ++b) u[b] += h * a_old[b];
  set_velocities(u, s);
  k.vel = velocities_of(s);
)" << (rattle ? "" : "  ConstraintSystem c;\n") << R"(  constraint_rows(k, s.t, c);
)" << (rattle ? "  constraint_directions(c);  // the factor stays that of the first drift\n" : "  " + factorize + ";\n") << R"(
  // Implicit stages: the first evaluates velocity-dependent loads at the
  // predicted end-of-step velocities u_half + h/2 a_old, the next ones at the
  // last result.
  for (int b = 0; b < kBodies; ++b) u[b] = u_half[b] + (0.5 * h) * a_old[b];
  Loads l;
  for (int stage = 0; stage < kStages; ++stage) {
    set_velocities(u, s);
    k.vel = velocities_of(s);
    )" << loads_call() << R"(;
    implicit_stage()" << system << R"(, l, u_half, u);
  }
  set_velocities(u, s);
  constraint_forces()" << system << R"(, l, stacked_phi(c), s);
)";
  } else {
    o << R"(  // Constraint terms at the new positions, factorized once per step, with
  // the quadratic terms at the predicted end-of-step velocity.
  Kinematics k;
  kinematics(s, k);
  BodyVectors u = u_half;
  for (int b = 0; b < kBodies; ++b) u[b] += (0.5 * h) * a_old[b];
  set_velocities(u, s);
  k.vel = velocities_of(s);
  ConstraintSystem c;
  constraint_rows(k, s.t, c);
  bool positive = factorize(c);
  const Rows phi = stacked_phi(c);

  // Implicit stages, fixed-point passes on u = u_half + h/2 a(t + h, u).
  Loads l;
  for (int stage = 0; stage < kStages; ++stage) {
    set_velocities(u, s);
    k.vel = velocities_of(s);
    )" << loads_call() << R"(;
    constraint_forces(c, l, phi, s);
    const BodyVectors a = accelerations_of(s);
    for (int b = 0; b < kBodies; ++b) u[b] = u_half[b] + (0.5 * h) * a[b];
  }
  set_velocities(u, s);
)";
    if (scheme_kind() == Scheme::blajer) {
      o << R"(
  // Post-step corrections, a fixed number for positions, then velocities.
  for (int i = 0; i < kCorrections; ++i) {
    if (i > 0) {
      kinematics(s, k);
      constraint_rows(k, s.t, c);
      positive = factorize(c) && positive;
    }
    correct_positions(c, s);
  }
  correct_velocities(c, s);
)";
    }
  }
  o << R"(
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

)";
}

}  // namespace mbrt::codegen
