// Kernels of ali3p (the step is mbrt::schemes::ali3p_step, include/mbrt/schemes/ali3p.hpp):
// index-3 augmented Lagrangian with the trapezoidal rule or generalized-alpha, then velocity and acceleration projections
// (Dopico et al. 2014; docs/ali3p.md). The tangent M + c B^T alpha B and the
// projection matrices are inverted through the Woodbury identity with the
// block Cholesky factor of S + shift, so every matrix keeps S's fixed pattern.
#include <algorithm>

#include "emitter.hpp"

namespace mbrt::codegen {

namespace {

// A Rows constant with one value per constraint row.
std::string rows_literal(const std::string& name, const std::vector<double>& values, const std::string& comment) {
  std::string s = "// " + comment + "\nstatic inline const Rows " + name + " = ";
  if (values.empty()) return s + "Rows::Zero();\n";
  s += "(Rows() << ";
  for (size_t i = 0; i < values.size(); ++i) s += (i ? ", " : "") + num(values[i]);
  return s + ").finished();\n";
}

// Diagonal shift that removes a row from a solve with S (its multiplier
// comes out ~1e-12 of what it would be).
constexpr double kDecoupled = 1.0e12;

}  // namespace

void Emitter::ali3p_constants(std::ostringstream& o) const {
  const Ali3pSettings& set = m_.solver.ali3p;
  const Ali3pPlan& p = a_.ali3p;
  const double h = m_.solver.step;
  const double c = (1.0 - p.delta_f) / (1.0 - p.delta_m) * p.beta * h * h;  // tangent weight of B^T alpha B
  const double w = set.cuadrado_projection ? c : 1.0;                        // projection weight
  std::vector<double> alpha, tangent_shift, projection_shift;
  for (int j = 0; j < blocks(); ++j) {
    for (int r = 0; r < rows(j); ++r) {
      const double a = p.alpha[static_cast<size_t>(j)];
      // Rows on velocities stay out of the index-3 stage (Dopico et al. 2014:
      // putting them there is wrong): no penalty, and a shift that decouples
      // them from the tangent's solve. They enter through the projections.
      const bool holonomic = r < block(j).holonomic_rows;
      alpha.push_back(holonomic ? a : 0.0);
      tangent_shift.push_back(holonomic ? 1.0 / (c * a) : kDecoupled);
      // Never below the regularization that keeps redundant rows factorable.
      projection_shift.push_back(std::max(1.0 / (w * a), a_.regularization));
    }
  }
  o << "// Integrator: " << (set.generalized_alpha ? "generalized-alpha, rho_inf = " + num(set.rho_inf) : "trapezoidal rule")
    << ".\nstatic constexpr double kBeta = " << num(p.beta) << ";\nstatic constexpr double kGamma = " << num(p.gamma)
    << ";\nstatic constexpr double kDeltaM = " << num(p.delta_m) << ";  // weight of t in the inertia term\n"
    << "static constexpr double kDeltaF = " << num(p.delta_f) << ";  // weight of t in the force terms\n"
    << "static constexpr int kNewtonIterations = " << set.newton_iterations << ";\n"
    << "static constexpr int kProjectionIterations = " << set.projection_iterations << ";  // "
    << (set.cuadrado_projection ? "cuadrado: P + w B^T alpha B = tangent" : "bayo: P = M, w = 1") << "\n"
    << rows_literal("kAlpha", alpha, "Penalty alpha per row.")
    << rows_literal("kTangentShift", tangent_shift,
                    "Tangent M + c B^T alpha B, c = (1 - dF)/(1 - dM) beta h^2: S's shift 1/(c alpha).")
    << rows_literal("kProjectionShift", projection_shift, "Projection matrix M + w B^T alpha B: S's shift 1/(w alpha).")
    << "static inline const Rows kProjectionWeight = kProjectionShift.cwiseInverse();\n\n";
}

void Emitter::ali3p_stages(std::ostringstream& o) const {
  ali3p_constants(o);
  o << "// (n, u_n, a_n, a) => (s, u): Newmark positions and velocities at t + h for\n"
    << "// the accelerations a; rotations advance by the body-frame increment\n"
    << "// through the Cayley map.\n"
    << "static void newmark_update(const State& n, const BodyVectors& u_n, const BodyVectors& a_n, const BodyVectors& a,\n"
    << "                    State& s, BodyVectors& u) noexcept {\n"
    << "  BodyVectors d;\n"
    << "  for (int b = 0; b < kBodies; ++b) {\n"
    << "    d[b] = h * u_n[b] + (h * h * (0.5 - kBeta)) * a_n[b] + (h * h * kBeta) * a[b];\n"
    << "    u[b] = u_n[b] + (h * (1.0 - kGamma)) * a_n[b] + (h * kGamma) * a[b];\n"
    << "  }\n";
  for (int i = 0; i < static_cast<int>(m_.bodies.size()); ++i) {
    const std::string x = (plan(i).rigid ? "rigid" : "particle") + slot_of(i);
    o << "  s." << x << ".r = n." << x << ".r + d" << at(i) << ".head<3>();\n";
    if (plan(i).rigid) {
      o << "  s." << x << ".p = mbrt::advance_euler_parameters(n." << x << ".p, d" << at(i)
        << ".tail<3>() / h, h, kEulerUpdates);\n";
    }
  }
  o << "  set_velocities(u, s);\n}\n\n";

  const bool weighted = ali3p_weighted();
  o << "// (c, l, lambda) => (M^-1 g): g = B^T lambda - F per body.\n"
    << "static BodyVectors constraint_minus_applied(" << mass_parameter()
    << "const ConstraintSystem& c, const Loads& l, const Rows& lambda) noexcept {\n"
    << "  BodyVectors x = free_accelerations(" << mass_argument() << "l);\n"
    << "  for (mbrt::Vec6& v : x) v = -v;\n"
    << "  subtract_constraint_forces(c, lambda, -1.0, x);\n"
    << "  return x;\n}\n\n";
  o << "// (c, l, lambda, a) => (a): one Newton correction of the dynamic equations\n"
    << "//   (1 - dM) M a + dM M a_n + (1 - dF) g + dF g_n = 0,  g = B^T lambda - F,\n"
    << "// lambda = lambda* + alpha phi, with the tangent M + c B^T alpha B inverted as\n"
    << "// M^-1 - M^-1 B^T (S + 1/(c alpha))^-1 B M^-1 (c is in kTangentShift).\n"
    << "static void newton_correction(" << mass_parameter() << "const ConstraintSystem& c, const Loads& l, const Rows& lambda,"
    << (weighted ? " const BodyVectors& a_n,\n                       const BodyVectors& g_n," : "")
    << " BodyVectors& a) noexcept {\n"
    << "  BodyVectors x = constraint_minus_applied(" << mass_argument() << "c, l, lambda);\n";
  if (weighted) {
    o << "  for (int b = 0; b < kBodies; ++b) {\n"
      << "    x[b] = a[b] + (kDeltaM * a_n[b] + (1.0 - kDeltaF) * x[b] + kDeltaF * g_n[b]) / (1.0 - kDeltaM);\n"
      << "  }\n";
  } else {
    o << "  for (int b = 0; b < kBodies; ++b) x[b] += a[b];\n";
  }
  o << "  Rows mu = jacobian_times(c, x);\n"
    << "  solve(c, mu);\n"
    << "  subtract_constraint_forces(c, mu, 1.0, x);\n"
    << "  for (int b = 0; b < kBodies; ++b) a[b] -= x[b];\n}\n\n";

  o << R"(// (c, g, x*) => (x, nu): augmented-Lagrangian projection (Dopico et al.
// 2014, eqs. 22 and 28) of velocities (g = phi_t) or accelerations (g = quad):
//   (M + B^T W B) x = M x* - B^T (W g + sigma),  sigma += W (B x + g),
// kProjectionIterations passes, W = kProjectionWeight. By the Woodbury
// identity each pass is x = x* - M^-1 B^T nu with
//   (S + W^-1) nu = B x* + g + W^-1 sigma,
// a form without the large products W g. nu is the projection's multiplier:
// for accelerations, the constraint forces' projection part.
static Rows project(const ConstraintSystem& c, const Rows& g, BodyVectors& x) noexcept {
  const BodyVectors x_star = x;
  const Rows b_x_star = jacobian_times(c, x_star) + g;
  Rows sigma = Rows::Zero();
  Rows nu;
  for (int i = 0; i < kProjectionIterations; ++i) {
    nu = b_x_star + kProjectionShift.cwiseProduct(sigma);
    solve(c, nu);
    x = x_star;
    subtract_constraint_forces(c, nu, 1.0, x);
    sigma += kProjectionWeight.cwiseProduct(jacobian_times(c, x) + g);
  }
  return nu;
}

// (c, l, phi, s) => (s.lambda, accelerations): consistent accelerations for
// the initial state, S lambda = B M^-1 F + quad.
)";
  constraint_forces_function(o, "");
}

}  // namespace mbrt::codegen
