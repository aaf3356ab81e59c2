// Emission of a model's inputs (commands applied as loads by the step) and
// outputs (signals computed from the state): their declarations in the
// header, the loads and outputs().
#include "emitter.hpp"

namespace mbrt::codegen {

// Inputs: index constants, ranges and safe values; State gains `inputs`.
void Emitter::input_declarations(std::ostringstream& o) const {
  o << "// Commands step() applies (State::inputs), SI units; limits and safe values in kInputInfo.\n"
    << "namespace input {\n";
  for (size_t i = 0; i < m_.inputs.size(); ++i) {
    const Input& in = m_.inputs[i];
    o << "inline constexpr int " << in.name << " = " << i << ";  // " << type_row(in.type).name << " "
      << input_target(in) << ", " << (in.type == InputType::joint_force ? "N" : "N m") << "\n";
  }
  o << "}  // namespace input\n"
    << "inline constexpr int kInputs = " << m_.inputs.size() << ";\n"
    << "using Inputs = std::array<double, kInputs>;\n"
    << "inline constexpr std::array<mbrt::InputInfo, kInputs> kInputInfo{{\n";
  for (const Input& in : m_.inputs) {
    o << "    {\"" << in.name << "\", \"" << type_row(in.type).name << "\", \"" << input_target(in) << "\", "
      << num(in.min) << ", " << num(in.max) << ", " << num(in.safe) << "},\n";
  }
  o << "}};\n\n";
}

// Outputs: one flat array of values; each signal's first index and count.
void Emitter::output_declarations(std::ostringstream& o) const {
  o << "// Signals outputs() computes, as one array of values; see kOutputInfo.\nnamespace output {\n";
  int first = 0;
  for (const Output& out : m_.outputs) {
    o << "inline constexpr int " << out.name << " = " << first << ";  // " << type_row(out.type).name << " of "
      << output_source(out) << ", " << output_layout(out) << "\n";
    first += type_row(out.type).values;
  }
  o << "}  // namespace output\n"
    << "inline constexpr int kOutputSignals = " << m_.outputs.size() << ";\n"
    << "inline constexpr int kOutputs = " << output_value_count() << ";  // values\n"
    << "using Outputs = std::array<double, kOutputs>;\n"
    << "inline constexpr std::array<mbrt::OutputInfo, kOutputSignals> kOutputInfo{{\n";
  first = 0;
  for (const Output& out : m_.outputs) {
    o << "    {\"" << out.name << "\", \"" << type_row(out.type).name << "\", \"" << output_source(out) << "\", "
      << first << ", " << type_row(out.type).values << "},\n";
    first += type_row(out.type).values;
  }
  o << "}};\n\n";
}

int Emitter::output_value_count() const {
  int n = 0;
  for (const Output& out : m_.outputs) n += type_row(out.type).values;
  return n;
}

std::string Emitter::input_target(const Input& in) const {
  if (in.type == InputType::motor_torque) return m_.body_name(in.body1) + "-" + m_.body_name(in.body2);
  return m_.joints[static_cast<size_t>(in.joint)].name;
}
std::string Emitter::output_source(const Output& out) const {
  if (out.contact >= 0) return m_.contacts[static_cast<size_t>(out.contact)].name;
  if (out.joint >= 0) return m_.joints[static_cast<size_t>(out.joint)].name;
  return out.node >= 0 ? modal_node_label(out.body, out.node) : m_.body_name(out.body);
}
bool Emitter::revolute_output(const Output& out) const {
  return m_.joints[static_cast<size_t>(out.joint)].type == JointType::revolute;
}
std::string Emitter::output_layout(const Output& out) const {
  switch (out.type) {
    case OutputType::joint_position: return revolute_output(out) ? "rad" : "m";
    case OutputType::joint_velocity: return revolute_output(out) ? "rad/s" : "m/s";
    case OutputType::body_pose: return "x, y, z (m, world), e0..e3";
    case OutputType::body_velocity: return "vx, vy, vz (m/s, world), wx, wy, wz (rad/s, body)";
    case OutputType::joint_friction: return revolute_output(out) ? "N m" : "N";
    case OutputType::joint_stuck: return "1 stuck, 0 slipping";
    case OutputType::contact_force: return "normal (N), friction x, y, z (N, world)";
    case OutputType::contact_stuck: return "1 stuck, 0 sliding or open";
  }
  return "";
}

// A torque `value` about the joint axis (`axis`, body-1 axes) on body2 with
// the reaction on body1, or a force along it at the joint point of each body
// (`s1`, `s2`); both points lie on the axis line, so the pair has no moment.
// At a modal body's node (node1, node2 >= 0) the end's share goes to the
// node's modes too.
// Planar: the force along an axis in the plane, the torque about the normal,
// z in plane coordinates (codegen/plan/planar_scene.cpp).
void Emitter::joint_axis_load(std::ostringstream& o, bool force, int body1, int body2, const std::string& value,
                              const std::string& axis, const std::string& s1, const std::string& s2, int node1,
                              int node2) const {
  if (force) {
    o << "    const mbrt::" << (planar_ ? "Vec2" : "Vec3") << " force = " << value << " * (" << pose(body1) << ".R * "
      << axis << (planar_ ? ".head<2>()" : "") << ");\n";
    for (const auto& [b, k, s, f] : {std::tuple{body2, node2, s2, "force"}, std::tuple{body1, node1, s1, "-force"}}) {
      if (b == kGround) continue;
      o << (k >= 0 ? node_force(b, k, f) : "    mbrt::add_point_force(l.w" + at(b) + ", " + pose(b) + ", " + s + ", " + f + ");\n");
    }
  } else if (planar_) {
    o << "    const double t = " << value << " * " << axis << ".z();\n";
    if (body2 != kGround) o << "    l.w" << at(body2) << ".tau += t;\n";
    if (body1 != kGround) o << "    l.w" << at(body1) << ".tau -= t;\n";
  } else {
    o << "    const mbrt::Vec3 t = " << value << " * (" << pose(body1) << ".R * " << axis << ");\n";
    torque_on_ends(o, body1, node1, body2, node2);
  }
}

void Emitter::input_load(std::ostringstream& o, const Input& in, const InputPlan& p) const {
  const std::string n = in.name;
  const auto end = [&](int b, int k) { return k >= 0 ? modal_node_label(b, k) : m_.body_name(b); };
  const Joint* j = in.joint >= 0 ? &m_.joints[static_cast<size_t>(in.joint)] : nullptr;
  const int node1 = j ? j->node1 : in.node1, node2 = j ? j->node2 : in.node2;
  o << "  {  // input " << n << ": " << type_row(in.type).name << " " << input_target(in) << " on " << end(p.body2, node2)
    << ", reaction on " << end(p.body1, node1) << "\n";
  if (j && (node1 >= 0 || node2 >= 0)) {  // a joint at a node: about or along its axis turned with the section
    o << node_joint_view(j->name + "_frame", j->body1, node1, j->body2, node2, true, "    ").code;
    joint_axis_load(o, in.type == InputType::joint_force, p.body1, p.body2, "u[input::" + n + "]", "f.a1", "f.s1", "f.s2", node1,
                    node2);
  } else {
    joint_axis_load(o, in.type == InputType::joint_force, p.body1, p.body2, "u[input::" + n + "]", n + "_axis", n + "_s1",
                    n + "_s2", node1, node2);
  }
  o << "  }\n";
}

void Emitter::outputs_function(std::ostringstream& o) const {
  o << "static void outputs(const State& s, Outputs& y) noexcept {\n  Kinematics k;\n  kinematics(s, k);\n";
  for (const Output& out : m_.outputs) {
    const std::string at = "y.data() + output::" + out.name;
    if (out.type == OutputType::joint_friction || out.type == OutputType::joint_stuck) {
      o << "  y[output::" << out.name << "] = s." << (out.type == OutputType::joint_friction ? "friction" : "stuck")
        << "[friction::" << m_.joints[static_cast<size_t>(out.joint)].name << "];\n";
      continue;
    }
    if (out.contact >= 0) {
      const std::string c = "[contact::" + m_.contacts[static_cast<size_t>(out.contact)].name + "]";
      if (out.type == OutputType::contact_stuck) {
        o << "  y[output::" << out.name << "] = s.contact_stuck" << c << ";\n";
      } else {
        o << "  y[output::" << out.name << "] = s.contact_normal" << c << ";\n"
          << "  Eigen::Map<mbrt::Vec3>(" << at << " + 1) = s.contact_tangential" << c << ";\n";
      }
      continue;
    }
    if (out.joint >= 0) {
      const Joint& j = m_.joints[static_cast<size_t>(out.joint)];
      const std::string value = out.type == OutputType::joint_position ? "position" : "velocity";
      const std::string kernel = std::string("mbrt::") + (revolute_output(out) ? "revolute" : "prismatic") + "_coordinate(";
      if (j.node1 >= 0 || j.node2 >= 0) {  // its axes turned with the node's section
        const NodeJointView view = node_joint_view(j.name + "_frame", j.body1, j.node1, j.body2, j.node2, true, "    ");
        o << "  {  // at a modal body's node\n" << view.code << "    y[output::" << out.name << "] = " << kernel << "f, " << view.motions[0]
          << ", " << view.motions[1] << ")." << value << ";\n  }\n";
        continue;
      }
      o << "  y[output::" << out.name << "] = " << kernel << j.name << "_frame, " << motion(j.body1) << ", " << motion(j.body2) << ")."
        << value << ";\n";
      continue;
    }
    if (out.node >= 0) {
      o << modal_node_output(out, at);
      continue;
    }
    const std::string st = state_of(out.body);
    const bool rigid = plan(out.body).rigid;
    if (out.type == OutputType::body_pose) {
      o << "  Eigen::Map<mbrt::Vec3>(" << at << ") = " << st << ".r;\n"
        << "  Eigen::Map<mbrt::Vec4>(" << at << " + 3) = " << (rigid ? st + ".p" : "mbrt::Vec4(1.0, 0.0, 0.0, 0.0)") << ";\n";
    } else {
      o << "  Eigen::Map<mbrt::Vec3>(" << at << ") = " << st << ".v;\n"
        << "  Eigen::Map<mbrt::Vec3>(" << at << " + 3) = " << (rigid ? st + ".w" : "mbrt::Vec3::Zero()") << ";\n";
    }
  }
  o << "}\n\n";
}

}  // namespace mbrt::codegen
