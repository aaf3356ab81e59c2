// The frames of the staggered-tree step (docs/staggered-tree.md): one joint
// frame per body, with z along its joint's axis and, where the tree allows,
// x along the common normal to its first child's axis (the modified
// Denavit-Hartenberg convention, Craig 1986, "Introduction to Robotics",
// section 3.4), so the transforms between frames are mostly zeros and ones
// that the generated recursion never multiplies.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "model.hpp"

namespace mbrt::codegen {

struct ConstraintBlock;

struct TreeFrame {
  int body;        // Model::bodies index; the joint coordinate's index is this frame's
  int parent;      // TreeFrames::frames index, or kGround
  int joint;       // Model::joints index
  bool revolute;   // else prismatic
  // Parent-frame to this frame's coordinates at angle phi = q + theta0:
  // E(q) = Rz(phi)^T Ex with Ex a turn about x by alpha (Craig's form) or,
  // where the parent's x axis could not be chosen for this body, Ex = E(0).
  double theta0 = 0.0;
  Eigen::Matrix3d Ex = Eigen::Matrix3d::Identity();
  Eigen::Vector4d turn = {1, 0, 0, 0};  // Euler parameters of Ex^T
  // This origin from the parent's at q = 0: r (parent axes) plus d along this
  // frame's z. Craig's form puts all of r on the parent's x axis.
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  double d = 0.0;
  // The body in this frame: mass, COM, inertia about the COM.
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d body_axes = Eigen::Matrix3d::Identity();  // body to frame axes
  Eigen::Vector4d body_turn = {1, 0, 0, 0};                  // Euler parameters of body_axes
  // The body's state from its parent body's, in the bodies' axes: Euler
  // parameters parent body to this body, relative_c ch + relative_s sh for
  // a revolute joint's half angle (relative_c alone for a slide); the joint's
  // origin at q = 0 from the parent's centre of mass and its axis, both in
  // the parent body's axes (world axes for the root); the centre of mass from
  // the origin, this body's axes.
  Eigen::Vector4d relative_c = {1, 0, 0, 0}, relative_s = {0, 0, 0, 0};
  Eigen::Vector3d joint_from_parent = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_in_parent = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d com_in_body = Eigen::Vector3d::Zero();
  double rate0 = 0.0;  // joint rate at t = 0
  // The model's joint coordinate (body 2 relative to body 1) is sign * q:
  // -1 where the tree hangs the joint's body 1 from its body 2.
  double sign = 1.0;
  double armature = 0.0;
  JointFriction friction;  // docs/friction.md
};

struct TreeFrames {
  std::vector<TreeFrame> frames;  // parents first
  std::string refusal;            // why the model is no tree of one-dof joints ("" when it is)
};

// Frames for a model whose bodies hang from ground by revolute and prismatic
// joints alone; otherwise frames is empty and refusal says why.
TreeFrames plan_tree_frames(const Model& model, const std::vector<ConstraintBlock>& blocks);


}  // namespace mbrt::codegen
