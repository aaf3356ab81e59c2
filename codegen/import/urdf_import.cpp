#include "urdf_import.hpp"

#include <stdexcept>

#include <urdf_parser/urdf_parser.h>

namespace mbrt::codegen {

namespace {

Eigen::Isometry3d isometry(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized().toRotationMatrix();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return t;
}

// A link's <inertial> in world axes; its origin is in the link frame, and
// the inertia matrix in the frame that origin rotates to (URDF spec, <inertial>).
MassPart mass_part(const urdf::Link& link, const Eigen::Isometry3d& link_pose) {
  MassPart p;
  if (!link.inertial) return p;
  const urdf::Inertial& in = *link.inertial;
  const Eigen::Isometry3d frame = link_pose * isometry(in.origin);
  Eigen::Matrix3d j;
  j << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  p.mass = in.mass;
  p.com = frame.translation();
  p.inertia = frame.linear() * j * frame.linear().transpose();
  return p;
}

class UrdfReader {
 public:
  UrdfReader(const urdf::ModelInterface& urdf, ImportedModel& out) : urdf_(urdf), out_(out) {}

  // Forward kinematics at the zero configuration: a child link's frame is
  // its joint's frame, the joint origin composed onto the parent link's frame.
  void add_children(const urdf::Link& link, const Eigen::Isometry3d& pose, int body) {
    for (const urdf::JointSharedPtr& joint : link.child_joints) {
      const urdf::Link& child = *urdf_.getLink(joint->child_link_name);
      const Eigen::Isometry3d child_pose = pose * isometry(joint->parent_to_joint_origin_transform);
      add_children(child, child_pose, add_joint(*joint, child, child_pose, body));
    }
  }

 private:
  // Adds the child link (a new body, or merged into `parent` by a fixed
  // joint) and its joint; returns the child's body.
  int add_joint(const urdf::Joint& joint, const urdf::Link& child, const Eigen::Isometry3d& pose, int parent) {
    const std::string where = out_.source + ": joint '" + joint.name + "'";
    if (joint.mimic) {
      throw std::runtime_error(where + " mimics joint '" + joint.mimic->joint_name +
                               "': mimic couplings are not supported; remove the <mimic> element");
    }
    if (joint.type == urdf::Joint::FIXED) {
      if (parent == kGround) {
        out_.notes.push_back("link '" + child.name + "' is fixed to the ground by joint '" + joint.name + "'");
      } else {
        merge_part(out_.bodies[static_cast<size_t>(parent)].mass, mass_part(child, pose));
        out_.notes.push_back("link '" + child.name + "' (fixed joint '" + joint.name + "') is merged into '" +
                             out_.bodies[static_cast<size_t>(parent)].name + "'");
      }
      return parent;
    }
    ImportedBody body;
    body.name = child.name;
    body.orientation = Eigen::Quaterniond(pose.linear());
    body.mass = mass_part(child, pose);
    out_.bodies.push_back(body);
    const int index = static_cast<int>(out_.bodies.size()) - 1;
    if (joint.type == urdf::Joint::FLOATING) {
      out_.notes.push_back("link '" + child.name + "' (floating joint '" + joint.name + "') is a free body");
      return index;
    }
    ImportedJoint j;
    j.name = joint.name;
    j.body1 = parent;
    j.body2 = index;
    j.point = pose.translation();
    j.axis = pose.linear() * Eigen::Vector3d(joint.axis.x, joint.axis.y, joint.axis.z).normalized();
    if (joint.type == urdf::Joint::REVOLUTE || joint.type == urdf::Joint::CONTINUOUS) j.type = JointType::revolute;
    else if (joint.type == urdf::Joint::PRISMATIC) j.type = JointType::prismatic;
    else if (joint.type == urdf::Joint::PLANAR) j.type = JointType::planar;
    else throw std::runtime_error(where + ": unknown joint type");
    if (joint.limits && joint.type != urdf::Joint::CONTINUOUS) {
      out_.warnings.push_back("joint '" + joint.name + "': limits [" + number_text(joint.limits->lower) + ", " +
                              number_text(joint.limits->upper) + "] are not enforced (mbrt has no joint limits)");
    }
    if (joint.dynamics) add_dynamics(joint, j);
    out_.joints.push_back(j);
    return index;
  }

  // <dynamics damping>: a joint_spring without stiffness; friction: a warning.
  void add_dynamics(const urdf::Joint& joint, ImportedJoint& j) {
    if (joint.dynamics->friction != 0.0) {
      out_.warnings.push_back("joint '" + joint.name + "': friction " + number_text(joint.dynamics->friction) +
                              " is not supported and left out");
    }
    if (joint.dynamics->damping == 0.0) return;
    if (j.type == JointType::planar) {
      out_.warnings.push_back("joint '" + joint.name + "': damping on a planar joint is not supported and left out");
      return;
    }
    j.damping = joint.dynamics->damping;
  }

  const urdf::ModelInterface& urdf_;
  ImportedModel& out_;
};

}  // namespace

ImportedModel import_urdf(const std::string& path) {
  const urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDFFile(path);
  if (!urdf) throw std::runtime_error(path + ": not a URDF file urdfdom can read (its messages above name the element)");
  ImportedModel out;
  out.name = urdf->getName();
  out.source = path;
  out.format = "URDF";
  out.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);  // URDF has none: standard gravity along -z
  const urdf::Link& root = *urdf->getRoot();
  out.notes.push_back("gravity: URDF has none; standard gravity along -z");
  out.notes.push_back("root link '" + root.name + "' is fixed to the ground");
  UrdfReader(*urdf, out).add_children(root, Eigen::Isometry3d::Identity(), kGround);
  int collisions = 0;
  std::vector<urdf::LinkSharedPtr> links;
  urdf->getLinks(links);
  for (const urdf::LinkSharedPtr& link : links) collisions += link->collision ? 1 : 0;
  if (collisions > 0) {
    out.warnings.push_back(std::to_string(collisions) + " links have <collision> geometry; contacts are not imported");
  }
  require_masses(out, "a link without <inertial>");
  return out;
}

}  // namespace mbrt::codegen
