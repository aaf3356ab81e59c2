#include "dart_engine.hpp"

#include <cmath>
#include <stdexcept>

#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/simulation/World.hpp>

#include "tree_peer.hpp"

namespace timing {
namespace {

using dart::dynamics::BodyNode;
using dart::dynamics::RevoluteJoint;
using dart::dynamics::SkeletonPtr;

Eigen::Vector3d vec(const mbrt::Vec3& v) { return {v[0], v[1], v[2]}; }

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(x, y, z);
  return t;
}

// A body on a revolute joint about z. The joint sits at parent_at in the
// parent's frame and at child_at in the body's; mass, centre of mass and
// central inertia diag(i) in the body's frame.
BodyNode* hinge(const SkeletonPtr& skeleton, BodyNode* parent, const std::string& name,
                const Eigen::Isometry3d& parent_at, const Eigen::Isometry3d& child_at, double mass,
                const Eigen::Vector3d& com, const Eigen::Vector3d& i) {
  RevoluteJoint::Properties joint;
  joint.mName = name + "_joint";
  joint.mAxis = Eigen::Vector3d::UnitZ();
  joint.mT_ParentBodyToJoint = parent_at;
  joint.mT_ChildBodyToJoint = child_at;
  BodyNode::Properties body;
  body.mName = name;
  body.mInertia = dart::dynamics::Inertia(mass, com, i.asDiagonal());
  return skeleton->createJointAndBodyNodePair<RevoluteJoint>(parent, joint, body).second;
}

SkeletonPtr build(const Problem& p) {
  SkeletonPtr s = dart::dynamics::Skeleton::create(p.name);
  switch (p.mechanism) {
    case Mechanism::a01_pendulum:
      // The bob is a point mass at the body origin, the pivot 1 m to its
      // right on a massless bar (1e-12 kg m^2 as in the other peers).
      hinge(s, nullptr, "bob", at(0, 0, 0), at(1, 0, 0), 1, Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(1e-12));
      break;
    case Mechanism::chain: {
      // Uniform 1 kg, 1 m rods along x from their joint: m L^2/12
      // transverse, 1e-4 axial (as the mbrt models).
      const double t = 1.0 / 12.0;
      BodyNode* parent = nullptr;
      for (int i = 0; i < p.n; ++i)
        parent = hinge(s, parent, "link_" + std::to_string(i), at(i == 0 ? 0 : 1, 0, 0), at(0, 0, 0), 1,
                       {0.5, 0, 0}, {1e-4, t, t});
      break;
    }
    case Mechanism::heavy_top:
    case Mechanism::n_four_bar:
    case Mechanism::andrews: throw std::invalid_argument("DART builds trees of revolute joints only, not " + p.name);
    case Mechanism::model_file: throw std::logic_error("a model file is built by tree_peer");
  }
  s->setGravity(vec(gravity(p.mechanism)));
  return s;
}

class DartEngine final : public PeerEngine {
 public:
  DartEngine(const Problem& p, double h) : skeleton_(build(p)), world_(dart::simulation::World::create()) {
    world_->setGravity(vec(gravity(p.mechanism)));
    world_->setTimeStep(h);
    world_->addSkeleton(skeleton_);
    body_ = skeleton_->getBodyNode(p.body);
    if (!body_) throw std::invalid_argument("DART skeleton has no body " + p.body);
    station_ = body_->getWorldTransform().inverse() * vec(p.point);
  }

  // World::step: forward dynamics, velocities, the constraint solver (here
  // with nothing to solve), then positions from the new velocities. The
  // check reads the joint angles one by one: getPositions() would allocate.
  bool step() override {
    world_->step();
    for (std::size_t i = 0; i < skeleton_->getNumDofs(); ++i)
      if (!std::isfinite(skeleton_->getPosition(i))) return false;
    return true;
  }
  double time() const override { return world_->getTime(); }
  mbrt::Vec3 observed() override {
    const Eigen::Vector3d x = body_->getWorldTransform() * station_;
    return {x[0], x[1], x[2]};
  }

 private:
  SkeletonPtr skeleton_;
  dart::simulation::WorldPtr world_;
  BodyNode* body_ = nullptr;
  Eigen::Vector3d station_;
};

}  // namespace

const std::vector<std::string>& dart_methods() {
  static const std::vector<std::string> names{"semi_implicit_euler"};
  return names;
}

// Not built: the four-bars and Andrews' squeezer, closed loops that DART
// would close with its constraint solver, and the heavy top.
bool dart_builds(const Problem& p) {
  return p.mechanism == Mechanism::a01_pendulum || p.mechanism == Mechanism::chain ||
         p.mechanism == Mechanism::model_file;
}

std::unique_ptr<PeerEngine> dart_engine(const Problem& p, const std::string&, double h) {
  if (p.mechanism == Mechanism::model_file) return tree_peer(p, "dart-euler", h);
  return std::make_unique<DartEngine>(p, h);
}

Measurement run_dart(const Problem& p, const std::string& method, double h) {
  const std::unique_ptr<PeerEngine> engine = dart_engine(p, method, h);
  return measure(p, *engine, {p.name, "dart", method, h});
}

}  // namespace timing
