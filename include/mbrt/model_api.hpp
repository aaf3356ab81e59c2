// Types every generated model shares in its interface.
#pragma once

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
