#include "modal_range.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>


namespace mbrt::codegen {
namespace {

// The largest node displacement at q, and its node.
std::pair<double, int> largest_displacement(const std::vector<ModalNode>& nodes, const Eigen::VectorXd& q) {
  std::pair<double, int> largest{0.0, 0};
  for (size_t k = 0; k < nodes.size(); ++k) {
    const double d = (nodes[k].displacement * q).norm();
    if (d > largest.first) largest = {d, static_cast<int>(k)};
  }
  return largest;
}

template <int N>
ModalRange search(const ModalPlan& p) {
  const mbrt::ModalBody<N> body = step_constants<N>(p);
  ModalRange r;
  std::vector<ModalNode> nodes;
  for (size_t k = 0; k < p.node_names.size(); ++k) {
    nodes.push_back(modal_node(p, static_cast<int>(k)));
    for (size_t j = 0; j < k; ++j) r.span = std::max(r.span, (p.node_points[k] - p.node_points[j]).norm());
  }
  using Modes = Eigen::Matrix<double, N, 1>;
  const auto definite = [&](const Modes& q) {
    const Eigen::Matrix<double, 6, 6> reduced = mbrt::modal_reduced_mass<N>(body, q);
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(reduced, Eigen::EigenvaluesOnly).eigenvalues()[0] > 0.0;
  };
  const Modes stiffness = p.omega.cwiseAbs2();
  const double reach = kModalRangeSpan * r.span;
  if (!(reach > 0.0)) return r;  // nodes in one place: no length to measure deflections by
  double least = INFINITY;  // t at unit strain stiffness d^T K d = 1: U = t^2 / 2
  std::mt19937 random(20261201u);
  std::normal_distribution<double> normal;
  for (int k = 0; k < 2 * N + 400; ++k) {
    Modes d = Modes::Zero();
    if (k < 2 * N) {
      d[k / 2] = k % 2 == 0 ? 1.0 : -1.0;
    } else {
      for (int i = 0; i < N; ++i) d[i] = normal(random);
    }
    const double energy = d.dot(stiffness.cwiseProduct(d));
    if (!(energy > 0.0)) continue;
    d /= std::sqrt(energy);
    const double unit = largest_displacement(nodes, Eigen::VectorXd(d)).first;  // per unit t
    if (!(unit > 0.0)) continue;
    // Out from a node displacement of 1e-4 of the reach, by 5 %, then bisected.
    double inside = 1e-4 * reach / unit, t = inside;
    while (t * unit <= reach && t < least && definite(Modes(t * d))) inside = t, t *= 1.05;
    if (t * unit > reach || t >= least) continue;
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (inside + t);
      (definite(Modes(mid * d)) ? inside : t) = mid;
    }
    least = t;
    const auto [displacement, node] = largest_displacement(nodes, Eigen::VectorXd(t * d));
    r.bounded = true;
    r.strain_energy = 0.5 * t * t;
    r.node_displacement = displacement;
    r.node = p.node_names[static_cast<size_t>(node)];
    r.deflection = t * d;
  }
  return r;
}

}  // namespace

ModalRange modal_definite_range(const ModalPlan& p) {
  switch (p.modes) {
    case 1: return search<1>(p);
    case 2: return search<2>(p);
    case 3: return search<3>(p);
    case 4: return search<4>(p);
    case 5: return search<5>(p);
    case 6: return search<6>(p);
    default: throw std::logic_error("modal_definite_range: " + std::to_string(p.modes) + " modes, expected 1 to " + std::to_string(kMaxModes));
  }
}

std::string modal_range_warning(const Model& m, const StableStep& s, const std::vector<ModalPlan>& plans) {
  const bool loaded = !m.drivers.empty() || !m.inputs.empty() ||
                      std::any_of(m.forces.begin(), m.forces.end(), [](const Force& f) {
                        return f.type == ForceType::force || f.type == ForceType::torque;
                      });
  std::ostringstream o;
  for (const ModalPlan& p : plans) {
    const ModalRange r = modal_definite_range(p);
    if (!r.bounded || (!loaded && s.energy_bound < r.strain_energy)) continue;
    if (!o.str().empty()) o << "\n";
    o << "warning: " << m.name << ": modal body " << m.body_name(p.body) << ": its frame's reduced mass stops being"
      << " positive definite at a strain energy of " << format(r.strain_energy) << " J (node " << r.node << " displaced "
      << format(r.node_displacement) << " m, " << format(100 * r.node_displacement / r.span) << " % of the body's "
      << format(r.span) << " m); past it the step's factor of that mass is wrong, and a step can stop (staggered-pcst, non-finite or with its constraint matrix no longer positive definite) or run on a wrong inverse, which moves the frame wrongly where its joints do not hold it; "
      << (loaded ? "the scene's drivers, inputs or forces can bend it that far"
                 : "the scene can release " + format(s.energy_bound) + " J")
      << ". Keep its deflection below that, or model it as a nodal beam (docs/flexible.md)";
  }
  return o.str();
}

}  // namespace mbrt::codegen
