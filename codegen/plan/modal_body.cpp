#include "modal_body.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace mbrt::codegen {

// Round-off where symmetry makes an entry zero (a bending mode's axial
// field, the other plane's coupling): zero, as generated code then says,
// against the largest entry of its kind.
template <class Matrix>
void zero_round_off(Matrix& m, double scale) {
  m = m.unaryExpr([&](double x) { return std::abs(x) <= 1e-12 * scale ? 0.0 : x; });
}

ModalPlan plan_modal_body(const BeamProperties& beam, int modes, double damping) {
  const int available = kNodeCoordinates * beam.elements;
  // Enough candidates that the lowest `modes` bending and axial ones are among
  // them whatever the torsion modes in between.
  const int candidates = std::min(available, 2 * modes + beam.elements + 6);
  const BeamModes all = beam_modes(beam, BeamSupport::clamped_root, candidates);
  const BeamField all_field = beam_field(beam, all.shapes);
  std::vector<int> chosen;
  for (int k = 0; k < candidates && static_cast<int>(chosen.size()) < modes; ++k) {
    double translational = 0.0;  // of the mode's unit modal mass
    for (size_t p = 0; p < all_field.displacement.size(); ++p) {
      translational += all_field.mass[static_cast<Eigen::Index>(p)] * all_field.displacement[p].col(k).squaredNorm();
    }
    if (translational > 0.5) chosen.push_back(k);
  }
  if (static_cast<int>(chosen.size()) < modes) {
    throw std::invalid_argument(std::to_string(modes) + " modes: " + std::to_string(beam.elements) +
                                " elements give " + std::to_string(chosen.size()) +
                                " bending and axial modes; use more elements");
  }
  ModalPlan p;
  p.modes = modes;
  const int n = static_cast<int>(all.shapes.rows());
  Eigen::MatrixXd shapes(n, modes);
  p.omega.resize(modes);
  for (int k = 0; k < modes; ++k) {
    shapes.col(k) = all.shapes.col(chosen[static_cast<size_t>(k)]);
    p.omega[k] = all.omega[chosen[static_cast<size_t>(k)]];
  }
  p.damping = damping * p.omega.cwiseAbs2();
  p.shapes = shapes;
  const double L = beam.length, centre = L / 2;
  p.m = beam.rho_A * L;
  p.J = Eigen::Vector3d(beam.rho_J * L, p.m * L * L / 12, p.m * L * L / 12).asDiagonal();
  p.root = Eigen::Vector3d(-centre, 0, 0);
  p.length = L;
  p.elements = beam.elements;

  // Invariants over the beam's mass, positions rho0 = (x - L/2, 0, 0).
  const BeamField f = beam_field(beam, shapes);
  Eigen::Matrix<double, 3, Eigen::Dynamic> St = Eigen::MatrixXd::Zero(3, modes), Sr = St;
  for (auto& e : p.E) e = Eigen::MatrixXd::Zero(modes, modes);
  for (auto& g : p.G) g = Eigen::RowVectorXd::Zero(modes);
  for (Eigen::Index k = 0; k < f.x.size(); ++k) {
    const double dm = f.mass[k];
    const Eigen::Vector3d rho0(f.x[k] - centre, 0, 0);
    const Eigen::Matrix<double, 3, Eigen::Dynamic>& u = f.displacement[static_cast<size_t>(k)];
    St += dm * u;
    for (int m = 0; m < modes; ++m) Sr.col(m) += dm * rho0.cross(u.col(m));
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        p.E[static_cast<size_t>(3 * a + b)] += dm * u.row(a).transpose() * u.row(b);
        p.G[static_cast<size_t>(3 * a + b)] += dm * rho0[a] * u.row(b);
      }
    }
  }
  p.St_T = St.transpose();
  p.Sr_T = Sr.transpose();
  Eigen::Matrix<double, 6, Eigen::Dynamic> S(6, modes);
  S << St, Sr;
  Eigen::Matrix<double, 6, 6> rigid = Eigen::Matrix<double, 6, 6>::Zero();
  rigid.topLeftCorner<3, 3>() = p.m * Eigen::Matrix3d::Identity();
  rigid.bottomRightCorner<3, 3>() = p.J;
  p.reduced_inverse = (rigid - S * S.transpose()).inverse();

  // Geometric stiffness: the axial force rho_A ((L^2 - x^2) / 2 - centre (L - x))
  // per unit (w_y^2 + w_z^2) about the centre, rho_A (L - x) per unit axial
  // acceleration towards the root (beam_modes' hub radius -centre, and 1 less 0).
  const auto projected = [&](double hub_radius) {
    const BeamMatrices m = assemble_beam(beam, hub_radius);
    return Eigen::MatrixXd(shapes.transpose() * m.KG * shapes);
  };
  p.kg_spin = projected(-centre);
  p.kg_axial = projected(1.0) - projected(0.0);
  const auto largest = [](const auto& list) {
    double x = 0;
    for (const auto& m : list) x = std::max(x, m.cwiseAbs().maxCoeff());
    return x;
  };
  const double coupling = std::max(p.St_T.cwiseAbs().maxCoeff(), p.Sr_T.cwiseAbs().maxCoeff());
  zero_round_off(p.St_T, coupling), zero_round_off(p.Sr_T, coupling);
  zero_round_off(p.kg_spin, p.kg_spin.cwiseAbs().maxCoeff()), zero_round_off(p.kg_axial, p.kg_axial.cwiseAbs().maxCoeff());
  zero_round_off(p.reduced_inverse, p.reduced_inverse.cwiseAbs().maxCoeff());
  const double e = largest(p.E), g = largest(p.G);
  for (auto& m : p.E) zero_round_off(m, e);
  for (auto& m : p.G) zero_round_off(m, g);
  return p;
}

ModalNode modal_node(const ModalPlan& p, int k) {
  ModalNode node;
  node.point = Eigen::Vector3d(p.length * (static_cast<double>(k) / p.elements - 0.5), 0, 0);
  node.displacement = p.shapes.block(kNodeCoordinates * k, 0, 3, p.modes);
  node.rotation = p.shapes.block(kNodeCoordinates * k + 3, 0, 3, p.modes);
  const double largest = std::max(node.displacement.cwiseAbs().maxCoeff(), node.rotation.cwiseAbs().maxCoeff());
  zero_round_off(node.displacement, largest), zero_round_off(node.rotation, largest);
  return node;
}

}  // namespace mbrt::codegen
