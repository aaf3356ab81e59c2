// A model read from another format (URDF, MJCF), in mbrt's terms: bodies
// with their world pose and mass properties, joints with their world point
// and axis and their elements, all at t = 0. The importers fill it
// (urdf_import.hpp, mjcf_import.hpp) and model_writer.hpp prints it as an
// mbrt model file.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "joint_types.hpp"
#include "model.hpp"

namespace mbrt::codegen {

// A rigid part's mass properties, world axes.
struct MassPart {
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about com
};

struct ImportedBody {
  std::string name;                                             // as the source names it
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // body to world
  MassPart mass;                                                // the body and every part merged into it
};

struct ImportedJoint {
  std::string name;  // as the source names it
  JointType type = JointType::revolute;  // revolute, prismatic, planar, spherical or fixed
  int body1 = kGround;                   // index in ImportedModel::bodies, or kGround
  int body2 = kGround;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // world
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // unit, world (revolute, prismatic; planar: normal)
  double armature = 0.0;
  // A joint_spring when stiffness or damping is non-zero; rest is measured
  // from the joint's position at t = 0, as mbrt measures joint coordinates.
  double stiffness = 0.0, damping = 0.0, rest = 0.0;
};

struct ImportedModel {
  std::string name;    // as the source names it
  std::string source;  // the file, as given
  std::string format;  // "URDF" or "MJCF"
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  std::optional<double> step;  // the source's time step, if it has one
  std::vector<ImportedBody> bodies;
  std::vector<ImportedJoint> joints;
  std::vector<std::string> notes;     // how the source was mapped (the output's header)
  std::vector<std::string> warnings;  // what the source has and the model has not (header and stderr)
};

// The shortest text that reads back as the same double (model file, messages).
std::string number_text(double x);

// Adds `part` to `into` (rigidly attached): total mass, combined centre of
// mass, inertia about it (parallel-axis theorem).
void merge_part(MassPart& into, const MassPart& part);

// Throws naming the body when a body has no mass: mbrt's rigid bodies need one.
void require_masses(const ImportedModel& model, const std::string& what_has_mass);

}  // namespace mbrt::codegen
