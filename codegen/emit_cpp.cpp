#include "emit_cpp.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include <Eigen/LU>

namespace mbrt::codegen {

namespace {

std::string num(double x) {
  std::ostringstream o;
  o << std::setprecision(17) << x;
  std::string s = o.str();
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string vec3(const Eigen::Vector3d& v) {
  return "mbrt::Vec3(" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + ")";
}

std::string vec4(const Eigen::Vector4d& v) {
  return "mbrt::Vec4(" + num(v[0]) + ", " + num(v[1]) + ", " + num(v[2]) + ", " + num(v[3]) + ")";
}

std::string mat3(const Eigen::Matrix3d& m) {
  std::string s = "(mbrt::Mat3() << ";
  for (int i = 0; i < 9; ++i) s += num(m(i / 3, i % 3)) + (i < 8 ? ", " : "");
  return s + ").finished()";
}

std::string rows_type(int n) { return "Eigen::Matrix<double, " + std::to_string(n) + ", 1>"; }
std::string block_type(int r, int c) {
  return "Eigen::Matrix<double, " + std::to_string(r) + ", " + std::to_string(c) + ">";
}

// Writes the generated files for one model.
class Emitter {
 public:
  Emitter(const Model& m, const Analysis& a) : m_(m), a_(a) {}

  GeneratedCode run() {
    GeneratedCode g;
    g.header_name = m_.name + ".hpp";
    g.source_name = m_.name + ".cpp";
    g.header = header();
    g.source = source();
    return g;
  }

 private:
  const Model& m_;
  const Analysis& a_;

  // Implicit passes per step: two when the end-of-step accelerations depend on
  // the end-of-step velocities (gyroscopic or damping loads, Baumgarte's
  // velocity term), else one.
  int stages() const {
    const bool baumgarte = m_.solver.scheme == "baumgarte" && a_.constraint_rows > 0;
    return a_.velocity_dependent_forces || baumgarte ? 2 : 1;
  }
  const Body& body(int i) const { return m_.bodies[static_cast<size_t>(i)]; }
  const BodyPlan& plan(int i) const { return a_.bodies[static_cast<size_t>(i)]; }
  const ConstraintBlock& block(int j) const { return a_.constraints[static_cast<size_t>(j)]; }
  int blocks() const { return static_cast<int>(a_.constraints.size()); }
  int rows(int j) const { return block(j).rows; }
  int first_row(int j) const { return block(j).first_row; }
  std::string jname(int j) const { return block(j).name; }

  std::string state_of(int i) const {
    return plan(i).rigid ? "s.rigid[" + std::to_string(plan(i).slot) + "]" : "s.particle[" + std::to_string(plan(i).slot) + "]";
  }
  std::string mass_of(int i) const { return body(i).name + "_mass"; }
  std::string motion(int i) const {
    if (i == kGround) return "mbrt::BodyMotion{kGroundPose, kGroundVelocity}";
    const std::string n = std::to_string(i);
    return "mbrt::BodyMotion{k.pose[" + n + "], k.vel[" + n + "]}";
  }
  std::string pose(int i) const { return i == kGround ? "kGroundPose" : "k.pose[" + std::to_string(i) + "]"; }
  // Name of the M^-1 B^T block of joint j for body b.
  std::string mbt(int j, int b) const { return "c.mbt_" + std::to_string(j) + "_" + std::to_string(b); }
  std::string L(int i, int k) const { return "c.L_" + std::to_string(i) + "_" + std::to_string(k); }
  std::string side(int j, int b) const { return block(j).body1 == b ? "J1" : "J2"; }
  std::vector<int> moving_bodies(int j) const {
    std::vector<int> out;
    for (int b : {block(j).body1, block(j).body2}) if (b != kGround) out.push_back(b);
    return out;
  }

  bool has_inputs() const { return !m_.inputs.empty(); }
  bool has_outputs() const { return !m_.outputs.empty(); }
  std::string loads_call() const { return has_inputs() ? "applied_loads(k, s.inputs, l)" : "applied_loads(k, l)"; }

  // Inputs: index constants, ranges and safe values; State gains `inputs`.
  void input_declarations(std::ostringstream& o) const {
    o << "// Commands step() applies (State::inputs), SI units; limits and safe values in kInputInfo.\n"
      << "namespace input {\n";
    for (size_t i = 0; i < m_.inputs.size(); ++i) {
      const Input& in = m_.inputs[i];
      o << "inline constexpr int " << in.name << " = " << i << ";  // " << input_type_name(in.type) << " "
        << input_target(in) << ", " << (in.type == InputType::joint_force ? "N" : "N m") << "\n";
    }
    o << "}  // namespace input\n"
      << "inline constexpr int kInputs = " << m_.inputs.size() << ";\n"
      << "using Inputs = std::array<double, kInputs>;\n"
      << "inline constexpr std::array<mbrt::InputInfo, kInputs> kInputInfo{{\n";
    for (const Input& in : m_.inputs) {
      o << "    {\"" << in.name << "\", \"" << input_type_name(in.type) << "\", \"" << input_target(in) << "\", "
        << num(in.min) << ", " << num(in.max) << ", " << num(in.safe) << "},\n";
    }
    o << "}};\n\n";
  }

  // Outputs: one flat array of values; each signal's first index and count.
  void output_declarations(std::ostringstream& o) const {
    o << "// Signals outputs() computes, as one array of values; see kOutputInfo.\nnamespace output {\n";
    int first = 0;
    for (const Output& out : m_.outputs) {
      o << "inline constexpr int " << out.name << " = " << first << ";  // " << output_type_name(out.type) << " of "
        << output_source(out) << ", " << output_layout(out) << "\n";
      first += output_count(out.type);
    }
    o << "}  // namespace output\n"
      << "inline constexpr int kOutputSignals = " << m_.outputs.size() << ";\n"
      << "inline constexpr int kOutputs = " << first << ";  // values\n"
      << "using Outputs = std::array<double, kOutputs>;\n"
      << "inline constexpr std::array<mbrt::OutputInfo, kOutputSignals> kOutputInfo{{\n";
    first = 0;
    for (const Output& out : m_.outputs) {
      o << "    {\"" << out.name << "\", \"" << output_type_name(out.type) << "\", \"" << output_source(out) << "\", "
        << first << ", " << output_count(out.type) << "},\n";
      first += output_count(out.type);
    }
    o << "}};\n\n";
  }

  std::string input_target(const Input& in) const {
    if (in.type == InputType::motor_torque) return m_.body_name(in.body1) + "-" + m_.body_name(in.body2);
    return m_.joints[static_cast<size_t>(in.joint)].name;
  }
  std::string output_source(const Output& out) const {
    return out.joint >= 0 ? m_.joints[static_cast<size_t>(out.joint)].name : m_.body_name(out.body);
  }
  bool revolute_output(const Output& out) const {
    return m_.joints[static_cast<size_t>(out.joint)].type == JointType::revolute;
  }
  std::string output_layout(const Output& out) const {
    switch (out.type) {
      case OutputType::joint_position: return revolute_output(out) ? "rad" : "m";
      case OutputType::joint_velocity: return revolute_output(out) ? "rad/s" : "m/s";
      case OutputType::body_pose: return "x, y, z (m, world), e0..e3";
      case OutputType::body_velocity: return "vx, vy, vz (m/s, world), wx, wy, wz (rad/s, body)";
    }
    return "";
  }

  std::string header() const {
    std::ostringstream o;
    o << "// mbrt generated model '" << m_.name << "' from " << m_.file << "\n"
      << "// scheme " << m_.solver.scheme << ", h = " << num(m_.solver.step) << " s, euler_updates = "
      << m_.solver.euler_updates << ". Generated code: regenerate, do not edit.\n"
      << "#pragma once\n\n#include <array>\n\n#include <mbrt/model_api.hpp>\n\n"
      << "namespace mbrt::models::" << m_.name << " {\n\n"
      << "inline constexpr const char* kName = \"" << m_.name << "\";\n"
      << "inline constexpr const char* kScheme = \"" << m_.solver.scheme << "\";\n"
      << "inline constexpr double kStep = " << num(m_.solver.step) << ";\n"
      << "inline constexpr int kEulerUpdates = " << m_.solver.euler_updates << ";\n"
      << "inline constexpr int kBodies = " << m_.bodies.size() << ";\n"
      << "inline constexpr int kRigidBodies = " << a_.rigid_count << ";\n"
      << "inline constexpr int kParticles = " << a_.particle_count << ";\n"
      << "inline constexpr int kConstraintBlocks = " << blocks() << ";  // joints, then drivers\n"
      << "inline constexpr int kConstraintRows = " << a_.constraint_rows << ";\n\n"
      << "inline constexpr std::array<mbrt::BodyInfo, kBodies> kBodyInfo{{\n";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      o << "    {\"" << m_.bodies[i].name << "\", " << (a_.bodies[i].rigid ? "true" : "false") << ", "
        << a_.bodies[i].slot << "},\n";
    }
    o << "}};\n\ninline constexpr std::array<mbrt::ConstraintInfo, kConstraintBlocks> kConstraintInfo{{\n";
    for (int j = 0; j < blocks(); ++j) {
      o << "    {\"" << jname(j) << "\", \"" << block(j).kernel << "\", " << first_row(j) << ", " << rows(j) << "},\n";
    }
    o << "}};\n\n";
    if (has_inputs()) input_declarations(o);
    if (has_outputs()) output_declarations(o);
    o << "// Everything that changes from step to step; the caller owns it.\n"
      << "struct State {\n"
      << "  double t = 0.0;\n"
      << "  std::array<mbrt::RigidState, kRigidBodies> rigid;     // see kBodyInfo\n"
      << "  std::array<mbrt::ParticleState, kParticles> particle;\n"
      << "  // Accelerations at t, reused by the next step's explicit stage.\n"
      << "  std::array<mbrt::RigidAcceleration, kRigidBodies> rigid_acceleration;\n"
      << "  std::array<mbrt::Vec3, kParticles> particle_acceleration;\n"
      << "  // Constraint multipliers of the last step, rows as in kConstraintInfo.\n"
      << "  Eigen::Matrix<double, kConstraintRows, 1> lambda;\n"
      << (has_inputs() ? "  Inputs inputs;  // applied by step(); initial_state() sets the safe values\n" : "")
      << "};\n\n"
      << "// The model file's initial state with consistent accelerations.\n"
      << "State initial_state() noexcept;\n\n"
      << "// Advances s by kStep. Allocates nothing, throws nothing, fixed work.\n"
      << "// On a non-finite result or a lost factorization s keeps its old value.\n"
      << "mbrt::StepStatus step(State& s) noexcept;\n\n"
      << "mbrt::Energy energy(const State& s) noexcept;\n"
      << "mbrt::ConstraintViolation constraint_violation(const State& s) noexcept;\n"
      << "double quaternion_norm_error(const State& s) noexcept;  // max | |p| - 1 |\n\n"
      << (has_outputs() ? "void outputs(const State& s, Outputs& y) noexcept;\n\n" : "")
      << "}  // namespace mbrt::models::" << m_.name << "\n";
    return o.str();
  }

  void constants(std::ostringstream& o) const {
    o << "constexpr double h = kStep;\n"
      << "constexpr int kStages = " << stages() << ";  // implicit stages per step\n"
      << "constexpr double kRegularization = " << num(a_.regularization) << ";  // added to diag(S)\n";
    switch (scheme_kind()) {
      case Scheme::pcst:
        o << "constexpr double kStabilization = " << num(a_.stabilization) << ";  // alpha, 1/s\n";
        break;
      case Scheme::baumgarte:
        o << "constexpr double kBaumgarteAlpha = " << num(a_.baumgarte_alpha) << ";  // 1/s\n"
          << "constexpr double kBaumgarteBeta = " << num(a_.baumgarte_beta) << ";  // 1/s\n";
        break;
      case Scheme::blajer:
        o << "constexpr int kCorrections = " << m_.solver.corrections << ";  // position corrections per step\n";
        break;
    }
    if (a_.gravity) o << "const mbrt::Vec3 kGravity = " << vec3(*m_.gravity) << ";\n";
    o << "const mbrt::BodyPose kGroundPose = mbrt::ground_pose();\n"
      << "const mbrt::BodyVelocity kGroundVelocity = mbrt::ground_velocity();\n\n"
      << "// Mass properties (constant; M is block diagonal).\n";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      const Body& b = m_.bodies[i];
      const BodyPlan& p = a_.bodies[i];
      if (!p.rigid) {
        o << "constexpr mbrt::PointMass " << mass_of(static_cast<int>(i)) << "{" << num(b.mass) << "};\n";
      } else if (p.principal_axes) {
        o << "const mbrt::PrincipalInertia " << mass_of(static_cast<int>(i)) << "{" << num(b.mass) << ", "
          << vec3(b.inertia.diagonal()) << "};\n";
      } else {
        o << "const mbrt::FullInertia " << mass_of(static_cast<int>(i)) << "{" << num(b.mass) << ", "
          << mat3(b.inertia) << ", " << mat3(b.inertia.inverse()) << "};\n";
      }
    }
    o << "\n// Joint and driver frames in body axes; drivers' functions of time.\n";
    for (int j = 0; j < blocks(); ++j) {
      const JointFrame& f = block(j).frame;
      o << "const mbrt::JointFrame " << jname(j) << "_frame{" << vec3(f.s1) << ", " << vec3(f.s2) << ",\n    "
        << vec3(f.a1) << ", " << vec3(f.b1) << ", " << vec3(f.c1) << ",\n    " << vec3(f.a2) << ", " << vec3(f.b2)
        << ", " << vec3(f.c2) << ", " << num(f.length) << ", " << num(f.pitch) << "};\n";
      if (const TimeFunction* fn = block(j).function) {
        if (fn->is_sine) {
          o << "const mbrt::Sine " << jname(j) << "_sine{" << num(fn->amplitude) << ", " << num(fn->omega) << ", "
            << num(fn->phase) << ", " << num(fn->offset) << "};  // offset + amplitude sin(omega t + phase)\n";
        } else {
          o << "constexpr std::array<double, " << fn->polynomial.size() << "> " << jname(j) << "_polynomial{";
          for (size_t k = 0; k < fn->polynomial.size(); ++k) o << (k ? ", " : "") << num(fn->polynomial[k]);
          o << "};  // c0 + c1 t + ...\n";
        }
      }
    }
    if (has_inputs()) o << "\n// Input axes (body-1 axes) and, for forces, points (body axes).\n";
    for (size_t i = 0; i < m_.inputs.size(); ++i) {
      const Input& in = m_.inputs[i];
      const InputPlan& p = a_.inputs[i];
      o << "const mbrt::Vec3 " << in.name << "_axis = " << vec3(p.axis1) << ";\n";
      if (in.type == InputType::joint_force) {
        o << "const mbrt::Vec3 " << in.name << "_s1 = " << vec3(p.s1) << ";\n"
          << "const mbrt::Vec3 " << in.name << "_s2 = " << vec3(p.s2) << ";\n";
      }
    }
    o << "\n// Force elements in body axes.\n";
    for (size_t e = 0; e < a_.forces.size(); ++e) {
      const Force& f = m_.forces[static_cast<size_t>(a_.forces[e].model_index)];
      const ForcePlan& p = a_.forces[e];
      const std::string n = "force_" + std::to_string(e);
      switch (f.type) {
        case ForceType::spring_damper:
          o << "const mbrt::SpringDamper " << n << "{" << vec3(p.spring.s1) << ", " << vec3(p.spring.s2) << ", "
            << num(p.spring.stiffness) << ", " << num(p.spring.damping) << ", " << num(p.spring.rest_length)
            << "};  // spring_damper " << m_.body_name(f.body1) << " - " << m_.body_name(f.body2) << "\n";
          break;
        case ForceType::torque:
          o << "const mbrt::AxialTorque " << n << "{" << vec3(p.torque.axis1) << ", " << num(p.torque.value)
            << "};  // torque on " << m_.body_name(f.body2) << ", reaction on " << m_.body_name(f.body1) << "\n";
          break;
        case ForceType::force:
          o << "const mbrt::Vec3 " << n << "_point = " << vec3(p.point) << ";  // force on "
            << m_.body_name(f.body) << "\n"
            << "const mbrt::Vec3 " << n << "_vector = " << vec3(f.vector) << ";\n";
          break;
      }
    }
    o << "\n";
  }

  void workspace_types(std::ostringstream& o) const {
    o << "using Rows = Eigen::Matrix<double, kConstraintRows, 1>;\n"
      << "using BodyVectors = std::array<mbrt::Vec6, kBodies>;  // [v; w_body] per body\n\n"
      << "struct Kinematics {\n"
      << "  std::array<mbrt::BodyPose, kBodies> pose;\n"
      << "  std::array<mbrt::BodyVelocity, kBodies> vel;\n"
      << "};\n\n"
      << "struct Loads {\n"
      << "  std::array<mbrt::Wrench, kBodies> w;\n"
      << "  double elastic_energy;\n"
      << "};\n\n"
      << "// Constraint rows, M^-1 B^T blocks and the block Cholesky factor of\n"
      << "// S = B M^-1 B^T + kRegularization I over the model's fixed pattern.\n"
      << "struct ConstraintSystem {\n";
    for (int ji = 0; ji < blocks(); ++ji) {
      o << "  mbrt::ConstraintRows<" << rows(ji) << "> rows_" << jname(ji) << ";  // " << block(ji).kernel << " "
        << m_.body_name(block(ji).body1) << " - " << m_.body_name(block(ji).body2) << ", rows " << first_row(ji)
        << ".." << first_row(ji) + rows(ji) - 1 << "\n";
      for (int b : moving_bodies(ji)) {
        o << "  " << block_type(6, rows(ji)) << " mbt_" << ji << "_" << b << ";  // M^-1 B^T: " << jname(ji) << ", "
          << body(b).name << "\n";
      }
    }
    for (int k : a_.pattern.order) {
      o << "  " << block_type(rows(k), rows(k)) << " L_" << k << "_" << k << ";  // " << jname(k) << "\n";
      for (int i : a_.pattern.lower[static_cast<size_t>(k)]) {
        o << "  " << block_type(rows(i), rows(k)) << " L_" << i << "_" << k << ";  // " << jname(i) << " x "
          << jname(k) << "\n";
      }
    }
    o << "};\n\n";
  }

  void velocity_helpers(std::ostringstream& o) const {
    o << "std::array<mbrt::BodyVelocity, kBodies> velocities_of(const State& s) noexcept {\n"
      << "  std::array<mbrt::BodyVelocity, kBodies> vel;\n";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      o << "  vel[" << i << "] = mbrt::velocity_of(" << state_of(static_cast<int>(i)) << ");\n";
    }
    o << "  return vel;\n}\n\n"
      << "// (s) => (u): generalized velocities [v; w_body] per body.\n"
      << "BodyVectors generalized_velocities(const State& s) noexcept {\n  BodyVectors u;\n";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      const std::string st = state_of(static_cast<int>(i));
      if (a_.bodies[i].rigid) o << "  u[" << i << "] << " << st << ".v, " << st << ".w;\n";
      else o << "  u[" << i << "] << " << st << ".v, mbrt::Vec3::Zero();\n";
    }
    o << "  return u;\n}\n\n"
      << "// (u) => (s): write generalized velocities back.\n"
      << "void set_velocities(const BodyVectors& u, State& s) noexcept {\n";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      const std::string st = state_of(static_cast<int>(i));
      o << "  " << st << ".v = u[" << i << "].head<3>();\n";
      if (a_.bodies[i].rigid) o << "  " << st << ".w = u[" << i << "].tail<3>();\n";
    }
    o << "}\n\n"
      << "// (a) => (s): accelerations kept for the next step.\n"
      << "void set_accelerations(const BodyVectors& a, State& s) noexcept {\n";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      const BodyPlan& p = a_.bodies[i];
      if (p.rigid) {
        o << "  s.rigid_acceleration[" << p.slot << "] = {a[" << i << "].head<3>(), a[" << i << "].tail<3>()};\n";
      } else {
        o << "  s.particle_acceleration[" << p.slot << "] = a[" << i << "].head<3>();\n";
      }
    }
    o << "}\n\n"
      << "BodyVectors accelerations_of(const State& s) noexcept {\n  BodyVectors a;\n";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      const BodyPlan& p = a_.bodies[i];
      if (p.rigid) {
        o << "  a[" << i << "] << s.rigid_acceleration[" << p.slot << "].a, s.rigid_acceleration[" << p.slot
          << "].alpha;\n";
      } else {
        o << "  a[" << i << "] << s.particle_acceleration[" << p.slot << "], mbrt::Vec3::Zero();\n";
      }
    }
    o << "  return a;\n}\n\n";
  }

  void loads_stage(std::ostringstream& o) const {
    o << "// (k" << (has_inputs() ? ", u" : "") << ") => (l): applied forces (world) and torques (body axes) per body,\n"
      << "// gyroscopic torques" << (has_inputs() ? " and inputs" : "") << " included, and the elastic energy stored.\n"
      << "void applied_loads(const Kinematics& k, " << (has_inputs() ? "const Inputs& u, " : "") << "Loads& l) noexcept {\n"
      << "  l.w.fill(mbrt::Wrench{});\n  l.elastic_energy = 0.0;\n";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      const BodyPlan& p = a_.bodies[i];
      if (a_.gravity) o << "  l.w[" << i << "].f += " << mass_of(static_cast<int>(i)) << ".m * kGravity;\n";
      if (p.rigid && !p.isotropic) {
        o << "  l.w[" << i << "].tau += mbrt::gyroscopic_torque(" << mass_of(static_cast<int>(i)) << ", k.vel[" << i
          << "].w);\n";
      }
    }
    for (size_t e = 0; e < a_.forces.size(); ++e) {
      const Force& f = m_.forces[static_cast<size_t>(a_.forces[e].model_index)];
      const std::string n = "force_" + std::to_string(e);
      switch (f.type) {
        case ForceType::spring_damper:
          o << "  {  // spring_damper " << m_.body_name(f.body1) << " - " << m_.body_name(f.body2) << "\n"
            << "    const mbrt::SpringDamperForce e = mbrt::spring_damper(" << n << ", " << motion(f.body1) << ", "
            << motion(f.body2) << ");\n";
          if (f.body2 != kGround) {
            o << "    mbrt::add_point_force(l.w[" << f.body2 << "], " << pose(f.body2) << ", " << n << ".s2, e.f2);\n";
          }
          if (f.body1 != kGround) {
            o << "    mbrt::add_point_force(l.w[" << f.body1 << "], " << pose(f.body1) << ", " << n << ".s1, -e.f2);\n";
          }
          o << "    l.elastic_energy += e.energy;\n  }\n";
          break;
        case ForceType::torque:
          o << "  {  // torque on " << m_.body_name(f.body2) << ", reaction on " << m_.body_name(f.body1) << "\n"
            << "    const mbrt::Vec3 t = mbrt::axial_torque_world(" << n << ", " << pose(f.body1) << ");\n";
          if (f.body2 != kGround) o << "    l.w[" << f.body2 << "].tau += " << pose(f.body2) << ".R.transpose() * t;\n";
          if (f.body1 != kGround) o << "    l.w[" << f.body1 << "].tau -= " << pose(f.body1) << ".R.transpose() * t;\n";
          o << "  }\n";
          break;
        case ForceType::force:
          o << "  mbrt::add_point_force(l.w[" << f.body << "], " << pose(f.body) << ", " << n << "_point, " << n
            << "_vector);\n";
          break;
      }
    }
    for (size_t i = 0; i < m_.inputs.size(); ++i) input_load(o, m_.inputs[i], a_.inputs[i]);
    o << "}\n\n";
  }

  // A torque input: value times the body-1 axis, on body2 with the reaction
  // on body1. A force input: along the axis, at the joint point of each body;
  // both points lie on the axis line, so the pair has no moment.
  void input_load(std::ostringstream& o, const Input& in, const InputPlan& p) const {
    const std::string n = in.name;
    o << "  {  // input " << n << ": " << input_type_name(in.type) << " " << input_target(in) << " on "
      << m_.body_name(p.body2) << ", reaction on " << m_.body_name(p.body1) << "\n";
    if (in.type == InputType::joint_force) {
      o << "    const mbrt::Vec3 f = u[input::" << n << "] * (" << pose(p.body1) << ".R * " << n << "_axis);\n";
      if (p.body2 != kGround) o << "    mbrt::add_point_force(l.w[" << p.body2 << "], " << pose(p.body2) << ", " << n << "_s2, f);\n";
      if (p.body1 != kGround) o << "    mbrt::add_point_force(l.w[" << p.body1 << "], " << pose(p.body1) << ", " << n << "_s1, -f);\n";
    } else {
      o << "    const mbrt::Vec3 t = u[input::" << n << "] * (" << pose(p.body1) << ".R * " << n << "_axis);\n";
      if (p.body2 != kGround) o << "    l.w[" << p.body2 << "].tau += " << pose(p.body2) << ".R.transpose() * t;\n";
      if (p.body1 != kGround) o << "    l.w[" << p.body1 << "].tau -= " << pose(p.body1) << ".R.transpose() * t;\n";
    }
    o << "  }\n";
  }

  void constraint_stage(std::ostringstream& o) const {
    o << "// (k, t) => (c.rows_*): constraint values, Jacobians and acceleration terms.\n"
      << "void constraint_rows(const Kinematics& k, double t, ConstraintSystem& c) noexcept {\n";
    if (blocks() == 0) o << "  (void)k;\n  (void)c;\n";
    if (!a_.rheonomic) o << "  (void)t;\n";
    for (int j = 0; j < blocks(); ++j) {
      const ConstraintBlock& b = block(j);
      o << "  c.rows_" << b.name << " = mbrt::" << b.kernel << "(" << b.name << "_frame, " << motion(b.body1) << ", "
        << motion(b.body2);
      if (b.function) {
        o << ",\n      " << (b.function->is_sine ? "mbrt::sine(" + b.name + "_sine, t)"
                                                  : "mbrt::polynomial(" + b.name + "_polynomial, t)");
      }
      o << ");\n";
    }
    o << "}\n\n"
      << "// (c.rows_*) => (c.mbt_*, c.L_*): M^-1 B^T, then S block by block in\n"
      << "// elimination order (" << a_.pattern.fill_blocks << " fill blocks); false if a pivot is not positive.\n"
      << "bool factorize(ConstraintSystem& c) noexcept {\n  bool positive = true;\n";
    for (int ji = 0; ji < blocks(); ++ji) {
      for (int b : moving_bodies(ji)) {
        o << "  " << mbt(ji, b) << " = mbrt::inverse_mass_times_transpose(" << mass_of(b) << ", c.rows_" << jname(ji)
          << "." << side(ji, b) << ");\n";
      }
    }
    const auto& order = a_.pattern.order;
    const auto& lower = a_.pattern.lower;
    auto in_lower = [&](int j, int i) {
      const auto& v = lower[static_cast<size_t>(j)];
      return std::find(v.begin(), v.end(), i) != v.end();
    };
    for (size_t pk = 0; pk < order.size(); ++pk) {
      const int k = order[pk];
      o << "  // " << jname(k) << "\n  " << L(k, k) << " = " << s_block(k, k) << " + kRegularization * "
        << block_type(rows(k), rows(k)) << "::Identity()";
      for (size_t pj = 0; pj < pk; ++pj) {
        const int j = order[pj];
        if (in_lower(j, k)) o << "\n      - " << L(k, j) << " * " << L(k, j) << ".transpose()";
      }
      o << ";\n  positive = mbrt::cholesky_in_place(" << L(k, k) << ") && positive;\n";
      for (int i : lower[static_cast<size_t>(k)]) {
        o << "  " << L(i, k) << " = " << s_block(i, k);
        for (size_t pj = 0; pj < pk; ++pj) {
          const int j = order[pj];
          if (in_lower(j, k) && in_lower(j, i)) o << "\n      - " << L(i, j) << " * " << L(k, j) << ".transpose()";
        }
        o << ";\n  mbrt::solve_right_lower_transposed(" << L(k, k) << ", " << L(i, k) << ");\n";
      }
    }
    o << "  return positive;\n}\n\n";

    o << "// (c.L_*, x) => (x): x := S^-1 x by forward and backward substitution.\n"
      << "void solve(const ConstraintSystem& c, Rows& x) noexcept {\n";
    if (blocks() == 0) o << "  (void)c;\n  (void)x;\n";
    for (size_t pk = 0; pk < order.size(); ++pk) {
      const int k = order[pk];
      o << "  {  // " << jname(k) << "\n    " << rows_type(rows(k)) << " y = " << seg("x", k) << ";\n";
      for (size_t pj = 0; pj < pk; ++pj) {
        const int j = order[pj];
        if (in_lower(j, k)) o << "    y -= " << L(k, j) << " * " << seg("x", j) << ";\n";
      }
      o << "    mbrt::solve_lower(" << L(k, k) << ", y);\n    " << seg("x", k) << " = y;\n  }\n";
    }
    for (size_t pk = order.size(); pk-- > 0;) {
      const int k = order[pk];
      o << "  {  // " << jname(k) << "\n    " << rows_type(rows(k)) << " y = " << seg("x", k) << ";\n";
      for (int i : lower[static_cast<size_t>(k)]) o << "    y -= " << L(i, k) << ".transpose() * " << seg("x", i) << ";\n";
      o << "    mbrt::solve_lower_transposed(" << L(k, k) << ", y);\n    " << seg("x", k) << " = y;\n  }\n";
    }
    o << "}\n\n";

    o << "// (c, u) => (B u)\n"
      << "Rows jacobian_times(const ConstraintSystem& c, const BodyVectors& u) noexcept {\n  Rows y;\n";
    if (blocks() == 0) o << "  (void)c;\n  (void)u;\n";
    for (int ji = 0; ji < blocks(); ++ji) {
      o << "  " << seg("y", ji) << " = ";
      const auto mb = moving_bodies(ji);
      for (size_t q = 0; q < mb.size(); ++q) {
        o << (q ? " + " : "") << "c.rows_" << jname(ji) << "." << side(ji, mb[q]) << " * u[" << mb[q] << "]";
      }
      o << ";\n";
    }
    o << "  return y;\n}\n\n"
      << "// (c, lambda) => (u): u -= scale M^-1 B^T lambda\n"
      << "void subtract_constraint_forces(const ConstraintSystem& c, const Rows& lambda, double scale,\n"
      << "                                BodyVectors& u) noexcept {\n";
    if (blocks() == 0) o << "  (void)c;\n  (void)lambda;\n  (void)scale;\n  (void)u;\n";
    for (int ji = 0; ji < blocks(); ++ji) {
      for (int b : moving_bodies(ji)) {
        o << "  u[" << b << "] -= scale * (" << mbt(ji, b) << " * " << seg("lambda", ji) << ");\n";
      }
    }
    o << "}\n\n"
      << "// (c) => (phi), (c) => (quad): stacked position residuals and acceleration terms.\n";
    stacked(o, "phi");
    stacked(o, "quad");
    if (a_.rheonomic) stacked(o, "phi_t");
    o << "// (c, u) => (phi_dot = B u + phi_t): velocity residuals.\n"
      << "Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept {\n";
    if (a_.rheonomic) {
      o << "  return jacobian_times(c, u) + stacked_phi_t(c);\n}\n\n";
    } else {
      o << "  return jacobian_times(c, u);  // no drivers: phi_t = 0\n}\n\n";
    }
  }

  // Rows stacked_<member>(c): one member of every block, stacked.
  void stacked(std::ostringstream& o, const std::string& member) const {
    o << "Rows stacked_" << member << "(const ConstraintSystem& c) noexcept {\n  Rows y;\n";
    if (blocks() == 0) o << "  (void)c;\n";
    for (int j = 0; j < blocks(); ++j) o << "  " << seg("y", j) << " = c.rows_" << jname(j) << "." << member << ";\n";
    o << "  return y;\n}\n\n";
  }

  std::string seg(const std::string& v, int j) const {
    return v + ".segment<" + std::to_string(rows(j)) + ">(" + std::to_string(first_row(j)) + ")";
  }

  // Expression for block S(i, j) = sum over shared moving bodies of B_i M^-1 B_j^T.
  std::string s_block(int i, int j) const {
    std::string e;
    for (int b : moving_bodies(i)) {
      const auto mj = moving_bodies(j);
      if (std::find(mj.begin(), mj.end(), b) == mj.end()) continue;
      e += (e.empty() ? "" : " + ") + std::string("c.rows_") + jname(i) + "." + side(i, b) + " * " + mbt(j, b);
    }
    return e.empty() ? block_type(rows(i), rows(j)) + "::Zero()" : e;
  }

  void mass_products(std::ostringstream& o) const {
    o << "// (l) => (M^-1 F) per body.\n"
      << "BodyVectors free_accelerations(const Loads& l) noexcept {\n  BodyVectors a;\n";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      o << "  a[" << i << "] = mbrt::inverse_mass_times(" << mass_of(static_cast<int>(i)) << ", l.w[" << i << "]);\n";
    }
    o << "  return a;\n}\n\n";
  }

  enum class Scheme { pcst, baumgarte, blajer };
  Scheme scheme_kind() const {
    if (m_.solver.scheme == "baumgarte") return Scheme::baumgarte;
    if (m_.solver.scheme == "blajer") return Scheme::blajer;
    return Scheme::pcst;
  }

  // The stabilization term of S lambda = B M^-1 F + quad + stabilization.
  std::string stabilization_term() const {
    switch (scheme_kind()) {
      case Scheme::pcst:
        return "(2.0 / h) * (velocity_residual(c, generalized_velocities(s)) + kStabilization * phi)";
      case Scheme::baumgarte:
        return "(2.0 * kBaumgarteAlpha) * velocity_residual(c, generalized_velocities(s)) + "
               "(kBaumgarteBeta * kBaumgarteBeta) * phi";
      case Scheme::blajer: return "";
    }
    return "";
  }

  void scheme_stages(std::ostringstream& o) const {
    o << R"(// (s, accelerations at t) => (s): explicit stage, central difference.
// Half kick of the velocities, then positions and Euler parameters to t + h
// with the half-step velocities (docs/staggered-pcst.md, eqs. 1-3).
void explicit_stage(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) {
    mbrt::RigidState& x = s.rigid[b];
    x.v += (0.5 * h) * s.rigid_acceleration[b].a;
    x.w += (0.5 * h) * s.rigid_acceleration[b].alpha;
    x.r += h * x.v;
    x.p = mbrt::advance_euler_parameters(x.p, x.w, h, kEulerUpdates);
  }
  for (int b = 0; b < kParticles; ++b) {
    mbrt::ParticleState& x = s.particle[b];
    x.v += (0.5 * h) * s.particle_acceleration[b];
    x.r += h * x.v;
  }
  s.t += h;
}

)";
    const std::string stab = stabilization_term();
    switch (scheme_kind()) {
      case Scheme::pcst:
        o << R"(// (c, l, u_half) => (u): implicit stage. The end-of-step velocities satisfy
// the velocity constraints, regularized by the penalty eps (eq. 5):
//   (h/2) (S + 2 eps/h I) mu = B u_hat,  u = u_hat - h/2 M^-1 B^T mu.
void implicit_stage(const ConstraintSystem& c, const Loads& l, const BodyVectors& u_half, BodyVectors& u) noexcept {
  const BodyVectors a_free = free_accelerations(l);
  for (int b = 0; b < kBodies; ++b) u[b] = u_half[b] + (0.5 * h) * a_free[b];
  Rows mu = (2.0 / h) * velocity_residual(c, u);
  solve(c, mu);
  subtract_constraint_forces(c, mu, 0.5 * h, u);
}

// (c, l, phi, s) => (s.lambda, accelerations): multipliers of the stabilized
// companion equation (eq. 7)
//   (S + 2 eps/h I) lambda = B M^-1 F + quad + (2/h) (B u + alpha phi)
// which the next explicit stage applies: it steers phi at the next step to
// (1 - alpha h) phi. quad was evaluated at the predicted half-step velocity.
)";
        break;
      case Scheme::baumgarte:
        o << R"(// (c, l, phi, s) => (s.lambda, accelerations): index-1 multipliers with
// Baumgarte's terms, phi'' + 2 alpha phi' + beta^2 phi = 0:
//   S lambda = B M^-1 F + quad + 2 alpha B u + beta^2 phi
)";
        break;
      case Scheme::blajer:
        o << R"(// (c, l, phi, s) => (s.lambda, accelerations): the projective (index-1)
// multipliers, S lambda = B M^-1 F + quad (Blajer 1997, eq. 26). Drift is
// removed after the step by mass-orthogonal corrections.
)";
        break;
    }
    o << "void constraint_forces(const ConstraintSystem& c, const Loads& l, const Rows& phi, State& s) noexcept {\n"
      << (stab.empty() ? "  (void)phi;\n" : "")
      << "  BodyVectors a = free_accelerations(l);\n"
      << "  s.lambda = jacobian_times(c, a) + stacked_quad(c)" << (stab.empty() ? "" : " +\n             " + stab)
      << ";\n  solve(c, s.lambda);\n  subtract_constraint_forces(c, s.lambda, 1.0, a);\n  set_accelerations(a, s);\n}\n\n";
    if (scheme_kind() == Scheme::blajer) {
      o << R"(// (c, s) => (s): mass-orthogonal position correction (Blajer eq. 38),
// dq = -M^-1 B^T S^-1 phi, rotations applied as body-frame increments.
void correct_positions(const ConstraintSystem& c, State& s) noexcept {
  Rows x = stacked_phi(c);
  solve(c, x);
  BodyVectors dq;
  for (mbrt::Vec6& d : dq) d.setZero();
  subtract_constraint_forces(c, x, 1.0, dq);
)";
      for (size_t i = 0; i < m_.bodies.size(); ++i) {
        const std::string st = state_of(static_cast<int>(i));
        o << "  " << st << ".r += dq[" << i << "].head<3>();\n";
        if (a_.bodies[i].rigid) {
          o << "  " << st << ".p = mbrt::quaternion_product(" << st << ".p, mbrt::cayley_increment(dq[" << i
            << "].tail<3>())).normalized();\n";
        }
      }
      o << R"(}

// (c, s) => (s): mass-orthogonal velocity correction (Blajer eq. 40),
// du = -M^-1 B^T S^-1 B u.
void correct_velocities(const ConstraintSystem& c, State& s) noexcept {
  BodyVectors u = generalized_velocities(s);
  Rows x = velocity_residual(c, u);
  solve(c, x);
  subtract_constraint_forces(c, x, 1.0, u);
  set_velocities(u, s);
}

)";
    }
    o << R"(bool finite(const State& s) noexcept {
  bool ok = std::isfinite(s.lambda.sum());
  for (const mbrt::RigidState& x : s.rigid) {
    ok = ok && mbrt::all_finite(x.r) && mbrt::all_finite(x.p) && mbrt::all_finite(x.v) && mbrt::all_finite(x.w);
  }
  for (const mbrt::ParticleState& x : s.particle) ok = ok && mbrt::all_finite(x.r) && mbrt::all_finite(x.v);
  return ok;
}

}  // namespace

)";
  }

  void initial_state_function(std::ostringstream& o) const {
    o << "State initial_state() noexcept {\n  State s;\n";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      const Body& b = m_.bodies[i];
      const std::string st = state_of(static_cast<int>(i));
      if (a_.bodies[i].rigid) {
        o << "  " << st << " = {" << vec3(b.position) << ", " << vec4(b.orientation) << ",\n      " << vec3(b.velocity)
          << ", " << vec3(b.angular_velocity) << "};  // " << b.name << "\n";
      } else {
        o << "  " << st << " = {" << vec3(b.position) << ", " << vec3(b.velocity) << "};  // " << b.name << "\n";
      }
    }
    if (has_inputs()) {
      o << "  s.inputs = {";
      for (size_t i = 0; i < m_.inputs.size(); ++i) o << (i ? ", " : "") << num(m_.inputs[i].safe);
      o << "};  // safe values\n";
    }
    o << R"(  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s.t, c);
  factorize(c);
  Loads l;
  )" << loads_call() << R"(;
  constraint_forces(c, l, stacked_phi(c), s);
  return s;
}

)";
  }

  void step_function(std::ostringstream& o) const {
    o << R"(mbrt::StepStatus step(State& s) noexcept {
  const State last_good = s;
  const BodyVectors a_old = accelerations_of(s);
  explicit_stage(s);
  const BodyVectors u_half = generalized_velocities(s);

)";
    if (scheme_kind() == Scheme::pcst) {
      o << R"(  // Constraint terms at the new positions, factorized once per step. The
  // quadratic terms are taken at the predicted next half-step velocity
  // u_half + h a_old, which the next explicit stage will drift with.
  Kinematics k;
  kinematics(s, k);
  BodyVectors u = u_half;
  for (int b = 0; b < kBodies; ++b) u[b] += h * a_old[b];
  set_velocities(u, s);
  k.vel = velocities_of(s);
  ConstraintSystem c;
  constraint_rows(k, s.t, c);
  bool positive = factorize(c);

  // Implicit stages: the first evaluates velocity-dependent loads at the
  // predicted end-of-step velocities u_half + h/2 a_old, the next ones at the
  // last result.
  for (int b = 0; b < kBodies; ++b) u[b] = u_half[b] + (0.5 * h) * a_old[b];
  Loads l;
  for (int stage = 0; stage < kStages; ++stage) {
    set_velocities(u, s);
    k.vel = velocities_of(s);
    )" << loads_call() << R"(;
    implicit_stage(c, l, u_half, u);
  }
  set_velocities(u, s);
  constraint_forces(c, l, stacked_phi(c), s);
)";
    } else {
      o << R"(  // Constraint terms at the new positions, factorized once per step, with
  // the quadratic terms at the predicted end-of-step velocity.
  Kinematics k;
  kinematics(s, k);
  BodyVectors u = u_half;
  for (int b = 0; b < kBodies; ++b) u[b] += (0.5 * h) * a_old[b];
  set_velocities(u, s);
  k.vel = velocities_of(s);
  ConstraintSystem c;
  constraint_rows(k, s.t, c);
  bool positive = factorize(c);
  const Rows phi = stacked_phi(c);

  // Implicit stages, fixed-point passes on u = u_half + h/2 a(t + h, u).
  Loads l;
  for (int stage = 0; stage < kStages; ++stage) {
    set_velocities(u, s);
    k.vel = velocities_of(s);
    )" << loads_call() << R"(;
    constraint_forces(c, l, phi, s);
    const BodyVectors a = accelerations_of(s);
    for (int b = 0; b < kBodies; ++b) u[b] = u_half[b] + (0.5 * h) * a[b];
  }
  set_velocities(u, s);
)";
      if (scheme_kind() == Scheme::blajer) {
        o << R"(
  // Post-step corrections, a fixed number for positions, then velocities.
  for (int i = 0; i < kCorrections; ++i) {
    if (i > 0) {
      kinematics(s, k);
      constraint_rows(k, s.t, c);
      positive = factorize(c) && positive;
    }
    correct_positions(c, s);
  }
  correct_velocities(c, s);
)";
      }
    }
    o << R"(
  if (!finite(s)) {
    s = last_good;
    return mbrt::StepStatus::non_finite;
  }
  if (!positive) {
    s = last_good;
    return mbrt::StepStatus::not_positive;
  }
  return mbrt::StepStatus::ok;
}

)";
  }

  void diagnostics(std::ostringstream& o) const {
    o << R"(mbrt::Energy energy(const State& s) noexcept {
  Kinematics k;
  kinematics(s, k);
  Loads l;
  )" << loads_call() << R"(;
  const BodyVectors u = generalized_velocities(s);
  mbrt::Energy e{0.0, l.elastic_energy};
)";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      o << "  e.kinetic += mbrt::kinetic_energy(" << mass_of(static_cast<int>(i)) << ", u[" << i << "]);\n";
      if (a_.gravity) {
        o << "  e.potential -= " << mass_of(static_cast<int>(i)) << ".m * kGravity.dot(k.pose[" << i << "].r);\n";
      }
    }
    o << R"(  return e;
}

mbrt::ConstraintViolation constraint_violation(const State& s) noexcept {
  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s.t, c);
  const Rows phi = stacked_phi(c);
  const Rows phi_dot = velocity_residual(c, generalized_velocities(s));
  if (kConstraintRows == 0) return {0.0, 0.0};
  return {phi.cwiseAbs().maxCoeff(), phi_dot.cwiseAbs().maxCoeff()};
}

double quaternion_norm_error(const State& s) noexcept {
  double e = 0.0;
  for (const mbrt::RigidState& x : s.rigid) e = std::max(e, std::abs(x.p.norm() - 1.0));
  return e;
}

)";
  }

  void outputs_function(std::ostringstream& o) const {
    o << "void outputs(const State& s, Outputs& y) noexcept {\n  Kinematics k;\n  kinematics(s, k);\n";
    for (const Output& out : m_.outputs) {
      const std::string at = "y.data() + output::" + out.name;
      if (out.joint >= 0) {
        const Joint& j = m_.joints[static_cast<size_t>(out.joint)];
        o << "  y[output::" << out.name << "] = mbrt::" << (revolute_output(out) ? "revolute" : "prismatic")
          << "_coordinate(" << j.name << "_frame, " << motion(j.body1) << ", " << motion(j.body2) << ")."
          << (out.type == OutputType::joint_position ? "position" : "velocity") << ";\n";
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

  std::string source() const {
    std::ostringstream o;
    o << "// mbrt generated model '" << m_.name << "': " << m_.bodies.size() << " bodies (" << a_.rigid_count
      << " rigid, " << a_.particle_count << " particles), " << m_.joints.size() << " joints, " << m_.drivers.size() << " drivers, " << a_.constraint_rows
      << " constraint rows.\n"
      << "// Scheme " << m_.solver.scheme << ". Stage order per step: explicit_stage -> kinematics ->\n"
      << "// constraint_rows -> factorize -> (applied_loads -> implicit stage) x kStages"
      << (scheme_kind() == Scheme::blajer ? " -> corrections" : "") << ".\n"
      << "// Left out for this scene:";
    for (const std::string& s : a_.skipped) o << "\n//   " << s;
    if (a_.skipped.empty()) o << " nothing";
    o << "\n#include \"" << m_.name << ".hpp\"\n\n#include <algorithm>\n#include <cmath>\n\n#include <mbrt/runtime.hpp>\n\n"
      << "namespace mbrt::models::" << m_.name << " {\n\nnamespace {\n\n";
    constants(o);
    workspace_types(o);
    velocity_helpers(o);
    o << "// (s) => (k): pose and velocity of every body.\n"
      << "void kinematics(const State& s, Kinematics& k) noexcept {\n";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      o << "  k.pose[" << i << "] = mbrt::pose_of(" << state_of(static_cast<int>(i)) << ");  // "
        << m_.bodies[i].name << "\n";
    }
    o << "  k.vel = velocities_of(s);\n}\n\n";
    loads_stage(o);
    constraint_stage(o);
    mass_products(o);
    scheme_stages(o);
    initial_state_function(o);
    step_function(o);
    diagnostics(o);
    if (has_outputs()) outputs_function(o);
    o << "}  // namespace mbrt::models::" << m_.name << "\n";
    return o.str();
  }
};

}  // namespace

GeneratedCode emit_cpp(const Model& model, const Analysis& analysis) { return Emitter(model, analysis).run(); }

}  // namespace mbrt::codegen
