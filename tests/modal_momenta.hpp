// A modal body's momentum and angular momentum (about the origin), summed
// point by point over the displaced beam (beam_field) plus the sections'
// polar inertia about the axis: the references the conservation tests hold
// the generated models to, independent of the step's invariants.
#pragma once

#include <array>

#include <Eigen/Geometry>

#include "beam_modes.hpp"
#include "modal_body.hpp"
#include "mbrt/body_state.hpp"

namespace modal_momenta {

class ModalBeamMass {
 public:
  ModalBeamMass(const mbrt::codegen::BeamProperties& beam, int modes)
      : beam_(beam), plan_(mbrt::codegen::plan_modal_body(beam, modes, 0.0)), field_(mbrt::codegen::beam_field(beam, plan_.shapes)) {}

  // b: the frame's state; q, p: modal coordinates and momenta.
  std::array<mbrt::Vec3, 2> momenta(const mbrt::RigidState& b, const Eigen::VectorXd& q, const Eigen::VectorXd& p) const {
    const mbrt::Mat3 R = Eigen::Quaterniond(b.p[0], b.p[1], b.p[2], b.p[3]).toRotationMatrix();
    const double centre = beam_.length / 2;
    // p = qdot + St^T R^T v + Sr(q)^T w, Sr(q) = int (rho0 + u) x Psi over the field.
    Eigen::MatrixXd Sr_T = Eigen::MatrixXd::Zero(plan_.modes, 3);
    for (Eigen::Index k = 0; k < field_.x.size(); ++k) {
      const Eigen::Matrix<double, 3, Eigen::Dynamic>& D = field_.displacement[static_cast<size_t>(k)];
      const mbrt::Vec3 rho = mbrt::Vec3(field_.x[k] - centre, 0, 0) + D * q;
      for (int j = 0; j < plan_.modes; ++j) Sr_T.row(j) += field_.mass[k] * rho.cross(mbrt::Vec3(D.col(j))).transpose();
    }
    const Eigen::VectorXd qd = p - plan_.St_T * (R.transpose() * b.v) - Sr_T * b.w;
    mbrt::Vec3 P = mbrt::Vec3::Zero(), H = R * mbrt::Vec3(beam_.rho_J * beam_.length * b.w.x(), 0, 0);
    for (Eigen::Index k = 0; k < field_.x.size(); ++k) {
      const Eigen::Matrix<double, 3, Eigen::Dynamic>& D = field_.displacement[static_cast<size_t>(k)];
      const mbrt::Vec3 rho = mbrt::Vec3(field_.x[k] - centre, 0, 0) + D * q;
      const mbrt::Vec3 v = b.v + R * (b.w.cross(rho) + D * qd);
      P += field_.mass[k] * v;
      H += field_.mass[k] * (b.r + R * rho).cross(v);
    }
    return {P, H};
  }

 private:
  mbrt::codegen::BeamProperties beam_;
  mbrt::codegen::ModalPlan plan_;
  mbrt::codegen::BeamField field_;
};

}  // namespace modal_momenta
