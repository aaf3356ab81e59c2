// A modal body's momentum and angular momentum (about the origin), summed
// point by point over the displaced beam (beam_field) plus the sections'
// polar inertia about the axis: the references the conservation tests hold
// the generated models to, independent of the step's invariants; and the
// run that measures how far a model strays from them.
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "beam_modes.hpp"
#include "modal_body.hpp"
#include "mbrt/body_state.hpp"
#include "mbrt/step_status.hpp"

namespace modal_momenta {

// The beam's points move by the modes' field plus the shortening that
// bending brings: a point x from the root moves back along the beam by
// (1/2) int_0^x |w'|^2 ds, w the transverse deflection (second order in q).
class ModalBeamMass {
 public:
  ModalBeamMass(const mbrt::codegen::BeamProperties& beam, int modes)
      : beam_(beam), plan_(mbrt::codegen::plan_modal_body(beam, modes, 0.0)), field_(mbrt::codegen::beam_field(beam, plan_.shapes)) {
    for (Eigen::Index k = 0; k < field_.x.size(); ++k) shortening_.push_back(slopes_squared(field_.x[k]));
  }

  // b: the frame's state; q, p: modal coordinates and momenta.
  std::array<mbrt::Vec3, 2> momenta(const mbrt::RigidState& b, const Eigen::VectorXd& q, const Eigen::VectorXd& p) const {
    const mbrt::Mat3 R = Eigen::Quaterniond(b.p[0], b.p[1], b.p[2], b.p[3]).toRotationMatrix();
    const double centre = beam_.length / 2;
    const auto place = [&](Eigen::Index k) -> mbrt::Vec3 {
      return mbrt::Vec3(field_.x[k] - centre - 0.5 * q.dot(shortening_[static_cast<size_t>(k)] * q), 0, 0) +
             field_.displacement[static_cast<size_t>(k)] * q;
    };
    const auto rate_columns = [&](Eigen::Index k) {  // d place / d q
      Eigen::Matrix<double, 3, Eigen::Dynamic> D = field_.displacement[static_cast<size_t>(k)];
      D.row(0) -= (shortening_[static_cast<size_t>(k)] * q).transpose();
      return D;
    };
    // p = qdot + St(q)^T R^T v + Sr(q)^T w: St(q) = int d place / d q, Sr(q) = int place x d place / d q.
    Eigen::MatrixXd St_T = Eigen::MatrixXd::Zero(plan_.modes, 3), Sr_T = St_T;
    for (Eigen::Index k = 0; k < field_.x.size(); ++k) {
      const Eigen::Matrix<double, 3, Eigen::Dynamic> D = rate_columns(k);
      const mbrt::Vec3 rho = place(k);
      for (int j = 0; j < plan_.modes; ++j) {
        St_T.row(j) += field_.mass[k] * D.col(j).transpose();
        Sr_T.row(j) += field_.mass[k] * rho.cross(mbrt::Vec3(D.col(j))).transpose();
      }
    }
    const Eigen::VectorXd qd = p - St_T * (R.transpose() * b.v) - Sr_T * b.w;
    mbrt::Vec3 P = mbrt::Vec3::Zero(), H = R * mbrt::Vec3(beam_.rho_J * beam_.length * b.w.x(), 0, 0);
    for (Eigen::Index k = 0; k < field_.x.size(); ++k) {
      const mbrt::Vec3 rho = place(k);
      const mbrt::Vec3 v = b.v + R * (b.w.cross(rho) + rate_columns(k) * qd);
      P += field_.mass[k] * v;
      H += field_.mass[k] * (b.r + R * rho).cross(v);
    }
    return {P, H};
  }

  // The mass matrix in (v body, w body, qdot) of the model's field: each
  // point x (from the centre) moved by the modes, by the beam's mean
  // shortening sigma(q) = -sum m_k s_k(q) / m and by a stretch beta(q) x
  // with beta = -sum m_k x_k s_k(q) / sum m_k x_k^2 (along the beam: the
  // affine field with the pointwise shortening s_k's first and second
  // moments), summed point by point as sum m_k V_k^T V_k,
  // V_k = [I, -[r_k]x, Psi_k + d (sigma + beta x_k) / dq], plus the sections'
  // polar inertia about the beam's axis.
  Eigen::MatrixXd mass_matrix(const Eigen::VectorXd& q) const {
    const int n = plan_.modes;
    const double centre = beam_.length / 2;
    double m = 0, second = 0, moment = 0, turning = 0;
    Eigen::RowVectorXd moment_rate = Eigen::RowVectorXd::Zero(n), turning_rate = moment_rate;
    for (Eigen::Index k = 0; k < field_.x.size(); ++k) {
      const double x = field_.x[k] - centre, dm = field_.mass[k];
      const Eigen::VectorXd Aq = shortening_[static_cast<size_t>(k)] * q;
      m += dm, second += dm * x * x;
      moment += dm * 0.5 * q.dot(Aq), moment_rate += dm * Aq.transpose();
      turning += dm * x * 0.5 * q.dot(Aq), turning_rate += dm * x * Aq.transpose();
    }
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(6 + n, 6 + n);
    for (Eigen::Index k = 0; k < field_.x.size(); ++k) {
      const double x = field_.x[k] - centre;
      const mbrt::Vec3 r = mbrt::Vec3(x - moment / m - turning / second * x, 0, 0) + field_.displacement[static_cast<size_t>(k)] * q;
      Eigen::MatrixXd V(3, 6 + n);
      V.leftCols<3>().setIdentity();
      V.middleCols<3>(3) = -mbrt::skew(r);
      V.rightCols(n) = field_.displacement[static_cast<size_t>(k)];
      V.row(0).tail(n) -= moment_rate / m + turning_rate / second * x;
      M += field_.mass[k] * V.transpose() * V;
    }
    M(3, 3) += beam_.rho_J * beam_.length;
    return M;
  }

 private:
  // int_0^x Y'^T Y' ds (modes x modes), Y' the transverse slopes (y, z) per
  // mode of the shapes' cubic Hermite elements (Przemieniecki 1968, ch. 5):
  // four-point Gauss over each element or its part below x, exact for the
  // squared slopes' degree 4.
  Eigen::MatrixXd slopes_squared(double x) const {
    static constexpr double points[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281, 0.9305681557970263};
    static constexpr double weights[4] = {0.1739274225687269, 0.3260725774312731, 0.3260725774312731, 0.1739274225687269};
    const double l = beam_.length / beam_.elements;
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(plan_.modes, plan_.modes);
    for (int e = 0; e < beam_.elements && e * l < x; ++e) {
      const double part = std::min(1.0, (x - e * l) / l);  // of the element below x
      for (int g = 0; g < 4; ++g) {
        const double s = part * points[g];
        const double n[4] = {(6 * s * s - 6 * s) / l, 1 - 4 * s + 3 * s * s, (6 * s - 6 * s * s) / l, 3 * s * s - 2 * s};
        Eigen::MatrixXd Y(2, plan_.modes);
        for (int m = 0; m < plan_.modes; ++m) {
          const auto c = plan_.shapes.col(m).segment(6 * e, 12);  // (x, y, z, rx, ry, rz) at both ends
          Y(0, m) = n[0] * c[1] + n[1] * c[5] + n[2] * c[7] + n[3] * c[11];
          Y(1, m) = n[0] * c[2] - n[1] * c[4] + n[2] * c[8] - n[3] * c[10];
        }
        A += (weights[g] * part * l) * Y.transpose() * Y;
      }
    }
    return A;
  }

  mbrt::codegen::BeamProperties beam_;
  mbrt::codegen::ModalPlan plan_;
  mbrt::codegen::BeamField field_;
  std::vector<Eigen::MatrixXd> shortening_;  // per field point: its shortening is q^T A q / 2
};

// The largest relative change of energy, momentum and angular momentum
// over 10 s, momenta(s) giving {momentum, angular momentum} of the model's
// bodies, and the largest modal coordinate of its first modal body.
struct Conservation {
  double energy, momentum, angular_momentum, largest_q;
};

template <class State, class Step, class EnergyOf, class MomentaOf>
Conservation conservation_errors(State s, Step step, EnergyOf energy, MomentaOf momenta, double h) {
  const auto [p0, h0] = momenta(s);
  const double e0 = energy(s);
  Conservation worst{0, 0, 0, 0};
  const int steps = static_cast<int>(std::lround(10.0 / h));
  for (int i = 0; i < steps; ++i) {
    REQUIRE(step(s) == mbrt::StepStatus::ok);
    const auto [p, hh] = momenta(s);
    worst.energy = std::max(worst.energy, std::abs(energy(s) - e0) / e0);
    worst.momentum = std::max(worst.momentum, (p - p0).norm() / p0.norm());
    worst.angular_momentum = std::max(worst.angular_momentum, (hh - h0).norm() / h0.norm());
    worst.largest_q = std::max(worst.largest_q, s.modal_q[0].cwiseAbs().maxCoeff());
  }
  return worst;
}

// The node-joint tests' bounds on two schemes at 1 ms, and second order:
// at a quarter of the step (fine, staggered-pcst) a sixth of pcst's errors,
// as a wrong column or quadratic term at the nodes would leave an error the
// step does not shrink.
inline void check_second_order(const Conservation& pcst, const Conservation& blajer, const Conservation& fine) {
  for (const Conservation& c : {pcst, blajer}) {
    MESSAGE("10 s at 1 ms: relative errors of energy " << c.energy << ", momentum " << c.momentum << ", angular momentum "
                                                       << c.angular_momentum << "; largest modal coordinate " << c.largest_q);
    CHECK(c.largest_q > 1e-3);  // the joints do bend it
    CHECK(c.energy < 2e-4);
    CHECK(c.momentum < 5e-4);
    CHECK(c.angular_momentum < 5e-3);
  }
  MESSAGE("staggered-pcst at 0.25 ms: " << fine.energy << ", " << fine.momentum << ", " << fine.angular_momentum);
  CHECK(fine.energy < pcst.energy / 6);
  CHECK(fine.momentum < pcst.momentum / 6);
  CHECK(fine.angular_momentum < pcst.angular_momentum / 6);
}

}  // namespace modal_momenta
