// The position stage's Newton matrix G = B(q*) M^-1 B(q(t))^T (staggered-pcst,
// docs/stability.md): block LU over the pattern of S, in S's elimination
// order. G is S(q*) plus a perturbation of the order of the rotation in one
// step, so its diagonal blocks stay invertible where S's do; the blocks are
// inverted with partial pivoting.
#include <algorithm>

#include "emitter.hpp"

namespace mbrt::codegen {

namespace {

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size())) s.replace(at, from.size(), to);
  return s;
}

}  // namespace

void Emitter::newton_matrix_type(std::ostringstream& o) const {
  o << "// Block LU factors of the position stage's Newton matrix G = B(q*) M^-1 B(q(t))^T:\n"
    << "// G = L U with unit-diagonal L, U's diagonal blocks kept inverted.\n"
    << "struct NewtonMatrix {\n";
  for (int k : a_.pattern.order) {
    o << "  " << block_type(rows(k), rows(k)) << " D_" << k << ";  // " << jname(k) << ", inverted\n";
    for (int i : a_.pattern.lower[static_cast<size_t>(k)]) {
      o << "  " << block_type(rows(i), rows(k)) << " L_" << i << "_" << k << ";\n"
        << "  " << block_type(rows(k), rows(i)) << " U_" << k << "_" << i << ";\n";
    }
  }
  o << "};\n\n";
}

void Emitter::newton_matrix(std::ostringstream& o) const {
  const auto& order = a_.pattern.order;
  const auto& lower = a_.pattern.lower;
  auto coupled = [&](int j, int i) {  // block (i, j) of the factor is kept, j before i in the order
    const auto& v = lower[static_cast<size_t>(j)];
    return std::find(v.begin(), v.end(), i) != v.end();
  };
  // Block (i, k) of G: B_i(q*) from c, M^-1 B_k(q(t))^T from c0.
  auto g_block = [&](int i, int k) { return replace_all(s_block(i, k), "c.mbt_", "c0.mbt_"); };
  auto lo = [](int i, int k) { return "g.L_" + std::to_string(i) + "_" + std::to_string(k); };
  auto up = [](int k, int i) { return "g.U_" + std::to_string(k) + "_" + std::to_string(i); };
  auto pivot = [](int k) { return "g.D_" + std::to_string(k); };

  o << "// (c0.mbt_*, c.rows_*) => (g): G block by block in S's elimination order.\n"
    << "static void factorize_newton(const ConstraintSystem& c0, const ConstraintSystem& c, NewtonMatrix& g) noexcept {\n";
  for (size_t pk = 0; pk < order.size(); ++pk) {
    const int k = order[pk];
    o << "  // " << jname(k) << "\n  " << pivot(k) << " = " << g_block(k, k) << " + kNewtonShift * "
      << block_type(rows(k), rows(k)) << "::Identity()";
    for (size_t pj = 0; pj < pk; ++pj) {
      const int j = order[pj];
      if (coupled(j, k)) o << "\n      - " << lo(k, j) << " * " << up(j, k);
    }
    o << ";\n";
    for (int i : lower[static_cast<size_t>(k)]) {
      o << "  " << lo(i, k) << " = " << g_block(i, k);
      for (size_t pj = 0; pj < pk; ++pj) {
        const int j = order[pj];
        if (coupled(j, k) && coupled(j, i)) o << "\n      - " << lo(i, j) << " * " << up(j, k);
      }
      o << ";\n  " << up(k, i) << " = " << g_block(k, i);
      for (size_t pj = 0; pj < pk; ++pj) {
        const int j = order[pj];
        if (coupled(j, k) && coupled(j, i)) o << "\n      - " << lo(k, j) << " * " << up(j, i);
      }
      o << ";\n";
    }
    o << "  " << pivot(k) << " = " << pivot(k) << ".partialPivLu().inverse();\n";
    for (int i : lower[static_cast<size_t>(k)]) o << "  " << lo(i, k) << " = " << lo(i, k) << " * " << pivot(k) << ";\n";
  }
  if (blocks() == 0) o << "  (void)c0;\n  (void)c;\n  (void)g;\n";
  o << "}\n\n"
    << "// (g, x) => (x): x := G^-1 x by forward and backward substitution.\n"
    << "static void solve_newton(const NewtonMatrix& g, Rows& x) noexcept {\n";
  for (size_t pk = 0; pk < order.size(); ++pk) {
    const int k = order[pk];
    for (size_t pj = 0; pj < pk; ++pj) {
      const int j = order[pj];
      if (coupled(j, k)) o << "  " << seg("x", k) << " -= " << lo(k, j) << " * " << seg("x", j) << ";\n";
    }
  }
  for (size_t pk = order.size(); pk-- > 0;) {
    const int k = order[pk];
    o << "  {  // " << jname(k) << "\n    " << rows_type(rows(k)) << " y = " << seg("x", k) << ";\n";
    for (int i : lower[static_cast<size_t>(k)]) o << "    y -= " << up(k, i) << " * " << seg("x", i) << ";\n";
    o << "    " << seg("x", k) << " = " << pivot(k) << " * y;\n  }\n";
  }
  o << "}\n\n";
}

}  // namespace mbrt::codegen
