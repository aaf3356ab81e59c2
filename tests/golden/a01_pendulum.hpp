// mbrt generated model 'a01_pendulum' from a01_pendulum.yaml
// scheme staggered-pcst, h = 0.00050000000000000001 s, euler_updates = 1. Generated code: regenerate, do not edit.
#pragma once

#include <array>

#include <mbrt/model_api.hpp>

namespace mbrt::models::a01_pendulum {

inline constexpr const char* kName = "a01_pendulum";
inline constexpr const char* kScheme = "staggered-pcst";
inline constexpr double kStep = 0.00050000000000000001;
inline constexpr int kEulerUpdates = 1;
inline constexpr int kBodies = 1;
inline constexpr int kRigidBodies = 0;
inline constexpr int kParticles = 1;
inline constexpr int kConstraintBlocks = 1;  // joints, then drivers
inline constexpr int kConstraintRows = 1;

inline constexpr std::array<mbrt::BodyInfo, kBodies> kBodyInfo{{
    {"bob", false, 0},
}};

inline constexpr std::array<mbrt::ConstraintInfo, kConstraintBlocks> kConstraintInfo{{
    {"bar", "distance", 0, 1},
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

}  // namespace mbrt::models::a01_pendulum
