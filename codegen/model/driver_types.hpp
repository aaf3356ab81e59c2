// The driver types a model file can name, one row each: rheonomic
// constraints. joint_angle (revolute, cylindrical: angle about the axis from
// t = 0, rad), joint_distance (prismatic, cylindrical: slide along the axis
// from t = 0, m), distance (between point1 of body1 and point2 of body2, m).
#pragma once

#include <array>
#include <cstddef>

#include "type_table.hpp"

namespace mbrt::codegen {

enum class DriverType { joint_angle, joint_distance, distance };
inline constexpr std::size_t kDriverTypeCount = 3;  // enumerators of DriverType

struct DriverTypeRow {
  DriverType type;
  const char* name;
  const char* keys;    // besides name, type and function
  int rows;            // constraint rows
  const char* kernel;  // the runtime function generated code calls (include/mbrt/joints.hpp)
};

inline constexpr std::array<DriverTypeRow, kDriverTypeCount> kDriverTypeTable{{
    // type                     name              keys                        rows kernel
    {DriverType::joint_angle,    "joint_angle",    "joint",                    1,   "joint_angle_driver"},
    {DriverType::joint_distance, "joint_distance", "joint",                    1,   "joint_distance_driver"},
    {DriverType::distance,       "distance",       "body1 body2 point1 point2", 1,   "distance_driver"},
}};
static_assert(rows_in_enum_order(kDriverTypeTable), "kDriverTypeTable needs one row per DriverType, in enum order");

constexpr const DriverTypeRow& type_row(DriverType type) { return row_of(kDriverTypeTable, type); }

// The keys a driver of this type takes: name, type, its own, then function.
Keys driver_keys(DriverType type);
// Every key some driver type takes.
Keys every_driver_key();

}  // namespace mbrt::codegen
