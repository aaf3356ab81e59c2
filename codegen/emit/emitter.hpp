// The C++ emitter: it writes a model's constants, types and kernels as the
// Analysis plans them; the schemes' steps are templates in
// include/mbrt/schemes/ over the emitted struct Model (docs/architecture.md).
// The definitions are split by concept: emit_cpp.cpp (model data, kinematics,
// loads, constraint system, diagnostics, the header and Workspace),
// emit_staggered.cpp (kernels of staggered-pcst, baumgarte, blajer),
// emit_newton.cpp (the position stage's matrix), emit_nps.cpp
// (staggered-nps), emit_ali3p.cpp (ali3p), emit_planar.cpp (the kernels in
// planar coordinates).
#pragma once

#include <algorithm>
#include <array>
#include <functional>
#include <iomanip>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "emit_cpp.hpp"
#include "op_count.hpp"
#include "parameters.hpp"
#include "principal_frame.hpp"
#include "planar_scene.hpp"
#include "straight_line.hpp"

namespace mbrt::codegen {

// Literals for generated code: doubles round-trip exactly.
inline std::string num(double x) {
  std::ostringstream o;
  o << std::setprecision(17) << x;
  std::string s = o.str();
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

inline std::string vec3(const Eigen::Vector3d& v) {
  return "mbrt::Vec3(" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + ")";
}

inline std::string vec4(const Eigen::Vector4d& v) {
  return "mbrt::Vec4(" + num(v[0]) + ", " + num(v[1]) + ", " + num(v[2]) + ", " + num(v[3]) + ")";
}

inline std::string mat3(const Eigen::Matrix3d& m) {
  std::string s = "(mbrt::Mat3() << ";
  for (int i = 0; i < 9; ++i) s += num(m(i / 3, i % 3)) + (i < 8 ? ", " : "");
  return s + ").finished()";
}

inline std::string rows_type(int n) { return "Eigen::Matrix<double, " + std::to_string(n) + ", 1>"; }
inline std::string block_type(int r, int c) {
  return "Eigen::Matrix<double, " + std::to_string(r) + ", " + std::to_string(c) + ">";
}

// A member of the generated State, in declaration order. The C++ header's
// struct State and the C interface's <name>_state (emit_c.cpp) are written
// from one list of them.
struct StateField {
  std::string declaration;  // its C++ lines, comments first ("" when declared with the one before)
  std::string name;
  std::string c_type;       // C element type: double, mbrt_rigid_state, ...
  std::string c_length;     // its array length's constant after "<NAME>_" (RIGID_BODIES, ...); "" for a scalar
  std::string c_inner;      // the element's own extent ("[3]" for a Vec3), or ""
  int count;                // elements; 0 leaves it out of the C struct (C has no empty arrays)
};

// The terms the tree's articulated-body recursion runs with (emit_tree.cpp):
// all of them for the joint accelerations; none but a unit force in one
// joint (a frame index) for that joint's column of M^-1.
struct TreeRecursionTerms {
  bool rates = true;
  bool gravity = true;
  bool loads = true;
  int unit_force = -1;
};

// Writes the generated files for one model.
class Emitter {
 public:
  Emitter(const Model& m, const Analysis& a) : m_(m), a_(a), params_(parameters(m)) {}

  GeneratedCode run();
  // emit_c.cpp: <name>_c.h and <name>_c.cpp, the C interface over the C++ one.
  std::vector<GeneratedFile> c_interface() const;

 private:
  // The emitter of the planar step: it owns an analysis with the planar constraint blocks.
  Emitter(const Model& m, Analysis&& planar_analysis)
      : m_(m), owned_(std::make_shared<Analysis>(std::move(planar_analysis))), a_(*owned_), planar_(true),
        params_(parameters(m)) {}
  Emitter planar_emitter() const {
    Analysis planar = a_;
    planar.constraints = a_.planar.constraints;
    planar.constraint_rows = a_.planar.constraint_rows;
    return Emitter(m_, std::move(planar));
  }

  const Model& m_;
  std::shared_ptr<const Analysis> owned_;  // the planar emitter's analysis
  const Analysis& a_;
  const bool planar_ = false;  // emitting the planar step's stages (emit_planar.cpp)
  const std::vector<Parameter> params_;  // the model's tunable keys (docs/parameters.md)

  // The runtime type of the coordinates emitted: spatial, or its planar counterpart.
  std::string type(const std::string& spatial) const {
    if (!planar_) return spatial;
    if (spatial == "ConstraintRows") return "PlanarRows";
    if (spatial == "BodyPose") return "PlanarPose";
    if (spatial == "BodyVelocity") return "PlanarVelocity";
    if (spatial == "BodyMotion") return "PlanarMotion";
    return "Planar" + spatial;  // Wrench
  }
  int body_dofs() const { return planar_ ? 3 : 6; }
  // A constant vector in the axes of the code emitted: the planar step's are
  // plane coordinates (codegen/plan/planar_scene.hpp).
  Eigen::Vector3d axes(const Eigen::Vector3d& v) const { return planar_ ? Plane{a_.planar.normal}.coordinates(v) : v; }
  // Whether this emitter writes the step's stages (the spatial one does not when the step is planar).
  bool emits_step() const { return planar_ || !a_.planar.applies; }

  // Implicit passes per step (the analysis' StepPlan; the planar step's own).
  int stages() const { return planar_ ? a_.planar.stages : a_.step.stages; }
  // Gravity's m g as a constant per body (folded) rather than a product in every load evaluation.
  bool folded_weights() const { return a_.specialize.folded_weights && m_.gravity.has_value(); }
  std::string weight_of(int i) const { return body(i).name + "_weight"; }
  const Body& body(int i) const { return m_.bodies[static_cast<size_t>(i)]; }
  const BodyPlan& plan(int i) const { return a_.bodies[static_cast<size_t>(i)]; }
  const ConstraintBlock& block(int j) const { return a_.constraints[static_cast<size_t>(j)]; }
  int blocks() const { return static_cast<int>(a_.constraints.size()); }
  int rows(int j) const { return block(j).rows; }
  int first_row(int j) const { return block(j).first_row; }
  std::string jname(int j) const { return block(j).name; }

  // Equal principal moments: w stays constant in a torque-free rotation. A
  // property of the body, not a specialization, so the step's arithmetic is the
  // same with or without specializations.
  bool spherical_inertia(int i) const {
    if (plan(i).tunable_inertia) return false;
    const Eigen::Matrix3d& j = body(i).inertia;
    return j == Eigen::Matrix3d(Eigen::Vector3d::Constant(j(0, 0)).asDiagonal());
  }
  // Bodies whose gyroscopic torque the step evaluates (not the isotropic ones
  // when specialized; a planar scene turns about a principal axis and has none).
  // A modal body's frame takes its inertia terms from the modal kernel.
  bool gyroscopic(int i) const { return plan(i).rigid && !plan(i).isotropic && !planar_ && plan(i).modal < 0; }
  // Where the gyroscopic torque is a load (StepPlan::free_rotation).
  bool gyroscopic_loads() const { return !free_rotation(); }
  bool free_rotation() const { return a_.step.free_rotation; }
  bool any_gyroscopic() const {
    for (int i = 0; i < static_cast<int>(m_.bodies.size()); ++i)
      if (gyroscopic(i)) return true;
    return false;
  }
  void gyroscopic_accelerations_function(std::ostringstream& o) const;

  // Indices by name (the header's namespaces body, rigid, particle, constraint):
  // body i in the per-body arrays, its slot in State, constraint block j.
  std::string at(int i) const { return "[body::" + body(i).name + "]"; }
  std::string slot_of(int i) const { return (plan(i).rigid ? "[rigid::" : "[particle::") + body(i).name + "]"; }
  std::string state_of(int i) const { return (plan(i).rigid ? "s.rigid" : "s.particle") + slot_of(i); }
  std::string acceleration_of(int i) const {
    return (plan(i).rigid ? "s.rigid_acceleration" : "s.particle_acceleration") + slot_of(i);
  }
  // Body i's mass (constant, or read from the parameters p where tunable).
  std::string mass_of(int i, const std::string& p = "s.params") const {
    return body(i).name + "_mass" + (plan(i).tunable_mass ? "(" + p + ")" : "");
  }
  // The kernels that form M^-1 take the state where masses are runtime
  // parameters (include/mbrt/schemes/staggered.hpp): parameter and argument.
  // (and where a modal body's frame is turned by its orientation).
  std::string mass_parameter() const { return a_.tunable_masses || modal() ? "const State& s, " : ""; }
  std::string mass_argument() const { return a_.tunable_masses || modal() ? "s, " : ""; }
  // Body i's M^-1 in the inverse-mass products: its mass, or a modal body's
  // reduced mass at its deformation, turned to its orientation
  // (include/mbrt/modal_body.hpp).
  std::string inverse_mass_of(int i) const {
    if (plan(i).modal < 0) return mass_of(i);
    const int k = plan(i).modal;
    return "mbrt::modal_inverse_mass<" + std::to_string(a_.modal[static_cast<size_t>(k)].modes) + ">(" + body(i).name +
           "_modal, " + state_of(i) + ".p, " + modal_coordinates(k, "modal_q") + ")";
  }

  // emit_modal.cpp: modal bodies (docs/flexible.md).
  bool modal() const { return !a_.modal.empty(); }
  std::string modal_slot(int k) const { return "[modal::" + body(a_.modal[static_cast<size_t>(k)].body).name + "]"; }
  std::string modal_coordinates(int k, const std::string& field) const;  // s.modal_q[modal::NAME].head<N>()
  void modal_constants(std::ostringstream& o) const;
  void modal_loads(std::ostringstream& o) const;
  void modal_kick(std::ostringstream& o) const;
  void modal_drift(std::ostringstream& o) const;
  void modal_initial_momenta(std::ostringstream& o) const;
  void modal_energy(std::ostringstream& o) const;
  // Node k of modal body i: NAME@root, NAME@tip or NAME@K, and its constants' name.
  std::string modal_node_label(int i, int k) const;
  std::string modal_node_constant(int i, int k) const { return body(i).name + "_node_" + std::to_string(k); }
  std::vector<int> modal_nodes(int i) const;  // the nodes the outputs, forces and inputs name, ascending
  std::string modal_node_output(const Output& out, const std::string& at) const;
  void modal_force_load(std::ostringstream& o, const Force& f, const std::string& n) const;
  // A joint at a modal body's node as the kernels see it: code (at `indent`)
  // declaring `f`, the joint's frame `frame` with each node's deformed place
  // and, where `turns`, its section's turned axes, and node1 / node2 (the
  // nodes' ModalPointMotion); and the motions to pass the kernels.
  struct NodeJointView {
    std::string code;
    std::array<std::string, 2> motions;
  };
  NodeJointView node_joint_view(const std::string& frame, int body1, int node1, int body2, int node2, bool turns,
                                const std::string& indent) const;
  // constraint_rows' line for block j, a joint (or its driver) at a modal body's node.
  std::string modal_node_block(int j) const;
  // The node's place (world) for reactions, at the state's deformation.
  std::string modal_node_place(int b, int k) const;
  // Block j's joint frame for reactions: body 1's axes turned with its node's section.
  std::string reaction_frame(int j) const;
  // Whether a joint at a node turns its axes with the section (not a point joint).
  static bool turns_axes(const ConstraintBlock& b);
  // The torque `t` (world, in scope) on body2, its reaction on body1, either
  // at a modal body's node (k >= 0) or on the body.
  void torque_on_ends(std::ostringstream& o, int body1, int node1, int body2, int node2) const;
  // The force `force` (world) on modal body b at its node k: the frame's load
  // there and the modes' share in l.modal.
  std::string node_force(int b, int k, const std::string& force) const;

  // emit_parameters.cpp: runtime parameters (docs/parameters.md).
  const Parameter* tunable(ParameterTarget target, int index, int component = 0) const;
  // A model value in generated code: the parameter p.value[parameter::NAME]
  // where it is tunable, else the file's literal.
  std::string value_of(ParameterTarget target, int index, int component, double folded, const std::string& p) const;
  std::string vec3_of(ParameterTarget target, int index, const Eigen::Vector3d& folded, const std::string& p) const;
  bool tunable_gravity() const;
  std::string gravity() const { return tunable_gravity() ? "gravity(s.params)" : "kGravity"; }
  bool tunable_force(int model_index) const;
  std::string force_name(int e) const;  // force_E, or force_E(s.params) where tunable
  void parameter_declarations(std::ostringstream& o) const;  // the header's Parameters, kParameterInfo, set_parameter
  void gravity_constant(std::ostringstream& o) const;
  void mass_constant(std::ostringstream& o, int i) const;
  void spring_constant(std::ostringstream& o, const Force& f, const ForcePlan& p, const std::string& n) const;
  bool tunable_driver(int driver) const;
  // A driver block's function of time: its constant NAME_sine or NAME_polynomial,
  // or a function of the parameters where its coefficients are tunable ...
  void driver_function_constant(std::ostringstream& o, const ConstraintBlock& b) const;
  // Some driver's function is piecewise (the step includes mbrt/piecewise_function.hpp).
  bool piecewise_drivers() const;
  // ... and its value and derivatives at s.t in constraint_rows.
  std::string driver_function_value(const ConstraintBlock& b) const;
  std::string motion(int i) const {
    if (i == kGround) return "mbrt::" + type("BodyMotion") + "{kGroundPose, kGroundVelocity}";
    return "mbrt::" + type("BodyMotion") + "{k.pose" + at(i) + ", k.vel" + at(i) + "}";
  }
  std::string pose(int i) const { return i == kGround ? "kGroundPose" : "k.pose" + at(i); }
  // ConstraintSystem holds one struct per block, named after its joint or
  // driver: rows, M^-1 B^T per moving body (mbt_BODY), and its row of the
  // factor of S: the diagonal block L and L_OTHER for block (this, OTHER).
  std::string rows_of(int j, const std::string& c = "c") const { return c + "." + jname(j) + ".rows"; }
  std::string mbt(int j, int b, const std::string& c = "c") const {
    return c + "." + jname(j) + ".mbt_" + body(b).name;
  }
  std::string L(int i, int k) const { return "c." + jname(i) + (i == k ? ".L" : ".L_" + jname(k)); }
  std::string side(int j, int b) const { return block(j).body1 == b ? "J1" : "J2"; }
  std::vector<int> moving_bodies(int j) const {
    std::vector<int> out;
    for (int b : {block(j).body1, block(j).body2}) if (b != kGround) out.push_back(b);
    return out;
  }
  // The modal bodies whose node a joint holds: the rows' modal columns
  // jq_BODY and momentum columns jp_BODY = jq M_qq^-1
  // (include/mbrt/modal_body.hpp, modal_node_rows): a force lambda moves the
  // momenta by jq^T lambda, and the rows read jp p; u[kBodies + modal::BODY]
  // in BodyVectors holds p.
  std::vector<int> node_bodies(int j) const {
    std::vector<int> out;
    if (block(j).node1 >= 0) out.push_back(block(j).body1);
    if (block(j).node2 >= 0) out.push_back(block(j).body2);
    return out;
  }
  std::string jq(int j, int b, const std::string& c = "c") const { return c + "." + jname(j) + ".jq_" + body(b).name; }
  std::string jp(int j, int b, const std::string& c = "c") const { return c + "." + jname(j) + ".jp_" + body(b).name; }
  std::string momenta_at(int b) const { return "[kBodies + modal::" + body(b).name + "]"; }
  int modes_of(int b) const { return a_.modal[static_cast<size_t>(plan(b).modal)].modes; }

  // emit_cpp.cpp: the model's data and the stages every scheme shares.
  std::string header() const;
  std::string source() const;
  void index_names(std::ostringstream& o) const;  // namespaces body, rigid, particle, constraint
  std::vector<StateField> state_fields() const;
  void friction_fields(std::vector<StateField>& f, const std::string& along) const;
  void constants(std::ostringstream& o) const;
  void frame_constants(std::ostringstream& o) const;  // joints', inputs' and force elements' vectors, in axes()
  void workspace_types(std::ostringstream& o) const;   // the kernels' types (Kinematics, ConstraintSystem, ...)
  void workspace_struct(std::ostringstream& o) const;  // Workspace: what step() works on
  void model_members(std::ostringstream& o) const;     // struct Model's types and constants for the scheme
  void kernels(std::ostringstream& o) const;           // struct Model's functions
  void public_functions(std::ostringstream& o) const;  // initial_state(), step(), ... forwarding to struct Model
  void velocity_helpers(std::ostringstream& o) const;
  void kinematics_function(std::ostringstream& o) const;
  void loads_stage(std::ostringstream& o, bool tree = false) const;  // tree: the recursion's external loads
  void joint_spring_load(std::ostringstream& o, const Force& f, const std::string& n) const;  // spatial or planar
  void constraint_stage(std::ostringstream& o) const;
  void factorization(std::ostringstream& o) const;  // factorize(c) and solve(c, x) over the pattern of S
  // The bodies of jacobian_times, subtract_constraint_forces and solve over
  // the constraint blocks marked in `in` (every_block(): all of them).
  std::vector<bool> every_block() const;
  std::string jacobian_lines(const std::vector<bool>& in, const std::string& indent) const;
  std::string constraint_force_lines(const std::vector<bool>& in, const std::string& indent) const;
  std::string solve_lines(const std::vector<bool>& in, const std::string& indent, OpCount* count) const;
  std::string solve_sweep_lines(const std::vector<bool>& in, const std::string& indent, OpCount* count, bool forward) const;
  // The parallel step: lines(in) for each part's blocks, the interface's
  // shared out among the parts (phase_part) or left out ...
  std::vector<std::string> per_part_blocks(const std::function<std::string(const std::vector<bool>&)>& lines,
                                           bool with_interface) const;
  // ... and subtract_constraint_forces's lines per part, by body.
  std::vector<std::string> constraint_force_lines_by_body() const;
  // Operations (op_count.hpp) of M^-1 J^T for body b and r rows, and of s_block(i, j).
  OpCount inverse_mass_ops(int b, int r) const;
  OpCount s_block_ops(int i, int j) const;
  void stacked(std::ostringstream& o, const std::string& member) const;  // Rows stacked_<member>(c)
  // emit_parallel.cpp: the parallel step's phases (Analysis::partition).
  bool parallel() const { return a_.partition.parts > 1; }
  int parts() const { return a_.partition.parts; }
  bool interface_block(int j) const { return parallel() && a_.partition.interface(j); }
  int phase_part(int j) const { return a_.partition.phase_part[static_cast<size_t>(j)]; }
  int body_part(int b) const { return a_.partition.body_part[static_cast<size_t>(b)]; }
  bool pcg_interface() const { return parallel() && a_.partition.pcg; }
  // solve()'s interface by preconditioned conjugate gradients (the parts' forward sweeps done).
  std::string interface_pcg_lines(OpCount* count) const;
  // A fork and join over the parts' lines; enter and leave run in every part.
  std::string parallel_region(const std::vector<std::string>& part_lines, const std::string& enter = "",
                              const std::string& leave = "") const;
  void worker_team_definition(std::ostringstream& o) const;
  std::string worker_declarations() const;  // the header's start_workers(), stop_workers()
  std::string worker_functions() const;
  std::string seg(const std::string& v, int j) const;
  // Expression for block S(i, j) = sum over shared moving bodies of B_i M^-1 B_j^T,
  // M^-1 B_j^T from the constraint system named directions.
  std::string s_block(int i, int j, const std::string& directions = "c") const;
  // Expression for B_j u: block j's Jacobian times its moving bodies' entries of u.
  std::string jacobian_product(int j, const std::string& u) const;
  void mass_products(std::ostringstream& o) const;
  // constraint_forces(c, l, phi, s): S lambda = B M^-1 F + quad + stabilization.
  void constraint_forces_function(std::ostringstream& o, const std::string& stabilization) const;
  void initial_state_function(std::ostringstream& o) const;
  void diagnostics(std::ostringstream& o) const;
  void reactions_function(std::ostringstream& o) const;

  mbrt::Scheme scheme_kind() const { return a_.step.scheme; }
  // The enumerator's name in generated code: staggered_pcst, ...
  std::string scheme_identifier() const {
    std::string s(mbrt::scheme_name(scheme_kind()));
    std::replace(s.begin(), s.end(), '-', '_');
    return s;
  }

  // emit_io.cpp: inputs (State::inputs, applied as loads) and outputs().
  bool has_contacts() const { return !a_.contacts.empty(); }
  void contact_declarations(std::ostringstream& o) const;  // kContacts, namespace contact
  void contact_members(std::ostringstream& o) const;       // struct Model's contact data and body views
  std::string contact_names() const;
  int contact_sweeps() const;
  std::string contact_groups() const;  // struct Model's kContactGroups
  void mechanism_kernels(std::ostringstream& o) const;  // jacobian_times_in, solve_in, subtract_constraint_forces_in
  void displace_function(std::ostringstream& o) const;  // positions moved by [dr; rotation vector] per body
  bool has_inputs() const { return !m_.inputs.empty(); }
  bool has_outputs() const { return !m_.outputs.empty(); }
  void input_declarations(std::ostringstream& o) const;   // index constants, ranges, safe values
  void output_declarations(std::ostringstream& o) const;  // one flat array; each signal's first index and count
  int output_value_count() const;                         // kOutputs: the values of all signals
  std::string input_target(const Input& in) const;
  std::string output_source(const Output& out) const;
  bool revolute_output(const Output& out) const;
  std::string output_layout(const Output& out) const;
  void joint_axis_load(std::ostringstream& o, bool force, int body1, int body2, const std::string& value,
                       const std::string& axis, const std::string& s1, const std::string& s2, int node1 = -1,
                       int node2 = -1) const;
  void input_load(std::ostringstream& o, const Input& in, const InputPlan& p) const;
  void outputs_function(std::ostringstream& o) const;

  // emit_staggered.cpp
  std::string stabilization_term() const;  // of S lambda = B M^-1 F + quad + stabilization
  void explicit_stage_function(std::ostringstream& o) const;
  // staggered-pcst's position stage (RATTLE's position step) after the drift.
  bool rattle() const { return a_.step.position_stage; }
  void position_stage_constants(std::ostringstream& o) const;
  // Newton steps of the position stage. staggered4's symmetry, which keeps
  // its energy from drifting, holds only as far as the stage converges: on
  // the heavy top at 1 ms two steps let the energy drift 1.3e-4 J/s, four
  // keep it bounded with |Phi| at 8e-13, six reach round-off (1e-15;
  // docs/schemes.md, "staggered4").
  int position_iterations() const { return scheme_kind() == Scheme::staggered4 ? 6 : 2; }
  void triple_jump_constants(std::ostringstream& o) const;  // staggered4's substeps
  void correct_positions_function(std::ostringstream& o) const;  // blajer
  void newton_matrix_type(std::ostringstream& o) const;  // emit_newton.cpp
  void newton_matrix(std::ostringstream& o) const;
  void staggered_stages(std::ostringstream& o) const;
  // staggered-tree (emit_tree.cpp)
  bool tree_scheme() const;
  bool runge_kutta_tree() const;  // rk4-tree or rk8-tree: the stages' slopes in the Workspace
  std::string tree_step_name() const;  // the template in include/mbrt/schemes/tree.hpp
  std::string step_function() const;   // the step's template in include/mbrt/schemes/
  std::string step_header() const;     // and its header there
  bool tree_external_loads() const;
  // solver.body_states: on_demand (tree schemes only; the analysis checks).
  bool body_states_on_demand() const { return m_.solver.body_states_on_demand; }
  std::string refresh_bodies_comment() const;
  std::string refresh_bodies_function() const;
  void tree_types(std::ostringstream& o) const;  // kDofs, Dofs, HalfAngles
  int tree_dofs() const { return static_cast<int>(a_.tree_frames.frames.size()); }
  void tree_kernels(std::ostringstream& o) const;
  std::vector<Expr> tree_recursion(const TreeRecursionTerms& terms) const;  // into StraightLine::current()
  // Joint friction in the tree (docs/friction.md): the frames of the joints
  // with friction, in the model's joint order; their constants and kernel.
  std::vector<size_t> friction_frames() const;
  void friction_constants(std::ostringstream& o) const;  // in struct Model
  void friction_response_kernel(std::ostringstream& o) const;
  // emit_friction.cpp: joint friction in both families. The model's joints
  // with friction, in its order; their names, quoted ("a", "b"); the
  // header's kFrictionJoints and namespace friction; struct Model's limits
  // and transverse loads; the absolute schemes' rows and columns.
  std::vector<int> friction_joints() const;
  std::string friction_joint_names() const;
  void friction_declarations(std::ostringstream& o) const;
  void friction_limits(std::ostringstream& o) const;
  void friction_loads_function(std::ostringstream& o) const;
  void absolute_friction_members(std::ostringstream& o) const;

  // emit_planar.cpp: namespace planar { ... step(s) } from a planar emitter.
  void planar_stages(std::ostringstream& o) const;
  void planar_constants(std::ostringstream& o) const;
  void planar_types(std::ostringstream& o) const;  // in the header's detail::planar
  void planar_velocity_helpers(std::ostringstream& o) const;
  void planar_explicit_stage(std::ostringstream& o) const;  // kick and drift
  void planar_force_load(std::ostringstream& o, const Force& f, const std::string& n) const;
  void store_multipliers(std::ostringstream& o) const;

  // emit_nps.cpp: the tree elimination (a_.tree) and the cut rows.
  bool nps_cuts() const { return a_.tree.cut_rows > 0; }
  // Body i's mass in the tree kernels: TreeSystem keeps the step's parameters
  // where masses are tunable (factorize_tree copies them from the state).
  std::string tree_mass(int i) const { return mass_of(i, "t.params"); }
  std::vector<std::string> null_space_columns(const TreeBody& tb) const;
  bool carries_parent_axes(const TreeBody& tb) const;
  std::string h_transpose_times(const TreeBody& tb, const std::string& x) const;
  std::string h_times(const TreeBody& tb, const std::string& z) const;
  void nps_workspace(std::ostringstream& o) const;  // TreeSystem, in the header
  void nps_factorize(std::ostringstream& o) const;
  void nps_tree_solve(std::ostringstream& o, bool with_targets) const;
  void nps_tree_multipliers(std::ostringstream& o) const;
  bool free_leaf(const TreeBody& tb) const;
  std::string ia_times(const TreeBody& tb, const std::string& x) const;
  std::string ia_matrix(const TreeBody& tb) const;
  void nps_cut_rows(std::ostringstream& o) const;
  void nps_stages(std::ostringstream& o) const;

  // emit_ali3p.cpp. Generalized-alpha keeps M^-1 (B^T lambda - F) of the last step.
  bool ali3p_weighted() const { return scheme_kind() == Scheme::ali3p && a_.ali3p.delta_f != 0.0; }
  void ali3p_constants(std::ostringstream& o) const;
  void ali3p_stages(std::ostringstream& o) const;
};

}  // namespace mbrt::codegen
