// A modal flexible body's constants (docs/flexible.md): the lowest bending
// and axial modes of its beam clamped at the root, and the inertia
// invariants the step's kernel (include/mbrt/modal_body.hpp) takes,
// integrated over the beam's finite elements at generation time.
#pragma once

#include <array>

#include <Eigen/Core>

#include "beam_modes.hpp"

namespace mbrt::codegen {

struct ModalPlan {
  int body = -1;  // Model::bodies index of the frame
  int modes = 0;
  double m = 0.0;
  Eigen::Matrix3d J;                        // undeformed, about the centre, body axes
  Eigen::Matrix<double, 6, 6> reduced_inverse;
  Eigen::MatrixXd St_T, Sr_T;               // modes x 3
  Eigen::VectorXd omega;                    // rad/s
  Eigen::VectorXd damping;                  // 1/s: stiffness-proportional, b omega^2
  Eigen::MatrixXd kg_spin, kg_axial;        // modes x modes
  std::array<Eigen::MatrixXd, 9> E;         // modes x modes
  std::array<Eigen::RowVectorXd, 9> G;      // 1 x modes
  Eigen::Vector3d root;                     // body axes, undeformed
  double length = 0.0;
  int elements = 0;
  Eigen::MatrixXd shapes;  // the kept modes over the beam's coordinates (beam_modes.hpp)
};

// Node K of a modal body (0 root .. elements tip): its undeformed place in
// body axes, and its displacement and small rotation per modal coordinate.
struct ModalNode {
  Eigen::Vector3d point;
  Eigen::MatrixXd displacement, rotation;  // 3 x modes
};

ModalNode modal_node(const ModalPlan& p, int k);

// The frame sits at the beam's centre, axes along it (x) and its bending axes.
// Torsion modes are skipped (their sections' rotation is not in the
// invariants); `damping` is stiffness-proportional (s). Throws
// std::invalid_argument where the elements give fewer bending and axial modes.
ModalPlan plan_modal_body(const BeamProperties& beam, int modes, double damping);

}  // namespace mbrt::codegen
