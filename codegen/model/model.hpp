// The validated model as the generator sees it. Everything is in SI units and
// world axes at t = 0, exactly as written in the model file; frames in body
// axes are derived later by the analysis.
#pragma once

#include <array>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include <mbrt/scheme.hpp>
#include <mbrt/piecewise_function.hpp>

#include "driver_types.hpp"
#include "force_types.hpp"
#include "input_types.hpp"
#include "joint_types.hpp"
#include "output_types.hpp"

namespace mbrt::codegen {

// Where a value came from, for error messages: "file:line:column".
struct SourceLocation {
  std::string file;
  int line = 0;    // 1-based, 0 when unknown
  int column = 0;  // 1-based, 0 when unknown
};

// A model file that cannot be used. what() reads
// "<file>:<line>:<column>: <key>: <what was expected>".
class ModelError : public std::runtime_error {
 public:
  ModelError(const SourceLocation& where, const std::string& key, const std::string& message);
  const SourceLocation& where() const noexcept { return where_; }
  const std::string& key() const noexcept { return key_; }

 private:
  SourceLocation where_;
  std::string key_;
};

constexpr int kGround = -1;  // body index of the fixed world body "ground"

struct Body {
  std::string name;
  SourceLocation where;
  double mass = 0.0;
  bool particle = false;
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the COM, body axes (zero for particles)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector4d orientation{1.0, 0.0, 0.0, 0.0};    // e0..e3, body to world
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  // body axes
};

// Coulomb friction in a revolute or prismatic joint (docs/friction.md): the
// limit on its friction torque (N m) or force (N) is a constant plus a
// multiple of the joint's transverse reaction force, the kinetic pair while
// it slides, the static pair (each >= the kinetic one) while at rest.
// Constant friction sets the constants; load-dependent friction the
// multiples, mu * radius (revolute, m) or mu (prismatic).
struct JointFriction {
  double kinetic = 0.0, static_limit = 0.0;
  double kinetic_per_load = 0.0, static_per_load = 0.0;
  bool any() const { return static_limit > 0.0 || static_per_load > 0.0; }
  bool load_dependent() const { return static_per_load > 0.0; }
};

struct Joint {
  std::string name;
  SourceLocation where;
  JointType type = JointType::spherical;
  int body1 = kGround;
  int body2 = kGround;
  int node1 = -1, node2 = -1;  // spherical, distance, revolute, universal, fixed, prismatic: a modal body's node (NAME@K), else -1
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // world, t = 0 (all but distance)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   // unit, world (revolute, cylindrical, prismatic, screw; planar: normal)
  Eigen::Vector3d axis1 = Eigen::Vector3d::UnitX();  // unit, world (universal, fixed in body 1)
  Eigen::Vector3d axis2 = Eigen::Vector3d::UnitY();  // unit, world (universal, fixed in body 2)
  Eigen::Vector3d point1 = Eigen::Vector3d::Zero();  // world (distance)
  Eigen::Vector3d point2 = Eigen::Vector3d::Zero();  // world (distance)
  double length = 0.0;                               // distance: given, or |point2 - point1|
  double lead = 0.0;                                 // screw: translation per turn along +axis, m (non-zero)
  // revolute, prismatic: a rotor's inertia reflected through its gear,
  // N^2 J_rotor (kg m^2; prismatic: kg), felt by the joint coordinate alone.
  double armature = 0.0;
  JointFriction friction;  // revolute, prismatic
  double radius = 0.0;                               // rolling_disk, rolling_ball, m
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();     // knife_edge: unit, world at t = 0, fixed in the body
  Eigen::Vector3d plane_point = Eigen::Vector3d::Zero();    // rolling_disk, rolling_ball: a point of the ground plane
  Eigen::Vector3d plane_normal = Eigen::Vector3d::UnitZ();  // contacts, velocity_toward: unit, world
  // rolling_ball: the sphere's centre (world, t = 0) is `point`, default the COM.
};

// One piece of a piecewise f(t): sum c[k] t^k plus harmonic terms, for
// t < until (the last piece: to the end of time).
struct FunctionPiece {
  double until = std::numeric_limits<double>::infinity();
  std::vector<double> polynomial;
  std::vector<mbrt::Harmonic> harmonics;  // amplitude sin(omega t + phase)
};

// f(t) of a driver: a polynomial sum c[k] t^k, offset + amplitude sin(omega
// t + phase), or (pieces non-empty) pieces, each valid until its time.
struct TimeFunction {
  bool is_sine = false;
  std::vector<double> polynomial;
  double amplitude = 0.0, omega = 0.0, phase = 0.0, offset = 0.0;
  std::vector<FunctionPiece> pieces;
  bool piecewise() const { return !pieces.empty(); }
};

struct Driver {
  std::string name;
  SourceLocation where;
  DriverType type = DriverType::joint_angle;
  int joint = -1;       // joint_angle, joint_distance: Model::joints index
  int body1 = kGround;  // distance
  int body2 = kGround;
  Eigen::Vector3d point1 = Eigen::Vector3d::Zero();
  Eigen::Vector3d point2 = Eigen::Vector3d::Zero();
  TimeFunction function;
};

struct Force {
  ForceType type = ForceType::force;
  SourceLocation where;
  int body1 = kGround;  // spring_damper, torque, joint_spring (the joint's)
  int body2 = kGround;  // spring_damper, torque, joint_spring (the joint's)
  int body = kGround;   // force
  int joint = -1;       // joint_spring: Model::joints index
  Eigen::Vector3d point1 = Eigen::Vector3d::Zero();  // spring_damper, world at t = 0
  Eigen::Vector3d point2 = Eigen::Vector3d::Zero();
  double stiffness = 0.0;  // spring_damper N/m; joint_spring N m/rad or N/m
  double damping = 0.0;    // spring_damper N s/m; joint_spring N m s/rad or N s/m
  double rest_length = 0.0;
  double rest = 0.0;       // joint_spring: joint coordinate of zero force, rad or m from t = 0
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   // torque: unit, world at t = 0, fixed in body 1
  double value = 0.0;                                // torque
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // force: world at t = 0, fixed in body
  Eigen::Vector3d vector = Eigen::Vector3d::Zero();  // force: world, constant
  // A modal body's node K that the force, or the spring_damper's or torque's
  // end, acts at (NAME@K); -1: a point fixed in the body (a torque: the body).
  int node = -1, node1 = -1, node2 = -1;
};

// A unilateral frictional contact of one body with a fixed plane
// (docs/contact.md): a body point (point_contact) or a sphere fixed in the
// body (sphere_contact) that may touch the plane, push on it, never pull, and
// slide or stick under Coulomb friction, static and kinetic coefficients.
enum class ContactType { point, sphere };

struct Contact {
  std::string name;
  SourceLocation where;
  ContactType type = ContactType::point;
  int body = kGround;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();         // world at t = 0: the body point, or the sphere's centre
  double radius = 0.0;                                     // sphere_contact, m
  Eigen::Vector3d plane_point = Eigen::Vector3d::Zero();   // world
  Eigen::Vector3d plane_normal = Eigen::Vector3d::UnitZ(); // unit, world, pointing out of the ground
  double mu_static = 0.0, mu_kinetic = 0.0;                // mu_static >= mu_kinetic >= 0
  double restitution = 0.0;                                // Newton's coefficient, 0..1
};

struct Input {
  std::string name;
  SourceLocation where;
  InputType type = InputType::joint_torque;
  int joint = -1;                                   // joint_torque, joint_force: Model::joints index
  int body1 = kGround;                              // motor_torque
  int body2 = kGround;
  int node1 = -1, node2 = -1;                       // motor_torque at a modal body's node (NAME@K); -1: the body
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // motor_torque: unit, world at t = 0, fixed in body1
  double min = 0.0, max = 0.0, safe = 0.0;          // accepted range; value when commands are stale
};

struct Output {
  std::string name;
  SourceLocation where;
  OutputType type = OutputType::joint_position;
  int joint = -1;     // joint_position, joint_velocity
  int body = kGround; // body_pose, body_velocity
  int contact = -1;   // contact_force, contact_stuck: Model::contacts index
  int node = -1;      // body_pose, body_velocity of a modal body's node K (NAME@K); -1: its frame
};

// ali3p (docs/ali3p.md): index-3 augmented Lagrangian with projections.
struct Ali3pSettings {
  // Penalty of every constraint; 0 picks the default that puts the
  // tangent's shift 1/(c alpha) at relative_shift times S's largest diagonal
  // entry.
  double alpha = 0.0;
  double relative_shift = 1.0e-6;
  std::vector<std::pair<std::string, double>> alpha_of;  // per joint or driver name
  SourceLocation alpha_of_where;
  int newton_iterations = 3;
  bool cuadrado_projection = false;  // projection: bayo (P = M, w = 1) or cuadrado (P + w B^T alpha B = tangent)
  int projection_iterations = 1;
  bool generalized_alpha = false;  // integrator: trapezoidal or generalized_alpha
  double rho_inf = 0.8;            // generalized_alpha: spectral radius at infinite frequency
};

struct SolverSettings {
  mbrt::Scheme scheme = mbrt::Scheme::staggered_pcst;
  bool scheme_given = false;  // by the file or --scheme; else default_scheme() decides
  double step = 1.0e-3;
  int euler_updates = 2;
  // staggered-pcst: regularization of S relative to its largest diagonal
  // entry at t = 0, and the decay rate of position violations (1/s; 0 picks
  // the default from the step, see docs/staggered-pcst.md).
  double penalty = 1.0e-10;
  double stabilization = 0.0;
  // baumgarte: gains of phi'' + 2 alpha phi' + beta^2 phi = 0 (1/s; 0 picks
  // the default 1/(10 h), see docs/schemes.md).
  double baumgarte_alpha = 0.0;
  double baumgarte_beta = 0.0;
  // blajer: mass-orthogonal position corrections after each step.
  int corrections = 1;
  Ali3pSettings ali3p;
  // The parallel step's subsystems, each on its own thread (docs/parallel.md).
  int parallel_parts = 1;
  SourceLocation parallel_parts_where;
  int parallel_min_rows = -1;  // constraint rows per part below which the step stays serial; -1: the default
  // The interface's Schur complement: factorized ("direct"), or solved by a
  // fixed number of preconditioned conjugate-gradient iterations ("pcg"; 0:
  // as many as the interface has rows) with a "block" (each interface block's
  // diagonal block) or "diagonal" preconditioner.
  std::string parallel_interface = "direct";
  int pcg_iterations = 0;
  std::string pcg_preconditioner = "block";
  // The tree schemes: form every body's world state (s.rigid) at the end of
  // each step, or only when refresh_bodies() or a tool asks for it
  // (docs/staggered-tree.md, "Body states on demand").
  bool body_states_on_demand = false;
  SourceLocation body_states_where;
};

// An entry of the model's `tunable:` list (docs/parameters.md), as written.
struct TunableKey {
  std::string key;  // "gravity", "upper_arm.mass", "pin.spring.stiffness", ...
  SourceLocation where;
};

// A flexible body as a nodal beam (docs/flexible.md): nodes are bodies
// named NAME_nK (K = 0 at the root to `elements` at the tip, referred to as
// NAME@root, NAME@tip or NAME@K), joined by beam elements. The beam runs
// along the body x axis from `position`; y and z are its bending axes.
struct BeamSection {
  double EA = 0.0, GAy = 0.0, GAz = 0.0, GJ = 0.0, EIy = 0.0, EIz = 0.0;  // N, N m^2
  double damping = 0.0;  // s: stiffness-proportional
};

struct FlexibleBody {
  std::string name;
  int first_node = 0;  // Model::bodies index of the root node; the others follow
  int elements = 0;
};

// One element of a nodal beam between two node bodies, through their centres
// of mass; y is its bending axis `normal` (world, t = 0).
struct BeamElementSpec {
  int body1 = kGround, body2 = kGround;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();
  BeamSection section;
};

// A modal body's structure read from a file (docs/flexible.md, "Modal data
// from a file"): nodes with lumped mass in the file's axes, and either a
// stiffness matrix and the nodes it is clamped at, or its modes.
struct ModalNodeData {
  std::string name;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // file axes and origin
  double mass = 0.0;
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the node; with 6 coordinates
};

struct ModalStructure {
  std::string file;     // as given, for messages
  int coordinates = 6;  // per node: x, y, z, then small rotations about x, y, z when 6
  std::vector<ModalNodeData> nodes;
  std::vector<int> clamped;      // nodes the modes hold still; joints attach there
  Eigen::MatrixXd stiffness;     // coordinates * nodes, square; empty when the modes are given
  Eigen::VectorXd frequencies;   // given modes: rad/s, ascending
  Eigen::MatrixXd shapes;        // given modes: coordinates * nodes x modes
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // the nodes' centre of mass: the frame's origin
  // Geometric stiffness per load case, over the file's coordinates (empty:
  // not given), cases as kGeometricStiffnessCases names them.
  std::array<Eigen::MatrixXd, 9> geometric_stiffness;
  bool spin_stiffens() const {
    for (int k = 0; k < 6; ++k) {
      if (geometric_stiffness[static_cast<size_t>(k)].size() > 0) return true;
    }
    return false;
  }
  // Node k's undeformed place from the frame's origin, the file's axes.
  Eigen::Vector3d node_place(int k) const { return nodes[static_cast<size_t>(k)].position - centre; }
};

// Node k of a beam of `elements` elements and `length` m, from its centre (the
// frame's origin) along its x axis: the root at -length / 2.
inline Eigen::Vector3d beam_node_place(double length, int elements, int k) {
  return {length * (static_cast<double>(k) / elements - 0.5), 0, 0};
}

// A structure's geometric stiffness load cases (docs/flexible.md): per
// w_a w_b of a spin about the file's origin, then per m/s^2 of its
// acceleration along its axes. The step's order (include/mbrt/modal_body.hpp).
inline constexpr std::array<const char*, 9> kGeometricStiffnessCases = {
    "spin_xx", "spin_yy", "spin_zz", "spin_xy", "spin_xz", "spin_yz", "acceleration_x", "acceleration_y", "acceleration_z"};

// A flexible body as a modal body (docs/flexible.md): the body `body` is the
// frame (the undeformed body's centre of mass), carrying `modes` modes of
// either a uniform beam clamped at its root (body point (-length / 2, 0, 0);
// its lowest bending and axial modes from `elements` finite elements), or a
// structure from a file.
inline constexpr int kMaxModes = 6;  // a modal body's modes kept, at most
// A node's 6 coordinates: displacements, then small rotations.
inline constexpr std::array<const char*, 6> kNodeCoordinateNames = {"x", "y", "z", "rx", "ry", "rz"};

struct ModalSource {
  int body = kGround;
  int modes = 0;
  double length = 0.0, EA = 0.0, GJ = 0.0, EIy = 0.0, EIz = 0.0, rho_A = 0.0, rho_J = 0.0;
  double damping = 0.0;  // beam: s, stiffness-proportional
  int elements = 0;
  std::vector<int> static_loads;  // coordinates (6 a node; a structure's, its own) whose unit loads' static shapes join the modes
  std::optional<ModalStructure> structure;  // instead of the beam
  double damping_ratio = 0.0;               // structure: of critical, every mode
  int nodes() const { return structure ? static_cast<int>(structure->nodes.size()) : elements + 1; }
  Eigen::Vector3d node_place(int k) const { return structure ? structure->node_place(k) : beam_node_place(length, elements, k); }
};

struct Model {
  std::string name;
  std::string file;  // path as given, for messages
  std::optional<Eigen::Vector3d> gravity;
  std::vector<Body> bodies;  // "ground" is not listed; it is kGround
  std::vector<Joint> joints;
  std::vector<Contact> contacts;  // listed under joints: in the file
  std::vector<Force> forces;
  std::vector<FlexibleBody> flexible;
  std::vector<BeamElementSpec> beam_elements;  // of the flexible bodies, in their order
  std::vector<ModalSource> modal;              // the modal bodies
  std::vector<Driver> drivers;
  std::vector<Input> inputs;
  std::vector<Output> outputs;
  SolverSettings solver;
  std::vector<TunableKey> tunable;  // kept as runtime parameters; everything else is folded

  const std::string& body_name(int index) const;  // "ground" for kGround
  // The file's name without its directory, for generated files: they must not
  // depend on where the model was generated from.
  std::string file_name() const;
};

// A revolute or prismatic joint's rate at t = 0 from its bodies' velocities
// in the file: body 2's turn about (slide along) the axis relative to body 1.
double joint_rate_at_start(const Model& model, const Joint& joint);

// Reads and validates a model file. Throws ModelError naming the file, line,
// key and what was expected.
Model load_model(const std::string& path);

// A driver function's value and derivatives at t, and one piece's (the
// generation-time evaluations; the step's are generated).
mbrt::TimeValue evaluate(const TimeFunction& f, double t);
mbrt::TimeValue evaluate(const FunctionPiece& piece, double t);

// Same from text (the file name is used for messages only).
Model parse_model(const std::string& yaml_text, const std::string& file_name);

}  // namespace mbrt::codegen
