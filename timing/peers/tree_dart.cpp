// DART 6.12 on an mbrt model file: World::step (forward dynamics by the
// articulated-body recursion in joint coordinates, then semi-implicit Euler).
// Each joint's frame is the child body's frame at t = 0 (origin at the joint),
// so every joint starts at q = 0; a ball joint's rates are then the relative
// angular velocity in the child's axes.
#include <cmath>
#include <memory>
#include <string>

#include <dart/dynamics/BallJoint.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/simulation/World.hpp>

#include "tree_engine.hpp"

namespace timing::tree {
namespace {

using dart::dynamics::BodyNode;

Eigen::Isometry3d pose(const Mat3& R, const Vec3& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = R;
  t.translation() = p;
  return t;
}

class DartEngine final : public Engine {
 public:
  DartEngine(const Model& m, double h)
      : skeleton_(dart::dynamics::Skeleton::create(m.name)), world_(dart::simulation::World::create()) {
    const std::vector<BodyState> s = model_states(m);
    nodes_.resize(m.bodies.size());
    for (const Link& l : links(m)) add(m, s, l);
    skeleton_->setGravity(gravity(m));
    world_->setGravity(gravity(m));
    world_->setTimeStep(h);
    world_->addSkeleton(skeleton_);
  }

  // The check reads the joint positions one by one: getPositions() would allocate.
  bool step() override {
    world_->step();
    for (std::size_t i = 0; i < skeleton_->getNumDofs(); ++i)
      if (!std::isfinite(skeleton_->getPosition(i)) || !std::isfinite(skeleton_->getVelocity(i))) return false;
    return true;
  }
  double time() const override { return world_->getTime(); }

  std::vector<BodyState> states() override {
    std::vector<BodyState> out;
    for (BodyNode* b : nodes_) {
      const Eigen::Isometry3d& x = b->getWorldTransform();  // origin at the COM
      out.push_back({x.translation(), b->getLinearVelocity(), b->getAngularVelocity(), x.linear()});
    }
    return out;
  }

 private:
  template <class JointType>
  typename JointType::Properties joint_properties(const std::vector<BodyState>& s, const Link& l) {
    const BodyState& child = s[static_cast<std::size_t>(l.body)];
    const BodyState ground{Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Mat3::Identity()};
    const BodyState& parent = l.parent == kGround ? ground : s[static_cast<std::size_t>(l.parent)];
    typename JointType::Properties p;
    p.mName = l.joint->name;
    p.mT_ParentBodyToJoint = pose(parent.R.transpose() * child.R, parent.R.transpose() * (l.joint->point - parent.r));
    p.mT_ChildBodyToJoint = pose(Mat3::Identity(), child.R.transpose() * (l.joint->point - child.r));
    return p;
  }

  void add(const Model& m, const std::vector<BodyState>& s, const Link& l) {
    const Body& b = m.bodies[static_cast<std::size_t>(l.body)];
    const BodyState& child = s[static_cast<std::size_t>(l.body)];
    BodyNode::Properties body;
    body.mName = b.name;
    body.mInertia = dart::dynamics::Inertia(b.mass, Vec3::Zero(), b.inertia);
    BodyNode* parent = l.parent == kGround ? nullptr : nodes_[static_cast<std::size_t>(l.parent)];
    const Vec3 w = child.R.transpose() * relative_angular_velocity(s, l);  // child axes
    if (l.joint->type == JointType::revolute) {
      auto joint = joint_properties<dart::dynamics::RevoluteJoint>(s, l);
      joint.mAxis = child.R.transpose() * l.joint->axis;
      auto pair = skeleton_->createJointAndBodyNodePair<dart::dynamics::RevoluteJoint>(parent, joint, body);
      pair.first->setVelocity(0, joint.mAxis.dot(w));
      nodes_[static_cast<std::size_t>(l.body)] = pair.second;
    } else {
      auto joint = joint_properties<dart::dynamics::BallJoint>(s, l);
      auto pair = skeleton_->createJointAndBodyNodePair<dart::dynamics::BallJoint>(parent, joint, body);
      for (int i = 0; i < 3; ++i) pair.first->setVelocity(static_cast<std::size_t>(i), w[i]);
      nodes_[static_cast<std::size_t>(l.body)] = pair.second;
    }
  }

  dart::dynamics::SkeletonPtr skeleton_;
  dart::simulation::WorldPtr world_;
  std::vector<BodyNode*> nodes_;  // of each mbrt body
};

}  // namespace

std::unique_ptr<Engine> dart_engine(const Model& m, double h) { return std::make_unique<DartEngine>(m, h); }

}  // namespace timing::tree
