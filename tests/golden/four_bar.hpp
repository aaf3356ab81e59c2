// mbrt generated model 'four_bar' from four_bar.yaml
// scheme staggered-pcst, h = 0.001 s, euler_updates = 2. Generated code: regenerate, do not edit.
#pragma once

#include <array>

#include <mbrt/model_api.hpp>

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

// The model file's initial state with consistent accelerations.
State initial_state() noexcept;

// Advances s by kStep. Allocates nothing, throws nothing, fixed work.
// On a non-finite result or a lost factorization s keeps its old value.
mbrt::StepStatus step(State& s) noexcept;

mbrt::Energy energy(const State& s) noexcept;
mbrt::ConstraintViolation constraint_violation(const State& s) noexcept;
double quaternion_norm_error(const State& s) noexcept;  // max | |p| - 1 |

// Force and torque of every joint and driver on its body2 (kConstraintInfo
// order), from the multipliers of the last step.
using Reactions = std::array<mbrt::JointReaction, kConstraintBlocks>;
void reactions(const State& s, Reactions& r) noexcept;

}  // namespace mbrt::models::four_bar
