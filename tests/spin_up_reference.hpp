// Simo & Vu-Quoc's spin-up (1986, "On the dynamics of flexible beams under
// large overall motions: the plane case", J. Appl. Mech. 53): the hub's
// angle and an independent reference for the tip's deflection, for the tests
// of nodal beams and modal bodies.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "beam_modes.hpp"

namespace spin_up {

// The spin-up's hub angle and its derivatives (Simo & Vu-Quoc 1986).
inline std::array<double, 3> hub_angle(double t) {
  const double a = 15.0 / (2 * M_PI), w = 2 * M_PI / 15.0;
  if (t >= 15.0) return {6 * t - 45, 6, 0};
  return {0.4 * (t * t / 2 + a * a * (std::cos(w * t) - 1)), 0.4 * (t - a * std::sin(w * t)), 0.4 * (1 - std::cos(w * t))};
}

// The reference: the beam's in-plane cantilever modes (40 cubic elements) in
// the hub's rotating frame, with the centrifugal softening of the transverse
// motion and the geometric stiffness of the axial load (Kane, Ryan &
// Banerjee 1987), driven by the hub's angular acceleration:
//   q'' + (Omega^2 + theta'^2 (KG - M_transverse)) q = -theta'' beta_z,
// stepped by the classical Runge-Kutta method at 1 ms.
struct SpinUpReference {
  std::vector<double> tip;  // transverse tip deflection every 10 ms
  bool diverged = false;
};

inline SpinUpReference spin_up_reference(bool geometric_stiffness) {
  mbrt::codegen::BeamProperties b;
  b.length = 10.0;
  b.EIz = 1.4e4;  // in-plane bending
  b.EIy = 1.4e7;  // out of plane: held far above
  b.EA = 2.8e9;
  b.GJ = 1.4e7;
  b.rho_A = 1.2;
  b.rho_J = 1e-3;
  b.elements = 40;
  const int kept = 5;
  const auto modes = mbrt::codegen::beam_modes(b, mbrt::codegen::BeamSupport::clamped_root, kept);
  const auto full = mbrt::codegen::assemble_beam(b);
  // The in-plane transverse motion: y displacements and z rotations.
  Eigen::MatrixXd transverse = full.M;
  for (int i = 0; i < transverse.rows(); ++i) {
    for (int j = 0; j < transverse.cols(); ++j) {
      const bool in_plane = (i % 6 == 1 || i % 6 == 5) && (j % 6 == 1 || j % 6 == 5);
      if (!in_plane) transverse(i, j) = 0;
    }
  }
  const Eigen::MatrixXd softening = modes.shapes.transpose() * transverse * modes.shapes;
  const Eigen::MatrixXd stiffening = geometric_stiffness ? modes.KG : Eigen::MatrixXd::Zero(kept, kept);
  const Eigen::VectorXd drive = modes.beta.row(2).transpose();
  const Eigen::RowVectorXd tip_row = modes.shapes.row(6 * b.elements + 1);
  using V = Eigen::VectorXd;
  const auto rate = [&](double t, const V& y) {
    const auto th = hub_angle(t);
    V out(2 * kept);
    out.head(kept) = y.tail(kept);
    out.tail(kept) = -(modes.omega.cwiseAbs2().asDiagonal() * y.head(kept)) -
                     th[1] * th[1] * ((stiffening - softening) * y.head(kept)) - th[2] * drive;
    return out;
  };
  SpinUpReference r;
  V y = V::Zero(2 * kept);
  const double h = 1e-3;
  for (int i = 0; i < 20000; ++i) {
    const double t = i * h;
    const V k1 = rate(t, y), k2 = rate(t + h / 2, y + h / 2 * k1), k3 = rate(t + h / 2, y + h / 2 * k2),
            k4 = rate(t + h, y + h * k3);
    y += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    if ((i + 1) % 10 == 0) r.tip.push_back(tip_row * y.head(kept));
    if (!(std::abs(r.tip.empty() ? 0.0 : r.tip.back()) < 10.0)) {
      r.diverged = true;
      break;
    }
  }
  return r;
}

}  // namespace spin_up
