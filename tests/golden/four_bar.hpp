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
inline constexpr int kParts = 1;  // subsystems stepped in parallel (docs/parallel.md)

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

// Indices by name: body:: into kBodyInfo and per-body arrays, rigid:: and
// particle:: into State, constraint:: into kConstraintInfo and Reactions.
namespace body {
inline constexpr int crank = 0;
inline constexpr int coupler = 1;
inline constexpr int rocker = 2;
}  // namespace body
namespace rigid {
inline constexpr int crank = 0;
inline constexpr int coupler = 1;
inline constexpr int rocker = 2;
}  // namespace rigid
namespace particle {
}  // namespace particle
namespace constraint {
inline constexpr int pin_o = 0;
inline constexpr int pin_a = 1;
inline constexpr int pin_b = 2;
inline constexpr int pin_c = 3;
}  // namespace constraint

// Everything that changes from step to step; the caller owns it.
struct State {
  double t = 0.0;
  std::array<mbrt::RigidState, kRigidBodies> rigid;     // by rigid::BODY
  std::array<mbrt::ParticleState, kParticles> particle;  // by particle::BODY
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
  struct {  // revolute ground - crank, rows 0..4
    mbrt::ConstraintRows<5> rows;
    Eigen::Matrix<double, 6, 5> mbt_crank;
    Eigen::Matrix<double, 5, 5> L;
  } pin_o;
  struct {  // revolute crank - coupler, rows 5..9
    mbrt::ConstraintRows<5> rows;
    Eigen::Matrix<double, 6, 5> mbt_crank;
    Eigen::Matrix<double, 6, 5> mbt_coupler;
    Eigen::Matrix<double, 5, 5> L;
    Eigen::Matrix<double, 5, 5> L_pin_b;
    Eigen::Matrix<double, 5, 5> L_pin_o;
  } pin_a;
  struct {  // revolute coupler - rocker, rows 10..14
    mbrt::ConstraintRows<5> rows;
    Eigen::Matrix<double, 6, 5> mbt_coupler;
    Eigen::Matrix<double, 6, 5> mbt_rocker;
    Eigen::Matrix<double, 5, 5> L;
    Eigen::Matrix<double, 5, 5> L_pin_c;
  } pin_b;
  struct {  // revolute rocker - ground, rows 15..19
    mbrt::ConstraintRows<5> rows;
    Eigen::Matrix<double, 6, 5> mbt_rocker;
    Eigen::Matrix<double, 5, 5> L;
  } pin_c;
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
  struct {  // planar_revolute ground - crank, rows 0..1
    mbrt::PlanarRows<2> rows;
    Eigen::Matrix<double, 3, 2> mbt_crank;
    Eigen::Matrix<double, 2, 2> L;
  } pin_o;
  struct {  // planar_revolute crank - coupler, rows 2..3
    mbrt::PlanarRows<2> rows;
    Eigen::Matrix<double, 3, 2> mbt_crank;
    Eigen::Matrix<double, 3, 2> mbt_coupler;
    Eigen::Matrix<double, 2, 2> L;
    Eigen::Matrix<double, 2, 2> L_pin_b;
    Eigen::Matrix<double, 2, 2> L_pin_o;
  } pin_a;
  struct {  // planar_revolute coupler - rocker, rows 4..5
    mbrt::PlanarRows<2> rows;
    Eigen::Matrix<double, 3, 2> mbt_coupler;
    Eigen::Matrix<double, 3, 2> mbt_rocker;
    Eigen::Matrix<double, 2, 2> L;
    Eigen::Matrix<double, 2, 2> L_pin_c;
  } pin_b;
  struct {  // planar_revolute rocker - ground, rows 6..7
    mbrt::PlanarRows<2> rows;
    Eigen::Matrix<double, 3, 2> mbt_rocker;
    Eigen::Matrix<double, 2, 2> L;
  } pin_c;
};

// Block LU factors of the position stage's Newton matrix G = B(q*) M^-1 B(q(t))^T:
// G = L U with unit-diagonal L, U's diagonal blocks kept inverted. Per
// constraint block: D, its row of L (L_OTHER) and of U (U_OTHER).
struct NewtonMatrix {
  struct {
    Eigen::Matrix<double, 2, 2> D;  // inverted
    Eigen::Matrix<double, 2, 2> U_pin_b;
  } pin_c;
  struct {
    Eigen::Matrix<double, 2, 2> D;  // inverted
    Eigen::Matrix<double, 2, 2> L_pin_c;
    Eigen::Matrix<double, 2, 2> U_pin_a;
  } pin_b;
  struct {
    Eigen::Matrix<double, 2, 2> D;  // inverted
    Eigen::Matrix<double, 2, 2> U_pin_a;
  } pin_o;
  struct {
    Eigen::Matrix<double, 2, 2> D;  // inverted
    Eigen::Matrix<double, 2, 2> L_pin_b;
    Eigen::Matrix<double, 2, 2> L_pin_o;
  } pin_a;
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

// Nothing to do here: the step advances s.rigid itself.
void refresh_bodies(State& s) noexcept;

// The serial step: no worker threads to start (docs/parallel.md).
inline void start_workers() {}
inline void stop_workers() noexcept {}

mbrt::Energy energy(const State& s) noexcept;
mbrt::ConstraintViolation constraint_violation(const State& s) noexcept;
double quaternion_norm_error(const State& s) noexcept;  // max | |p| - 1 |

// Force and torque of every joint and driver on its body2 (kConstraintInfo
// order), from the multipliers of the last step.
using Reactions = std::array<mbrt::JointReaction, kConstraintBlocks>;
void reactions(const State& s, Reactions& r) noexcept;

}  // namespace mbrt::models::four_bar
