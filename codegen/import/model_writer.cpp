#include "model_writer.hpp"

#include <set>
#include <sstream>

namespace mbrt::codegen {

namespace {

template <typename Vector>
std::string list(const Vector& v) {
  std::string s = "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) s += (i ? ", " : "") + number_text(v(i));
  return s + "]";
}

// Names unique within one kind, valid as mbrt names.
class Names {
 public:
  explicit Names(std::set<std::string> taken) : taken_(std::move(taken)) {}
  std::string add(const std::string& source) {
    std::string name;
    for (char c : source) {
      const char l = (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
      name += ((l >= 'a' && l <= 'z') || (l >= '0' && l <= '9')) ? l : '_';
    }
    if (name.empty() || name[0] < 'a' || name[0] > 'z') name = "x_" + name;
    std::string unique = name;
    for (int k = 2; !taken_.insert(unique).second; ++k) unique = name + "_" + std::to_string(k);
    return unique;
  }

 private:
  std::set<std::string> taken_;
};

std::string renamed(const std::string& name, const std::string& source) {
  return name == source ? "" : "  # '" + source + "' in the source";
}

// [Ixx, Iyy, Izz] when the body axes are principal, else all six.
std::string inertia(const ImportedBody& b) {
  const Eigen::Matrix3d r = b.orientation.toRotationMatrix();
  const Eigen::Matrix3d j = r.transpose() * b.mass.inertia * r;
  const Eigen::Vector3d diagonal = j.diagonal();
  const Eigen::Vector3d products(j(0, 1), j(0, 2), j(1, 2));
  if (products.cwiseAbs().maxCoeff() <= 1e-14 * diagonal.sum()) return list(diagonal);
  Eigen::Matrix<double, 6, 1> six;
  six << diagonal, products;
  return list(six);
}

}  // namespace

std::string model_yaml(const ImportedModel& model) {
  std::ostringstream o;
  o << "# Imported by `mbrt import` from " << model.source << " (" << model.format << ").\n";
  for (const std::string& n : model.notes) o << "# " << n << "\n";
  for (const std::string& w : model.warnings) o << "# warning: " << w << "\n";
  o << "name: " << Names({}).add(model.name.empty() ? "imported" : model.name) << "\n";
  if (model.gravity != Eigen::Vector3d::Zero()) o << "gravity: " << list(model.gravity) << "\n";

  Names body_names({"ground"});
  std::vector<std::string> bodies;
  if (!model.bodies.empty()) o << "bodies:\n";
  for (const ImportedBody& b : model.bodies) {
    bodies.push_back(body_names.add(b.name));
    const Eigen::Quaterniond q = b.orientation.normalized();
    o << "  - {name: " << bodies.back() << ", mass: " << number_text(b.mass.mass) << ", inertia: " << inertia(b)
      << ", position: " << list(b.mass.com) << ", orientation: " << list(Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()))
      << "}" << renamed(bodies.back(), b.name) << "\n";
  }
  const auto body = [&bodies](int i) { return i == kGround ? std::string("ground") : bodies[static_cast<size_t>(i)]; };

  Names joint_names({});
  std::vector<std::string> joints;
  if (!model.joints.empty()) o << "joints:\n";
  for (const ImportedJoint& j : model.joints) {
    joints.push_back(joint_names.add(j.name));
    o << "  - {name: " << joints.back() << ", type: " << type_row(j.type).name << ", body1: " << body(j.body1)
      << ", body2: " << body(j.body2) << ", point: " << list(j.point);
    if (j.type == JointType::revolute || j.type == JointType::prismatic || j.type == JointType::planar) {
      o << ", axis: " << list(j.axis);
    }
    if (j.armature != 0.0) o << ", armature: " << number_text(j.armature);
    o << "}" << renamed(joints.back(), j.name) << "\n";
  }

  bool forces = false;
  for (size_t i = 0; i < model.joints.size(); ++i) {
    const ImportedJoint& j = model.joints[i];
    if (j.stiffness == 0.0 && j.damping == 0.0) continue;
    if (!forces) o << "forces:\n";
    forces = true;
    o << "  - {type: joint_spring, joint: " << joints[i] << ", stiffness: " << number_text(j.stiffness)
      << ", damping: " << number_text(j.damping) << ", rest: " << number_text(j.rest) << "}\n";
  }
  if (model.step) o << "solver: {step: " << number_text(*model.step) << "}\n";
  return o.str();
}

}  // namespace mbrt::codegen
