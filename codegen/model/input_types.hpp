// The input types a model file can name, one row each: commands from a
// controller, applied as loads by the step. joint_torque about a revolute
// joint's axis on body2 (reaction on body1), joint_force along a prismatic
// joint's axis on body2 (reaction on body1), motor_torque about an axis fixed
// in body1 between two bodies.
#pragma once

#include <array>
#include <cstddef>

#include "type_table.hpp"

namespace mbrt::codegen {

enum class InputType { joint_torque, joint_force, motor_torque };
inline constexpr std::size_t kInputTypeCount = 3;  // enumerators of InputType

struct InputTypeRow {
  InputType type;
  const char* name;
  const char* keys;  // besides name, type, min, max and safe
};

inline constexpr std::array<InputTypeRow, kInputTypeCount> kInputTypeTable{{
    // type                   name            keys
    {InputType::joint_torque, "joint_torque", "joint"},
    {InputType::joint_force,  "joint_force",  "joint"},
    {InputType::motor_torque, "motor_torque", "body1 body2 axis"},
}};
static_assert(rows_in_enum_order(kInputTypeTable), "kInputTypeTable needs one row per InputType, in enum order");

constexpr const InputTypeRow& type_row(InputType type) { return row_of(kInputTypeTable, type); }

// The keys an input of this type takes: name, type, its own, then its range.
Keys input_keys(InputType type);
// Every key some input type takes.
Keys every_input_key();

}  // namespace mbrt::codegen
