// The parallel step's phases (docs/parallel.md): a kernel whose statements
// fall into the partition's parts runs them as one fork and join of the
// model's WorkerTeam (include/mbrt/worker_team.hpp), part p on worker p. The
// statements and their order within a part are the serial kernel's, so the
// team's results equal its serial run's bit for bit.
#include "emitter.hpp"

namespace mbrt::codegen {

std::string Emitter::parallel_region(const std::vector<std::string>& part_lines, const std::string& enter,
                                     const std::string& leave) const {
  const auto indented = [](const std::string& lines, const std::string& by) {
    std::string out;
    size_t start = 0;
    while (start < lines.size()) {
      const size_t end = lines.find('\n', start);
      const std::string line = lines.substr(start, end == std::string::npos ? std::string::npos : end - start);
      out += (line.empty() ? "" : by) + line + "\n";
      if (end == std::string::npos) break;
      start = end + 1;
    }
    return out;
  };
  std::string o = "  {\n    auto phase = [&](int part) noexcept {\n" + indented(enter, "    ") + "      switch (part) {\n";
  for (size_t p = 0; p < part_lines.size(); ++p) {
    o += "        case " + std::to_string(p) + ":\n" + indented(part_lines[p], "      ") + "          break;\n";
  }
  o += "      }\n" + indented(leave, "    ") + "    };\n    team.run(phase);\n  }\n";
  return o;
}

// C x_I = r_I on the interface, C = S_II - sum_p L_Ip L_Ip^T the Schur
// complement of the parts, by a fixed number of preconditioned conjugate-
// gradient iterations from x_I = 0 (Hestenes and Stiefel 1952; the
// preconditioner is C's diagonal blocks' Cholesky factors or C's diagonal).
// C is applied without being formed: S_II p from the rows and the directions,
// L_Ip (L_Ip^T p) from the parts' factor blocks. The iteration count is fixed,
// so the work is; a converged iteration (zero residual) takes zero steps.
std::string Emitter::interface_pcg_lines(OpCount* count) const {
  const auto& order = a_.pattern.order;
  const auto& lower = a_.pattern.lower;
  const auto in_lower = [&](int j, int i) { return a_.pattern.kept(j, i); };
  std::vector<int> interface;
  std::vector<int> offset(static_cast<size_t>(blocks()), 0);
  int size = 0;
  for (int k : order) {
    if (!interface_block(k)) continue;
    interface.push_back(k);
    offset[static_cast<size_t>(k)] = size;
    size += rows(k);
  }
  const auto packed = [&](const std::string& v, int k) {
    return v + ".segment<" + std::to_string(rows(k)) + ">(" + std::to_string(offset[static_cast<size_t>(k)]) + ")";
  };
  OpCount ops_once, ops_iteration;
  std::ostringstream o;
  o << "  {  // the interface: " << a_.partition.pcg_iterations << " iterations of preconditioned conjugate gradients\n"
    << "    using InterfaceRows = Eigen::Matrix<double, " << size << ", 1>;\n"
    << "    InterfaceRows r, z, p, q, x_interface = InterfaceRows::Zero();\n";
  for (int k : interface) {  // the right-hand side less the parts' forward sweeps
    o << "    " << packed("r", k) << " = " << seg("x", k);
    for (int j : order) {
      if (interface_block(j) || !in_lower(j, k)) continue;
      o << "\n        - " << L(k, j) << " * " << seg("x", j);
      ops_once += ops::product(rows(k), rows(j), 1);
      ops_once += ops::sum(rows(k), 1);
    }
    o << ";\n";
  }
  const auto precondition = [&](OpCount& c) {
    std::string lines;
    for (int k : interface) {
      if (a_.partition.block_preconditioner) {
        lines += "    {\n      " + rows_type(rows(k)) + " y = " + packed("r", k) + ";\n      mbrt::solve_lower(" + L(k, k) +
                 ", y);\n      mbrt::solve_lower_transposed(" + L(k, k) + ", y);\n      " + packed("z", k) + " = y;\n    }\n";
        c += ops::triangular_solve(rows(k));
        c += ops::triangular_solve(rows(k));
      } else {
        lines += "    " + packed("z", k) + " = " + packed("r", k) + ".cwiseQuotient(" + L(k, k) + ".diagonal());\n";
        c += OpCount{0, 0, rows(k), 0};
      }
    }
    return lines;
  };
  o << precondition(ops_once) << "    p = z;\n    double rz = r.dot(z);\n"
    << "    for (int iteration = 0; iteration < " << a_.partition.pcg_iterations << "; ++iteration) {\n";
  // q = C p: the parts' terms through L_Ip^T p ...
  for (int j : order) {
    if (interface_block(j)) continue;
    std::string terms;
    for (int i : lower[static_cast<size_t>(j)]) {
      if (!interface_block(i)) continue;
      terms += (terms.empty() ? "" : "\n          + ") + L(i, j) + ".transpose() * " + packed("p", i);
      ops_iteration += ops::product(rows(j), rows(i), 1);
    }
    if (!terms.empty()) o << "      const " << rows_type(rows(j)) << " t_" << jname(j) << " = " << terms << ";\n";
  }
  // ... and S_II p from the rows and directions, body by body.
  for (int k : interface) {
    o << "      " << packed("q", k) << " = kRegularization * " << packed("p", k);
    std::vector<int> neighbours = {k};
    for (int i : a_.pattern.coupled[static_cast<size_t>(k)]) {
      if (interface_block(i)) neighbours.push_back(i);
    }
    for (int i : neighbours) {
      for (int b : moving_bodies(k)) {
        const auto mi = moving_bodies(i);
        if (std::find(mi.begin(), mi.end(), b) == mi.end()) continue;
        o << "\n          + " << rows_of(k) << "." << side(k, b) << " * (" << mbt(i, b) << " * " << packed("p", i) << ")";
        ops_iteration += ops::product(body_dofs(), rows(i), 1);
        ops_iteration += ops::product(rows(k), body_dofs(), 1);
      }
    }
    for (int j : order) {
      if (interface_block(j) || !in_lower(j, k)) continue;
      o << "\n          - " << L(k, j) << " * t_" << jname(j);
      ops_iteration += ops::product(rows(k), rows(j), 1);
    }
    o << ";\n";
  }
  o << "      const double pq = p.dot(q);\n      const double alpha = pq > 0.0 ? rz / pq : 0.0;\n"
    << "      x_interface += alpha * p;\n      r -= alpha * q;\n"
    << precondition(ops_iteration)
    << "      const double rz_next = r.dot(z);\n      const double beta = rz > 0.0 ? rz_next / rz : 0.0;\n"
    << "      p = z + beta * p;\n      rz = rz_next;\n    }\n";
  ops_iteration += OpCount{5 * size, 5 * size, 2, 0};  // two dot products and three updates
  for (int k : interface) o << "    " << seg("x", k) << " = " << packed("x_interface", k) << ";\n";
  o << "  }\n";
  if (count) {
    *count += ops_once;
    for (int it = 0; it < a_.partition.pcg_iterations; ++it) *count += ops_iteration;
  }
  return o.str();
}

void Emitter::worker_team_definition(std::ostringstream& o) const {
  if (!parallel()) return;
  o << "// The threads the step's phases run on (docs/parallel.md); start_workers()\n"
    << "// starts them, and until then the step runs every part on the caller's thread.\n"
    << "mbrt::WorkerTeam team{kParts};\n\n";
}

std::string Emitter::worker_declarations() const {
  if (!parallel()) {
    return "// The serial step: no worker threads to start (docs/parallel.md).\n"
           "inline void start_workers() {}\ninline void stop_workers() noexcept {}\n\n";
  }
  return "// Starts the kParts - 1 worker threads the step shares its phases with,\n"
         "// pinned to their own cores where permitted: call once before the loop (it\n"
         "// allocates). Until then, and after stop_workers(), step() runs the parts\n"
         "// one after the other on the caller's thread, with the same results.\n"
         "void start_workers();\nvoid stop_workers() noexcept;\n\n";
}

std::string Emitter::worker_functions() const {
  if (!parallel()) return "";
  return "void start_workers() { team.start(); }\n\nvoid stop_workers() noexcept { team.stop(); }\n\n";
}

}  // namespace mbrt::codegen
