// The output types a model file can name, one row each: signals the model
// publishes. joint_position and joint_velocity of a revolute (rad, rad/s) or
// prismatic (m, m/s) joint, measured from t = 0; body_pose (x, y, z,
// e0..e3) and body_velocity (vx, vy, vz world; wx, wy, wz body axes) of a
// body; joint_friction (N m or N, along the joint's coordinate) and
// joint_stuck (1 stuck, 0 slipping) of a joint with friction, from the last
// step (docs/friction.md); contact_force (normal force, then the friction
// force's x, y, z in world axes, N) and contact_stuck (1 stuck, 0 sliding or
// open) of a point or sphere contact, from the last step (docs/contact.md).
#pragma once

#include <array>
#include <cstddef>

#include "type_table.hpp"

namespace mbrt::codegen {

enum class OutputType {
  joint_position, joint_velocity, body_pose, body_velocity, joint_friction, joint_stuck, contact_force, contact_stuck
};
inline constexpr std::size_t kOutputTypeCount = 8;  // enumerators of OutputType

struct OutputTypeRow {
  OutputType type;
  const char* name;
  const char* keys;  // besides name and type
  int values;        // per signal
};

inline constexpr std::array<OutputTypeRow, kOutputTypeCount> kOutputTypeTable{{
    // type                      name              keys    values
    {OutputType::joint_position, "joint_position", "joint", 1},
    {OutputType::joint_velocity, "joint_velocity", "joint", 1},
    {OutputType::body_pose,      "body_pose",      "body",  7},
    {OutputType::body_velocity,  "body_velocity",  "body",  6},
    {OutputType::joint_friction, "joint_friction", "joint", 1},
    {OutputType::joint_stuck,    "joint_stuck",    "joint", 1},
    {OutputType::contact_force,  "contact_force",  "contact", 4},
    {OutputType::contact_stuck,  "contact_stuck",  "contact", 1},
}};
static_assert(rows_in_enum_order(kOutputTypeTable), "kOutputTypeTable needs one row per OutputType, in enum order");

constexpr const OutputTypeRow& type_row(OutputType type) { return row_of(kOutputTypeTable, type); }

// The keys an output of this type takes: name, type, then its own.
Keys output_keys(OutputType type);
// Every key some output type takes.
Keys every_output_key();

}  // namespace mbrt::codegen
