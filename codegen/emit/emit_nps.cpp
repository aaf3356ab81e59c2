// Step emission for staggered-nps (docs/staggered-nps.md): the staggered
// explicit-implicit stages of staggered-pcst, with the spanning tree's joints
// eliminated body by body through their explicit null spaces and the cut rows
// (loop closures, drivers, contacts) left to penalty-regularized multipliers.
#include "emitter.hpp"

namespace mbrt::codegen {

// Expressions of the null-space columns of the joint that carries tb, in the
// child's body axes: turns about and slides along the joint's directions
// fixed in body 1. Those keep every row of the joint satisfied to first
// order even where the positions have drifted (body 2's copies only do so
// on the constraint manifold), so B H = 0 holds to round-off.
std::vector<std::string> Emitter::null_space_columns(const TreeBody& tb) const {
  const std::string f = jname(tb.joint) + "_frame.";
  const std::string p = pose(tb.body);
  const std::string s = f + (tb.child_is_body2 ? "s2" : "s1");
  // A body-1 direction in the child's axes (to_child = R_child^T R_parent).
  auto body1 = [&](const std::string& d) {
    return tb.child_is_body2 ? "mbrt::Vec3(to_child * " + f + d + "1)" : f + d + "1";
  };
  auto turn = [&](const std::string& e) { return "mbrt::turn_about(" + p + ", " + s + ", " + e + ")"; };
  auto slide = [&](const std::string& e) { return "mbrt::slide_along(" + p + ", " + e + ")"; };
  const std::string a = body1("a");
  switch (m_.joints[static_cast<size_t>(tb.joint)].type) {
    case JointType::revolute: return {turn(a)};
    case JointType::prismatic: return {slide(a)};
    case JointType::cylindrical: return {turn(a), slide(a)};
    case JointType::spherical:
      return {turn("mbrt::Vec3::UnitX()"), turn("mbrt::Vec3::UnitY()"), turn("mbrt::Vec3::UnitZ()")};
    case JointType::universal:  // about either axis: axis 1 of body 1, axis 2 of body 2
      return {turn(a), turn(tb.child_is_body2 ? f + "a2" : "mbrt::Vec3(to_child * " + f + "a2)")};
    case JointType::planar: return {turn(a), slide(body1("b")), slide(body1("c"))};
    case JointType::screw: return {turn(a) + " + " + f + "pitch * " + slide(a)};
    case JointType::fixed: return {};
    case JointType::distance:
    case JointType::rolling_disk:
    case JointType::rolling_ball:
    case JointType::knife_edge:
    case JointType::velocity_toward: break;  // never tree joints (tree_plan.cpp)
  }
  return {};
}

// Whether the columns need to_child = R_child^T R_parent.
bool Emitter::carries_parent_axes(const TreeBody& tb) const {
  const JointType type = m_.joints[static_cast<size_t>(tb.joint)].type;
  if (type == JointType::spherical || type == JointType::fixed) return false;
  return tb.child_is_body2 || type == JointType::universal;
}

// H^T x and H z for one tree body. A free body that reaches elimination has
// children, so it is rigid (tree joints join rigid bodies only): H = I.
std::string Emitter::h_transpose_times(const TreeBody& tb, const std::string& x) const {
  return tb.joint >= 0 ? "t.H_" + body(tb.body).name + ".transpose() * " + x : x;
}

std::string Emitter::h_times(const TreeBody& tb, const std::string& z) const {
  return tb.joint >= 0 ? "t.H_" + body(tb.body).name + " * " + z : z;
}

// A free body without children needs no elimination: u' = M^-1 force.
bool Emitter::free_leaf(const TreeBody& tb) const { return tb.joint < 0 && tb.leaf; }

// IA x; a leaf's articulated inertia is its mass matrix, which is sparse.
std::string Emitter::ia_times(const TreeBody& tb, const std::string& x) const {
  if (tb.leaf) return "mbrt::mass_times(" + tree_mass(tb.body) + ", " + x + ")";
  return "t.IA_" + body(tb.body).name + " * " + x;
}

std::string Emitter::ia_matrix(const TreeBody& tb) const {
  return tb.leaf ? "mbrt::mass_matrix(" + tree_mass(tb.body) + ")" : "t.IA_" + body(tb.body).name;
}

void Emitter::nps_workspace(std::ostringstream& o) const {
  const TreePlan& tree = a_.tree;
  o << "// The tree elimination of the step's positions (docs/staggered-nps.md):\n"
    << "// per body the articulated inertia IA, the null space H of its joint,\n"
    << "// L L^T = H^T IA H, W = IA H L^-T, the transfer X from its parent, and\n"
    << "// Q = M^-1 B^T G^-T with G G^T = B M^-1 B^T for its joint's rows.\n"
    << "struct TreeSystem {\n";
  for (const TreeBody& tb : tree.order) {
    const std::string i = body(tb.body).name;
    o << "  // " << body(tb.body).name << "\n";
    if (!tb.leaf) o << "  mbrt::Mat6 IA_" << i << ";\n";
    if (tb.joint >= 0 && tb.dofs > 0) o << "  " << block_type(6, tb.dofs) << " H_" << i << ";\n";
    if (tb.dofs > 0 && !free_leaf(tb)) o << "  " << block_type(tb.dofs, tb.dofs) << " L_" << i << ";\n";
    if (tb.parent != kGround) {
      o << "  mbrt::Mat6 X_" << i << ";\n";
      if (tb.dofs > 0) o << "  " << block_type(6, tb.dofs) << " W_" << i << ";\n";
    }
    if (tb.joint >= 0) {
      o << "  " << block_type(6, rows(tb.joint)) << " Q_" << i << ";\n"
        << "  " << block_type(rows(tb.joint), rows(tb.joint)) << " G_" << i << ";\n";
    }
  }
  if (nps_cuts()) o << "  Eigen::Matrix<double, kCutRows, kCutRows> S_cut;  // Cholesky factor\n";
  if (a_.tunable_masses) o << "  Parameters params;  // the runtime masses it was formed with (factorize_tree)\n";
  o << "};\n\n";
}

void Emitter::nps_factorize(std::ostringstream& o) const {
  const TreePlan& tree = a_.tree;
  o << "// (k, c) => (t): the tree elimination, leaves first. IA of a body is its\n"
    << "// mass plus X^T (IA - W W^T) X of each child; false if a pivot is not positive.\n"
    << "static bool factorize_tree(" << mass_parameter()
    << "[[maybe_unused]] const Kinematics& k, [[maybe_unused]] const ConstraintSystem& c,\n                           [[maybe_unused]] TreeSystem& t) noexcept {\n"
    << "  bool positive = true;\n";
  if (a_.tunable_masses) o << "  t.params = s.params;\n";
  for (const TreeBody& tb : tree.order) {
    if (!tb.leaf) o << "  t.IA_" << body(tb.body).name << " = mbrt::mass_matrix(" << tree_mass(tb.body) << ");\n";
  }
  for (size_t n = tree.order.size(); n-- > 0;) {
    const TreeBody& tb = tree.order[n];
    const std::string i = body(tb.body).name;
    if (free_leaf(tb)) continue;
    o << "  {  // " << body(tb.body).name
      << (tb.joint >= 0 ? ", joint " + jname(tb.joint) + " to " + m_.body_name(tb.parent) : ", free") << "\n";
    if (tb.joint >= 0) {
      if (carries_parent_axes(tb)) {
        o << "    const mbrt::Mat3 to_child = " << pose(tb.body) << ".R.transpose() * " << pose(tb.parent) << ".R;\n";
      }
      const std::vector<std::string> cols = null_space_columns(tb);
      for (size_t q = 0; q < cols.size(); ++q) o << "    t.H_" << i << ".col(" << q << ") = " << cols[q] << ";\n";
    }
    if (tb.joint >= 0 && tb.dofs > 0) {
      o << "    const " << block_type(6, tb.dofs) << " U = "
        << (tb.leaf ? "mbrt::mass_times_columns(" + tree_mass(tb.body) + ", t.H_" + i + ")" : "t.IA_" + i + " * t.H_" + i)
        << ";\n"
        << "    t.L_" << i << " = t.H_" << i << ".transpose() * U;\n";
    } else if (tb.joint < 0) {  // a free body with children: H = I
      o << "    t.L_" << i << " = t.IA_" << i << ";\n";
    }
    if (tb.dofs > 0) o << "    positive = mbrt::cholesky_in_place(t.L_" << i << ") && positive;\n";
    if (tb.parent != kGround) {
      const std::string p = body(tb.parent).name;
      o << "    t.X_" << i << " = mbrt::rigid_transfer(" << pose(tb.parent) << ", " << pose(tb.body);
      if (tb.joint >= 0 && has_coincidence_rows(m_.joints[static_cast<size_t>(tb.joint)].type)) {
        const std::string f = jname(tb.joint) + "_frame.";
        o << ", " << f << (tb.child_is_body2 ? "s1, " : "s2, ") << f << (tb.child_is_body2 ? "s2" : "s1");
      }
      o << ");\n";
      if (tb.dofs > 0) {
        o << "    t.W_" << i << " = U;\n    mbrt::solve_right_lower_transposed(t.L_" << i << ", t.W_" << i << ");\n"
          << "    t.IA_" << p << " += t.X_" << i << ".transpose() * (" << ia_matrix(tb) << " - t.W_" << i << " * t.W_"
          << i << ".transpose()) * t.X_" << i << ";\n";
      } else {
        o << "    t.IA_" << p << " += t.X_" << i << ".transpose() * " << ia_matrix(tb) << " * t.X_" << i << ";\n";
      }
    }
    if (tb.joint >= 0) {
      const std::string J = rows_of(tb.joint) + "." + (tb.child_is_body2 ? "J2" : "J1");
      o << "    t.Q_" << i << " = mbrt::inverse_mass_times_transpose(" << tree_mass(tb.body) << ", " << J << ");\n"
        << "    t.G_" << i << " = " << J << " * t.Q_" << i << ";\n"
        << "    positive = mbrt::cholesky_in_place(t.G_" << i << ") && positive;\n"
        << "    mbrt::solve_right_lower_transposed(t.G_" << i << ", t.Q_" << i << ");\n";
    }
    o << "  }\n";
  }
  o << "  return positive;\n}\n\n";
}

// tree_solve with targets gives the particular parts and what the
// multipliers need; tree_response (targets zero) only the accelerations, for
// projections and the cut rows.
void Emitter::nps_tree_solve(std::ostringstream& o, bool with_targets) const {
  const TreePlan& tree = a_.tree;
  if (with_targets) {
    o << "// What tree_solve leaves per body for tree_multipliers.\n"
      << "struct TreeSolution {\n"
      << "  BodyVectors acc;   // u'\n"
      << "  BodyVectors g;     // IA a_p - force + what the children pass on\n"
      << "  BodyVectors part;  // a_p\n"
      << "};\n\n"
      << "// (t, force, target) => (x): the body accelerations u' = D z' + a_p with\n"
      << "// B u' = target on the tree rows and D^T (M u' - force) = 0. a_p = Q G^-1\n"
      << "// target is a particular solution per joint. Leaves first, then from the\n"
      << "// roots.\n"
      << "static void tree_solve([[maybe_unused]] const TreeSystem& t, const BodyVectors& force, [[maybe_unused]] const Rows& target,\n"
      << "                TreeSolution& x) noexcept {\n"
      << "  BodyVectors& acc = x.acc;\n  BodyVectors& g = x.g;\n  BodyVectors& part = x.part;\n"
      << "  for (int b = 0; b < kBodies; ++b) {\n    g[b] = -force[b];\n    part[b].setZero();\n  }\n";
  } else {
    o << "// (t, force) => (acc): u' = D z' with D^T (M u' - force) = 0, the tree's\n"
      << "// response to a force (with a momentum as force: the M-orthogonal\n"
      << "// projection onto the tree's velocity constraints).\n"
      << "static void tree_response([[maybe_unused]] const TreeSystem& t, const BodyVectors& force, BodyVectors& acc) noexcept {\n"
      << "  BodyVectors g;  // -force + what the children pass on\n"
      << "  for (int b = 0; b < kBodies; ++b) g[b] = -force[b];\n";
  }
  for (const TreeBody& tb : tree.order) {
    if (tb.dofs > 0 && !free_leaf(tb)) o << "  " << rows_type(tb.dofs) << " y_" << body(tb.body).name << ";  // L^-1 H^T g\n";
  }
  for (size_t n = tree.order.size(); n-- > 0;) {
    const TreeBody& tb = tree.order[n];
    const std::string i = body(tb.body).name;
    if (free_leaf(tb)) continue;
    o << "  {  // " << body(tb.body).name << "\n";
    if (with_targets && tb.joint >= 0) {
      o << "    " << rows_type(rows(tb.joint)) << " x = " << seg("target", tb.joint) << ";\n"
        << "    mbrt::solve_lower(t.G_" << i << ", x);\n"
        << "    part[body::" << i << "] = t.Q_" << i << " * x;\n"
        << "    g[body::" << i << "] += " << ia_times(tb, "part[body::" + i + "]") << ";\n";
    }
    if (tb.dofs > 0) {
      o << "    y_" << i << " = " << h_transpose_times(tb, "g[body::" + i + "]") << ";\n"
        << "    mbrt::solve_lower(t.L_" << i << ", y_" << i << ");\n";
    }
    if (tb.parent != kGround) {
      o << "    g" << at(tb.parent) << " += t.X_" << i << ".transpose() * "
        << (tb.dofs > 0 ? "(g[body::" + i + "] - t.W_" + i + " * y_" + i + ")" : "g[body::" + i + "]") << ";\n";
    }
    o << "  }\n";
  }
  for (const TreeBody& tb : tree.order) {
    const std::string i = body(tb.body).name;
    const std::string particular = with_targets ? "part[body::" + i + "]" : "";
    if (free_leaf(tb)) {
      o << "  acc[body::" << i << "] = mbrt::inverse_mass_times(" << tree_mass(tb.body) << ", force[body::" << i << "]);  // "
        << body(tb.body).name << ", free\n";
      continue;
    }
    o << "  {  // " << body(tb.body).name << "\n";
    if (tb.parent != kGround) {
      o << "    const mbrt::Vec6 carried = t.X_" << i << " * acc" << at(tb.parent) << ";\n"
        << "    acc[body::" << i << "] = carried" << (with_targets ? " + " + particular : "") << ";\n";
    } else {
      o << "    acc[body::" << i << "] = " << (with_targets ? particular : "mbrt::Vec6::Zero()") << ";\n";
    }
    if (tb.dofs > 0) {
      o << "    " << rows_type(tb.dofs) << " z = -y_" << i;
      if (tb.parent != kGround) o << " - t.W_" << i << ".transpose() * carried";
      o << ";\n    mbrt::solve_lower_transposed(t.L_" << i << ", z);\n"
        << "    acc[body::" << i << "] += " << h_times(tb, "z") << ";\n";
    }
    o << "  }\n";
  }
  o << "}\n\n";
}

// The tree joints' multipliers from the force each one carries, apart from
// tree_solve: with cut rows, constraint_forces solves the tree twice and
// needs them from the second solve only.
void Emitter::nps_tree_multipliers(std::ostringstream& o) const {
  o << "// (t, x) => (tree rows of lambda): each tree joint's force on its child,\n"
    << "// -B^T lambda = IA (u' - a_p) + g.\n"
    << "static void tree_multipliers([[maybe_unused]] const TreeSystem& t, [[maybe_unused]] const TreeSolution& x,\n                             [[maybe_unused]] Rows& lambda) noexcept {\n";
  for (const TreeBody& tb : a_.tree.order) {
    if (tb.joint < 0) continue;
    const std::string i = body(tb.body).name;
    o << "  {  // " << body(tb.body).name << "\n"
      << "    " << rows_type(rows(tb.joint)) << " l = -(t.Q_" << i << ".transpose() * ("
      << ia_times(tb, "mbrt::Vec6(x.acc[body::" + i + "] - x.part[body::" + i + "])") << " + x.g[body::" << i << "]));\n"
      << "    mbrt::solve_lower_transposed(t.G_" << i << ", l);\n"
      << "    " << seg("lambda", tb.joint) << " = l;\n  }\n";
  }
  o << "}\n\n";
}

void Emitter::nps_cut_rows(std::ostringstream& o) const {
  const TreePlan& tree = a_.tree;
  o << "using CutRows = Eigen::Matrix<double, kCutRows, 1>;\n\n"
    << "// (x) => (the cut rows of x, stacked)\n"
    << "static CutRows cut_rows_of(const Rows& x) noexcept {\n  CutRows y;\n";
  int offset = 0;
  for (int j : tree.cut_blocks) {
    o << "  y.segment<" << rows(j) << ">(" << offset << ") = " << seg("x", j) << ";  // " << jname(j) << "\n";
    offset += rows(j);
  }
  o << "  return y;\n}\n\n"
    << "// (c, u) => (B_cut u): jacobian_times on the cut rows alone\n"
    << "static CutRows cut_jacobian_times(const ConstraintSystem& c, const BodyVectors& u) noexcept {\n  CutRows y;\n";
  offset = 0;
  for (int j : tree.cut_blocks) {
    o << "  y.segment<" << rows(j) << ">(" << offset << ") = " << jacobian_product(j, "u") << ";\n";
    offset += rows(j);
  }
  o << "  return y;\n}\n\n"
    << "// (c, mu) => (B_cut^T mu per body)\n"
    << "static BodyVectors cut_forces(const ConstraintSystem& c, const CutRows& mu) noexcept {\n  BodyVectors f;\n"
    << "  for (mbrt::Vec6& x : f) x.setZero();\n";
  offset = 0;
  for (int j : tree.cut_blocks) {
    for (int b : moving_bodies(j)) {
      o << "  f" << at(b) << " += " << rows_of(j) << "." << side(j, b) << ".transpose() * mu.segment<" << rows(j)
        << ">(" << offset << ");\n";
    }
    offset += rows(j);
  }
  o << "  return f;\n}\n\n"
    << "// (c, t) => (t.S_cut): S_cut = B_cut T B_cut^T + kRegularization I with T\n"
    << "// the tree's response to a force, one tree solve per cut row.\n"
    << "static bool factorize_cut(const ConstraintSystem& c, TreeSystem& t) noexcept {\n"
    << "  BodyVectors acc;\n"
    << "  for (int r = 0; r < kCutRows; ++r) {\n"
    << "    tree_response(t, cut_forces(c, CutRows::Unit(r)), acc);\n"
    << "    t.S_cut.col(r) = cut_jacobian_times(c, acc);\n  }\n"
    << "  t.S_cut.diagonal().array() += kRegularization;\n"
    << "  return mbrt::cholesky_in_place(t.S_cut);\n}\n\n"
    << "// (t, x) => (x): x := S_cut^-1 x\n"
    << "static void solve_cut(const TreeSystem& t, CutRows& x) noexcept {\n"
    << "  mbrt::solve_lower(t.S_cut, x);\n  mbrt::solve_lower_transposed(t.S_cut, x);\n}\n\n"
    << "// (t, c, mu, u) => (u): u -= T B_cut^T mu\n"
    << "static void subtract_cut_response(const TreeSystem& t, const ConstraintSystem& c, const CutRows& mu,\n"
    << "                           BodyVectors& u) noexcept {\n"
    << "  BodyVectors du;\n"
    << "  tree_response(t, cut_forces(c, mu), du);\n"
    << "  for (int b = 0; b < kBodies; ++b) u[b] -= du[b];\n}\n\n";
}

void Emitter::nps_stages(std::ostringstream& o) const {
  nps_factorize(o);
  nps_tree_solve(o, true);
  nps_tree_multipliers(o);
  nps_tree_solve(o, false);
  if (nps_cuts()) nps_cut_rows(o);
  o << "// (c, t, l, u_half) => (u): implicit stage. u is the M-orthogonal projection\n"
    << "// of u_half + h/2 M^-1 F onto the tree's velocity constraints (a tree solve\n"
    << "// with the momentum as force), then onto the cut rows, regularized as in\n"
    << "// staggered-pcst.\n"
    << "static void implicit_stage(const ConstraintSystem& c, const TreeSystem& t, const Loads& l, const BodyVectors& u_half,\n"
    << "                    BodyVectors& u) noexcept {\n"
    << "  BodyVectors momentum;\n";
  for (int i = 0; i < static_cast<int>(m_.bodies.size()); ++i) {
    o << "  momentum" << at(i) << " = mbrt::mass_times(" << tree_mass(i) << ", u_half" << at(i)
      << ") + (0.5 * h) * mbrt::as_vector(l.w" << at(i) << ");\n";
  }
  o << "  tree_response(t, momentum, u);\n";
  if (nps_cuts()) {
    // velocity_residual on the cut rows: B_cut u + phi_t
    o << "  CutRows mu = cut_jacobian_times(c, u)" << (a_.rheonomic ? " + cut_rows_of(stacked_phi_t(c))" : "")
      << ";\n  solve_cut(t, mu);\n"
      << "  subtract_cut_response(t, c, mu, u);\n";
  } else {
    o << "  (void)c;\n";
  }
  o << "}\n\n"
    << "// (c, t, l, phi, s) => (s.lambda, accelerations): the accelerations meet\n"
    << "// B u' + quad + (2/h) (B u + alpha phi) = 0 on every row (eq. 7 of\n"
    << "// docs/staggered-pcst.md): exactly on the tree rows, through the\n"
    << "// regularized S_cut on the cut rows.\n"
    << "static void constraint_forces(const ConstraintSystem& c, const TreeSystem& t, const Loads& l, const Rows& phi,\n"
    << "                       State& s) noexcept {\n"
    << "  const Rows target = -(stacked_quad(c) + (2.0 / h) * (velocity_residual(c, generalized_velocities(s)) +\n"
    << "                                                        kStabilization * phi));\n"
    << "  BodyVectors f;\n  for (int b = 0; b < kBodies; ++b) f[b] = mbrt::as_vector(l.w[b]);\n"
    << "  TreeSolution x;\n  tree_solve(t, f, target, x);\n";
  if (nps_cuts()) {
    o << "  CutRows lambda_cut = cut_jacobian_times(c, x.acc) - cut_rows_of(target);\n  solve_cut(t, lambda_cut);\n"
      << "  const BodyVectors f_cut = cut_forces(c, lambda_cut);\n"
      << "  for (int b = 0; b < kBodies; ++b) f[b] -= f_cut[b];\n"
      << "  tree_solve(t, f, target, x);\n";
    int offset = 0;
    for (int j : a_.tree.cut_blocks) {
      o << "  " << seg("s.lambda", j) << " = lambda_cut.segment<" << rows(j) << ">(" << offset << ");\n";
      offset += rows(j);
    }
  }
  o << "  tree_multipliers(t, x, s.lambda);\n  set_accelerations(x.acc, s);\n}\n\n";
}

}  // namespace mbrt::codegen
