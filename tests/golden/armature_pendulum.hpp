// mbrt generated model 'armature_pendulum' from armature_pendulum.yaml
// scheme staggered-tree, h = 0.001 s, euler_updates = 2. Generated code: regenerate, do not edit.
#pragma once

#include <array>
#include <cstddef>

#include <mbrt/model_api.hpp>
#include <mbrt/sin_cos.hpp>
#include <mbrt/runtime.hpp>

namespace mbrt::models::armature_pendulum {

inline constexpr const char* kName = "armature_pendulum";
inline constexpr const char* kScheme = "staggered-tree";
inline constexpr double kStep = 0.001;
inline constexpr int kEulerUpdates = 2;
inline constexpr int kBodies = 1;
inline constexpr int kRigidBodies = 1;
inline constexpr int kParticles = 0;
inline constexpr int kConstraintBlocks = 1;  // joints, then drivers
inline constexpr int kConstraintRows = 5;
inline constexpr int kParts = 1;  // subsystems stepped in parallel (docs/parallel.md)

inline constexpr std::array<mbrt::BodyInfo, kBodies> kBodyInfo{{
    {"rod", true, 0},
}};

inline constexpr std::array<mbrt::ConstraintInfo, kConstraintBlocks> kConstraintInfo{{
    {"pin", "revolute", 0, 5},
}};

// Indices by name: body:: into kBodyInfo and per-body arrays, rigid:: and
// particle:: into State, constraint:: into kConstraintInfo and Reactions.
namespace body {
inline constexpr int rod = 0;
}  // namespace body
namespace rigid {
inline constexpr int rod = 0;
}  // namespace rigid
namespace particle {
}  // namespace particle
namespace constraint {
inline constexpr int pin = 0;
}  // namespace constraint

// Signals outputs() computes, as one array of values; see kOutputInfo.
namespace output {
inline constexpr int pin_angle = 0;  // joint_position of pin, rad
}  // namespace output
inline constexpr int kOutputSignals = 1;
inline constexpr int kOutputs = 1;  // values
using Outputs = std::array<double, kOutputs>;
inline constexpr std::array<mbrt::OutputInfo, kOutputSignals> kOutputInfo{{
    {"pin_angle", "joint_position", "pin", 0, 1},
}};

inline constexpr int kDofs = 1;  // joint coordinates, in kBodyInfo order
using Dofs = std::array<double, kDofs>;
// cos and sin of half of each revolute joint's angle from its frame's x axis.
using HalfAngles = std::array<mbrt::SinCos, kDofs>;

// Everything that changes from step to step; the caller owns it.
struct State {
  double t = 0.0;
  std::array<mbrt::RigidState, kRigidBodies> rigid;     // by rigid::BODY
  std::array<mbrt::ParticleState, kParticles> particle;  // by particle::BODY
  // The joint coordinates (rad or m from t = 0), their rates and accelerations:
  // what step() advances; rigid holds the bodies they put where.
  Dofs q, qd, qdd;
  // Body accelerations and constraint multipliers at the state, which
  // step() does not need: set by initial_state() and set_multipliers().
  std::array<mbrt::RigidAcceleration, kRigidBodies> rigid_acceleration;
  std::array<mbrt::Vec3, kParticles> particle_acceleration;
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
  struct {  // revolute ground - rod, rows 0..4
    mbrt::ConstraintRows<5> rows;
    Eigen::Matrix<double, 6, 5> mbt_rod;
    Eigen::Matrix<double, 5, 5> L;
  } pin;
};

}  // namespace detail

// What step() works on. The caller owns it, so a real-time loop can keep it
// in memory locked and touched before the loop starts; nothing in it
// carries over from one step to the next.
struct Workspace {
  double t0;
  Dofs q0, qd0, qdd0;  // the joint coordinates at t, restored when a step fails
  HalfAngles half_angles;  // of s.q
  Dofs rates;              // the rates the recursion runs at
  detail::Kinematics k;    // where loads other than gravity need the bodies
  detail::Loads l;
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

// (s.q, s.qd) => (s.rigid): where every body is and how it moves; step()
// does this itself, so only a caller who sets s.q or s.qd needs it.
void refresh_bodies(State& s) noexcept;

// The serial step: no worker threads to start (docs/parallel.md).
inline void start_workers() {}
inline void stop_workers() noexcept {}

// (s) => (s.rigid_acceleration, s.lambda): the body accelerations and
// multipliers that go with the joint coordinates.
void set_multipliers(State& s) noexcept;

mbrt::Energy energy(const State& s) noexcept;
mbrt::ConstraintViolation constraint_violation(const State& s) noexcept;
double quaternion_norm_error(const State& s) noexcept;  // max | |p| - 1 |

// Force and torque of every joint and driver on its body2 (kConstraintInfo
// order), from the multipliers at the state.
using Reactions = std::array<mbrt::JointReaction, kConstraintBlocks>;
void reactions(const State& s, Reactions& r) noexcept;

void outputs(const State& s, Outputs& y) noexcept;

}  // namespace mbrt::models::armature_pendulum
