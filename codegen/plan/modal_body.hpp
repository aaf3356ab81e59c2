// A modal flexible body's constants (docs/flexible.md): its modes (the
// lowest bending and axial modes of a beam clamped at its root, or those of
// a structure from a file), and the inertia invariants the step's kernel
// (include/mbrt/modal_body.hpp) takes, summed over the body's mass at
// generation time.
#pragma once

#include <array>

#include <Eigen/Core>
#include <mbrt/modal_body.hpp>

#include <string>
#include <vector>

#include "beam_modes.hpp"
#include "model.hpp"

namespace mbrt::codegen {

inline constexpr size_t kSpinYY = 1, kSpinZZ = 2, kAccelerationX = 6;  // ModalPlan::kg's cases

struct ModalPlan {
  int body = -1;  // Model::bodies index of the frame
  int modes = 0;
  double m = 0.0;
  Eigen::Matrix3d J;                        // undeformed, about the centre, body axes
  Eigen::Matrix<double, 6, 6> reduced_inverse;
  Eigen::MatrixXd St_T, Sr_T;               // modes x 3
  Eigen::VectorXd omega;                    // rad/s
  Eigen::VectorXd damping;                  // 1/s: stiffness-proportional, b omega^2
  // Geometric stiffness (modes x modes) per load case: the spin's products
  // w_a w_b (xx, yy, zz, xy, xz, yz) about the frame's origin, then the
  // frame's acceleration less gravity along x, y, z (body axes).
  std::array<Eigen::MatrixXd, 9> kg;
  // A beam's stretch along x (include/mbrt/modal_body.hpp), which carries
  // its spin cases in the mass instead (step_geometric_stiffness), and
  // int x^2 dm; zero (and empty) for a structure from a file.
  Eigen::MatrixXd stretch;
  double axial_moment = 0.0;
  std::array<Eigen::MatrixXd, 9> E;         // modes x modes
  std::array<Eigen::RowVectorXd, 9> G;      // 1 x modes
  // The nodes: their names (a beam's root, 1, ..., tip), undeformed places
  // (body axes, from the frame's origin), and those the modes are clamped at.
  std::vector<std::string> node_names;
  std::vector<Eigen::Vector3d> node_points;
  std::vector<int> clamped;
  // The kept modes over the nodes' coordinates, 6 a node (x, y, z, then
  // small rotations; zero where a structure has 3 a node).
  Eigen::MatrixXd shapes;
};

// Node K of a modal body: its undeformed place in body axes, and its
// displacement and small rotation per modal coordinate.
struct ModalNode {
  Eigen::Vector3d point;
  Eigen::MatrixXd displacement, rotation;  // 3 x modes
};

ModalNode modal_node(const ModalPlan& p, int k);

// The frame sits at the beam's centre, axes along it (x) and its bending axes.
// Torsion modes are skipped (their sections' rotation is not in the
// invariants); `damping` is stiffness-proportional (s). `static_loads`
// (coordinates, 6 a node) add the static shapes of unit loads there to the
// `modes` kept, all turned into modes. Throws std::invalid_argument where the
// elements give fewer bending and axial modes, or a static load adds nothing.
ModalPlan plan_modal_body(const BeamProperties& beam, int modes, double damping, const std::vector<int>& static_loads = {});

// A structure's modes: computed from its stiffness (the clamped nodes held;
// none: the 6 rigid-body modes dropped; coordinates without mass condensed
// out, Guyan 1965), or as the file gives them, scaled to unit modal mass in
// the nodes' lumped mass. Damping: `damping_ratio` of critical. Geometric
// stiffness: the file's load cases on the modes. Static loads (coordinates,
// `coordinates` a node) add their static shapes as plan_modal_body's do, for
// a structure given by its stiffness with clamped nodes. Throws
// std::invalid_argument naming the file and what is wrong.
ModalPlan plan_modal_structure(const ModalStructure& s, int modes, double damping_ratio, const std::vector<int>& static_loads = {});

// Either, as the model gives it (the frame body not set).
ModalPlan plan_modal(const ModalSource& source);

// Load case k of the geometric stiffness as the step applies it: a beam's
// spin cases are in its stretch.
inline Eigen::MatrixXd step_geometric_stiffness(const ModalPlan& p, size_t k) {
  return k < kAccelerationX && p.axial_moment > 0.0 ? Eigen::MatrixXd::Zero(p.modes, p.modes) : p.kg[k];
}

// The constants the generated step holds for the body (emit_modal.cpp
// writes the same fields), for checks at generation time and in tests.
template <int N>
inline mbrt::ModalBody<N> step_constants(const ModalPlan& p) {
  mbrt::ModalBody<N> b;
  b.St_T = p.St_T;
  b.Sr_T = p.Sr_T;
  b.stiffness = p.omega.cwiseAbs2();
  b.damping = p.damping;
  b.kg_cases = 0;
  for (size_t k = 0; k < p.kg.size(); ++k) {
    b.kg[k] = step_geometric_stiffness(p, k);
    if (!b.kg[k].isZero(0.0)) b.kg_cases |= 1u << k;
  }
  b.axial_moment = p.axial_moment;
  if (p.axial_moment > 0.0) {
    b.stretch = p.stretch;
  } else {
    b.stretch.setZero();
  }
  for (size_t k = 0; k < 9; ++k) b.E[k] = p.E[k], b.G[k] = p.G[k];
  b.J = p.J;
  b.m = p.m;
  return b;
}

}  // namespace mbrt::codegen
