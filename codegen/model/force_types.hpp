// The force types a model file can name, one row each: spring_damper and
// torque act between two bodies, force on one, joint_spring across a
// revolute or prismatic joint.
#pragma once

#include <array>
#include <cstddef>

#include "type_table.hpp"

namespace mbrt::codegen {

enum class ForceType { spring_damper, torque, force, joint_spring };
inline constexpr std::size_t kForceTypeCount = 4;  // enumerators of ForceType

struct ForceTypeRow {
  ForceType type;
  const char* name;
  const char* keys;  // besides type
};

inline constexpr std::array<ForceTypeRow, kForceTypeCount> kForceTypeTable{{
    // type                    name             keys
    {ForceType::spring_damper, "spring_damper", "body1 body2 point1 point2 stiffness damping rest_length"},
    {ForceType::torque,        "torque",        "body1 body2 axis value"},
    {ForceType::force,         "force",         "body point vector"},
    {ForceType::joint_spring,  "joint_spring",  "joint stiffness damping rest"},
}};
static_assert(rows_in_enum_order(kForceTypeTable), "kForceTypeTable needs one row per ForceType, in enum order");

constexpr const ForceTypeRow& type_row(ForceType type) { return row_of(kForceTypeTable, type); }

// The keys a force of this type takes: type, then its own.
Keys force_keys(ForceType type);
// Every key some force type takes.
Keys every_force_key();

}  // namespace mbrt::codegen
