// The position stage's Newton matrix G = B(q*) M^-1 B(q(t))^T (staggered-pcst,
// docs/stability.md): block LU over the pattern of S, in S's elimination
// order. G is S(q*) plus a perturbation of the order of the rotation in one
// step, so its diagonal blocks stay invertible where S's do; the blocks are
// inverted with partial pivoting.
#include <algorithm>

#include "emitter.hpp"

namespace mbrt::codegen {

void Emitter::newton_matrix_type(std::ostringstream& o) const {
  o << "// Block LU factors of the position stage's Newton matrix G = B(q*) M^-1 B(q(t))^T:\n"
    << "// G = L U with unit-diagonal L, U's diagonal blocks kept inverted. Per\n"
    << "// constraint block: D, its row of L (L_OTHER) and of U (U_OTHER).\n"
    << "struct NewtonMatrix {\n";
  for (int k : a_.pattern.order) {
    o << "  struct {\n    " << block_type(rows(k), rows(k)) << " D;  // inverted\n";
    for (int j : a_.pattern.order) {
      const auto& lower = a_.pattern.lower[static_cast<size_t>(j)];
      if (std::find(lower.begin(), lower.end(), k) != lower.end()) {
        o << "    " << block_type(rows(k), rows(j)) << " L_" << jname(j) << ";\n";
      }
    }
    for (int i : a_.pattern.lower[static_cast<size_t>(k)]) {
      o << "    " << block_type(rows(k), rows(i)) << " U_" << jname(i) << ";\n";
    }
    o << "  } " << jname(k) << ";\n";
  }
  o << "};\n\n";
}

void Emitter::newton_matrix(std::ostringstream& o) const {
  const auto& order = a_.pattern.order;
  const auto& lower = a_.pattern.lower;
  auto coupled = [&](int j, int i) { return a_.pattern.kept(j, i); };  // block (i, j) kept, j before i
  // Block (i, k) of G: B_i(q*) from c, M^-1 B_k(q(t))^T from c0.
  auto g_block = [&](int i, int k) { return s_block(i, k, "c0"); };
  auto lo = [&](int i, int k) { return "g." + jname(i) + ".L_" + jname(k); };
  auto up = [&](int k, int i) { return "g." + jname(k) + ".U_" + jname(i); };
  auto pivot = [&](int k) { return "g." + jname(k) + ".D"; };

  OpCount factor;
  std::ostringstream body;  // the serial step's, or the interface's
  // The parallel step: each part's blocks in its own stream.
  std::vector<std::ostringstream> part_body(static_cast<size_t>(parts()));
  const auto stream = [&](int k) -> std::ostringstream& {
    return parallel() && !interface_block(k) ? part_body[static_cast<size_t>(phase_part(k))] : body;
  };
  const auto part_lines = [&]() {
    std::vector<std::string> lines;
    for (auto& p : part_body) {
      lines.push_back(p.str());
      p.str("");
    }
    return lines;
  };
  for (size_t pk = 0; pk < order.size(); ++pk) {
    const int k = order[pk];
    std::ostringstream& out = stream(k);
    out << "  // " << jname(k) << "\n  " << pivot(k) << " = " << g_block(k, k) << " + kNewtonShift * "
         << block_type(rows(k), rows(k)) << "::Identity()";
    factor += s_block_ops(k, k);
    factor += ops::sum(rows(k), 1);
    for (size_t pj = 0; pj < pk; ++pj) {
      const int j = order[pj];
      if (!coupled(j, k)) continue;
      out << "\n      - " << lo(k, j) << " * " << up(j, k);
      factor += ops::product(rows(k), rows(j), rows(k));
      factor += ops::sum(rows(k), rows(k));
    }
    out << ";\n";
    for (int i : lower[static_cast<size_t>(k)]) {
      out << "  " << lo(i, k) << " = " << g_block(i, k);
      factor += s_block_ops(i, k);
      for (size_t pj = 0; pj < pk; ++pj) {
        const int j = order[pj];
        if (!(coupled(j, k) && coupled(j, i))) continue;
        out << "\n      - " << lo(i, j) << " * " << up(j, k);
        factor += ops::product(rows(i), rows(j), rows(k));
        factor += ops::sum(rows(i), rows(k));
      }
      out << ";\n  " << up(k, i) << " = " << g_block(k, i);
      factor += s_block_ops(k, i);
      for (size_t pj = 0; pj < pk; ++pj) {
        const int j = order[pj];
        if (!(coupled(j, k) && coupled(j, i))) continue;
        out << "\n      - " << lo(k, j) << " * " << up(j, i);
        factor += ops::product(rows(k), rows(j), rows(i));
        factor += ops::sum(rows(k), rows(i));
      }
      out << ";\n";
    }
    out << "  mbrt::invert_with_pivoting(" << pivot(k) << ");\n";
    factor += ops::lu_inverse(rows(k));
    for (int i : lower[static_cast<size_t>(k)]) {
      out << "  " << lo(i, k) << " = " << lo(i, k) << " * " << pivot(k) << ";\n";
      factor += ops::product(rows(i), rows(k), rows(k));
    }
  }
  if (blocks() == 0) body << "  (void)c0;\n  (void)c;\n  (void)g;\n";
  o << "// (c0.*.mbt_*, c.*.rows) => (g): G block by block in S's elimination order.\n"
    << "// " << factor.text() << ".\n"
    << "static void factorize_newton(const ConstraintSystem& c0, const ConstraintSystem& c, NewtonMatrix& g) noexcept {\n"
    << (parallel() ? parallel_region(part_lines()) + "  // the interface\n" : "") << body.str() << "}\n\n";

  OpCount solving;
  body.str("");
  for (size_t pk = 0; pk < order.size(); ++pk) {
    const int k = order[pk];
    for (size_t pj = 0; pj < pk; ++pj) {
      const int j = order[pj];
      if (!coupled(j, k)) continue;
      stream(k) << "  " << seg("x", k) << " -= " << lo(k, j) << " * " << seg("x", j) << ";\n";
      solving += ops::product(rows(k), rows(j), 1);
      solving += ops::sum(rows(k), 1);
    }
  }
  // Forward: the parts, then the interface; backward: the interface, then the parts.
  std::string lines = parallel() ? parallel_region(part_lines()) + "  // the interface\n" : "";
  for (size_t pk = order.size(); pk-- > 0;) {
    const int k = order[pk];
    std::ostringstream& out = stream(k);
    out << "  {  // " << jname(k) << "\n    " << rows_type(rows(k)) << " y = " << seg("x", k) << ";\n";
    for (int i : lower[static_cast<size_t>(k)]) {
      out << "    y -= " << up(k, i) << " * " << seg("x", i) << ";\n";
      solving += ops::product(rows(k), rows(i), 1);
      solving += ops::sum(rows(k), 1);
    }
    out << "    " << seg("x", k) << " = " << pivot(k) << " * y;\n  }\n";
    solving += ops::product(rows(k), rows(k), 1);
  }
  lines += body.str() + (parallel() ? parallel_region(part_lines()) : "");
  o << "// (g, x) => (x): x := G^-1 x by forward and backward substitution.\n"
    << "// " << solving.text() << ".\n"
    << "static void solve_newton(const NewtonMatrix& g, Rows& x) noexcept {\n" << lines << "}\n\n";
}

}  // namespace mbrt::codegen
