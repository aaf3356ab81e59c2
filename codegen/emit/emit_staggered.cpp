// Step emission for the schemes built on the staggered explicit stage:
// staggered-pcst (docs/staggered-pcst.md), staggered4, baumgarte and blajer
// (docs/schemes.md).
#include <cmath>

#include "emitter.hpp"

namespace mbrt::codegen {

std::string Emitter::stabilization_term() const {
  switch (scheme_kind()) {
    case Scheme::staggered_pcst:
    case Scheme::staggered4:
    case Scheme::staggered_nps:
      return "(2.0 / h) * (velocity_residual(c, generalized_velocities(s)) + kStabilization * phi)";
    case Scheme::baumgarte:
      return "(2.0 * kBaumgarteAlpha) * velocity_residual(c, generalized_velocities(s)) + "
             "(kBaumgarteBeta * kBaumgarteBeta) * phi";
    case Scheme::blajer:
    case Scheme::rk4_projected:
    case Scheme::staggered_tree:
    case Scheme::midpoint_tree:
    case Scheme::rk4_tree:
    case Scheme::rk8_tree:
    case Scheme::ali3p: return "";
  }
  return "";
}

void Emitter::explicit_stage_function(std::ostringstream& o) const {
  o << R"(// (s, accelerations at t) => (s): half kick of the velocities (central
// difference, docs/staggered-pcst.md eq. 1).
static void kick(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) {
    s.rigid[b].v += (0.5 * h) * s.rigid_acceleration[b].a;
    s.rigid[b].w += (0.5 * h) * s.rigid_acceleration[b].alpha;
  }
  for (int b = 0; b < kParticles; ++b) s.particle[b].v += (0.5 * h) * s.particle_acceleration[b];
)";
  modal_kick(o);
  o << R"(}

// (s) => (s): positions to t + h with the half-step velocities (eq. 2), and
// the Euler parameters (eq. 3): under staggered-pcst each body's torque-free
// rotation over h, which carries its gyroscopic torque (docs/stability.md).
static void drift(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) s.rigid[b].r += h * s.rigid[b].v;
  for (int b = 0; b < kParticles; ++b) s.particle[b].r += h * s.particle[b].v;
)";
  for (const ModalPlan& p : a_.modal) {
    o << "  const mbrt::Mat3 " << body(p.body).name << "_start = mbrt::rotation_matrix(" << state_of(p.body) << ".p);\n";
  }
  std::vector<std::string> part_lines(static_cast<size_t>(parts()));
  for (int i = 0; i < static_cast<int>(m_.bodies.size()); ++i) {
    if (!plan(i).rigid) continue;
    const std::string st = state_of(i);
    std::string& out = part_lines[static_cast<size_t>(parallel() ? body_part(i) : 0)];
    if (!free_rotation() || spherical_inertia(i) || plan(i).modal >= 0) {  // w constant over the step
      out += "  " + st + ".p = mbrt::advance_euler_parameters(" + st + ".p, " + st + ".w, h, kEulerUpdates);  // " +
             body(i).name + "\n";
    } else {
      out += "  mbrt::free_rotation(" + mass_of(i) + ", " + st + ".p, " + st + ".w, h, kEulerUpdates);  // " +
             body(i).name + "\n";
    }
  }
  o << (parallel() ? parallel_region(part_lines) : part_lines[0]);
  modal_drift(o);
  o << "  s.t += h;\n}\n\n";
}

// The kernels only the staggered schemes' step calls; the step itself is
// mbrt::schemes::staggered_step (include/mbrt/schemes/staggered.hpp).
void Emitter::staggered_stages(std::ostringstream& o) const {
  if (planar_) planar_explicit_stage(o);
  else explicit_stage_function(o);
  if (rattle()) newton_matrix(o);
  if (scheme_kind() == Scheme::staggered_nps) {
    nps_stages(o);
    return;
  }
  switch (scheme_kind()) {
    case Scheme::staggered_pcst:
    case Scheme::staggered4:
      o << R"(// (c, l, phi, s) => (s.lambda, accelerations): multipliers of the stabilized
// companion equation (docs/staggered-pcst.md eq. 7)
//   (S + 2 eps/h I) lambda = B M^-1 F + quad + (2/h) (B u + alpha phi)
// which the next explicit stage applies: it steers phi at the next step to
// (1 - alpha h) phi. quad was evaluated at the predicted half-step velocity.
)";
      break;
    case Scheme::staggered_nps:
    case Scheme::staggered_tree:
    case Scheme::midpoint_tree:
    case Scheme::rk4_tree:
    case Scheme::rk8_tree:
    case Scheme::ali3p: break;
    case Scheme::baumgarte:
      o << R"(// (c, l, phi, s) => (s.lambda, accelerations): index-1 multipliers with
// Baumgarte's terms, phi'' + 2 alpha phi' + beta^2 phi = 0:
//   S lambda = B M^-1 F + quad + 2 alpha B u + beta^2 phi
)";
      break;
    case Scheme::blajer:
    case Scheme::rk4_projected:
      o << R"(// (c, l, phi, s) => (s.lambda, accelerations): the projective (index-1)
// multipliers, S lambda = B M^-1 F + quad (Blajer 1997, eq. 26). Drift is
// removed after the step by mass-orthogonal corrections.
)";
      break;
  }
  constraint_forces_function(o, stabilization_term());
  if (scheme_kind() == Scheme::blajer || scheme_kind() == Scheme::rk4_projected) correct_positions_function(o);
}

void Emitter::correct_positions_function(std::ostringstream& o) const {
  o << R"(// (c, s) => (s): mass-orthogonal position correction (Blajer eq. 38),
// dq = -M^-1 B^T S^-1 phi, rotations applied as body-frame increments.
static void correct_positions(const ConstraintSystem& c, State& s) noexcept {
  Rows x = stacked_phi(c);
  solve(c, x);
  BodyVectors dq;
  for (auto& d : dq) d.setZero();
  subtract_constraint_forces(c, x, 1.0, dq);
)";
  // A modal body whose node a joint holds: dq holds the momenta's
  // direction, dq_p = M_qq dq_q + S^T dq_frame (include/mbrt/modal_body.hpp,
  // modal_frame_share), the mass-orthogonal step: dq_q is modal_rates' of
  // the step's dq. Without such joints the rows do not see q, and leaving it
  // is a Newton step too: moving it by -S^T dq_frame, which nearly cancels
  // dq_frame where the frame is light next to its modes, turned
  // test_modal_body's pinned tool unstable.
  std::vector<bool> held(m_.bodies.size(), false);
  for (int j = 0; j < blocks(); ++j)
    for (int b : node_bodies(j)) held[static_cast<size_t>(b)] = true;
  for (size_t k = 0; k < a_.modal.size(); ++k) {
    const int i = a_.modal[k].body, n = static_cast<int>(k);
    if (!held[static_cast<size_t>(i)]) continue;
    const std::string b = body(i).name + "_modal", q = modal_coordinates(n, "modal_q"), N = std::to_string(a_.modal[k].modes);
    o << "  " << q << " += mbrt::modal_rates<" << N << ">(" << b << ", mbrt::rotation_matrix(" << state_of(i) << ".p), dq" << at(i)
      << ".head<3>(), dq" << at(i) << ".tail<3>(), " << q << ", dq" << momenta_at(i) << ".head<" << N << ">());\n";
  }
  for (size_t i = 0; i < m_.bodies.size(); ++i) {
    const std::string st = state_of(static_cast<int>(i));
    if (planar_) {
      o << "  mbrt::correct_planar_position<kNormal>(" << st << ", dq" << at(static_cast<int>(i)) << ");\n";
      continue;
    }
    o << "  " << st << ".r += dq" << at(static_cast<int>(i)) << ".head<3>();\n";
    if (a_.bodies[i].rigid) {
      o << "  " << st << ".p = mbrt::quaternion_product(" << st << ".p, mbrt::cayley_increment(dq" << at(static_cast<int>(i))
        << ".tail<3>())).normalized();\n";
    }
  }
  o << "}\n\n";
}

void Emitter::position_stage_constants(std::ostringstream& o) const {
  o << "constexpr double kNewtonShift = " << num(a_.newton_shift) << ";  // added to diag(G)"
    << (a_.redundant_rows > 0 ? " (" + std::to_string(a_.redundant_rows) + " redundant rows)" : "") << "\n";
}

// Yoshida's triple jump (Yoshida 1990, "Construction of higher order
// symplectic integrators", Phys. Lett. A 150; Hairer, Lubich & Wanner 2006,
// "Geometric Numerical Integration", section II.4): substeps g1 h, g0 h, g1 h
// with g1 = 1 / (2 - 2^(1/3)), g0 = 1 - 2 g1 = -2^(1/3) g1.
void Emitter::triple_jump_constants(std::ostringstream& o) const {
  const double g1 = 1.0 / (2.0 - std::cbrt(2.0));
  const double g0 = -std::cbrt(2.0) * g1;
  o << "// Substeps of Yoshida's triple jump: kSubsteps[0], [1], [0] (docs/schemes.md, \"staggered4\").\n"
    << "constexpr double kSubsteps[2] = {" << num(g1 * m_.solver.step) << ", " << num(g0 * m_.solver.step) << "};\n";
}

}  // namespace mbrt::codegen
