#include "beam_modes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace mbrt::codegen {

namespace {

// Four-point Gauss-Legendre on [0, 1]: exact to degree 7, enough for the
// cubic shapes' mass (degree 6) and the quadratic axial force times the
// shapes' slopes (degree 6).
constexpr std::array<double, 4> kGaussPoints{0.0694318442029737, 0.3300094782075719, 0.6699905217924281,
                                             0.9305681557970263};
constexpr std::array<double, 4> kGaussWeights{0.1739274225687269, 0.3260725774312731, 0.3260725774312731,
                                              0.1739274225687269};

// Cubic Hermite shapes of a bending plane on an element of length l, for the
// coordinates (w_i, w'_i, w_j, w'_j) at s = x / l: values, slopes, curvatures.
using Row4 = Eigen::Matrix<double, 1, 4>;
Row4 hermite(double s, double l) {
  return {1 - 3 * s * s + 2 * s * s * s, l * (s - 2 * s * s + s * s * s), 3 * s * s - 2 * s * s * s, l * (s * s * s - s * s)};
}
Row4 hermite_slope(double s, double l) {
  return {(6 * s * s - 6 * s) / l, 1 - 4 * s + 3 * s * s, (6 * s - 6 * s * s) / l, 3 * s * s - 2 * s};
}
Row4 hermite_curvature(double s, double l) {
  return {(12 * s - 6) / (l * l), (6 * s - 4) / l, (6 - 12 * s) / (l * l), (6 * s - 2) / l};
}

struct Element {
  Eigen::Matrix<double, 12, 12> M, K, KG;
};

// One element from x0 to x0 + l of the beam in local coordinates
// (u, v, w, rx, ry, rz) at its two nodes.
Element element(const BeamProperties& b, double x0, double l, double hub_radius) {
  Element e;
  e.M.setZero();
  e.K.setZero();
  e.KG.setZero();
  // Axial (u) and torsion (rx): linear shapes.
  const auto two_node = [&](int c, double stiffness, double inertia) {
    const int i = c, j = kNodeCoordinates + c;
    e.K(i, i) = e.K(j, j) = stiffness / l;
    e.K(i, j) = e.K(j, i) = -stiffness / l;
    e.M(i, i) = e.M(j, j) = inertia * l / 3;
    e.M(i, j) = e.M(j, i) = inertia * l / 6;
  };
  two_node(0, b.EA, b.rho_A);
  two_node(3, b.GJ, b.rho_J);
  // Bending: v with slope rz (plane x-y), w with slope -ry (plane x-z).
  const double L = b.length;
  const auto plane = [&](int w, int slope, double sign, double EI) {
    const std::array<int, 4> at{w, slope, kNodeCoordinates + w, kNodeCoordinates + slope};
    const Eigen::Vector4d signs(1.0, sign, 1.0, sign);
    for (size_t g = 0; g < kGaussPoints.size(); ++g) {
      const double s = kGaussPoints[g], dx = kGaussWeights[g] * l, x = x0 + s * l;
      const double axial_force = b.rho_A * ((L * L - x * x) / 2 + hub_radius * (L - x));
      const Row4 h = hermite(s, l).cwiseProduct(signs.transpose());
      const Row4 slope_row = hermite_slope(s, l).cwiseProduct(signs.transpose());
      const Row4 curvature = hermite_curvature(s, l).cwiseProduct(signs.transpose());
      for (int p = 0; p < 4; ++p) {
        for (int q = 0; q < 4; ++q) {
          e.M(at[p], at[q]) += b.rho_A * h[p] * h[q] * dx;
          e.K(at[p], at[q]) += EI * curvature[p] * curvature[q] * dx;
          e.KG(at[p], at[q]) += axial_force * slope_row[p] * slope_row[q] * dx;
        }
      }
    }
  };
  plane(1, 5, 1.0, b.EIz);
  plane(2, 4, -1.0, b.EIy);
  return e;
}

// The coordinates a support leaves free.
std::vector<int> free_coordinates(const BeamProperties& b, BeamSupport support) {
  std::vector<int> out;
  const int first = support == BeamSupport::clamped_root ? kNodeCoordinates : 0;
  for (int i = first; i < kNodeCoordinates * (b.elements + 1); ++i) out.push_back(i);
  return out;
}

Eigen::MatrixXd restrict(const Eigen::MatrixXd& A, const std::vector<int>& keep) {
  Eigen::MatrixXd R(keep.size(), keep.size());
  for (size_t i = 0; i < keep.size(); ++i) {
    for (size_t j = 0; j < keep.size(); ++j) R(i, j) = A(keep[i], keep[j]);
  }
  return R;
}

}  // namespace

void check_beam(const BeamProperties& b) {
  const std::array<std::pair<const char*, double>, 7> positive{{{"length", b.length},
                                                                {"EA", b.EA},
                                                                {"GJ", b.GJ},
                                                                {"EIy", b.EIy},
                                                                {"EIz", b.EIz},
                                                                {"rho_A", b.rho_A},
                                                                {"rho_J", b.rho_J}}};
  for (const auto& [name, value] : positive) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(std::string("beam ") + name + ": expected a finite number > 0, got " +
                                  std::to_string(value));
    }
  }
  if (b.elements < 1) throw std::invalid_argument("beam elements: expected at least 1, got " + std::to_string(b.elements));
}

BeamMatrices assemble_beam(const BeamProperties& b, double hub_radius) {
  check_beam(b);
  const int n = kNodeCoordinates * (b.elements + 1);
  BeamMatrices out{Eigen::MatrixXd::Zero(n, n), Eigen::MatrixXd::Zero(n, n), Eigen::MatrixXd::Zero(n, n)};
  const double l = b.length / b.elements;
  for (int k = 0; k < b.elements; ++k) {
    const Element e = element(b, k * l, l, hub_radius);
    const int at = kNodeCoordinates * k;
    out.M.block<12, 12>(at, at) += e.M;
    out.K.block<12, 12>(at, at) += e.K;
    out.KG.block<12, 12>(at, at) += e.KG;
  }
  return out;
}

BeamModes beam_modes(const BeamProperties& b, BeamSupport support, int kept, double hub_radius) {
  const BeamMatrices full = assemble_beam(b, hub_radius);
  const std::vector<int> keep = free_coordinates(b, support);
  const int rigid = support == BeamSupport::free ? 6 : 0;
  if (kept < 1 || kept + rigid > static_cast<int>(keep.size())) {
    throw std::invalid_argument("beam modes: " + std::to_string(kept) + " kept, but " + std::to_string(b.elements) +
                                " elements give " + std::to_string(keep.size() - rigid) + " elastic modes");
  }
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(restrict(full.K, keep), restrict(full.M, keep));
  if (eig.info() != Eigen::Success) throw std::runtime_error("beam modes: the eigensolver failed");
  BeamModes m;
  const int n = static_cast<int>(full.M.rows());
  m.shapes = Eigen::MatrixXd::Zero(n, kept);
  m.omega.resize(kept);
  for (int k = 0; k < kept; ++k) {
    // Eigen sorts ascending; the free beam's 6 rigid-body modes come first.
    m.omega[k] = std::sqrt(std::max(0.0, eig.eigenvalues()[rigid + k]));
    for (size_t i = 0; i < keep.size(); ++i) m.shapes(keep[i], k) = eig.eigenvectors()(i, rigid + k);
    // A mode's sign is the solver's choice, which rounding can flip between
    // builds; its largest entry positive makes the generated constants the same.
    Eigen::Index largest = 0;
    m.shapes.col(k).cwiseAbs().maxCoeff(&largest);
    if (m.shapes(largest, k) < 0) m.shapes.col(k) *= -1.0;
  }
  m.KG = m.shapes.transpose() * full.KG * m.shapes;
  m.alpha.resize(3, kept);
  m.beta.resize(3, kept);
  const double l = b.length / b.elements;
  for (int d = 0; d < 3; ++d) {
    Eigen::VectorXd translation = Eigen::VectorXd::Zero(n), rotation = Eigen::VectorXd::Zero(n);
    for (int node = 0; node <= b.elements; ++node) {
      const int at = kNodeCoordinates * node;
      translation[at + d] = 1.0;
      // A small rotation e_d about the root moves the node at (x, 0, 0) by e_d x (x, 0, 0).
      const Eigen::Vector3d moved = Eigen::Vector3d::Unit(d).cross(Eigen::Vector3d(node * l, 0, 0));
      rotation.segment<3>(at) = moved;
      rotation[at + 3 + d] = 1.0;
    }
    m.alpha.row(d) = (m.shapes.transpose() * full.M * translation).transpose();
    m.beta.row(d) = (m.shapes.transpose() * full.M * rotation).transpose();
  }
  return m;
}

Eigen::VectorXd clamped_static_displacement(const BeamProperties& b, const Eigen::VectorXd& load, double spin_rate,
                                            double hub_radius) {
  const BeamMatrices full = assemble_beam(b, hub_radius);
  if (load.size() != full.K.rows()) {
    throw std::invalid_argument("beam load: expected " + std::to_string(full.K.rows()) + " entries, got " +
                                std::to_string(load.size()));
  }
  const std::vector<int> keep = free_coordinates(b, BeamSupport::clamped_root);
  const Eigen::MatrixXd K = restrict(full.K + spin_rate * spin_rate * full.KG, keep);
  Eigen::VectorXd f(keep.size());
  for (size_t i = 0; i < keep.size(); ++i) f[i] = load[keep[i]];
  const Eigen::VectorXd u = K.ldlt().solve(f);
  Eigen::VectorXd out = Eigen::VectorXd::Zero(full.K.rows());
  for (size_t i = 0; i < keep.size(); ++i) out[keep[i]] = u[i];
  return out;
}

BeamField beam_field(const BeamProperties& b, const Eigen::MatrixXd& shapes) {
  check_beam(b);
  const int modes = static_cast<int>(shapes.cols());
  const double l = b.length / b.elements;
  const int points = b.elements * static_cast<int>(kGaussPoints.size());
  BeamField f{Eigen::VectorXd(points), Eigen::VectorXd(points), {}};
  f.displacement.reserve(static_cast<size_t>(points));
  for (int k = 0; k < b.elements; ++k) {
    const int i = kNodeCoordinates * k, j = i + kNodeCoordinates;
    for (size_t g = 0; g < kGaussPoints.size(); ++g) {
      const double s = kGaussPoints[g];
      const int at = k * static_cast<int>(kGaussPoints.size()) + static_cast<int>(g);
      f.x[at] = (k + s) * l;
      f.mass[at] = b.rho_A * kGaussWeights[g] * l;
      const Row4 h = hermite(s, l);
      Eigen::Matrix<double, 3, Eigen::Dynamic> u(3, modes);
      for (int m = 0; m < modes; ++m) {
        const auto c = shapes.col(m);
        u(0, m) = (1 - s) * c[i] + s * c[j];
        u(1, m) = h[0] * c[i + 1] + h[1] * c[i + 5] + h[2] * c[j + 1] + h[3] * c[j + 5];
        u(2, m) = h[0] * c[i + 2] - h[1] * c[i + 4] + h[2] * c[j + 2] - h[3] * c[j + 4];
      }
      f.displacement.push_back(u);
    }
  }
  return f;
}

}  // namespace mbrt::codegen
