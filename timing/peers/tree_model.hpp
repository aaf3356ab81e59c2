// An mbrt model file as a tree of rigid bodies, the way the peer engines
// build it (tree_engine.hpp): bodies on revolute and spherical joints from
// ground under gravity, nothing else. Also mbrt's energy from body states, so
// every engine's energy compares with mbrt's.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "model.hpp"

namespace timing::tree {

using mbrt::codegen::Body;
using mbrt::codegen::Joint;
using mbrt::codegen::JointType;
using mbrt::codegen::kGround;
using mbrt::codegen::Model;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// One rigid body's state, all in world axes: COM position and velocity,
// body-to-world rotation, angular velocity.
struct BodyState {
  Vec3 r, v, w;
  Mat3 R;
};

Mat3 rotation(const Eigen::Vector4d& euler_parameters);
Vec3 gravity(const Model& m);

// The model's initial states (the file gives angular velocities in body axes).
std::vector<BodyState> model_states(const Model& m);

struct Energy {
  double kinetic = 0, potential = 0;
  double total() const { return kinetic + potential; }
};

// mbrt's energy: translational and rotational kinetic energy, and gravity's
// potential -m g.r (zero at the origin).
Energy energy(const Model& m, const std::vector<BodyState>& s);

// A body with the joint that connects it to its parent (kGround or a body
// index).
struct Link {
  int body;
  int parent;
  const Joint* joint;
};

// The model as a tree from ground, parents before their children, or an
// exception saying why it is not one the peer engines can run.
std::vector<Link> links(const Model& m);

// Angular velocity of a link relative to its parent, world axes.
Vec3 relative_angular_velocity(const std::vector<BodyState>& s, const Link& l);

// Whether the n values from x (an engine's state vector) are all finite.
template <class T>
bool all_finite(const T* x, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(x[i])) return false;
  return true;
}

// Empty when an engine's states match the model's initial ones (positions,
// orientations, velocities, energy) to 1e-9 relative; otherwise what differs.
std::string initial_mismatch(const Model& m, const std::vector<BodyState>& engine);

}  // namespace timing::tree
