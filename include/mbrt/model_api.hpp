// Types every generated model shares in its interface.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>

#include "mbrt/body_state.hpp"
#include "mbrt/step_status.hpp"

namespace mbrt {

struct BodyInfo {
  const char* name;
  bool rigid;
  int slot;  // index in State::rigid or State::particle
};

struct ConstraintInfo {  // a joint or a driver
  const char* name;
  const char* type;  // runtime kernel: "revolute", "joint_angle_driver", ...
  int first_row;
  int rows;
};

// A runtime parameter (docs/parameters.md): a key the model file marks
// tunable, "upper_arm.mass", "gravity.z", "pin.spring.stiffness", and the
// file's value.
struct ParameterInfo {
  const char* name;
  double default_value;
};

template <std::size_t N>
constexpr std::array<double, N> default_values(const std::array<ParameterInfo, N>& info) noexcept {
  std::array<double, N> v{};
  for (std::size_t i = 0; i < N; ++i) v[i] = info[i].default_value;
  return v;
}

// values[i] = value for the parameter of that name; false if there is none.
template <std::size_t N>
bool set_parameter(const std::array<ParameterInfo, N>& info, std::array<double, N>& values, std::string_view name,
                   double value) noexcept {
  for (std::size_t i = 0; i < N; ++i) {
    if (name != info[i].name) continue;
    values[i] = value;
    return true;
  }
  return false;
}

// A command input: what it drives and the range a command must respect.
struct InputInfo {
  const char* name;
  const char* type;    // joint_torque, joint_force, motor_torque
  const char* target;  // the joint, or "body1-body2" for a motor_torque
  double min, max;     // commands outside are rejected
  double safe;         // applied while commands are stale
};

// An output signal: values [first, first + count) of the model's Outputs.
struct OutputInfo {
  const char* name;
  const char* type;    // joint_position, joint_velocity, body_pose, body_velocity
  const char* source;  // the joint or body
  int first;
  int count;
};

// Force and torque a joint or driver transmits to its body2, about body2's
// joint point, in world axes and in the joint frame (body 1's a1, b1, c1).
struct JointReaction {
  Vec3 force, torque;
  Vec3 force_joint, torque_joint;
};

struct Energy {
  double kinetic;
  double potential;  // gravity (zero at the origin) plus springs
  double total() const noexcept { return kinetic + potential; }
};

// Largest constraint residuals at position (phi), velocity (phi_dot) and
// acceleration (phi_ddot) level.
struct ConstraintViolation {
  double position;
  double velocity;
  double acceleration;  // B a + quad with the state's accelerations
};

}  // namespace mbrt
