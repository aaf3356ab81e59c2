#include "tree_frames.hpp"

#include <cmath>

#include <Eigen/Geometry>

#include <mbrt/rotation.hpp>

#include "analysis.hpp"
#include "tree_plan.hpp"

namespace mbrt::codegen {

namespace {

// Geometry given as exact axes gives entries like 6e-17 where 0 is meant;
// those would cost multiplications in every step.
double snap(double x) {
  constexpr double tol = 1e-12;
  if (std::abs(x) < tol) return 0.0;
  if (std::abs(x - 1.0) < tol) return 1.0;
  if (std::abs(x + 1.0) < tol) return -1.0;
  return x;
}

template <class M>
M snapped(M m) {
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = snap(m.data()[i]);
  return m;
}

Eigen::Vector4d euler_parameters(const Eigen::Matrix3d& r) {
  Eigen::Quaterniond q(r);
  q.normalize();
  return snapped(Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()));
}

// A unit vector normal to z, as close as possible to the given direction.
Eigen::Vector3d normal_to(const Eigen::Vector3d& z, const Eigen::Vector3d& toward) {
  Eigen::Vector3d x = toward - toward.dot(z) * z;
  if (x.norm() < 1e-9) {
    const Eigen::Index k = z.cwiseAbs().minCoeff() == std::abs(z.x()) ? 0 : z.cwiseAbs().minCoeff() == std::abs(z.y()) ? 1 : 2;
    x = Eigen::Vector3d::Unit(k) - z[k] * z;
  }
  return x.normalized();
}

struct WorldFrame {
  Eigen::Matrix3d R;  // frame to world
  Eigen::Vector3d o;  // origin, world
};

}  // namespace

TreeFrames plan_tree_frames(const Model& model, const std::vector<ConstraintBlock>& blocks) {
  TreeFrames out;
  const auto refuse = [&](const std::string& why) {
    out.frames.clear();
    out.refusal = why;
    return out;
  };
  if (!model.drivers.empty()) return refuse("drivers are constraints outside a tree (model a driven joint with an input)");
  for (const Body& b : model.bodies) {
    if (b.particle) return refuse("particle " + b.name + " has no joint coordinates");
  }
  for (const Joint& j : model.joints) {
    if (j.type != JointType::revolute && j.type != JointType::prismatic) {
      return refuse("joint " + j.name + " is " + std::string(type_row(j.type).name) +
                    "; the tree step takes revolute and prismatic joints");
    }
  }
  const TreePlan tree = plan_tree(model, blocks);
  if (!tree.cut_blocks.empty()) {
    return refuse("a joint closes a loop: " + blocks[static_cast<size_t>(tree.cut_blocks.front())].name);
  }
  std::vector<int> frame_of(model.bodies.size(), -1);
  std::vector<int> first_child(tree.order.size(), -1);
  for (size_t k = 0; k < tree.order.size(); ++k) {
    const TreeBody& tb = tree.order[k];
    if (tb.joint < 0) return refuse("body " + model.bodies[static_cast<size_t>(tb.body)].name + " hangs from no joint");
    frame_of[static_cast<size_t>(tb.body)] = static_cast<int>(k);
    if (tb.parent != kGround) {
      int& f = first_child[static_cast<size_t>(frame_of[static_cast<size_t>(tb.parent)])];
      if (f < 0) f = static_cast<int>(k);
    }
  }

  // World frames at t = 0: z along the joint axis, origin on it, x along the
  // common normal to the first child's axis.
  std::vector<WorldFrame> world(tree.order.size());
  for (size_t k = 0; k < tree.order.size(); ++k) {
    const TreeBody& tb = tree.order[k];
    const Joint& j = model.joints[static_cast<size_t>(tb.joint)];
    const Body& body = model.bodies[static_cast<size_t>(tb.body)];
    const Eigen::Vector3d z = j.axis.normalized();
    Eigen::Vector3d o = j.point, x;
    if (const int c = first_child[k]; c >= 0) {
      const Joint& jc = model.joints[static_cast<size_t>(tree.order[static_cast<size_t>(c)].joint)];
      const Eigen::Vector3d zc = jc.axis.normalized();
      const Eigen::Vector3d n = z.cross(zc);
      if (n.norm() > 1e-9) {
        const Eigen::Vector3d w0 = j.point - jc.point;
        const double b = z.dot(zc), d = z.dot(w0), e = zc.dot(w0);
        o = j.point + ((b * e - d) / (1.0 - b * b)) * z;
        x = n.normalized();
      } else {
        x = normal_to(z, jc.point - j.point);
      }
    } else {
      // A leaf: x toward the COM, which then has one coordinate off the axis.
      const Eigen::Vector3d to_com = body.position - j.point;
      o = j.point + to_com.dot(z) * z;
      x = normal_to(z, to_com.norm() > 1e-12 ? to_com : mbrt::rotation_matrix(body.orientation).col(0));
    }
    world[k].R.col(0) = x;
    world[k].R.col(1) = z.cross(x);
    world[k].R.col(2) = z;
    world[k].o = o;
  }

  for (size_t k = 0; k < tree.order.size(); ++k) {
    const TreeBody& tb = tree.order[k];
    const Joint& j = model.joints[static_cast<size_t>(tb.joint)];
    const Body& body = model.bodies[static_cast<size_t>(tb.body)];
    TreeFrame f;
    f.body = tb.body;
    f.parent = tb.parent == kGround ? kGround : frame_of[static_cast<size_t>(tb.parent)];
    f.joint = tb.joint;
    f.revolute = j.type == JointType::revolute;
    const WorldFrame parent = f.parent == kGround ? WorldFrame{Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()}
                                                   : world[static_cast<size_t>(f.parent)];
    const Eigen::Matrix3d e0 = snapped(Eigen::Matrix3d(world[k].R.transpose() * parent.R));
    // Craig's form needs the child's z axis normal to the parent's x axis.
    const double c0 = e0(0, 0), s0 = -e0(1, 0);
    Eigen::Matrix3d ex = Eigen::Matrix3d::Identity();
    ex(1, 1) = e0(2, 2);
    ex(1, 2) = -e0(2, 1);
    ex(2, 1) = e0(2, 1);
    ex(2, 2) = e0(2, 2);
    const double theta0 = std::atan2(s0, c0);
    Eigen::Matrix3d rz = Eigen::Matrix3d::Identity();  // Rz(theta0)^T
    rz << std::cos(theta0), std::sin(theta0), 0, -std::sin(theta0), std::cos(theta0), 0, 0, 0, 1;
    if (f.revolute && e0(2, 0) == 0.0 && (rz * ex - e0).cwiseAbs().maxCoeff() < 1e-12) {
      f.theta0 = snap(theta0);
      f.Ex = snapped(ex);
    } else {
      f.Ex = e0;
    }
    f.turn = euler_parameters(f.Ex.transpose());
    f.r = snapped(Eigen::Vector3d(parent.R.transpose() * (world[k].o - parent.o)));
    // Two shifts along one axis each cost less than one along a general r.
    const Eigen::Vector3d z_in_parent = f.Ex.transpose().col(2);
    const double along_z = f.r.dot(z_in_parent);
    const Eigen::Vector3d rest = f.r - along_z * z_in_parent;
    if (std::abs(rest.y()) < 1e-12 && std::abs(rest.z()) < 1e-12 && f.r.cwiseAbs().maxCoeff() > 0.0) {
      f.d = snap(along_z);
      f.r = snapped(Eigen::Vector3d(rest.x(), 0.0, 0.0));
    }
    const Eigen::Matrix3d body_R = mbrt::rotation_matrix(body.orientation);
    f.body_axes = snapped(Eigen::Matrix3d(world[k].R.transpose() * body_R));
    f.body_turn = euler_parameters(f.body_axes);
    f.mass = body.mass;
    f.com = snapped(Eigen::Vector3d(world[k].R.transpose() * (body.position - world[k].o)));
    f.inertia = snapped(Eigen::Matrix3d(f.body_axes * body.inertia * f.body_axes.transpose()));

    // The joint rate at t = 0, the child's relative to its parent.
    f.armature = j.armature;
    f.friction = j.friction;
    f.sign = tb.body == j.body2 ? 1.0 : -1.0;
    f.rate0 = f.sign * joint_rate_at_start(model, j);
    out.frames.push_back(f);
  }

  for (TreeFrame& f : out.frames) {
    const bool root = f.parent == kGround;
    const TreeFrame* parent = root ? nullptr : &out.frames[static_cast<size_t>(f.parent)];
    const Eigen::Matrix3d parent_axes = root ? Eigen::Matrix3d::Identity() : parent->body_axes;
    const Eigen::Vector3d parent_com = root ? Eigen::Vector3d::Zero() : parent->com;
    const Eigen::Vector4d parent_turn = root ? Eigen::Vector4d(1, 0, 0, 0) : parent->body_turn;
    const Eigen::Vector3d axis = f.Ex.transpose().col(2);  // parent frame
    f.joint_from_parent = snapped(Eigen::Vector3d(parent_axes.transpose() * (f.r + f.d * axis - parent_com)));
    f.axis_in_parent = snapped(Eigen::Vector3d(parent_axes.transpose() * axis));
    f.com_in_body = snapped(Eigen::Vector3d(f.body_axes.transpose() * f.com));
    // conj(parent body_turn) turn (ch + sh k) body_turn.
    const Eigen::Vector4d lead = mbrt::quaternion_product(
        Eigen::Vector4d(parent_turn[0], -parent_turn[1], -parent_turn[2], -parent_turn[3]), f.turn);
    f.relative_c = snapped(Eigen::Vector4d(mbrt::quaternion_product(lead, f.body_turn)));
    if (f.revolute) {
      f.relative_s = snapped(Eigen::Vector4d(
          mbrt::quaternion_product(lead, mbrt::quaternion_product(Eigen::Vector4d(0, 0, 0, 1), f.body_turn))));
    }
  }
  return out;
}

}  // namespace mbrt::codegen
