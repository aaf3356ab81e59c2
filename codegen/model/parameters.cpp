#include "parameters.hpp"

#include <algorithm>

namespace mbrt::codegen {

namespace {

const char* const kAxes[] = {"x", "y", "z"};
const char* const kDiagonal[] = {"xx", "yy", "zz"};
// The components of a sine driver in the order of mbrt::Sine.
const char* const kSine[] = {"amplitude", "omega", "phase", "offset"};

bool diagonal(const Eigen::Matrix3d& j) { return j == Eigen::Matrix3d(j.diagonal().asDiagonal()); }

// Every parameter the model could mark, with the file's values.
std::vector<Parameter> candidates(const Model& model) {
  std::vector<Parameter> out;
  const auto vector = [&](const std::string& name, ParameterTarget target, int index, const Eigen::Vector3d& v,
                          const char* const* components) {
    for (int k = 0; k < 3; ++k) out.push_back({name + "." + components[k], target, index, k, v[k], {}, {}});
  };
  if (model.gravity) vector("gravity", ParameterTarget::gravity, -1, *model.gravity, kAxes);
  for (size_t i = 0; i < model.bodies.size(); ++i) {
    const Body& b = model.bodies[i];
    const int n = static_cast<int>(i);
    out.push_back({b.name + ".mass", ParameterTarget::mass, n, 0, b.mass, {}, {}});
    if (!b.particle && diagonal(b.inertia)) vector(b.name + ".inertia", ParameterTarget::inertia, n, b.inertia.diagonal(), kDiagonal);
    vector(b.name + ".position", ParameterTarget::position, n, b.position, kAxes);
    vector(b.name + ".velocity", ParameterTarget::velocity, n, b.velocity, kAxes);
    if (!b.particle) vector(b.name + ".angular_velocity", ParameterTarget::angular_velocity, n, b.angular_velocity, kAxes);
  }
  for (size_t i = 0; i < model.joints.size(); ++i) {
    const Joint& j = model.joints[i];
    if (j.type != JointType::revolute && j.type != JointType::prismatic) continue;
    const int n = static_cast<int>(i);
    out.push_back({j.name + ".coordinate", ParameterTarget::joint_coordinate, n, 0, 0.0, {}, {}});
    out.push_back({j.name + ".rate", ParameterTarget::joint_rate, n, 0, joint_rate_at_start(model, j), {}, {}});
  }
  for (size_t i = 0; i < model.forces.size(); ++i) {
    const Force& f = model.forces[i];
    const int n = static_cast<int>(i);
    std::string prefix;
    if (f.type == ForceType::joint_spring) prefix = model.joints[static_cast<size_t>(f.joint)].name + ".spring.";
    else if (f.type == ForceType::spring_damper) prefix = "forces." + std::to_string(i) + ".";
    else continue;
    const bool joint = f.type == ForceType::joint_spring;
    out.push_back({prefix + "stiffness", ParameterTarget::spring_stiffness, n, 0, f.stiffness, {}, {}});
    out.push_back({prefix + "damping", ParameterTarget::spring_damping, n, 0, f.damping, {}, {}});
    out.push_back({prefix + (joint ? "rest" : "rest_length"), ParameterTarget::spring_rest, n, 0,
                   joint ? f.rest : f.rest_length, {}, {}});
  }
  for (size_t i = 0; i < model.drivers.size(); ++i) {
    const Driver& d = model.drivers[i];
    const TimeFunction& f = d.function;
    const int n = static_cast<int>(i);
    const std::string prefix = d.name + ".function.";
    if (f.piecewise()) continue;  // not tunable: its pieces' coefficients are fixed at generation
    if (f.is_sine) {
      const double values[] = {f.amplitude, f.omega, f.phase, f.offset};
      for (int k = 0; k < 4; ++k) out.push_back({prefix + kSine[k], ParameterTarget::driver_coefficient, n, k, values[k], {}, {}});
    } else {
      for (size_t k = 0; k < f.polynomial.size(); ++k) {
        out.push_back({prefix + "c" + std::to_string(k), ParameterTarget::driver_coefficient, n, static_cast<int>(k),
                       f.polynomial[k], {}, {}});
      }
    }
  }
  return out;
}

std::string keys_help(const Model& model) {
  return "tunable keys are gravity (when the model has it), BODY.mass, BODY.inertia (a diagonal one), BODY.position, "
         "BODY.velocity, BODY.angular_velocity, JOINT.coordinate and JOINT.rate (a revolute or prismatic joint, in "
         "the tree schemes), JOINT.spring (of a joint_spring), forces.N (a spring_damper, N its index in forces), "
         "DRIVER.function (c0, c1, ... of a polynomial, amplitude, omega, phase, offset of a sine; not a piecewise one) or one component "
         "of them, e.g. " +
         (model.bodies.empty() ? std::string("body.mass") : model.bodies.front().name + ".position.x");
}

}  // namespace

std::vector<Parameter> parameters(const Model& model) {
  const std::vector<Parameter> all = candidates(model);
  std::vector<Parameter> out;
  for (size_t i = 0; i < model.tunable.size(); ++i) {
    const TunableKey& t = model.tunable[i];
    const std::string key = "tunable[" + std::to_string(i) + "]";
    const auto selects = [&](const Parameter& p) { return p.name == t.key || p.name.rfind(t.key + ".", 0) == 0; };
    size_t found = 0;
    for (Parameter p : all) {
      if (!selects(p)) continue;
      ++found;
      if (std::any_of(out.begin(), out.end(), [&](const Parameter& q) { return q.name == p.name; })) {
        throw ModelError(t.where, key, "'" + t.key + "': " + p.name + " is marked tunable twice");
      }
      p.where = t.where;
      p.entry = t.key;
      out.push_back(p);
    }
    if (found > 0) continue;
    for (const Body& b : model.bodies) {
      if (!b.particle && !diagonal(b.inertia) && t.key.rfind(b.name + ".inertia", 0) == 0) {
        throw ModelError(t.where, key, "'" + t.key + "': the inertia of " + b.name +
                                           " has products; only a diagonal inertia can be tunable (its principal "
                                           "moments in principal body axes)");
      }
    }
    throw ModelError(t.where, key, "'" + t.key + "' is not a tunable key of this model; " + keys_help(model));
  }
  return out;
}

std::vector<std::string> tunable_names(const Model& model) {
  std::vector<std::string> names;
  for (const Parameter& p : parameters(model)) names.push_back(p.name);
  return names;
}

std::string parameter_identifier(const std::string& name) {
  std::string s = name;
  std::replace(s.begin(), s.end(), '.', '_');
  return s;
}

}  // namespace mbrt::codegen
