// A straight uniform beam discretized into finite elements at generation
// time, and its vibration modes: the generation-time half of a modal
// flexible body (the floating frame of reference: a body frame's motion plus
// modal coordinates, Jerkovsky's transformation operator approach).
//
// Elements: Euler-Bernoulli bending in two planes (cubic Hermite), linear
// axial and torsion, consistent mass (Przemieniecki 1968, Theory of Matrix
// Structural Analysis, ch. 5 and 11). Geometric stiffness: the element's
// int N(x) w' w' dx for the axial force of a spin about an axis
// perpendicular to the beam (Cook, Malkus & Plesha 1989, Concepts and
// Applications of Finite Element Analysis, ch. 14), which stiffens a
// rotating beam (Kane, Ryan & Banerjee 1987).
//
// Axes: the beam runs along x from its root node (x = 0) to its tip node
// (x = length). Each node has 6 coordinates: displacements x, y, z, then
// small rotations about x, y, z.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace mbrt::codegen {

struct BeamProperties {
  double length = 0.0;  // m
  double EA = 0.0;      // N: axial stiffness
  double GJ = 0.0;      // N m^2: torsional stiffness
  double EIy = 0.0;     // N m^2: bending about y (deflection along z)
  double EIz = 0.0;     // N m^2: bending about z (deflection along y)
  double rho_A = 0.0;   // kg/m: mass per length
  double rho_J = 0.0;   // kg m: polar mass moment of inertia per length (torsion)
  int elements = 0;
};

// Rejects a beam with a non-positive or non-finite property or fewer than one
// element (std::invalid_argument naming the property).
void check_beam(const BeamProperties& b);

inline constexpr int kNodeCoordinates = 6;

// Assembled over all 6 (elements + 1) coordinates, no supports.
struct BeamMatrices {
  Eigen::MatrixXd M;  // consistent mass
  Eigen::MatrixXd K;  // elastic stiffness
  // Geometric stiffness per unit spin rate squared (1/s^2) about an axis
  // perpendicular to the beam, hub_radius before its root: the axial force
  // N(x) = rho_A ((L^2 - x^2) / 2 + hub_radius (L - x)) in both bending planes.
  Eigen::MatrixXd KG;
};

BeamMatrices assemble_beam(const BeamProperties& b, double hub_radius = 0.0);

// clamped_root: the root node's 6 coordinates held (a cantilever, the modes
// of a beam on a hub); free: none held, the 6 rigid-body modes dropped.
enum class BeamSupport { clamped_root, free };

struct BeamModes {
  Eigen::VectorXd omega;   // rad/s, ascending: the elastic modes kept
  // 6 (elements + 1) x kept, unit modal mass (shapes^T M shapes = I); a
  // clamped root's rows are zero.
  Eigen::MatrixXd shapes;
  Eigen::MatrixXd KG;      // kept x kept: shapes^T KG shapes
  // The modes' coupling with the frame's motion (mass-weighted integrals of
  // the shapes): alpha's row d is shapes^T M times a unit translation along
  // d, beta's a unit rotation about d through the root.
  Eigen::Matrix<double, 3, Eigen::Dynamic> alpha, beta;
};

// The `kept` lowest elastic modes (std::invalid_argument when the
// discretization has fewer).
BeamModes beam_modes(const BeamProperties& b, BeamSupport support, int kept, double hub_radius = 0.0);

// The clamped beam's static displacement under nodal loads (6 (elements + 1)
// entries; the root's are ignored), with the elastic stiffness plus
// spin_rate^2 times the geometric stiffness.
Eigen::VectorXd clamped_static_displacement(const BeamProperties& b, const Eigen::VectorXd& load,
                                            double spin_rate = 0.0, double hub_radius = 0.0);

// The beam's mass as quadrature points along it (four per element, exact for
// products of two element shapes), for integrals of the displacement field
// such as a modal body's inertia invariants: at point k, x[k] from the root
// carries mass[k] (rho_A times the weight) and moves by displacement[k] q
// (3 x modes: x, y, z) for modal coordinates q of `shapes`.
struct BeamField {
  Eigen::VectorXd x, mass;
  std::vector<Eigen::Matrix<double, 3, Eigen::Dynamic>> displacement;
};

BeamField beam_field(const BeamProperties& b, const Eigen::MatrixXd& shapes);

}  // namespace mbrt::codegen
