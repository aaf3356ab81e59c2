#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "emitter.hpp"

namespace mbrt::codegen {

GeneratedCode Emitter::run() {
  GeneratedCode g;
  g.header_name = m_.name + ".hpp";
  g.source_name = m_.name + ".cpp";
  g.header = header();
  g.source = source();
  return g;
}

std::string Emitter::header() const {
  std::ostringstream o;
  o << "// mbrt generated model '" << m_.name << "' from " << m_.file_name() << "\n"
    << "// scheme " << mbrt::scheme_name(scheme_kind()) << ", h = " << num(m_.solver.step) << " s, euler_updates = "
    << m_.solver.euler_updates << ". Generated code: regenerate, do not edit.\n"
    << "#pragma once\n\n#include <array>\n#include <cstddef>\n\n#include <mbrt/model_api.hpp>\n"
    << (scheme_kind() == Scheme::staggered_nps ? "#include <mbrt/natural_partitioning.hpp>\n" : "")
    << (tree_scheme() ? "#include <mbrt/sin_cos.hpp>\n" : "")
    << (modal() ? "#include <mbrt/modal_body.hpp>  // the Loads' M^-1 of the modal frames\n" : "")
    << "#include <mbrt/runtime.hpp>\n\n"
    << "namespace mbrt::models::" << m_.name << " {\n\n"
    << "inline constexpr const char* kName = \"" << m_.name << "\";\n"
    << "inline constexpr const char* kScheme = \"" << mbrt::scheme_name(scheme_kind()) << "\";\n"
    << "inline constexpr double kStep = " << num(m_.solver.step) << ";\n"
    << "inline constexpr int kEulerUpdates = " << m_.solver.euler_updates << ";\n"
    << "inline constexpr int kBodies = " << m_.bodies.size() << ";\n"
    << "inline constexpr int kRigidBodies = " << a_.rigid_count << ";\n"
    << "inline constexpr int kParticles = " << a_.particle_count << ";\n"
    << (modal() ? "inline constexpr int kModalBodies = " + std::to_string(a_.modal.size()) +
                      ";  // flexible bodies with modal coordinates (docs/flexible.md)\n"
                : "")
    << "inline constexpr int kConstraintBlocks = " << blocks() << ";  // joints, then drivers\n"
    << "inline constexpr int kConstraintRows = " << a_.constraint_rows << ";\n"
    << "inline constexpr int kParts = " << parts() << ";  // subsystems stepped in parallel (docs/parallel.md)\n\n"
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
  index_names(o);
  if (has_contacts()) contact_declarations(o);
  if (has_inputs()) input_declarations(o);
  if (has_outputs()) output_declarations(o);
  if (tree_scheme()) tree_types(o);
  else if (!friction_joints().empty()) friction_declarations(o);
  if (a_.tunable) parameter_declarations(o);
  o << "// Everything that changes from step to step; the caller owns it.\n"
    << "struct State {\n";
  for (const StateField& f : state_fields()) o << f.declaration;
  o << "};\n\n";
  workspace_struct(o);
  o << "// The model file's initial state with consistent accelerations.\n"
    << "State initial_state() noexcept;\n"
    << (a_.tunable ? "// The same with the parameters p (State::params = p). Where they move a body\n"
                     "// off its joints, constraint_violation() of the result says by how much.\n"
                     "State initial_state(const Parameters& p) noexcept;\n"
                   : "")
    << "\n"
    << "// Advances s by kStep in the caller's workspace. Allocates nothing, throws\n"
    << "// nothing, fixed work. On a non-finite result or a lost factorization s\n"
    << "// keeps its old value.\n"
    << "mbrt::StepStatus step(State& s, Workspace& w) noexcept;\n"
    << "// The same with a workspace on the stack, for tools and tests.\n"
    << "mbrt::StepStatus step(State& s) noexcept;\n\n"
    << refresh_bodies_comment() << "void refresh_bodies(State& s) noexcept;\n\n"
    << worker_declarations()
    << (tree_scheme() ? "// (s) => (s.rigid_acceleration, s.lambda): the body accelerations and\n"
                        "// multipliers that go with the joint coordinates.\n"
                        "void set_multipliers(State& s) noexcept;\n\n"
                      : "")
    << "mbrt::Energy energy(const State& s) noexcept;\n"
    << "mbrt::ConstraintViolation constraint_violation(const State& s) noexcept;\n"
    << "double quaternion_norm_error(const State& s) noexcept;  // max | |p| - 1 |\n\n"
    << "// Force and torque of every joint and driver on its body2 (kConstraintInfo\n"
    << "// order), from the multipliers " << (tree_scheme() ? "at the state" : "of the last step") << ".\n"
    << "using Reactions = std::array<mbrt::JointReaction, kConstraintBlocks>;\n"
    << "void reactions(const State& s, Reactions& r) noexcept;\n\n"
    << (has_outputs() ? "void outputs(const State& s, Outputs& y) noexcept;\n\n" : "")
    << "}  // namespace mbrt::models::" << m_.name << "\n";
  return o.str();
}

// Joint friction's State fields (docs/friction.md), `along`: the
// coordinate its sign follows.
void Emitter::friction_fields(std::vector<StateField>& f, const std::string& along) const {
  const int friction = static_cast<int>(friction_joints().size());
  if (friction == 0) return;
  f.push_back({"  // Joint friction by friction:: index (docs/friction.md): the friction torque or\n"
               "  // force of the last step (its impulse / h; N m or N, along " + along + "), and 1\n"
               "  // where the joint stuck in it, 0 where it slipped.\n"
               "  std::array<double, kFrictionJoints> friction{}, stuck{};\n"
               "  static constexpr std::array<const char*, kFrictionJoints> friction_joints{{" + friction_joint_names() +
               "}};  // their names\n",
               "friction", "double", "FRICTION_JOINTS", "", friction});
  f.push_back({"", "stuck", "double", "FRICTION_JOINTS", "", friction});
}

std::vector<StateField> Emitter::state_fields() const {
  const int nr = a_.rigid_count, np = a_.particle_count, rows = a_.constraint_rows;
  std::vector<StateField> f = {
      {"  double t = 0.0;\n", "t", "double", "", "", 1},
      {"  std::array<mbrt::RigidState, kRigidBodies> rigid;     // by rigid::BODY\n", "rigid", "mbrt_rigid_state",
       "RIGID_BODIES", "", nr},
      {"  std::array<mbrt::ParticleState, kParticles> particle;  // by particle::BODY\n", "particle",
       "mbrt_particle_state", "PARTICLES", "", np},
  };
  std::string acceleration_comment = "  // Accelerations at t, reused by the next step's explicit stage.\n";
  if (tree_scheme()) {
    const std::string qdd = scheme_kind() == Scheme::midpoint_tree ? "\n  // (qdd at the last step's midpoint)"
                            : runge_kutta_tree()                     ? "\n  // (qdd from the last step's last stage)"
                                                                   : "";
    f.push_back({"  // The joint coordinates (rad or m from t = 0), their rates and accelerations" + qdd +
                     ":\n  // what step() advances; rigid holds the bodies they put where.\n  Dofs q, qd, qdd;\n",
                 "q", "double", "DOFS", "", tree_dofs()});
    f.push_back({"", "qd", "double", "DOFS", "", tree_dofs()});
    f.push_back({"", "qdd", "double", "DOFS", "", tree_dofs()});
    friction_fields(f, "+q");
    acceleration_comment =
        "  // Body accelerations and constraint multipliers at the state, which\n"
        "  // step() does not need: set by initial_state() and set_multipliers().\n";
  }
  f.push_back({acceleration_comment + "  std::array<mbrt::RigidAcceleration, kRigidBodies> rigid_acceleration;\n",
               "rigid_acceleration", "mbrt_rigid_acceleration", "RIGID_BODIES", "", nr});
  f.push_back({"  std::array<mbrt::Vec3, kParticles> particle_acceleration;\n", "particle_acceleration", "double",
               "PARTICLES", "[3]", np});
  if (modal()) {
    const int nm = static_cast<int>(a_.modal.size());
    f.push_back({"  // Modal bodies by modal:: index (docs/flexible.md), their first N entries:\n"
                 "  // modal coordinates q, momenta p = qdot + St(q)^T R^T v + Sr(q)^T w, and dp/dt at t.\n"
                 "  std::array<mbrt::Vec6, kModalBodies> modal_q, modal_p, modal_rate;\n",
                 "modal_q", "double", "MODAL_BODIES", "[6]", nm});
    f.push_back({"", "modal_p", "double", "MODAL_BODIES", "[6]", nm});
    f.push_back({"", "modal_rate", "double", "MODAL_BODIES", "[6]", nm});
  }
  f.push_back({std::string(tree_scheme() ? "" : "  // Constraint multipliers of the last step, rows as in kConstraintInfo.\n") +
                   "  Eigen::Matrix<double, kConstraintRows, 1> lambda;\n",
               "lambda", "double", "CONSTRAINT_ROWS", "", rows});
  const int contacts = static_cast<int>(a_.contacts.size());
  if (contacts > 0) {
    f.push_back({"  // Contacts by contact:: index (docs/contact.md): the last step's normal force\n"
                 "  // (N, >= 0), tangential friction force (N, world) and 1 where the contact\n"
                 "  // stuck, 0 where it slid or was open.\n"
                 "  std::array<double, kContacts> contact_normal{}, contact_stuck{};\n"
                 "  std::array<mbrt::Vec3, kContacts> contact_tangential{};\n"
                 "  static constexpr std::array<const char*, kContacts> contacts{{" + contact_names() + "}};  // their names\n",
                 "contact_normal", "double", "CONTACTS", "", contacts});
    f.push_back({"", "contact_stuck", "double", "CONTACTS", "", contacts});
    f.push_back({"", "contact_tangential", "double", "CONTACTS", "[3]", contacts});
  }
  if (!tree_scheme()) friction_fields(f, "the joint coordinate");
  if (has_inputs()) {
    f.push_back({"  Inputs inputs;  // applied by step(); initial_state() sets the safe values\n", "inputs", "double",
                 "INPUTS", "", static_cast<int>(m_.inputs.size())});
  }
  if (scheme_kind() == Scheme::ali3p) {
    f.push_back({"  // ali3p: lambda* + alpha phi of the last step, the next one's start\n"
                 "  // (lambda adds the acceleration projection's part).\n"
                 "  Eigen::Matrix<double, kConstraintRows, 1> ali3p_lambda_star;\n",
                 "ali3p_lambda_star", "double", "CONSTRAINT_ROWS", "", rows});
  }
  if (ali3p_weighted()) {
    f.push_back({"  // M^-1 (B^T lambda - F) at t, the generalized-alpha weighting's old term.\n"
                 "  std::array<mbrt::Vec6, kBodies> ali3p_force;\n",
                 "ali3p_force", "double", "BODIES", "[6]", static_cast<int>(m_.bodies.size())});
  }
  if (a_.tunable) {
    f.push_back({"  Parameters params = kDefaultParameters;  // read by step(), energy(), ...; the caller may set them\n",
                 "params", "double", "PARAMETERS", "", static_cast<int>(params_.size())});
  }
  return f;
}

// The model's names as indices, so code reads s.rigid[rigid::crank] and
// r[constraint::pin_a] rather than positions that move when the model does.
void Emitter::index_names(std::ostringstream& o) const {
  o << "// Indices by name: body:: into kBodyInfo and per-body arrays, rigid:: and\n"
    << "// particle:: into State, constraint:: into kConstraintInfo and Reactions.\nnamespace body {\n";
  for (size_t i = 0; i < m_.bodies.size(); ++i) o << "inline constexpr int " << m_.bodies[i].name << " = " << i << ";\n";
  for (const bool rigid : {true, false}) {
    o << "}  // namespace " << (rigid ? "body" : "rigid") << "\nnamespace " << (rigid ? "rigid" : "particle") << " {\n";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      if (a_.bodies[i].rigid != rigid) continue;
      o << "inline constexpr int " << m_.bodies[i].name << " = " << a_.bodies[i].slot << ";\n";
    }
  }
  o << "}  // namespace particle\n";
  if (modal()) {
    o << "namespace modal {  // into State::modal_q, modal_p, modal_rate\n";
    for (size_t k = 0; k < a_.modal.size(); ++k) o << "inline constexpr int " << body(a_.modal[k].body).name << " = " << k << ";\n";
    o << "}  // namespace modal\n";
  }
  o << "namespace constraint {\n";
  for (int j = 0; j < blocks(); ++j) o << "inline constexpr int " << jname(j) << " = " << j << ";\n";
  o << "}  // namespace constraint\n\n";
}

void Emitter::constants(std::ostringstream& o) const {
  o << "constexpr double h = kStep;\n"
    << "constexpr double kRegularization = " << num(a_.regularization) << ";  // added to diag(S)\n";
  if (rattle()) position_stage_constants(o);
  if (scheme_kind() == Scheme::staggered4) triple_jump_constants(o);
  switch (scheme_kind()) {
    case Scheme::staggered_pcst:
    case Scheme::staggered4:
    case Scheme::staggered_nps:
      o << "constexpr double kStabilization = " << num(a_.stabilization) << ";  // alpha, 1/s\n";
      break;
    case Scheme::baumgarte:
      o << "constexpr double kBaumgarteAlpha = " << num(a_.baumgarte_alpha) << ";  // 1/s\n"
        << "constexpr double kBaumgarteBeta = " << num(a_.baumgarte_beta) << ";  // 1/s\n";
      break;
    case Scheme::blajer:
    case Scheme::rk4_projected:
    case Scheme::ali3p:
    case Scheme::staggered_tree:
    case Scheme::midpoint_tree:
    case Scheme::rk4_tree:
    case Scheme::rk8_tree:
      break;  // in struct Model; ali3p's are per row
  }
  if (a_.gravity) gravity_constant(o);
  o << "const mbrt::BodyPose kGroundPose = mbrt::ground_pose();\n"
    << "const mbrt::BodyVelocity kGroundVelocity = mbrt::ground_velocity();\n\n"
    << "// Mass properties (constant; M is block diagonal).\n";
  for (size_t i = 0; i < m_.bodies.size(); ++i) {
    const Body& b = m_.bodies[i];
    mass_constant(o, static_cast<int>(i));
    if (folded_weights()) {
      o << "const mbrt::Vec3 " << weight_of(static_cast<int>(i)) << " = " << vec3(b.mass * *m_.gravity) << ";\n";
    }
  }
  frame_constants(o);
  modal_constants(o);
  o << "\n";
}

// Joint frames, inputs' axes and points, and force elements, in the
// emitter's axes (axes(): plane coordinates for the planar step).
void Emitter::frame_constants(std::ostringstream& o) const {
  o << "\n// Joint and driver frames in body axes; drivers' functions of time.\n";
  for (int j = 0; j < blocks(); ++j) {
    const JointFrame& f = block(j).frame;
    o << "const mbrt::JointFrame " << jname(j) << "_frame{" << vec3(axes(f.s1)) << ", " << vec3(axes(f.s2)) << ",\n    "
      << vec3(axes(f.a1)) << ", " << vec3(axes(f.b1)) << ", " << vec3(axes(f.c1)) << ",\n    " << vec3(axes(f.a2)) << ", " << vec3(axes(f.b2))
      << ", " << vec3(axes(f.c2)) << ", " << num(f.length) << ", " << num(f.pitch) << "};\n";
    if (block(j).function) driver_function_constant(o, block(j));
  }
  if (has_inputs()) o << "\n// Input axes (body-1 axes) and, for forces, points (body axes).\n";
  for (size_t i = 0; i < m_.inputs.size(); ++i) {
    const Input& in = m_.inputs[i];
    const InputPlan& p = a_.inputs[i];
    o << "const mbrt::Vec3 " << in.name << "_axis = " << vec3(axes(p.axis1)) << ";\n";
    if (in.type == InputType::joint_force) {
      o << "const mbrt::Vec3 " << in.name << "_s1 = " << vec3(axes(p.s1)) << ";\n"
        << "const mbrt::Vec3 " << in.name << "_s2 = " << vec3(axes(p.s2)) << ";\n";
    }
  }
  o << "\n// Force elements in body axes.\n";
  for (size_t e = 0; e < a_.forces.size(); ++e) {
    const Force& f = m_.forces[static_cast<size_t>(a_.forces[e].model_index)];
    const ForcePlan& p = a_.forces[e];
    const std::string n = "force_" + std::to_string(e);
    switch (f.type) {
      case ForceType::spring_damper:
      case ForceType::joint_spring: spring_constant(o, f, p, n); break;
      case ForceType::torque:
        o << "const mbrt::AxialTorque " << n << "{" << vec3(axes(p.torque.axis1)) << ", " << num(p.torque.value)
          << "};  // torque on " << m_.body_name(f.body2) << ", reaction on " << m_.body_name(f.body1) << "\n";
        break;
      case ForceType::force:
        o << "const mbrt::Vec3 " << n << "_point = " << vec3(axes(p.point)) << ";  // force on "
          << m_.body_name(f.body) << "\n"
          << "const mbrt::Vec3 " << n << "_vector = " << vec3(axes(f.vector)) << ";\n";
        break;
    }
  }
  if (!a_.beams.empty()) o << "\n// Flexible bodies' beam elements: ends, axes in body axes, length, stiffnesses, damping.\n";
  for (size_t e = 0; e < a_.beams.size(); ++e) {
    const mbrt::BeamElement& b = a_.beams[e];
    const BeamElementSpec& spec = m_.beam_elements[e];
    o << "const mbrt::BeamElement beam_" << e << "{" << vec3(b.s1) << ", " << vec3(b.s2) << ",\n    " << mat3(b.Q1)
      << ",\n    " << mat3(b.Q2) << ",\n    " << num(b.l0) << ", " << num(b.EA) << ", " << num(b.GAy) << ", "
      << num(b.GAz) << ", " << num(b.GJ) << ", " << num(b.EIy) << ", " << num(b.EIz) << ", " << num(b.damping)
      << "};  // " << m_.body_name(spec.body1) << " - " << m_.body_name(spec.body2) << "\n";
  }
}

// The types of the step's working memory, in the header's namespace detail
// (detail::planar for the planar step), and the Workspace made of them.
void Emitter::workspace_struct(std::ostringstream& o) const {
  o << "// The types step() works with (generated kernels' data).\nnamespace detail {\n\n";
  if (nps_cuts()) o << "inline constexpr int kCutRows = " << a_.tree.cut_rows << ";  // rows outside the tree\n\n";
  workspace_types(o);
  if (rattle() && !a_.planar.applies) newton_matrix_type(o);
  if (a_.planar.applies) planar_types(o);
  o << "}  // namespace detail\n\n";
  const std::string ns = a_.planar.applies ? "detail::planar::" : "detail::";
  o << "// What step() works on. The caller owns it, so a real-time loop can keep it\n"
    << "// in memory locked and touched before the loop starts; nothing in it\n"
    << "// carries over from one step to the next.\n"
    << "struct Workspace {\n";
  if (tree_scheme()) {
    o << "  double t0;\n  Dofs q0, qd0, qdd0;  // the joint coordinates at t, restored when a step fails\n"
      << "  HalfAngles half_angles;  // of s.q\n"
      << "  Dofs rates;              // the rates the recursion runs at\n"
      << (runge_kutta_tree() ? "  std::array<Dofs, " + std::to_string(stages()) +
                                   "> stage_rates, stage_accelerations;  // each stage's slopes\n"
                             : "")
      << (friction_joints().empty() ? "" : "  FrictionColumns friction_columns;  // M^-1's columns of the friction joints\n")
      << "  detail::Kinematics k;    // where loads other than gravity need the bodies\n"
      << "  detail::Loads l;\n"
      << "};\n\n"
      << "inline constexpr std::size_t kWorkspaceBytes = sizeof(Workspace);\n\n";
    return;
  }
  o << "  State last_good;  // the state at t, restored when a step fails\n"
    << "  " << ns << "Kinematics k;\n"
    << "  " << ns << "ConstraintSystem c;  // at t + h\n";
  if (rattle()) {
    o << "  " << ns << "ConstraintSystem c0;  // at t: the position stage's force directions\n"
      << "  " << ns << "NewtonMatrix g;       // the position stage's Newton matrix\n";
  }
  if (scheme_kind() == Scheme::staggered_nps) o << "  " << ns << "TreeSystem t;\n";
  if (scheme_kind() == Scheme::staggered4) o << "  State start;  // the state at t, restored when a substep fails\n";
  if (!friction_joints().empty()) {
    o << "  std::array<" << ns << "BodyVectors, kFrictionJoints> friction_columns;  // responses to the friction impulses\n";
  }
  if (scheme_kind() == Scheme::rk4_projected) {
    o << "  State sum;  // the Runge-Kutta stages' weighted rates, in a state's fields\n"
      << "  std::array<mbrt::EulerParameters, kRigidBodies> p_stage;  // a stage's Euler parameters, not normalized\n";
  }
  o << "  " << ns << "Loads l;\n"
    << "};\n\n"
    << "inline constexpr std::size_t kWorkspaceBytes = sizeof(Workspace);\n\n";
}

void Emitter::model_members(std::ostringstream& o) const {
  const std::string ns = planar_ ? "detail::planar::" : "detail::";
  o << "// The model as the scheme's step (include/mbrt/schemes/) sees it: types,\n"
    << "// constants and kernels.\n"
    << (scheme_kind() == Scheme::staggered4 ? "// kSubstep: 0 for the first and last substep, 1 for the middle one.\n"
                                               "template <int kSubstep>\nstruct ModelAt {\n"
                                               "static constexpr double h = kSubsteps[kSubstep];  // the substep's length\n"
                                               "static constexpr double kFullStep = mbrt::models::" + m_.name + "::kStep;\n"
                                             : "struct Model {\n")
    << "using State = mbrt::models::" << m_.name << "::State;\n";
  if (emits_step()) o << "using Workspace = mbrt::models::" << m_.name << "::Workspace;\n";
  for (const char* t : {"Rows", "BodyVectors", "Kinematics", "Loads", "ConstraintSystem"}) {
    o << "using " << t << " = " << ns << t << ";\n";
  }
  if (rattle() && emits_step()) o << "using NewtonMatrix = " << ns << "NewtonMatrix;\n";
  if (scheme_kind() == Scheme::staggered_nps) o << "using TreeSystem = " << ns << "TreeSystem;\n";
  if (!emits_step()) {  // a planar scene: the step runs over planar::Model
    o << "// The spatial kernels serve initial_state() and the diagnostics.\n\n";
    return;
  }
  o << "static constexpr mbrt::Scheme kScheme = mbrt::Scheme::" << scheme_identifier() << ";\n"
    << "static constexpr double kStep = h;\n";
  switch (scheme_kind()) {
    case Scheme::ali3p:
      o << "static constexpr bool kWeighted = " << (ali3p_weighted() ? "true" : "false")
        << ";  // generalized-alpha: M^-1 (B^T lambda - F) of the last step\n"
        << "static constexpr bool kRheonomic = " << (a_.rheonomic ? "true" : "false") << ";\n";
      break;
    case Scheme::staggered_pcst:
    case Scheme::staggered4:
    case Scheme::staggered_nps:
    case Scheme::baumgarte:
    case Scheme::blajer:
      o << "static constexpr int kStages = " << stages() << ";  // implicit passes per step\n"
        << "static constexpr bool kPositionStage = " << (rattle() ? "true" : "false") << ";\n";
      if (rattle()) {
        o << "static constexpr int kPositionIterations = " << position_iterations()
          << ";  // Newton steps of the position stage\n";
      }
      if (scheme_kind() == Scheme::blajer) {
        o << "static constexpr int kCorrections = " << m_.solver.corrections << ";  // position corrections per step\n";
      }
      if (scheme_kind() == Scheme::staggered_nps) {
        o << "static constexpr int kCutRows = " << (nps_cuts() ? "detail::kCutRows" : "0") << ";\n";
      }
      break;
    case Scheme::rk4_projected:
      o << "static constexpr int kCorrections = " << m_.solver.corrections << ";  // position corrections per step\n"
        << "static constexpr bool kInputs = " << (has_inputs() ? "true" : "false")
        << ";  // inputs may change between steps: the first stage is evaluated afresh\n";
      break;
    case Scheme::staggered_tree:
    case Scheme::midpoint_tree:
    case Scheme::rk4_tree:
    case Scheme::rk8_tree:
      o << "using Dofs = mbrt::models::" << m_.name << "::Dofs;\n"
        << "using HalfAngles = mbrt::models::" << m_.name << "::HalfAngles;\n"
        << "static constexpr int kStages = " << stages() << ";  // recursions per step"
        << (scheme_kind() == Scheme::midpoint_tree ? " (fixed-point iterations)"
            : runge_kutta_tree()                     ? " (Runge-Kutta stages)"
                                                   : "")
        << "\n"
        << "static constexpr bool kExternalLoads = " << (tree_external_loads() ? "true" : "false")
        << ";  // loads other than gravity\n"
        << "static constexpr bool kBodyStatesEachStep = " << (body_states_on_demand() ? "false" : "true")
        << ";  // s.rigid formed by every step, else by refresh_bodies()\n";
      friction_constants(o);
      break;
  }
  if (has_contacts()) contact_members(o);
  if (!tree_scheme()) absolute_friction_members(o);
  o << "\n";
}

void Emitter::workspace_types(std::ostringstream& o) const {
  o << "using Rows = Eigen::Matrix<double, " << (planar_ ? "kPlanarRows" : "kConstraintRows") << ", 1>;\n"
    << "using BodyVectors = std::array<mbrt::" << (planar_ ? "Vec3, kBodies>;  // [v_i; v_j; omega_k], plane coordinates" : modal() ? "Vec6, kBodies + kModalBodies>;  // [v; w_body]" : "Vec6, kBodies>;  // [v; w_body]")
    << " per body" << (modal() ? ", then the modal bodies' momenta" : "") << "\n\n"
    << "struct Kinematics {\n"
    << "  std::array<mbrt::" << type("BodyPose") << ", kBodies> pose;\n"
    << "  std::array<mbrt::" << type("BodyVelocity") << ", kBodies> vel;\n"
    << "};\n\n"
    << "struct Loads {\n"
    << "  std::array<mbrt::" << type("Wrench") << ", kBodies> w;\n"
    << "  double elastic_energy;\n"
    << (modal() ? "  std::array<mbrt::Vec6, kModalBodies> modal;  // the modal momenta's rates\n"
                  "  std::array<mbrt::ModalInverseMass, kModalBodies> modal_inverse;  // the frames' M^-1 where the loads were taken\n"
                : "")
    << "};\n\n"
    << (scheme_kind() == Scheme::staggered_nps ? "// Constraint rows.\n"
                                     : "// Constraint rows, M^-1 B^T blocks and the block Cholesky factor of\n"
                                       "// S = B M^-1 B^T + kRegularization I over the model's fixed pattern.\n")
    << "struct ConstraintSystem {\n";
  const bool factor = scheme_kind() != Scheme::staggered_nps;
  for (int j = 0; j < blocks(); ++j) {
    o << "  struct {  // " << block(j).kernel << " " << m_.body_name(block(j).body1) << " - "
      << m_.body_name(block(j).body2) << ", rows " << first_row(j) << ".." << first_row(j) + rows(j) - 1 << "\n"
      << "    mbrt::" << type("ConstraintRows") << "<" << rows(j) << "> rows;\n";
    if (factor) {
      for (int b : moving_bodies(j)) o << "    " << block_type(body_dofs(), rows(j)) << " mbt_" << body(b).name << ";\n";
      for (int b : node_bodies(j)) {
        o << "    " << block_type(rows(j), 6) << " jq_" << body(b).name << ";  // the modes' columns: their force is jq^T lambda\n"
          << "    " << block_type(rows(j), 6) << " jp_" << body(b).name << ";  // the modal momenta's: jq M_qq^-1\n";
      }
      o << "    " << block_type(rows(j), rows(j)) << " L;\n";
      for (int k : a_.pattern.order) {
        const auto& lower = a_.pattern.lower[static_cast<size_t>(k)];
        if (std::find(lower.begin(), lower.end(), j) == lower.end()) continue;
        o << "    " << block_type(rows(j), rows(k)) << " L_" << jname(k) << ";\n";
      }
    }
    o << "  } " << jname(j) << ";\n";
  }
  o << "};\n\n";
  if (scheme_kind() == Scheme::staggered_nps) nps_workspace(o);
}

void Emitter::velocity_helpers(std::ostringstream& o) const {
  const std::string velocity_type = "std::array<mbrt::" + type("BodyVelocity") + ", kBodies>";
  o << "static " << velocity_type << " velocities_of(const State& s) noexcept {\n  " << velocity_type << " vel;\n";
  for (size_t i = 0; i < m_.bodies.size(); ++i) {
    o << "  vel" << at(static_cast<int>(i)) << " = mbrt::" << (planar_ ? "planar_velocity_of<kNormal>(" : "velocity_of(") << state_of(static_cast<int>(i))
      << ");\n";
  }
  o << "  return vel;\n}\n\n";
  if (planar_) {
    planar_velocity_helpers(o);
    return;
  }
  o << "// (s) => (u): generalized velocities [v; w_body] per body.\n"
    << "static BodyVectors generalized_velocities(const State& s) noexcept {\n  BodyVectors u;\n";
  for (size_t i = 0; i < m_.bodies.size(); ++i) {
    const std::string st = state_of(static_cast<int>(i));
    if (a_.bodies[i].rigid) o << "  u" << at(static_cast<int>(i)) << " << " << st << ".v, " << st << ".w;\n";
    else o << "  u" << at(static_cast<int>(i)) << " << " << st << ".v, mbrt::Vec3::Zero();\n";
  }
  if (modal()) o << "  for (int b = 0; b < kModalBodies; ++b) u[kBodies + b] = s.modal_p[b];\n";
  o << "  return u;\n}\n\n";
  if (emits_step()) {
    o << "// (u) => (s): write generalized velocities back.\n"
      << "static void set_velocities(const BodyVectors& u, State& s) noexcept {\n";
    for (size_t i = 0; i < m_.bodies.size(); ++i) {
      const std::string st = state_of(static_cast<int>(i));
      o << "  " << st << ".v = u" << at(static_cast<int>(i)) << ".head<3>();\n";
      if (a_.bodies[i].rigid) o << "  " << st << ".w = u" << at(static_cast<int>(i)) << ".tail<3>();\n";
    }
    if (modal()) o << "  for (int b = 0; b < kModalBodies; ++b) s.modal_p[b] = u[kBodies + b];\n";
    o << "}\n\n";
  }
  o << "// (a) => (s): accelerations kept for the next step.\n"
    << "static void set_accelerations(const BodyVectors& a, State& s) noexcept {\n";
  for (int i = 0; i < static_cast<int>(m_.bodies.size()); ++i) {
    if (plan(i).rigid) {
      o << "  " << acceleration_of(i) << " = {a" << at(i) << ".head<3>(), a" << at(i) << ".tail<3>()};\n";
    } else {
      o << "  " << acceleration_of(i) << " = a" << at(i) << ".head<3>();\n";
    }
  }
  if (modal()) o << "  for (int b = 0; b < kModalBodies; ++b) s.modal_rate[b] = a[kBodies + b];\n";
  o << "}\n\n"
    << "static BodyVectors accelerations_of(const State& s) noexcept {\n  BodyVectors a;\n";
  for (int i = 0; i < static_cast<int>(m_.bodies.size()); ++i) {
    if (plan(i).rigid) {
      o << "  a" << at(i) << " << " << acceleration_of(i) << ".a, " << acceleration_of(i) << ".alpha;\n";
    } else {
      o << "  a" << at(i) << " << " << acceleration_of(i) << ", mbrt::Vec3::Zero();\n";
    }
  }
  if (modal()) o << "  for (int b = 0; b < kModalBodies; ++b) a[kBodies + b] = s.modal_rate[b];\n";
  o << "  return a;\n}\n\n";
}

void Emitter::loads_stage(std::ostringstream& o, bool tree) const {
  const bool gyroscopic_torques = gyroscopic_loads() && any_gyroscopic() && !tree;
  if (tree) o << "// The loads the recursion takes from outside: all but gravity and the\n// gyroscopic torques, which it holds itself.\n";
  o << "// (k" << (has_inputs() ? ", s.inputs" : "") << ") => (l): applied forces (world) and torques (body axes) per body";
  if (gyroscopic_torques || has_inputs()) {
    o << ",\n// " << (gyroscopic_torques ? "gyroscopic torques " : "") << (has_inputs() ? "inputs " : "") << "included";
  }
  o << ", and the elastic energy stored.\n"
    << "static void " << (tree ? "tree_loads" : "applied_loads") << "([[maybe_unused]] const Kinematics& k, const State& s, Loads& l) noexcept {\n"
    << (has_inputs() ? "  const Inputs& u = s.inputs;\n" : "  (void)s;\n")
    << "  l.w.fill(mbrt::" << type("Wrench") << "{});\n  l.elastic_energy = 0.0;\n"
    << (modal() && !tree ? "  l.modal.fill(mbrt::Vec6::Zero());  // the forces at nodes add the modes' share\n" : "");
  for (size_t i = 0; i < m_.bodies.size(); ++i) {
    if (tree) continue;
    if (folded_weights()) o << "  l.w" << at(static_cast<int>(i)) << ".f += " << weight_of(static_cast<int>(i)) << ";\n";
    else if (a_.gravity) o << "  l.w" << at(static_cast<int>(i)) << ".f += " << mass_of(static_cast<int>(i)) << ".m * " << gravity() << ";\n";
    if (gyroscopic(static_cast<int>(i)) && gyroscopic_loads()) {
      o << "  l.w" << at(static_cast<int>(i)) << ".tau += mbrt::gyroscopic_torque(" << mass_of(static_cast<int>(i)) << ", k.vel"
        << at(static_cast<int>(i)) << ".w);\n";
    }
  }
  for (size_t e = 0; e < a_.forces.size(); ++e) {
    const Force& f = m_.forces[static_cast<size_t>(a_.forces[e].model_index)];
    const std::string n = force_name(static_cast<int>(e));
    if (planar_) {
      planar_force_load(o, f, n);
      continue;
    }
    if (f.type != ForceType::torque && (f.node >= 0 || f.node1 >= 0 || f.node2 >= 0)) {
      modal_force_load(o, f, n);
      continue;
    }
    switch (f.type) {
      case ForceType::spring_damper:
        o << "  {  // spring_damper " << m_.body_name(f.body1) << " - " << m_.body_name(f.body2) << "\n"
          << "    const mbrt::SpringDamperForce e = mbrt::spring_damper(" << n << ", " << motion(f.body1) << ", "
          << motion(f.body2) << ");\n";
        if (f.body2 != kGround) {
          o << "    mbrt::add_point_force(l.w" << at(f.body2) << ", " << pose(f.body2) << ", " << n << ".s2, e.f2);\n";
        }
        if (f.body1 != kGround) {
          o << "    mbrt::add_point_force(l.w" << at(f.body1) << ", " << pose(f.body1) << ", " << n << ".s1, -e.f2);\n";
        }
        o << "    l.elastic_energy += e.energy;\n  }\n";
        break;
      case ForceType::torque:
        o << "  {  // torque on " << (f.node2 >= 0 ? modal_node_label(f.body2, f.node2) : m_.body_name(f.body2)) << ", reaction on "
          << (f.node1 >= 0 ? modal_node_label(f.body1, f.node1) : m_.body_name(f.body1)) << "\n"
          << "    const mbrt::Vec3 t = mbrt::axial_torque_world(" << n << ", " << pose(f.body1) << ");\n";
        torque_on_ends(o, f.body1, f.node1, f.body2, f.node2);
        o << "  }\n";
        break;
      case ForceType::force:
        o << "  mbrt::add_point_force(l.w" << at(f.body) << ", " << pose(f.body) << ", " << n << "_point, " << n
          << "_vector);\n";
        break;
      case ForceType::joint_spring: joint_spring_load(o, f, n); break;
    }
  }
  for (size_t e = 0; e < a_.beams.size(); ++e) {
    const BeamElementSpec& spec = m_.beam_elements[e];
    const int b1 = spec.body1, b2 = spec.body2;
    o << "  {  // beam element " << m_.body_name(b1) << " - " << m_.body_name(b2) << " (ends at the centres of mass)\n"
      << "    const mbrt::BeamElementLoad e = mbrt::beam_element(beam_" << e << ", " << motion(b1) << ", " << motion(b2)
      << ");\n"
      << "    l.w" << at(b1) << ".f -= e.f2;\n    l.w" << at(b1) << ".tau += e.tau1;\n"
      << "    l.w" << at(b2) << ".f += e.f2;\n    l.w" << at(b2) << ".tau += e.tau2;\n"
      << "    l.elastic_energy += e.energy;\n  }\n";
  }
  for (size_t i = 0; i < m_.inputs.size(); ++i) input_load(o, m_.inputs[i], a_.inputs[i]);
  if (!tree) modal_loads(o);  // last: it reduces the frame's whole load
  o << "}\n\n";
}

// A joint_spring on its joint's coordinate, about or along the joint's axis
// like a joint input; the same text for the spatial and the planar step but
// for the coordinate's kernel.
void Emitter::joint_spring_load(std::ostringstream& o, const Force& f, const std::string& n) const {
  const Joint& j = m_.joints[static_cast<size_t>(f.joint)];
  const bool prismatic = j.type == JointType::prismatic;
  std::string frame = jname(f.joint) + "_frame";
  std::array<std::string, 2> motions = {motion(f.body1), motion(f.body2)};
  const auto end = [&](int b, int k) { return k >= 0 ? modal_node_label(b, k) : m_.body_name(b); };
  o << "  {  // joint_spring " << j.name << " on " << end(f.body2, j.node2) << ", reaction on " << end(f.body1, j.node1) << "\n";
  if (j.node1 >= 0 || j.node2 >= 0) {  // a joint at a node: its axes turned with the section
    const NodeJointView view = node_joint_view(frame, j.body1, j.node1, j.body2, j.node2, true, "    ");
    o << view.code;
    frame = "f", motions = view.motions;
  }
  o << "    const mbrt::JointSpringLoad e = mbrt::joint_spring(" << n << ", mbrt::" << (planar_ ? "planar_" : "")
    << (prismatic ? "prismatic" : "revolute") << "_coordinate(" << frame << ", " << motions[0] << ", " << motions[1] << "));\n";
  joint_axis_load(o, prismatic, f.body1, f.body2, "e.value", frame + ".a1", frame + ".s1", frame + ".s2", j.node1, j.node2);
  o << "    l.elastic_energy += e.energy;\n  }\n";
}

void Emitter::constraint_stage(std::ostringstream& o) const {
  o << "// (k, s.t, s.params) => (c.*.rows): constraint values, Jacobians and acceleration terms.\n"
    << "static void constraint_rows(const Kinematics& k, [[maybe_unused]] const State& s, ConstraintSystem& c) noexcept {\n";
  if (blocks() == 0) o << "  (void)k;\n  (void)c;\n";
  std::vector<std::string> part_lines(static_cast<size_t>(parts()));
  for (int j = 0; j < blocks(); ++j) {
    const ConstraintBlock& b = block(j);
    if (!node_bodies(j).empty()) {
      part_lines[0] += modal_node_block(j);
      continue;
    }
    std::string line = "  " + rows_of(j) + " = mbrt::" + b.kernel + "(" + b.name + "_frame, " + motion(b.body1) + ", " +
                       motion(b.body2);
    if (b.function) line += ",\n      " + driver_function_value(b);
    part_lines[static_cast<size_t>(parallel() ? phase_part(j) : 0)] += line + ");\n";
  }
  o << (parallel() ? parallel_region(part_lines) : part_lines[0]) << "}\n\n";
  if (scheme_kind() != Scheme::staggered_nps) factorization(o);
  OpCount jacobian;
  for (int j = 0; j < blocks(); ++j) {
    for (size_t n = 0; n < moving_bodies(j).size(); ++n) {
      jacobian += ops::product(rows(j), body_dofs(), 1);
      if (n > 0) jacobian += ops::sum(rows(j), 1);
    }
    for (int b : node_bodies(j)) {
      jacobian += ops::product(rows(j), modes_of(b), 1);
      jacobian += ops::sum(rows(j), 1);
    }
  }
  o << "// (c, u) => (B u). " << jacobian.text() << ".\n"
    << "static Rows jacobian_times(const ConstraintSystem& c, const BodyVectors& u) noexcept {\n  Rows y;\n";
  if (blocks() == 0) o << "  (void)c;\n  (void)u;\n";
  o << (parallel() ? parallel_region(per_part_blocks([&](const std::vector<bool>& in) { return jacobian_lines(in, "  "); }, true))
                   : jacobian_lines(every_block(), "  "))
    << "  return y;\n}\n\n";
  if (scheme_kind() != Scheme::staggered_nps) {
    OpCount forces;
    for (int j = 0; j < blocks(); ++j) {
      for (size_t n = 0; n < moving_bodies(j).size(); ++n) {
        forces += ops::product(body_dofs(), rows(j), 1);
        forces += ops::scale(body_dofs(), 1);
        forces += ops::sum(body_dofs(), 1);
      }
      for (int b : node_bodies(j)) {
        forces += ops::product(modes_of(b), rows(j), 1);
        forces += ops::scale(modes_of(b), 1);
        forces += ops::sum(modes_of(b), 1);
      }
    }
    o << "// (c, lambda) => (u): u -= scale M^-1 B^T lambda. " << forces.text() << ".\n"
      << "static void subtract_constraint_forces(const ConstraintSystem& c, const Rows& lambda, double scale,\n"
      << "                                BodyVectors& u) noexcept {\n";
    if (blocks() == 0) o << "  (void)c;\n  (void)lambda;\n  (void)scale;\n  (void)u;\n";
    o << (parallel() ? parallel_region(constraint_force_lines_by_body()) : constraint_force_lines(every_block(), "  "))
      << "}\n\n";
  }
  o << "// (c) => (phi), (c) => (quad): stacked position residuals and acceleration terms.\n";
  stacked(o, "phi");
  stacked(o, "quad");
  if (a_.rheonomic) stacked(o, "phi_t");
  o << "// (c, u) => (phi_dot = B u + phi_t): velocity residuals.\n"
    << "static Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept {\n";
  if (a_.rheonomic) {
    o << "  return jacobian_times(c, u) + stacked_phi_t(c);\n}\n\n";
  } else {
    o << "  return jacobian_times(c, u);  // no drivers: phi_t = 0\n}\n\n";
  }
}

// M^-1 J^T for one moving body of a block: translations divide by the mass,
// rotations by the principal moments or through the inverse inertia.
OpCount Emitter::inverse_mass_ops(int b, int r) const {
  const long n = r;
  if (planar_) return {0, 0, (plan(b).rigid ? 3 : 2) * n, 0};
  if (!plan(b).rigid) return {0, 0, 3 * n, 0};
  if (plan(b).principal_axes) return {0, 0, 6 * n, 0};
  OpCount c{0, 0, 3 * n, 0};
  c += ops::product(3, 3, r);
  return c;
}

OpCount Emitter::s_block_ops(int i, int j) const {
  OpCount c;
  int terms = 0;
  for (int b : moving_bodies(i)) {
    const auto mj = moving_bodies(j);
    if (std::find(mj.begin(), mj.end(), b) == mj.end()) continue;
    c += ops::product(rows(i), body_dofs(), rows(j));
    if (terms++ > 0) c += ops::sum(rows(i), rows(j));
  }
  for (int b : node_bodies(i)) {
    const auto nj = node_bodies(j);
    if (std::find(nj.begin(), nj.end(), b) == nj.end()) continue;
    c += ops::product(rows(i), modes_of(b), rows(j));
    if (terms++ > 0) c += ops::sum(rows(i), rows(j));
  }
  return c;
}

void Emitter::factorization(std::ostringstream& o) const {
  // ali3p factorizes S with a different diagonal shift for its tangent and
  // its projections; the other schemes add kRegularization.
  const bool shifted = scheme_kind() == Scheme::ali3p;
  OpCount directions;
  std::ostringstream body;
  if (blocks() == 0) body << (mass_parameter().empty() ? "" : "  (void)s;\n") << "  (void)c;\n";
  std::vector<std::string> part_lines(static_cast<size_t>(parts()));
  for (int ji = 0; ji < blocks(); ++ji) {
    for (int b : moving_bodies(ji)) {
      part_lines[static_cast<size_t>(parallel() ? phase_part(ji) : 0)] +=
          "  " + mbt(ji, b) + " = mbrt::inverse_mass_times_transpose(" + inverse_mass_of(b) + ", " + rows_of(ji) + "." + side(ji, b) + ");\n";
      directions += inverse_mass_ops(b, rows(ji));
    }
  }
  body << (parallel() ? parallel_region(part_lines) : part_lines[0]);
  o << "// (c.*.rows) => (c.*.mbt_*): M^-1 B^T, the directions constraint forces move the bodies in.\n"
    << "// " << directions.text() << ".\n"
    << "static void constraint_directions(" << mass_parameter() << "ConstraintSystem& c) noexcept {\n"
    << body.str() << "}\n\n";

  const auto& order = a_.pattern.order;
  const auto& lower = a_.pattern.lower;
  const auto in_lower = [&](int j, int i) { return a_.pattern.kept(j, i); };
  OpCount factor = directions;
  body.str("");
  // The parallel step: each part's blocks in its own stream, the interface's in body.
  std::vector<std::ostringstream> part_body(static_cast<size_t>(parts()));
  for (size_t pk = 0; pk < order.size(); ++pk) {
    const int k = order[pk];
    std::ostringstream& out = parallel() && !interface_block(k) ? part_body[static_cast<size_t>(phase_part(k))] : body;
    // With conjugate gradients on the interface, its blocks keep only their
    // diagonal block of the Schur complement, the preconditioner.
    const bool preconditioner = pcg_interface() && interface_block(k);
    out << "  // " << jname(k) << (preconditioner ? ": the preconditioner" : "") << "\n  " << L(k, k) << " = "
        << s_block(k, k);
    factor += s_block_ops(k, k);
    factor += ops::sum(rows(k), 1);  // the diagonal shift
    if (!shifted) out << " + kRegularization * " << block_type(rows(k), rows(k)) << "::Identity()";
    for (size_t pj = 0; pj < pk; ++pj) {
      const int j = order[pj];
      if (!in_lower(j, k) || (preconditioner && interface_block(j))) continue;
      out << "\n      - " << L(k, j) << " * " << L(k, j) << ".transpose()";
      factor += ops::product(rows(k), rows(j), rows(k));
      factor += ops::sum(rows(k), rows(k));
    }
    out << ";\n";
    if (shifted) out << "  " << L(k, k) << ".diagonal() += " << seg("shift", k) << ";\n";
    if (preconditioner && !a_.partition.block_preconditioner) {
      out << "  positive = (" << L(k, k) << ".diagonal().array() > 0.0).all() && positive;\n";
      continue;
    }
    out << "  positive = mbrt::cholesky_in_place(" << L(k, k) << ") && positive;\n";
    factor += ops::cholesky(rows(k));
    if (preconditioner) continue;
    for (int i : lower[static_cast<size_t>(k)]) {
      out << "  " << L(i, k) << " = " << s_block(i, k);
      factor += s_block_ops(i, k);
      for (size_t pj = 0; pj < pk; ++pj) {
        const int j = order[pj];
        if (!(in_lower(j, k) && in_lower(j, i))) continue;
        out << "\n      - " << L(i, j) << " * " << L(k, j) << ".transpose()";
        factor += ops::product(rows(i), rows(j), rows(k));
        factor += ops::sum(rows(i), rows(k));
      }
      out << ";\n  mbrt::solve_right_lower_transposed(" << L(k, k) << ", " << L(i, k) << ");\n";
      factor += ops::solve_right_lower_transposed(rows(i), rows(k));
    }
  }
  o << "// (c.*.rows) => (c.*.mbt_*, c.*.L*): M^-1 B^T, then S block by block in\n"
    << "// elimination order (" << a_.pattern.fill_blocks << " fill blocks); false if a pivot is not positive.\n"
    << "// " << factor.text() << ".\n"
    << "static bool factorize(" << mass_parameter() << "ConstraintSystem& c" << (shifted ? ", const Rows& shift" : "")
    << ") noexcept {\n";
  if (parallel()) {
    // Each part's factor on its own thread, then the interface's: the Schur
    // complement of the parts, formed from their L(interface, part) blocks.
    std::vector<std::string> part_lines;
    for (const auto& p : part_body) part_lines.push_back(p.str());
    o << "  constraint_directions(" << mass_argument() << "c);\n  std::array<bool, kParts> part_positive{};\n"
      << parallel_region(part_lines, "  bool positive = true;\n", "  part_positive[static_cast<size_t>(part)] = positive;\n")
      << "  bool positive = std::all_of(part_positive.begin(), part_positive.end(), [](bool p) { return p; });\n  // the interface\n";
  } else {
    o << "  bool positive = true;\n  constraint_directions(" << mass_argument() << "c);\n";
  }
  if (shifted && blocks() == 0) o << "  (void)shift;\n";
  o << body.str() << "  return positive;\n}\n\n";

  OpCount solving;
  body.str("");
  if (blocks() == 0) body << "  (void)c;\n  (void)x;\n";
  if (parallel()) {
    // Forward: the parts, then the interface; backward: the interface, then the parts.
    std::vector<bool> in_interface(static_cast<size_t>(blocks()));
    for (int j = 0; j < blocks(); ++j) in_interface[static_cast<size_t>(j)] = interface_block(j);
    const auto forward = per_part_blocks([&](const std::vector<bool>& in) { return solve_sweep_lines(in, "  ", &solving, true); }, false);
    const auto backward = per_part_blocks([&](const std::vector<bool>& in) { return solve_sweep_lines(in, "  ", &solving, false); }, false);
    body << parallel_region(forward)
         << (pcg_interface() ? interface_pcg_lines(&solving)
                             : "  // the interface\n" + solve_sweep_lines(in_interface, "  ", &solving, true) +
                                   solve_sweep_lines(in_interface, "  ", &solving, false))
         << parallel_region(backward);
  } else {
    body << solve_lines(every_block(), "  ", &solving);
  }
  o << "// (c.*.L*, x) => (x): x := S^-1 x by forward and backward substitution.\n"
    << "// " << solving.text() << ".\n"
    << "static void solve(const ConstraintSystem& c, Rows& x) noexcept {\n" << body.str() << "}\n\n";
}

std::vector<std::string> Emitter::per_part_blocks(const std::function<std::string(const std::vector<bool>&)>& lines,
                                                  bool with_interface) const {
  std::vector<std::string> out;
  for (int p = 0; p < parts(); ++p) {
    std::vector<bool> in(static_cast<size_t>(blocks()));
    for (int j = 0; j < blocks(); ++j) {
      in[static_cast<size_t>(j)] = (with_interface || !interface_block(j)) && phase_part(j) == p;
    }
    out.push_back(lines(in));
  }
  return out;
}

// Each body's updates in block order, as the serial kernel makes them, in its part.
std::vector<std::string> Emitter::constraint_force_lines_by_body() const {
  std::vector<std::string> out(static_cast<size_t>(parts()));
  for (int b = 0; b < static_cast<int>(m_.bodies.size()); ++b) {
    for (int ji = 0; ji < blocks(); ++ji) {
      const auto moving = moving_bodies(ji);
      if (std::find(moving.begin(), moving.end(), b) == moving.end()) continue;
      out[static_cast<size_t>(body_part(b))] += "  u" + at(b) + " -= scale * (" + mbt(ji, b) + " * " + seg("lambda", ji) + ");\n";
    }
  }
  return out;
}

std::vector<bool> Emitter::every_block() const { return std::vector<bool>(static_cast<size_t>(blocks()), true); }

std::string Emitter::jacobian_lines(const std::vector<bool>& in, const std::string& indent) const {
  std::string lines;
  for (int ji = 0; ji < blocks(); ++ji) {
    if (in[static_cast<size_t>(ji)]) lines += indent + seg("y", ji) + " = " + jacobian_product(ji, "u") + ";\n";
  }
  return lines;
}

std::string Emitter::constraint_force_lines(const std::vector<bool>& in, const std::string& indent) const {
  std::string lines;
  for (int ji = 0; ji < blocks(); ++ji) {
    if (!in[static_cast<size_t>(ji)]) continue;
    for (int b : moving_bodies(ji)) {
      lines += indent + "u" + at(b) + " -= scale * (" + mbt(ji, b) + " * " + seg("lambda", ji) + ");\n";
    }
    for (int b : node_bodies(ji)) {
      const std::string N = "<" + std::to_string(modes_of(b)) + ">()";
      lines += indent + "u" + momenta_at(b) + ".head" + N + " -= scale * (" + jq(ji, b) + ".leftCols" + N + ".transpose() * " +
               seg("lambda", ji) + ");\n";
    }
  }
  return lines;
}

// Forward and backward substitution with S's factor over the blocks `in`
// (whole components of S's pattern: no fill crosses between components).
std::string Emitter::solve_lines(const std::vector<bool>& in, const std::string& indent, OpCount* count) const {
  return solve_sweep_lines(in, indent, count, true) + solve_sweep_lines(in, indent, count, false);
}

std::string Emitter::solve_sweep_lines(const std::vector<bool>& in, const std::string& indent, OpCount* count,
                                       bool forward) const {
  const auto& order = a_.pattern.order;
  const auto& lower = a_.pattern.lower;
  const auto in_lower = [&](int j, int i) { return a_.pattern.kept(j, i); };
  OpCount solving;
  std::ostringstream body;
  for (size_t pk = 0; forward && pk < order.size(); ++pk) {
    const int k = order[pk];
    if (!in[static_cast<size_t>(k)]) continue;
    body << indent << "{  // " << jname(k) << "\n" << indent << "  " << rows_type(rows(k)) << " y = " << seg("x", k) << ";\n";
    for (size_t pj = 0; pj < pk; ++pj) {
      const int j = order[pj];
      if (!in_lower(j, k)) continue;
      body << indent << "  y -= " << L(k, j) << " * " << seg("x", j) << ";\n";
      solving += ops::product(rows(k), rows(j), 1);
      solving += ops::sum(rows(k), 1);
    }
    body << indent << "  mbrt::solve_lower(" << L(k, k) << ", y);\n" << indent << "  " << seg("x", k) << " = y;\n" << indent << "}\n";
    solving += ops::triangular_solve(rows(k));
  }
  for (size_t pk = order.size(); !forward && pk-- > 0;) {
    const int k = order[pk];
    if (!in[static_cast<size_t>(k)]) continue;
    body << indent << "{  // " << jname(k) << "\n" << indent << "  " << rows_type(rows(k)) << " y = " << seg("x", k) << ";\n";
    for (int i : lower[static_cast<size_t>(k)]) {
      body << indent << "  y -= " << L(i, k) << ".transpose() * " << seg("x", i) << ";\n";
      solving += ops::product(rows(k), rows(i), 1);
      solving += ops::sum(rows(k), 1);
    }
    body << indent << "  mbrt::solve_lower_transposed(" << L(k, k) << ", y);\n" << indent << "  " << seg("x", k) << " = y;\n" << indent << "}\n";
    solving += ops::triangular_solve(rows(k));
  }
  if (count) *count += solving;
  return body.str();
}

void Emitter::stacked(std::ostringstream& o, const std::string& member) const {
  o << "static Rows stacked_" << member << "(const ConstraintSystem& c) noexcept {\n  Rows y;\n";
  if (blocks() == 0) o << "  (void)c;\n";
  for (int j = 0; j < blocks(); ++j) o << "  " << seg("y", j) << " = " << rows_of(j) << "." << member << ";\n";
  o << "  return y;\n}\n\n";
}

std::string Emitter::seg(const std::string& v, int j) const {
  return v + ".segment<" + std::to_string(rows(j)) + ">(" + std::to_string(first_row(j)) + ")";
}

std::string Emitter::jacobian_product(int j, const std::string& u) const {
  std::string e;
  for (int b : moving_bodies(j)) {
    e += (e.empty() ? "" : " + ") + rows_of(j) + "." + side(j, b) + " * " + u + at(b);
  }
  for (int b : node_bodies(j)) {
    const std::string N = "<" + std::to_string(modes_of(b)) + ">()";
    e += " + " + jp(j, b) + ".leftCols" + N + " * " + u + momenta_at(b) + ".head" + N;
  }
  return e;
}

std::string Emitter::s_block(int i, int j, const std::string& directions) const {
  std::string e;
  for (int b : moving_bodies(i)) {
    const auto mj = moving_bodies(j);
    if (std::find(mj.begin(), mj.end(), b) == mj.end()) continue;
    e += (e.empty() ? "" : " + ") + rows_of(i) + "." + side(i, b) + " * " + mbt(j, b, directions);
  }
  for (int b : node_bodies(i)) {
    const auto nj = node_bodies(j);
    const std::string N = "<" + std::to_string(modes_of(b)) + ">()";
    if (std::find(nj.begin(), nj.end(), b) != nj.end()) {
      e += " + " + jp(i, b) + ".leftCols" + N + " * " + jq(j, b, directions) + ".leftCols" + N + ".transpose()";
    }
  }
  return e.empty() ? block_type(rows(i), rows(j)) + "::Zero()" : e;
}

void Emitter::mass_products(std::ostringstream& o) const {
  o << "// (l) => (M^-1 F) per body.\n"
    << "static BodyVectors free_accelerations(" << mass_parameter() << "const Loads& l) noexcept {\n  BodyVectors a;\n";
  if (std::none_of(a_.bodies.begin(), a_.bodies.end(), [](const BodyPlan& p) { return p.loaded; })) o << "  (void)l;\n";
  std::vector<std::string> part_lines(static_cast<size_t>(parts()));
  for (int i = 0; i < static_cast<int>(m_.bodies.size()); ++i) {
    std::string& out = part_lines[static_cast<size_t>(parallel() ? body_part(i) : 0)];
    if (!plan(i).loaded) {
      out += "  a" + at(i) + ".setZero();  // " + body(i).name + ": no applied load\n";
      continue;
    }
    const std::string inverse = plan(i).modal < 0 ? inverse_mass_of(i) : "l.modal_inverse" + modal_slot(plan(i).modal);
    out += "  a" + at(i) + " = mbrt::inverse_mass_times(" + inverse + ", l.w" + at(i) + ");\n";
  }
  if (modal()) part_lines[0] += "  (void)s;  // the modal bodies' M^-1 comes with the loads\n";
  if (modal()) part_lines[0] += "  for (int b = 0; b < kModalBodies; ++b) a[kBodies + b] = l.modal[b];  // the momenta's rates\n";
  o << (parallel() ? parallel_region(part_lines) : part_lines[0]) << "  return a;\n}\n\n";
}

void Emitter::initial_state_function(std::ostringstream& o) const {
  if (a_.tunable) {
    o << "// The initial state of the model file, or of the parameters p where its\n"
      << "// keys are tunable: check constraint_violation() when they move a body.\n"
      << "static State initial_state(const Parameters& p) noexcept {\n  State s;\n  s.params = p;\n";
  } else {
    o << "static State initial_state() noexcept {\n  State s;\n";
  }
  for (size_t i = 0; i < m_.bodies.size(); ++i) {
    const Body& b = m_.bodies[i];
    const int n = static_cast<int>(i);
    const std::string st = state_of(n);
    const std::string r = vec3_of(ParameterTarget::position, n, b.position, "p");
    const std::string v = vec3_of(ParameterTarget::velocity, n, b.velocity, "p");
    if (a_.bodies[i].rigid) {
      o << "  " << st << " = {" << r << ", " << vec4(b.orientation) << ",\n      " << v
        << ", " << vec3_of(ParameterTarget::angular_velocity, n, b.angular_velocity, "p") << "};\n";
    } else {
      o << "  " << st << " = {" << r << ", " << v << "};\n";
    }
  }
  modal_initial_momenta(o);
  if (has_inputs()) {
    o << "  s.inputs = {";
    for (size_t i = 0; i < m_.inputs.size(); ++i) o << (i ? ", " : "") << num(m_.inputs[i].safe);
    o << "};  // safe values\n";
  }
  if (tree_scheme()) {
    // The joint coordinates are zero at the file's pose; a tunable one is
    // the model's coordinate (body 2 relative to body 1), the tree's q times sign.
    const auto joint_value = [&](const TreeFrame& f, ParameterTarget target, double folded) {
      if (!tunable(target, f.joint, 0)) return num(folded);
      return (f.sign < 0.0 ? "-" : "") + value_of(target, f.joint, 0, 0.0, "p");
    };
    std::vector<std::string> q(m_.bodies.size(), "0.0"), rates(m_.bodies.size(), "0.0");
    for (const TreeFrame& f : a_.tree_frames.frames) {
      q[static_cast<size_t>(f.body)] = joint_value(f, ParameterTarget::joint_coordinate, 0.0);
      rates[static_cast<size_t>(f.body)] = joint_value(f, ParameterTarget::joint_rate, f.rate0);
    }
    const auto list = [&](const std::vector<std::string>& v) {
      std::string out;
      for (size_t k = 0; k < v.size(); ++k) out += (k ? ", " : "") + v[k];
      return out;
    };
    if (std::all_of(q.begin(), q.end(), [](const std::string& x) { return x == "0.0"; })) {
      o << "  s.q.fill(0.0);\n";
    } else {
      o << "  s.q = {" << list(q) << "};\n";
    }
    o << "  s.qd = {" << list(rates) << "};\n  HalfAngles ha;\n  half_angles(s.q, ha);\n  body_states(s.q, ha, s.qd, s);\n"
      << "  Kinematics k;\n  kinematics(s, k);\n  Loads l;\n  tree_loads(k, s, l);\n"
      << "  joint_accelerations(s, ha, s.qd, k, l, s.qdd);\n  set_multipliers(s);\n  return s;\n}\n\n";
    return;
  }
  const bool ali3p = scheme_kind() == Scheme::ali3p;
  const bool nps = scheme_kind() == Scheme::staggered_nps;
  o << "  Kinematics k;\n  kinematics(s, k);\n  ConstraintSystem c;\n  constraint_rows(k, s, c);\n";
  if (nps) {
    o << "  TreeSystem t;\n  factorize_tree(" << mass_argument() << "k, c, t);\n" << (nps_cuts() ? "  factorize_cut(c, t);\n" : "");
  } else {
    o << "  factorize(" << mass_argument() << (ali3p ? "c, Rows::Constant(kRegularization));\n" : "c);\n");
  }
  o << "  Loads l;\n  applied_loads(k, s, l);\n  constraint_forces(" << (nps ? "c, t" : "c")
    << ", l, stacked_phi(c), s);\n";
  if (modal()) {  // the modal loads take the accelerations: once more with the first ones
    o << "  applied_loads(k, s, l);\n  constraint_forces(c, l, stacked_phi(c), s);\n";
  }
  if (ali3p) o << "  s.ali3p_lambda_star = s.lambda;\n";
  if (ali3p_weighted()) {
    o << "  const BodyVectors a = accelerations_of(s);\n"
      << "  for (int b = 0; b < kBodies; ++b) s.ali3p_force[b] = -a[b];  // M a = F - B^T lambda\n";
  }
  if (has_contacts()) o << "  mbrt::start_contacts<Model>(s);\n";
  o << R"(  return s;
}

)";
}

void Emitter::diagnostics(std::ostringstream& o) const {
  o << R"(static mbrt::Energy energy(const State& s) noexcept {
  Kinematics k;
  kinematics(s, k);
  Loads l;
  applied_loads(k, s, l);
)" << (modal() ? "  [[maybe_unused]] " : "  ") << R"(const BodyVectors u = generalized_velocities(s);
  mbrt::Energy e{0.0, l.elastic_energy};
)";
  for (size_t i = 0; i < m_.bodies.size(); ++i) {
    if (plan(static_cast<int>(i)).modal < 0) {
      o << "  e.kinetic += mbrt::kinetic_energy(" << mass_of(static_cast<int>(i)) << ", u" << at(static_cast<int>(i)) << ");\n";
    }
    if (a_.gravity) {
      o << "  e.potential -= " << mass_of(static_cast<int>(i)) << ".m * " << gravity() << ".dot(" << pose(static_cast<int>(i)) << ".r);\n";
    }
  }
  modal_energy(o);
  for (const TreeFrame& f : a_.tree_frames.frames) {
    if (f.armature == 0.0) continue;
    o << "  e.kinetic += " << num(0.5 * f.armature) << " * s.qd" << at(f.body) << " * s.qd" << at(f.body) << ";  // armature of "
      << m_.joints[static_cast<size_t>(f.joint)].name << "\n";
  }
  o << R"(  return e;
}

static mbrt::ConstraintViolation constraint_violation(const State& )" << (tree_scheme() ? "given" : "s") << R"() noexcept {
)" << (tree_scheme() ? "  State s = given;\n  set_multipliers(s);\n" : "") << R"(  Kinematics k;
  kinematics(s, k);
  ConstraintSystem c;
  constraint_rows(k, s, c);
  const Rows phi = stacked_phi(c);
  const Rows phi_dot = velocity_residual(c, generalized_velocities(s));
  BodyVectors a = accelerations_of(s);
)" << (free_rotation() && any_gyroscopic()
           ? "  const BodyVectors g = gyroscopic_accelerations(s);  // the free rotation's part\n"
             "  for (int b = 0; b < kBodies; ++b) a[b] += g[b];\n"
           : "") << R"(  const Rows phi_ddot = jacobian_times(c, a) + stacked_quad(c);
  if (kConstraintRows == 0) return {0.0, 0.0, 0.0};
  return {phi.cwiseAbs().maxCoeff(), phi_dot.cwiseAbs().maxCoeff(), phi_ddot.cwiseAbs().maxCoeff()};
}

static double quaternion_norm_error(const State& s) noexcept {
  double e = 0.0;
  for (const mbrt::RigidState& x : s.rigid) e = std::max(e, std::abs(x.p.norm() - 1.0));
  return e;
}

)";
}

void Emitter::kinematics_function(std::ostringstream& o) const {
  o << "// (s) => (k): pose and velocity of every body.\n"
    << "static void kinematics(const State& s, Kinematics& k) noexcept {\n";
  std::vector<std::string> part_lines(static_cast<size_t>(parts()));
  for (int i = 0; i < static_cast<int>(m_.bodies.size()); ++i) {
    part_lines[static_cast<size_t>(parallel() ? body_part(i) : 0)] +=
        "  " + pose(i) + " = mbrt::" + (planar_ ? "planar_pose_of<kNormal>(" : "pose_of(") + state_of(i) + ");\n";
  }
  o << (parallel() ? parallel_region(part_lines) : part_lines[0]) << "  k.vel = velocities_of(s);\n}\n\n";
}

std::string Emitter::step_function() const {
  if (scheme_kind() == Scheme::ali3p) return "ali3p_step";
  if (scheme_kind() == Scheme::staggered4) return "staggered4_step";
  if (scheme_kind() == Scheme::rk4_projected) return "rk4_projected_step";
  return tree_scheme() ? tree_step_name() : "staggered_step";
}

std::string Emitter::step_header() const {
  if (scheme_kind() == Scheme::ali3p) return "ali3p.hpp";
  if (scheme_kind() == Scheme::staggered4) return "staggered4.hpp";
  if (scheme_kind() == Scheme::rk4_projected) return "rk4_projected.hpp";
  return tree_scheme() ? "tree.hpp" : "staggered.hpp";
}

std::string Emitter::source() const {
  std::ostringstream o;
  o << "// mbrt generated model '" << m_.name << "': " << m_.bodies.size() << " bodies (" << a_.rigid_count
    << " rigid, " << a_.particle_count << " particles), " << m_.joints.size() << " joints, " << m_.drivers.size() << " drivers, " << a_.constraint_rows
    << " constraint rows.\n"
    << "// Scheme " << mbrt::scheme_name(scheme_kind()) << ": the step is mbrt::schemes::"
    << step_function() << " (include/mbrt/schemes/" << step_header() << ")"
    << "\n// over " << (a_.planar.applies ? "planar::Model" : "Model") << ", the model's types, constants and kernels below.\n";
  o << "// Left out for this scene:";
  for (const Skipped& s : a_.skipped) o << "\n//   " << s.specialization << ": " << s.removed;
  if (a_.skipped.empty()) o << " nothing";
  if (!a_.planar.refusal.empty()) o << "\n// Kept: spatial coordinates, since " << a_.planar.refusal << ".";
  o << "\n#include \"" << m_.name << ".hpp\"\n\n#include <algorithm>\n#include <cmath>\n\n"
    << (a_.beams.empty() ? "" : "#include <mbrt/beam_element.hpp>\n")
    << (piecewise_drivers() ? "#include <mbrt/piecewise_function.hpp>\n" : "")
    << "#include <mbrt/reactions.hpp>\n#include <mbrt/schemes/"
    << step_header() << ">\n" << (parallel() ? "#include <mbrt/worker_team.hpp>\n" : "") << "\n"
    << "namespace mbrt::models::" << m_.name << " {\n\nnamespace {\n\n";
  worker_team_definition(o);
  constants(o);
  model_members(o);
  kernels(o);
  o << "};\n\n";
  if (scheme_kind() == Scheme::staggered4) o << "using Model = ModelAt<0>;  // the kernels that serve the tools\n\n";
  if (a_.planar.applies) planar_stages(o);
  o << "}  // namespace\n\n";
  public_functions(o);
  o << "}  // namespace mbrt::models::" << m_.name << "\n";
  return o.str();
}

// struct Model's functions: the kernels the scheme's step calls, and the
// implementations of the model's tools (initial state, energy, violations,
// reactions, outputs).
void Emitter::kernels(std::ostringstream& o) const {
  velocity_helpers(o);
  kinematics_function(o);
  loads_stage(o);
  constraint_stage(o);
  if (scheme_kind() != Scheme::staggered_nps) mass_products(o);
  if (tree_scheme()) {
    loads_stage(o, true);
    constraint_forces_function(o, "");
    tree_kernels(o);
  } else if (scheme_kind() == Scheme::ali3p) {
    ali3p_stages(o);
  } else if (a_.planar.applies) {
    // The spatial multipliers serve initial_state(); the step is planar.
    constraint_forces_function(o, stabilization_term());
  } else {
    staggered_stages(o);
  }
  initial_state_function(o);
  diagnostics(o);
  reactions_function(o);
  if (has_outputs()) outputs_function(o);
}

void Emitter::public_functions(std::ostringstream& o) const {
  const std::string stepper = a_.planar.applies ? "planar::Model" : "Model";
  o << (a_.tunable ? "State initial_state() noexcept { return Model::initial_state(kDefaultParameters); }\n\n"
                    "State initial_state(const Parameters& p) noexcept { return Model::initial_state(p); }\n\n"
                  : "State initial_state() noexcept { return Model::initial_state(); }\n\n")
    << "mbrt::StepStatus step(State& s, Workspace& w) noexcept {\n  return mbrt::schemes::"
    << step_function() << "<" << (scheme_kind() == Scheme::staggered4 ? "ModelAt<0>, ModelAt<1>" : stepper) << ">(s, w);\n}\n\n"
    << "mbrt::StepStatus step(State& s) noexcept {\n  Workspace w;\n  return step(s, w);\n}\n\n"
    << refresh_bodies_function();
  // Where the step leaves s.rigid as it was, the tools read a copy of the
  // state with its bodies' states formed.
  const std::string read = body_states_on_demand() ? "with_bodies(s)" : "s";
  if (body_states_on_demand()) o << "static State with_bodies(State s) noexcept {\n  refresh_bodies(s);\n  return s;\n}\n\n";
  if (tree_scheme()) {
    o << "void set_multipliers(State& s) noexcept {\n" << (body_states_on_demand() ? "  refresh_bodies(s);\n" : "")
      << "  Model::set_multipliers(s);\n}\n\n";
  }
  o << "mbrt::Energy energy(const State& s) noexcept { return Model::energy(" << read << "); }\n\n"
    << "mbrt::ConstraintViolation constraint_violation(const State& s) noexcept { return Model::constraint_violation(" << read << "); }\n\n"
    << "double quaternion_norm_error(const State& s) noexcept { return Model::quaternion_norm_error(" << read << "); }\n\n"
    << "void reactions(const State& s, Reactions& r) noexcept { Model::reactions(" << read << ", r); }\n\n"
    << (has_outputs() ? "void outputs(const State& s, Outputs& y) noexcept { Model::outputs(" + read + ", y); }\n\n" : "")
    << worker_functions();
}

void Emitter::reactions_function(std::ostringstream& o) const {
  if (tree_scheme()) {
    o << "// (s) => (s.rigid_acceleration, s.lambda): what the joint coordinates imply,\n"
      << "// from the index-1 multipliers S lambda = B M^-1 F + quad.\n"
      << "static void set_multipliers(State& s) noexcept {\n"
      << "  Kinematics k;\n  kinematics(s, k);\n  ConstraintSystem c;\n  constraint_rows(k, s, c);\n  factorize(" << mass_argument() << "c);\n"
      << "  Loads l;\n  applied_loads(k, s, l);\n  constraint_forces(c, l, stacked_phi(c), s);\n}\n\n";
  }
  o << "static void reactions(const State& " << (tree_scheme() ? "given" : "s") << ", Reactions& r) noexcept {\n";
  if (tree_scheme()) o << "  State s = given;\n  set_multipliers(s);\n";
  if (blocks() == 0) {
    o << "  (void)s;\n  (void)r;\n}\n\n";
    return;
  }
  o << "  Kinematics k;\n  kinematics(s, k);\n  ConstraintSystem c;\n  constraint_rows(k, s, c);\n";
  for (int j = 0; j < blocks(); ++j) {
    const ConstraintBlock& b = block(j);
    const bool on_body2 = b.body2 != kGround;
    const int on = on_body2 ? b.body2 : b.body1, node = on_body2 ? b.node2 : b.node1;
    std::string point = on_body2 ? pose(b.body2) + ".r + " + pose(b.body2) + ".R * " + b.name + "_frame.s2"
                                 : b.name + "_frame.s2";
    // At a modal body's node: the frame's columns before the modal momenta took their share.
    std::string columns = rows_of(j) + "." + (on_body2 ? "J2" : "J1");
    if (node >= 0) {
      if (on_body2) point = modal_node_place(on, node);
      columns = "(" + columns + " + mbrt::modal_frame_share<" + std::to_string(modes_of(on)) + ", " + std::to_string(rows(j)) +
                ">(" + body(on).name + "_modal, " + pose(on) + ".R, " + modal_coordinates(plan(on).modal, "modal_q") + ", " +
                jp(j, on) + "))";
    }
    o << "  r[constraint::" << b.name << "] = mbrt::joint_reaction(-(" << columns
      << ".transpose() * " << seg("s.lambda", j) << "), " << pose(on) << ",\n      " << point << ", "
      << (on_body2 ? "1.0" : "-1.0") << ", " << pose(b.body1) << ", " << reaction_frame(j) << ");\n";
  }
  o << "}\n\n";
}

void Emitter::gyroscopic_accelerations_function(std::ostringstream& o) const {
  o << "// (s) => (J^-1 (-w x J w)) per body: the gyroscopic accelerations, which the\n"
    << "// explicit stage's free rotation applies and the multipliers must balance.\n"
    << "static BodyVectors gyroscopic_accelerations(const State& s) noexcept {\n  BodyVectors g;\n";
  for (int i = 0; i < static_cast<int>(m_.bodies.size()); ++i) {
    if (!gyroscopic(i)) {
      o << "  g" << at(i) << ".setZero();\n";
      continue;
    }
    o << "  g" << at(i) << " << mbrt::Vec3::Zero(), mbrt::inverse_inertia_times(" << mass_of(i)
      << ", mbrt::gyroscopic_torque(" << mass_of(i) << ", " << state_of(i) << ".w));\n";
  }
  o << "  return g;\n}\n\n";
}

void Emitter::constraint_forces_function(std::ostringstream& o, const std::string& stabilization) const {
  // Planar multipliers go to their rows of the spatial s.lambda at the end.
  const std::string lambda = planar_ ? "lambda" : "s.lambda";
  // The multipliers balance the gyroscopic accelerations too; the stored
  // accelerations, which the next half kick applies, leave them out.
  const bool gyro = any_gyroscopic() && !gyroscopic_loads();
  if (gyro) gyroscopic_accelerations_function(o);
  o << "static void constraint_forces(const ConstraintSystem& c, const Loads& l, const Rows& phi, State& s) noexcept {\n"
    << (stabilization.empty() ? "  (void)phi;\n" : "") << "  BodyVectors a = free_accelerations(" << (planar_ ? "" : mass_argument()) << "l);\n";
  if (gyro) {
    o << "  const BodyVectors g = gyroscopic_accelerations(s);\n"
      << "  for (int b = 0; b < kBodies; ++b) a[b] += g[b];\n";
  }
  o << "  " << (planar_ ? "Rows " : "") << lambda << " = jacobian_times(c, a) + stacked_quad(c)"
    << (stabilization.empty() ? "" : " +\n             " + stabilization) << ";\n  solve(c, " << lambda << ");\n";
  if (scheme_kind() == Scheme::rk4_projected) {
    // S's regularization bends every stage's accelerations off the
    // constraints by about kRegularization / S, which the projections then
    // turn into a first-order error; one refinement squares it.
    o << "  Rows refinement = kRegularization * " << lambda << ";  // (S + d) x = b, then x += (S + d)^-1 d x\n"
      << "  solve(c, refinement);\n  " << lambda << " += refinement;\n";
  }
  o << "  subtract_constraint_forces(c, " << lambda << ", 1.0, a);\n";
  if (gyro) o << "  for (int b = 0; b < kBodies; ++b) a[b] -= g[b];\n";
  o << "  set_accelerations(a, s);\n" << (planar_ ? "  store_multipliers(lambda, s);\n" : "") << "}\n\n";
}

GeneratedCode emit_cpp(const Model& model, const Analysis& analysis) { return Emitter(model, analysis).run(); }

}  // namespace mbrt::codegen
