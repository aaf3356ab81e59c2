// The joint types a model file can name, one row each. rolling_disk,
// rolling_ball and knife_edge are contacts of one body with the ground plane
// (body1 = ground); velocity_toward is Dopico et al.'s two-mass constraint.
// Their rows past the holonomic ones act on velocities only, see
// include/mbrt/nonholonomic.hpp.
#pragma once

#include <array>
#include <cstddef>

#include "type_table.hpp"

namespace mbrt::codegen {

enum class JointType {
  spherical, revolute, universal, cylindrical, prismatic, fixed, distance, screw, planar,
  rolling_disk, rolling_ball, knife_edge, velocity_toward
};
inline constexpr std::size_t kJointTypeCount = 13;  // enumerators of JointType

struct JointTypeRow {
  JointType type;
  const char* name;
  const char* keys;     // besides name and type
  int rows;             // constraint rows
  int holonomic_rows;   // the first rows; the rest act on velocities only
  bool ground_contact;  // one body ("body") on the ground plane
  bool rigid_bodies;    // its rows use the bodies' orientations: no particles
  const char* kernel;   // the runtime function generated code calls (include/mbrt/joints.hpp, nonholonomic.hpp)
};

inline constexpr std::array<JointTypeRow, kJointTypeCount> kJointTypeTable{{
    // type, name, keys, rows, holonomic_rows, ground_contact, rigid_bodies, kernel
    {JointType::spherical,       "spherical",       "body1 body2 point",                           3, 3, false, false, "spherical"},
    {JointType::revolute,        "revolute",        "body1 body2 point axis armature friction",    5, 5, false, true,  "revolute"},
    {JointType::universal,       "universal",       "body1 body2 point axis1 axis2",               4, 4, false, true,  "universal"},
    {JointType::cylindrical,     "cylindrical",     "body1 body2 point axis",                      4, 4, false, true,  "cylindrical"},
    {JointType::prismatic,       "prismatic",       "body1 body2 point axis armature friction",    5, 5, false, true,  "prismatic"},
    {JointType::fixed,           "fixed",           "body1 body2 point",                           6, 6, false, true,  "fixed"},
    {JointType::distance,        "distance",        "body1 body2 point1 point2 length",            1, 1, false, false, "distance"},
    {JointType::screw,           "screw",           "body1 body2 point axis lead",                 5, 5, false, true,  "screw"},
    {JointType::planar,          "planar",          "body1 body2 point axis",                      3, 3, false, true,  "planar"},
    {JointType::rolling_disk,    "rolling_disk",    "body radius axis plane_point plane_normal",   3, 1, true,  true,  "rolling_disk"},
    {JointType::rolling_ball,    "rolling_ball",    "body radius center plane_point plane_normal", 3, 1, true,  true,  "rolling_ball"},
    {JointType::knife_edge,      "knife_edge",      "body point direction plane_normal",           1, 0, true,  true,  "knife_edge"},
    {JointType::velocity_toward, "velocity_toward", "body1 body2 point1 point2 plane_normal",      1, 0, false, false, "velocity_toward"},
}};
static_assert(rows_in_enum_order(kJointTypeTable), "kJointTypeTable needs one row per JointType, in enum order");

constexpr const JointTypeRow& type_row(JointType type) { return row_of(kJointTypeTable, type); }

// The keys a joint of this type takes: name, type, then its own.
Keys joint_keys(JointType type);
// Every key some joint type takes.
Keys every_joint_key();

}  // namespace mbrt::codegen
