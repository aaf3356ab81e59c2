// mbrt generated model 'four_bar' from four_bar.yaml
// scheme staggered-pcst, h = 0.001 s, euler_updates = 2. Generated code: regenerate, do not edit.
#pragma once

#include <array>
#include <cstddef>

#include <mbrt/model_api.hpp>
#include <mbrt/runtime.hpp>

namespace mbrt::models::four_bar {

inline constexpr const char* kName = "four_bar";
inline constexpr const char* kScheme = "staggered-pcst";
inline constexpr double kStep = 0.001;
inline constexpr int kEulerUpdates = 2;
inline constexpr int kBodies = 3;
inline constexpr int kRigidBodies = 3;
inline constexpr int kParticles = 0;
inline constexpr int kConstraintBlocks = 4;  // joints, then drivers
inline constexpr int kConstraintRows = 20;

inline constexpr std::array<mbrt::BodyInfo, kBodies> kBodyInfo{{
    {"crank", true, 0},
    {"coupler", true, 1},
    {"rocker", true, 2},
}};

inline constexpr std::array<mbrt::ConstraintInfo, kConstraintBlocks> kConstraintInfo{{
    {"pin_o", "revolute", 0, 5},
    {"pin_a", "revolute", 5, 5},
    {"pin_b", "revolute", 10, 5},
    {"pin_c", "revolute", 15, 5},
}};

// Everything that changes from step to step; the caller owns it.
struct State {
  double t = 0.0;
  std::array<mbrt::RigidState, kRigidBodies> rigid;     // see kBodyInfo
  std::array<mbrt::ParticleState, kParticles> particle;
  // Accelerations at t, reused by the next step's explicit stage.
  std::array<mbrt::RigidAcceleration, kRigidBodies> rigid_acceleration;
  std::array<mbrt::Vec3, kParticles> particle_acceleration;
  // Constraint multipliers of the last step, rows as in kConstraintInfo.
  Eigen::Matrix<double, kConstraintRows, 1> lambda;
};

// The types step() works with (generated kernels' data).
namespace detail {

using Rows = Eigen::Matrix<double, kConstraintRows, 1>;
using BodyVectors = std::array<mbrt::Vec6, kBodies>;  // [v; w_body] per body

struct Kinematics {
  std::array<mbrt::BodyPose, kBodies> pose;
  std::array<mbrt::BodyVelocity, kBodies> vel;
};

struct Loads {
  std::array<mbrt::Wrench, kBodies> w;
  double elastic_energy;
};

// Constraint rows, M^-1 B^T blocks and the block Cholesky factor of
// S = B M^-1 B^T + kRegularization I over the model's fixed pattern.
struct ConstraintSystem {
  mbrt::ConstraintRows<5> rows_pin_o;  // revolute ground - crank, rows 0..4
  Eigen::Matrix<double, 6, 5> mbt_0_0;  // M^-1 B^T: pin_o, crank
  mbrt::ConstraintRows<5> rows_pin_a;  // revolute crank - coupler, rows 5..9
  Eigen::Matrix<double, 6, 5> mbt_1_0;  // M^-1 B^T: pin_a, crank
  Eigen::Matrix<double, 6, 5> mbt_1_1;  // M^-1 B^T: pin_a, coupler
  mbrt::ConstraintRows<5> rows_pin_b;  // revolute coupler - rocker, rows 10..14
  Eigen::Matrix<double, 6, 5> mbt_2_1;  // M^-1 B^T: pin_b, coupler
  Eigen::Matrix<double, 6, 5> mbt_2_2;  // M^-1 B^T: pin_b, rocker
  mbrt::ConstraintRows<5> rows_pin_c;  // revolute rocker - ground, rows 15..19
  Eigen::Matrix<double, 6, 5> mbt_3_2;  // M^-1 B^T: pin_c, rocker
  Eigen::Matrix<double, 5, 5> L_3_3;  // pin_c
  Eigen::Matrix<double, 5, 5> L_2_3;  // pin_b x pin_c
  Eigen::Matrix<double, 5, 5> L_2_2;  // pin_b
  Eigen::Matrix<double, 5, 5> L_1_2;  // pin_a x pin_b
  Eigen::Matrix<double, 5, 5> L_0_0;  // pin_o
  Eigen::Matrix<double, 5, 5> L_1_0;  // pin_a x pin_o
  Eigen::Matrix<double, 5, 5> L_1_1;  // pin_a
};

namespace planar {

inline constexpr int kPlanarRows = 8;  // of kConstraintRows
using Rows = Eigen::Matrix<double, kPlanarRows, 1>;
using BodyVectors = std::array<mbrt::Vec3, kBodies>;  // [v_i; v_j; omega_k], plane coordinates per body

struct Kinematics {
  std::array<mbrt::PlanarPose, kBodies> pose;
  std::array<mbrt::PlanarVelocity, kBodies> vel;
};

struct Loads {
  std::array<mbrt::PlanarWrench, kBodies> w;
  double elastic_energy;
};

// Constraint rows, M^-1 B^T blocks and the block Cholesky factor of
// S = B M^-1 B^T + kRegularization I over the model's fixed pattern.
struct ConstraintSystem {
  mbrt::PlanarRows<2> rows_pin_o;  // planar_revolute ground - crank, rows 0..1
  Eigen::Matrix<double, 3, 2> mbt_0_0;  // M^-1 B^T: pin_o, crank
  mbrt::PlanarRows<2> rows_pin_a;  // planar_revolute crank - coupler, rows 2..3
  Eigen::Matrix<double, 3, 2> mbt_1_0;  // M^-1 B^T: pin_a, crank
  Eigen::Matrix<double, 3, 2> mbt_1_1;  // M^-1 B^T: pin_a, coupler
  mbrt::PlanarRows<2> rows_pin_b;  // planar_revolute coupler - rocker, rows 4..5
  Eigen::Matrix<double, 3, 2> mbt_2_1;  // M^-1 B^T: pin_b, coupler
  Eigen::Matrix<double, 3, 2> mbt_2_2;  // M^-1 B^T: pin_b, rocker
  mbrt::PlanarRows<2> rows_pin_c;  // planar_revolute rocker - ground, rows 6..7
  Eigen::Matrix<double, 3, 2> mbt_3_2;  // M^-1 B^T: pin_c, rocker
  Eigen::Matrix<double, 2, 2> L_3_3;  // pin_c
  Eigen::Matrix<double, 2, 2> L_2_3;  // pin_b x pin_c
  Eigen::Matrix<double, 2, 2> L_2_2;  // pin_b
  Eigen::Matrix<double, 2, 2> L_1_2;  // pin_a x pin_b
  Eigen::Matrix<double, 2, 2> L_0_0;  // pin_o
  Eigen::Matrix<double, 2, 2> L_1_0;  // pin_a x pin_o
  Eigen::Matrix<double, 2, 2> L_1_1;  // pin_a
};

// Block LU factors of the position stage's Newton matrix G = B(q*) M^-1 B(q(t))^T:
// G = L U with unit-diagonal L, U's diagonal blocks kept inverted.
struct NewtonMatrix {
  Eigen::Matrix<double, 2, 2> D_3;  // pin_c, inverted
  Eigen::Matrix<double, 2, 2> L_2_3;
  Eigen::Matrix<double, 2, 2> U_3_2;
  Eigen::Matrix<double, 2, 2> D_2;  // pin_b, inverted
  Eigen::Matrix<double, 2, 2> L_1_2;
  Eigen::Matrix<double, 2, 2> U_2_1;
  Eigen::Matrix<double, 2, 2> D_0;  // pin_o, inverted
  Eigen::Matrix<double, 2, 2> L_1_0;
  Eigen::Matrix<double, 2, 2> U_0_1;
  Eigen::Matrix<double, 2, 2> D_1;  // pin_a, inverted
};

}  // namespace planar

}  // namespace detail

// What step() works on. The caller owns it, so a real-time loop can keep it
// in memory locked and touched before the loop starts; nothing in it
// carries over from one step to the next.
struct Workspace {
  State last_good;  // the state at t, restored when a step fails
  detail::planar::Kinematics k;
  detail::planar::ConstraintSystem c;  // at t + h
  detail::planar::ConstraintSystem c0;  // at t: the position stage's force directions
  detail::planar::NewtonMatrix g;       // the position stage's Newton matrix
  detail::planar::Loads l;
};

inline constexpr std::size_t kWorkspaceBytes = sizeof(Workspace);

// The model file's initial state with consistent accelerations.
State initial_state() noexcept;

// Advances s by kStep in the caller's workspace. Allocates nothing, throws
// nothing, fixed work. On a non-finite result or a lost factorization s
// keeps its old value.
mbrt::StepStatus step(State& s, Workspace& w) noexcept;
// The same with a workspace on the stack, for tools and tests.
mbrt::StepStatus step(State& s) noexcept;

mbrt::Energy energy(const State& s) noexcept;
mbrt::ConstraintViolation constraint_violation(const State& s) noexcept;
double quaternion_norm_error(const State& s) noexcept;  // max | |p| - 1 |

// Force and torque of every joint and driver on its body2 (kConstraintInfo
// order), from the multipliers of the last step.
using Reactions = std::array<mbrt::JointReaction, kConstraintBlocks>;
void reactions(const State& s, Reactions& r) noexcept;

}  // namespace mbrt::models::four_bar
