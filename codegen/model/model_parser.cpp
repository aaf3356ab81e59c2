// Reads a model file (YAML) into a Model and validates it. Every problem is
// reported as a ModelError naming the file, 1-based line and column, the key
// path a user recognizes ("bodies[1].mass") and what was expected.
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Eigenvalues>
#include <yaml-cpp/yaml.h>

#include <mbrt/rotation.hpp>

#include "model.hpp"
#include "parameters.hpp"

namespace mbrt::codegen {

namespace {

const Keys kTopKeys = {"name", "gravity", "bodies", "joints", "forces", "drivers", "inputs", "outputs", "solver", "tunable"};
const Keys kBodyKeys = {"name",        "mass",     "particle", "inertia", "position",
                        "orientation", "velocity", "angular_velocity", "flexible"};
const Keys kFlexibleBodyKeys = {"name", "flexible", "position", "orientation", "velocity", "angular_velocity"};
const Keys kBeamKeys = {"length", "elements", "EA", "GA", "GJ", "EI", "rho_A", "rho_J", "damping", "modes", "static_loads"};
// A modal body from a file (docs/flexible.md, "Modal data from a file").
const Keys kModalFileBodyKeys = {"file", "modes", "damping_ratio", "static_loads"};
const Keys kModalFileKeys = {"coordinates", "nodes", "clamped", "stiffness", "modes", "geometric_stiffness"};
const Keys kModalFileNodeKeys = {"name", "position", "mass", "inertia"};
const Keys kModalFileModeKeys = {"frequency", "shape"};
const Keys kRotationalKeys = {"inertia", "orientation", "angular_velocity"};  // not for particles
const Keys kFunctionKeys = {"polynomial", "sine", "pieces"};
const Keys kSineKeys = {"amplitude", "omega", "phase", "offset"};
const Keys kPieceKeys = {"until", "polynomial", "harmonics"};
const Keys kHarmonicKeys = {"amplitude", "omega", "phase"};
// Fields every generated LCM message has besides the signals.
const Keys kMessageFields = {"utime", "seq", "state_utime", "command_seq", "t"};
const Keys kSolverKeys = {"scheme",        "step",          "euler_updates", "penalty",
                          "stabilization", "baumgarte_alpha", "baumgarte_beta", "corrections",
                          "ali3p",         "parallel_parts", "parallel_min_rows", "parallel_interface",
                          "pcg_iterations", "pcg_preconditioner", "body_states"};
const Keys kAli3pKeys = {"alpha",      "relative_shift",        "alpha_of",   "newton_iterations",
                         "projection", "projection_iterations", "integrator", "rho_inf"};

// A joint's friction: constant Coulomb friction, a torque (revolute) or a
// force (prismatic), one value or a static and a kinetic one; the
// load-dependent keys are refused by name.
const Keys kFrictionKeys = {"torque",        "force",        "static_torque", "kinetic_torque", "static_force",
                            "kinetic_force", "static",       "kinetic",       "radius"};

// point_contact and sphere_contact (docs/contact.md): listed under joints,
// with constraint-free unilateral physics of their own.
const Keys kPointContactKeys = {"name", "type", "body", "point", "plane_point", "plane_normal", "friction", "restitution"};
const Keys kSphereContactKeys = {"name", "type", "body", "radius", "center", "plane_point", "plane_normal", "friction",
                                 "restitution"};
const Keys kContactFrictionKeys = {"static", "kinetic"};
const Keys kContactTypes = {"point_contact", "sphere_contact"};

const Keys kSchemes(mbrt::kSchemeNames.begin(), mbrt::kSchemeNames.end());

// Axes shorter than this cannot be normalized meaningfully.
constexpr double kMinAxisLength = 1e-12;
// Tolerances the file format promises (docs: Euler parameters, universal axes).
constexpr double kUnitNormTolerance = 1e-6;
constexpr double kPerpendicularTolerance = 1e-6;

std::string join(const Keys& words) {
  std::string s;
  for (const auto& w : words) s += (s.empty() ? "" : ", ") + w;
  return s;
}

bool contains(const Keys& words, const std::string& w) {
  return std::find(words.begin(), words.end(), w) != words.end();
}

// Computed numbers (norms, eigenvalues) in messages: enough digits to see a
// 1e-6 deviation from 1, no trailing noise.
std::string format_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

SourceLocation location(const std::string& file, const YAML::Mark& mark) {
  if (mark.is_null()) return {file, 0, 0};
  return {file, mark.line + 1, mark.column + 1};
}

bool is_quoted(const YAML::Node& node) { return node.Tag() == "!"; }

bool decodes_as_number(const YAML::Node& node) {
  double x;
  return node.IsScalar() && !is_quoted(node) && YAML::convert<double>::decode(node, x);
}

// A scalar as echoed in messages: long ones (an indentation slip can swallow
// half the file into one scalar) are cut short.
std::string excerpt(const std::string& s) {
  constexpr std::size_t kMax = 40;
  return s.size() <= kMax ? s : s.substr(0, kMax) + "...";
}

// What the user wrote, for "expected ..., got <describe>".
std::string describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      if (is_quoted(node)) return "the string \"" + excerpt(node.Scalar()) + "\"";
      if (decodes_as_number(node)) return node.Scalar();
      return "'" + excerpt(node.Scalar()) + "'";
    case YAML::NodeType::Sequence:
      return "a list of " + std::to_string(node.size()) + (node.size() == 1 ? " item" : " items");
    case YAML::NodeType::Map:
      return "a map";
    case YAML::NodeType::Null:
    case YAML::NodeType::Undefined:
      break;
  }
  return "an empty value";
}

// A value in the file with its key path and where it is.
struct Value {
  YAML::Node node;
  std::string key;
  SourceLocation where;
};

[[noreturn]] void fail(const Value& v, const std::string& message) {
  throw ModelError(v.where, v.key, message);
}

[[noreturn]] void fail_expected(const Value& v, const std::string& expected) {
  fail(v, "expected " + expected + ", got " + describe(v.node));
}

// Element i of a list, keyed "parent[i]".
Value element(const Value& list, std::size_t i) {
  const YAML::Node item = list.node[i];
  return {item, list.key + "[" + std::to_string(i) + "]", location(list.where.file, item.Mark())};
}

// A YAML map with its key path: rejects unknown, repeated and non-scalar keys
// up front, then hands out values by key.
class Section {
 public:
  Section(const Value& map, const Keys& allowed) : map_(map) {
    if (!map.node.IsMap()) fail_expected(map, "a map with keys " + join(allowed));
    // entry is a lifetime-extended copy: yaml-cpp iterators yield temporaries,
    // so `it->first` would dangle.
    for (const auto& entry : map.node) {
      const YAML::Node key_node = entry.first;
      const YAML::Mark key_mark = key_node.Mark();
      if (!key_node.IsScalar()) {
        fail_expected({key_node, map.key, location(file(), key_mark)}, "a key name");
      }
      const std::string name = key_node.Scalar();
      const SourceLocation key_where = location(file(), key_mark);
      if (!contains(allowed, name)) {
        throw ModelError(key_where, path(name),
                         "unknown key '" + excerpt(name) + "' (expected one of: " +
                             join(allowed) + ")");
      }
      if (const Entry* first = lookup(name)) {
        throw ModelError(key_where, path(name),
                         "duplicate key '" + name + "' (first given at line " +
                             std::to_string(first->key_where.line) + ")");
      }
      // Point at the value when it is on the key's line (e.g. "mass: -1"),
      // else at the key: empty values and block lists start elsewhere.
      const YAML::Mark value_mark = entry.second.Mark();
      const bool same_line = !value_mark.is_null() && value_mark.line == key_mark.line;
      entries_.push_back(
          {name, key_where,
           {entry.second, path(name), same_line ? location(file(), value_mark) : key_where}});
    }
  }

  std::optional<Value> find(const std::string& name) const {
    if (const Entry* e = lookup(name)) return e->value;
    return std::nullopt;
  }

  // A required key; `hint` is appended to the message when it is missing.
  Value get(const std::string& name, const std::string& hint = "") const {
    if (const Entry* e = lookup(name)) return e->value;
    throw ModelError(map_.where, path(name), "missing required key '" + name + "'" + hint);
  }

  // Keys valid somewhere in this kind of map but not for this variant
  // (an axis on a spherical joint): reject rather than silently ignore.
  void restrict_to(const Keys& keys, const std::string& owner) const {
    for (const auto& e : entries_) {
      if (!contains(keys, e.name)) {
        throw ModelError(e.key_where, e.value.key,
                         "key '" + e.name + "' does not apply to " + owner + " (it takes: " +
                             join(keys) + ")");
      }
    }
  }

 private:
  struct Entry {
    std::string name;
    SourceLocation key_where;
    Value value;
  };

  const std::string& file() const { return map_.where.file; }
  std::string path(const std::string& name) const {
    return map_.key.empty() ? name : map_.key + "." + name;
  }
  const Entry* lookup(const std::string& name) const {
    for (const auto& e : entries_) {
      if (e.name == name) return &e;
    }
    return nullptr;
  }

  Value map_;
  std::vector<Entry> entries_;
};

// ---- scalars --------------------------------------------------------------

// A finite number; `expected` names the constraint for type errors too, so a
// string where a positive number belongs says "expected a number > 0".
double read_number(const Value& v, const std::string& expected = "a number") {
  double x = 0.0;
  // Quoted scalars are strings even when they look like numbers.
  if (!v.node.IsScalar() || is_quoted(v.node) || !YAML::convert<double>::decode(v.node, x)) {
    fail_expected(v, expected);
  }
  if (!std::isfinite(x)) fail_expected(v, "a finite number");
  return x;
}

double read_positive(const Value& v) {
  const double x = read_number(v, "a number > 0");
  if (!(x > 0.0)) fail_expected(v, "a number > 0");
  return x;
}

double read_non_negative(const Value& v) {
  const double x = read_number(v, "a number >= 0");
  if (!(x >= 0.0)) fail_expected(v, "a number >= 0");
  return x;
}

// Strict decimal integer: "2.0" and "2.5" are rejected, not truncated.
int read_integer_at_least(const Value& v, int min) {
  const std::string expected = "an integer >= " + std::to_string(min);
  if (!v.node.IsScalar() || is_quoted(v.node)) fail_expected(v, expected);
  const std::string& s = v.node.Scalar();
  int x = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (ec != std::errc() || end != s.data() + s.size() || x < min) fail_expected(v, expected);
  return x;
}

// Only true/false (YAML 1.2): "yes", "on" etc. are more likely typos than intent.
bool read_bool(const Value& v) {
  if (v.node.IsScalar() && !is_quoted(v.node)) {
    const std::string& s = v.node.Scalar();
    if (s == "true" || s == "True" || s == "TRUE") return true;
    if (s == "false" || s == "False" || s == "FALSE") return false;
  }
  fail_expected(v, "true or false");
}

std::string read_string(const Value& v, const std::string& expected = "a name") {
  if (!v.node.IsScalar() || v.node.Scalar().empty()) fail_expected(v, expected);
  return v.node.Scalar();
}

// Model, body and joint names become C++ identifiers in generated code.
std::string read_identifier(const Value& v) {
  const std::string expected =
      "a name matching [a-z][a-z0-9_]* (a lowercase letter, then lowercase letters, digits or _)";
  const std::string s = read_string(v, expected);
  const bool ok = s[0] >= 'a' && s[0] <= 'z' &&
                  std::all_of(s.begin(), s.end(), [](char c) {
                    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
                  });
  if (!ok) fail_expected(v, expected);
  static const Keys cpp_keywords = {
      "alignas", "alignof", "and", "asm", "auto", "bool", "break", "case", "catch", "char", "class", "const",
      "constexpr", "continue", "decltype", "default", "delete", "do", "double", "else", "enum", "explicit",
      "export", "extern", "false", "float", "for", "friend", "goto", "if", "inline", "int", "long", "mutable",
      "namespace", "new", "noexcept", "not", "nullptr", "operator", "or", "private", "protected", "public",
      "register", "return", "short", "signed", "sizeof", "static", "struct", "switch", "template", "this",
      "throw", "true", "try", "typedef", "typeid", "typename", "union", "unsigned", "using", "virtual", "void",
      "volatile", "while", "xor"};
  if (contains(cpp_keywords, s)) fail_expected(v, "a name that is not a C++ keyword, got '" + s + "'");
  return s;
}

std::string read_choice(const Value& v, const Keys& choices) {
  const std::string expected = "one of: " + join(choices);
  if (!v.node.IsScalar() || !contains(choices, v.node.Scalar())) fail_expected(v, expected);
  return v.node.Scalar();
}

// A type named by its table row (joint_types.hpp, ...).
template <typename Row, std::size_t N>
auto read_type(const Value& v, const std::array<Row, N>& table) {
  return *type_named(table, read_choice(v, type_names(table)));
}

// Names must be unique within their kind; `seen` maps each name to the line
// where it was first defined.
void check_unique(const Value& name_value, const std::string& name, const std::string& kind,
                  std::map<std::string, int>& seen) {
  const auto [it, inserted] = seen.emplace(name, name_value.where.line);
  if (!inserted) {
    fail(name_value, "duplicate " + kind + " name '" + name + "' (first defined at line " +
                         std::to_string(it->second) + ")");
  }
}

// ---- vectors --------------------------------------------------------------

// A list of numbers whose length is one of `sizes`.
Eigen::VectorXd read_numbers(const Value& v, const std::vector<std::size_t>& sizes,
                             const std::string& expected) {
  if (!v.node.IsSequence() ||
      std::find(sizes.begin(), sizes.end(), v.node.size()) == sizes.end()) {
    fail_expected(v, expected);
  }
  Eigen::VectorXd x(static_cast<Eigen::Index>(v.node.size()));
  for (std::size_t i = 0; i < v.node.size(); ++i) {
    x(static_cast<Eigen::Index>(i)) = read_number(element(v, i));
  }
  return x;
}

Eigen::Vector3d read_vector3(const Value& v) {
  return read_numbers(v, {3}, "a list of 3 numbers");
}

// A direction: normalized, so only its length being zero is an error.
Eigen::Vector3d read_axis(const Value& v) {
  const Eigen::Vector3d a = read_vector3(v);
  if (!(a.norm() >= kMinAxisLength)) fail(v, "zero-length axis (expected a nonzero direction)");
  return a.normalized();
}

// Euler parameters must already be unit (a typo should not silently become a
// different rotation); within tolerance they are renormalized exactly.
Eigen::Vector4d read_euler_parameters(const Value& v) {
  const Eigen::Vector4d p = read_numbers(v, {4}, "a list of 4 numbers (Euler parameters e0..e3)");
  const double n = p.norm();
  if (!(std::abs(n - 1.0) <= kUnitNormTolerance)) {
    fail(v, "Euler parameters must have unit norm (|p| = " + format_number(n) +
                "); [1, 0, 0, 0] is no rotation");
  }
  return p / n;
}

// [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]; products are the matrix
// entries themselves (J(0,1) = Ixy), not their negatives.
Eigen::Matrix3d read_inertia(const Value& v) {
  const Eigen::VectorXd x = read_numbers(
      v, {3, 6}, "a list of 3 or 6 numbers ([Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz])");
  Eigen::Matrix3d j = Eigen::Matrix3d::Zero();
  j.diagonal() = x.head<3>();
  if (x.size() == 6) {
    j(0, 1) = j(1, 0) = x(3);
    j(0, 2) = j(2, 0) = x(4);
    j(1, 2) = j(2, 1) = x(5);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(j, Eigen::EigenvaluesOnly);
  const double smallest = eig.eigenvalues()(0);  // sorted ascending
  if (!(smallest > 0.0)) {
    fail(v, "inertia is not positive definite (smallest eigenvalue " + format_number(smallest) +
                ")");
  }
  // A rigid body's principal moments obey the triangle inequality
  // (I3 = integral of x^2 + y^2 <= I1 + I2); a larger one belongs to no body
  // and makes the gyroscopic dynamics unphysical.
  const Eigen::Vector3d m = eig.eigenvalues();
  if (m(2) > (m(0) + m(1)) * (1.0 + 1e-9)) {
    fail(v, "inertia belongs to no rigid body: its largest principal moment " + format_number(m(2)) +
                " exceeds the sum of the other two (" + format_number(m(0)) + " + " + format_number(m(1)) +
                "); a thin rod or plate has at most equality");
  }
  return j;
}

// ---- model parts ----------------------------------------------------------

// A beam's node by name: root, tip or K (0 <= K <= elements).
int node_number(const Value& v, const std::string& kind, const std::string& body, const std::string& node, int elements) {
  int k = -1;
  if (node == "root") k = 0;
  else if (node == "tip") k = elements;
  else if (!node.empty() && node.size() < 6 && std::all_of(node.begin(), node.end(), [](char c) { return c >= '0' && c <= '9'; }))
    k = std::stoi(node);
  if (k < 0 || k > elements) {
    fail(v, "unknown node '" + excerpt(node) + "' of " + kind + " '" + body + "' (root, tip or 0 to " + std::to_string(elements) + ")");
  }
  return k;
}

// A flexible body's node: NAME@root, NAME@tip or NAME@K (0 <= K <= elements).
int read_node_ref(const Value& v, const Model& model, const std::string& body, const std::string& node) {
  Keys names;
  for (const FlexibleBody& f : model.flexible) {
    if (f.name == body) return f.first_node + node_number(v, "flexible body", body, node, f.elements);
    names.push_back(f.name);
  }
  fail(v, "'" + excerpt(body) + "' is not a flexible body" +
              (names.empty() ? std::string(" (the model has none)") : " (flexible bodies: " + join(names) + ")"));
}

// The modal body whose frame is body `body`; nullptr for others.
const ModalSource* modal_source(const Model& model, int body) {
  for (const ModalSource& m : model.modal) {
    if (m.body == body) return &m;
  }
  return nullptr;
}

// A structure's node by name or number (0 first), of modal body `body`.
int structure_node(const Value& v, const ModalStructure& st, const std::string& body, const std::string& node) {
  Keys names;
  for (size_t k = 0; k < st.nodes.size(); ++k) {
    if (st.nodes[k].name == node || std::to_string(k) == node) return static_cast<int>(k);
    names.push_back(st.nodes[k].name);
  }
  fail(v, "unknown node '" + excerpt(node) + "' of modal body '" + body + "' (its nodes in " + st.file + ": " + join(names) +
              ", or 0 to " + std::to_string(st.nodes.size() - 1) + ")");
}

// A modal body's node: a beam's root, tip or K (0 <= K <= elements), a
// structure's node by name or number (0 first); the body in `body`; -1 when
// `name` is not a modal body.
int read_modal_node(const Value& v, const Model& model, const std::string& name, const std::string& node, int& body) {
  for (const ModalSource& source : model.modal) {
    if (model.bodies[static_cast<size_t>(source.body)].name != name) continue;
    body = source.body;
    if (!source.structure) return node_number(v, "modal body", name, node, source.elements);
    return structure_node(v, *source.structure, name, node);
  }
  return -1;
}

// A torque at a modal body's node (`what`: a torque, or a joint's) turns its
// modes through the node's small rotations, which a structure of 3
// coordinates a node does not have.
void check_node_turns(const Value& v, const Model& model, int body, int node, const std::string& what = "a torque") {
  if (node < 0) return;
  const ModalSource& source = *modal_source(model, body);
  if (!source.structure || source.structure->coordinates == 6) return;
  fail(v, "node '" + source.structure->nodes[static_cast<size_t>(node)].name + "' of modal body '" + model.body_name(body) +
              "' has no rotations (coordinates: 3 in " + source.structure->file + "): " + what +
              " there would reach only its frame; give 6 coordinates a node");
}

// "ground" or a declared body; returns kGround or the index in model.bodies.
// With `node`, a modal body's node is taken too (NAME@K: the body, and K in
// *node; -1 for a body itself); without, only joints' places: its root.
int read_body_ref(const Value& v, const Model& model, int* node = nullptr) {
  Keys names = {"ground"};
  for (const auto& b : model.bodies) names.push_back(b.name);
  const std::string s = read_string(v, "a body name (" + join(names) + ")");
  if (node) *node = -1;
  if (s == "ground") return kGround;
  if (const auto at = s.find('@'); at != std::string::npos) {
    const std::string name = s.substr(0, at);
    int body = kGround;
    const int k = read_modal_node(v, model, name, s.substr(at + 1), body);
    if (k >= 0 && !node) {
      const bool beam = !modal_source(model, body)->structure;
      fail(v, "'" + name + "' is a modal body: name it, and this attaches " +
                  (beam ? "at its root" : "at one of its clamped nodes' places") +
                  " (joints, forces, torques, spring_dampers, motor_torque inputs and outputs take " + name + (beam ? "@tip or " + name + "@K)" : "@NODE)"));
    }
    if (k >= 0) {
      *node = k;
      return body;
    }
    return read_node_ref(v, model, name, s.substr(at + 1));
  }
  for (std::size_t i = 0; i < model.bodies.size(); ++i) {
    if (model.bodies[i].name == s) return static_cast<int>(i);
  }
  for (const FlexibleBody& f : model.flexible) {
    if (f.name == s) fail(v, "'" + s + "' is a flexible body: name one of its nodes, " + s + "@root, " + s + "@tip or " + s + "@K");
  }
  fail(v, "unknown body '" + excerpt(s) + "' (bodies: " + join(names) + ")");
}

// Where node K of a modal body is at t = 0, world.
Eigen::Vector3d modal_node_place(const Model& model, int body, int k) {
  const Body& b = model.bodies[static_cast<size_t>(body)];
  return b.position + mbrt::rotation_matrix(b.orientation) * modal_source(model, body)->node_place(k);
}

// A modal body's static loads, {NODE: [DIRECTION, ...], ...}: the
// coordinates (a beam's 6 a node: x, y, z, rx, ry, rz; a structure's, its
// own) whose unit loads' static shapes join the modes kept, at most
// kMaxModes in all. A beam's nodes are root, tip or K, a structure's its
// names or numbers.
std::vector<int> read_static_loads(const Value& v, const ModalSource& source, const std::string& body) {
  const ModalStructure* st = source.structure ? &*source.structure : nullptr;
  const std::string expected = std::string("a map of nodes to load directions, such as {") + (st ? "NODE" : "tip") + ": [y, " +
                               (st && st->coordinates == 3 ? "z" : "rz") + "]}";
  if (!v.node.IsMap() || v.node.size() == 0) fail_expected(v, expected);
  if (st && (st->stiffness.size() == 0 || st->clamped.empty())) {
    fail(v, "static_loads need the structure's stiffness and clamped nodes; " + st->file + " gives " +
                (st->stiffness.size() == 0 ? "modes" : "no clamped nodes"));
  }
  const int per_node = st ? st->coordinates : 6;
  const Keys directions(kNodeCoordinateNames.begin(), kNodeCoordinateNames.begin() + per_node);
  std::vector<int> coordinates;
  for (const auto& entry : v.node) {
    const Value key{entry.first, v.key, location(v.where.file, entry.first.Mark())};
    const Value list{entry.second, v.key + "." + entry.first.Scalar(), location(v.where.file, entry.second.Mark())};
    int node = -1;
    if (st) {
      const std::string name = read_string(key, "a node of " + st->file);
      node = structure_node(key, *st, body, name);
      if (std::find(st->clamped.begin(), st->clamped.end(), node) != st->clamped.end()) {
        fail(key, "node '" + name + "' is clamped: a load there does not deform the structure; name another node");
      }
    } else {
      node = node_number(key, "modal body", body, read_string(key, "a node (root, tip or K)"), source.elements);
      if (node == 0) fail(key, "the root is clamped: a load there does not bend the beam; name another node");
    }
    if (!list.node.IsSequence() || list.node.size() == 0) {
      fail_expected(list, st ? "a list of directions (" + join(directions) + ")" : "a list of directions (x, y, z, ry, rz)");
    }
    for (std::size_t i = 0; i < list.node.size(); ++i) {
      const Value item = element(list, i);
      const std::string d = read_choice(item, directions);
      if (!st && d == "rx") fail(item, "rx twists the beam, and its modes leave torsion out; load it along x, y, z, ry or rz");
      const int c = per_node * node + static_cast<int>(std::find(directions.begin(), directions.end(), d) - directions.begin());
      if (std::find(coordinates.begin(), coordinates.end(), c) != coordinates.end()) fail(item, "'" + d + "' given twice for this node");
      coordinates.push_back(c);
    }
  }
  if (source.modes + static_cast<int>(coordinates.size()) > kMaxModes) {
    fail(v, std::to_string(source.modes) + " modes and " + std::to_string(coordinates.size()) + " static loads make " +
                std::to_string(source.modes + static_cast<int>(coordinates.size())) + " modes; a body keeps at most " +
                std::to_string(kMaxModes) + ": keep fewer modes or loads");
  }
  return coordinates;
}

// An optional list (joints, forces): an empty value means none.
bool is_empty_or_list(const Value& v, const std::string& expected) {
  if (v.node.IsNull()) return true;
  if (!v.node.IsSequence()) fail_expected(v, expected);
  return false;
}

Body parse_body(const Value& item, std::map<std::string, int>& names_seen) {
  const Section s(item, kBodyKeys);
  Body b;
  b.where = item.where;
  const Value name = s.get("name");
  b.name = read_identifier(name);
  if (b.name == "ground") {
    fail(name, "'ground' is the reserved name of the fixed world body; choose another name");
  }
  check_unique(name, b.name, "body", names_seen);
  b.mass = read_positive(s.get("mass"));
  if (auto v = s.find("particle")) b.particle = read_bool(*v);
  if (b.particle) {
    // A particle has no rotational state, so rotational data is a mistake.
    for (const auto& key : kRotationalKeys) {
      if (auto v = s.find(key)) {
        fail(*v, "a particle must not have " + key + " (remove it, or set particle: false)");
      }
    }
  } else {
    b.inertia = read_inertia(
        s.get("inertia", " (a rigid body needs [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz];"
                         " set particle: true for a point mass)"));
    if (auto v = s.find("orientation")) b.orientation = read_euler_parameters(*v);
    if (auto v = s.find("angular_velocity")) b.angular_velocity = read_vector3(*v);
  }
  if (auto v = s.find("position")) b.position = read_vector3(*v);
  if (auto v = s.find("velocity")) b.velocity = read_vector3(*v);
  return b;
}

// One or two numbers: the same value in both bending planes, or y and z.
std::pair<double, double> read_pair(const Value& v) {
  if (v.node.IsScalar()) {
    const double x = read_positive(v);
    return {x, x};
  }
  if (!v.node.IsSequence() || v.node.size() != 2) fail_expected(v, "a number > 0 or a list [y, z] of two");
  return {read_positive(element(v, 0)), read_positive(element(v, 1))};
}

// A square, symmetric matrix over a structure's n coordinates (c a node),
// row by row.
Eigen::MatrixXd read_symmetric_matrix(const Value& v, std::size_t n, int c) {
  const std::string row_size = "a row of " + std::to_string(n) + " numbers (" + std::to_string(c) + " per node)";
  if (!v.node.IsSequence() || v.node.size() != n) fail_expected(v, std::to_string(n) + " rows");
  Eigen::MatrixXd m(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) m.row(static_cast<Eigen::Index>(i)) = read_numbers(element(v, i), {n}, row_size).transpose();
  const double largest = m.cwiseAbs().maxCoeff();
  Eigen::Index i = 0, j = 0;
  if ((m - m.transpose()).cwiseAbs().maxCoeff(&i, &j) > 1e-9 * largest) {
    fail(v, "not symmetric: row " + std::to_string(i) + ", column " + std::to_string(j) + " is " + format_number(m(i, j)) +
                ", row " + std::to_string(j) + ", column " + std::to_string(i) + " is " + format_number(m(j, i)));
  }
  return m;
}

// A modal body's structure from its data file (docs/flexible.md, "Modal data
// from a file"); `v` is the model's `file:` entry, a path from the model
// file's directory. Messages name the data file, its line and key.
ModalStructure read_modal_structure(const Value& v, const std::string& model_file) {
  const std::string given = read_string(v, "the modal data file's path");
  std::filesystem::path path(given);
  if (path.is_relative()) path = std::filesystem::path(model_file).parent_path() / path;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(v, "cannot open the modal data file '" + path.string() + "' (not a file)");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(v, "cannot open the modal data file '" + path.string() + "' (" + std::strerror(errno) + ")");
  YAML::Node root;
  try {
    root = YAML::Load(in);
  } catch (const YAML::Exception& e) {
    throw ModelError(location(path.string(), e.mark), "", "invalid YAML: " + e.msg);
  }
  ModalStructure out;
  out.file = path.string();
  const Value top{root, "", {out.file, 1, 1}};
  const Section s(top, kModalFileKeys);
  if (auto c = s.find("coordinates")) {
    out.coordinates = read_integer_at_least(*c, 3);
    if (out.coordinates != 3 && out.coordinates != 6) fail_expected(*c, "3 (translations) or 6 (and small rotations)");
  }
  const int c = out.coordinates;
  const Value nodes = s.get("nodes");
  if (!nodes.node.IsSequence() || nodes.node.size() < 2) fail_expected(nodes, "a list of at least 2 nodes");
  if (c * nodes.node.size() > 1200) fail(nodes, "at most 1,200 coordinates (" + std::to_string(1200 / c) + " nodes)");
  std::map<std::string, int> seen;
  for (std::size_t i = 0; i < nodes.node.size(); ++i) {
    const Section n(element(nodes, i), kModalFileNodeKeys);
    ModalNodeData d;
    const Value name = n.get("name");
    d.name = read_identifier(name);
    check_unique(name, d.name, "node", seen);
    d.position = read_vector3(n.get("position"));
    d.mass = read_non_negative(n.get("mass"));
    if (auto inertia = n.find("inertia")) {
      if (c == 3) fail(*inertia, "a node's inertia turns with its small rotations: give coordinates: 6");
      d.inertia = read_inertia(*inertia);
    }
    out.nodes.push_back(d);
  }
  double mass = 0.0;
  for (const ModalNodeData& d : out.nodes) mass += d.mass, out.centre += d.mass * d.position;
  if (!(mass > 0.0)) fail(nodes, "the nodes carry no mass");
  out.centre /= mass;
  if (auto clamped = s.find("clamped")) {
    if (!clamped->node.IsSequence()) fail_expected(*clamped, "a list of node names");
    for (std::size_t i = 0; i < clamped->node.size(); ++i) {
      const Value name = element(*clamped, i);
      const std::string n = read_string(name, "a node name");
      const auto it = seen.find(n);
      if (it == seen.end()) fail(name, "unknown node '" + excerpt(n) + "'");
      const int k = static_cast<int>(std::find_if(out.nodes.begin(), out.nodes.end(), [&](const ModalNodeData& d) { return d.name == n; }) -
                                     out.nodes.begin());
      if (std::find(out.clamped.begin(), out.clamped.end(), k) != out.clamped.end()) fail(name, "node '" + n + "' is listed twice");
      out.clamped.push_back(k);
    }
  }
  const auto stiffness = s.find("stiffness");
  const auto modes = s.find("modes");
  if (stiffness.has_value() == modes.has_value()) {
    fail(top, "give either stiffness (its modes are computed) or modes (frequencies and shapes), not " +
                  std::string(stiffness ? "both" : "neither"));
  }
  const std::size_t n = static_cast<std::size_t>(c) * out.nodes.size();
  if (auto geometric = s.find("geometric_stiffness")) {
    const Keys cases(kGeometricStiffnessCases.begin(), kGeometricStiffnessCases.end());
    const Section g(*geometric, cases);
    for (std::size_t k = 0; k < cases.size(); ++k) {
      if (auto m = g.find(cases[k])) out.geometric_stiffness[k] = read_symmetric_matrix(*m, n, c);
    }
  }
  if (stiffness) {
    out.stiffness = read_symmetric_matrix(*stiffness, n, c);
    return out;
  }
  if (!modes->node.IsSequence() || modes->node.size() < 1) fail_expected(*modes, "a list of modes");
  out.frequencies.resize(static_cast<Eigen::Index>(modes->node.size()));
  out.shapes.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(modes->node.size()));
  for (std::size_t m = 0; m < modes->node.size(); ++m) {
    const Section mode(element(*modes, m), kModalFileModeKeys);
    const Value frequency = mode.get("frequency");
    const auto k = static_cast<Eigen::Index>(m);
    out.frequencies[k] = 2 * M_PI * read_positive(frequency);  // Hz in the file
    if (m > 0 && out.frequencies[k] < out.frequencies[k - 1]) fail_expected(frequency, "the modes in ascending frequency");
    const Value shape = mode.get("shape");
    if (!shape.node.IsSequence() || shape.node.size() != out.nodes.size()) {
      fail_expected(shape, std::to_string(out.nodes.size()) + " entries, one per node");
    }
    for (std::size_t node = 0; node < out.nodes.size(); ++node) {
      out.shapes.block(static_cast<Eigen::Index>(c * node), k, c, 1) =
          read_numbers(element(shape, node), {static_cast<std::size_t>(c)}, "a list of " + std::to_string(c) + " numbers");
    }
  }
  return out;
}

// A flexible body's placement: where its own origin goes (`position`), how
// its axes turn, and its velocities at t = 0 (angular velocity in its axes).
struct Placement {
  Eigen::Vector4d orientation{1.0, 0.0, 0.0, 0.0};
  Eigen::Vector3d origin = Eigen::Vector3d::Zero(), velocity = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();

  Eigen::Matrix3d R() const { return mbrt::rotation_matrix(orientation); }
  // Places body b at `arm` (its own axes) from the origin, moving rigidly with it.
  void place(Body& b, const Eigen::Vector3d& arm) const {
    const Eigen::Vector3d world = R() * arm;
    b.orientation = orientation;
    b.position = origin + world;
    b.velocity = velocity + (R() * w).cross(world);
    b.angular_velocity = w;
  }
};

Placement read_placement(const Section& s) {
  Placement p;
  if (auto v = s.find("orientation")) p.orientation = read_euler_parameters(*v);
  if (auto v = s.find("position")) p.origin = read_vector3(*v);
  if (auto v = s.find("velocity")) p.velocity = read_vector3(*v);
  if (auto v = s.find("angular_velocity")) p.w = read_vector3(*v);
  return p;
}

// A modal body from a file: one body, its frame at the nodes' centre of
// mass, `position` and `orientation` placing the file's origin and axes.
void parse_modal_file_body(const std::string& name, const Value& item, const Section& s, const Value& data, Model& model) {
  const Section f(data, kModalFileBodyKeys);
  ModalSource source;
  source.body = static_cast<int>(model.bodies.size());
  source.structure = read_modal_structure(f.get("file"), model.file);
  const ModalStructure& st = *source.structure;
  source.modes = read_integer_at_least(f.get("modes"), 1);
  if (source.modes > kMaxModes) fail_expected(f.get("modes"), "at most " + std::to_string(kMaxModes) + " modes");
  if (auto z = f.find("damping_ratio")) source.damping_ratio = read_non_negative(*z);
  if (auto v = f.find("static_loads")) source.static_loads = read_static_loads(*v, source, name);
  Body frame;
  frame.name = name;
  frame.where = item.where;
  frame.inertia.setZero();
  for (const ModalNodeData& d : st.nodes) {
    const Eigen::Vector3d x = d.position - st.centre;
    frame.mass += d.mass;
    frame.inertia += d.mass * (x.squaredNorm() * Eigen::Matrix3d::Identity() - x * x.transpose()) + d.inertia;
  }
  if (!(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(frame.inertia, Eigen::EigenvaluesOnly).eigenvalues()(0) > 1e-12 * frame.inertia.trace())) {
    fail(f.get("file"), "the nodes' mass in " + st.file + " has no inertia about some axis (its nodes lie on one line); "
                        "give nodes inertia (coordinates: 6) or mass off that line");
  }
  read_placement(s).place(frame, st.centre);
  model.bodies.push_back(frame);
  model.modal.push_back(std::move(source));
}

// A body with `flexible:` beam data: its nodes become bodies NAME_n0 ...
// NAME_nN with the beam's mass lumped on them, each carrying its slice's
// inertia, and its elements join neighbouring nodes (docs/flexible.md).
void parse_flexible_body(const Value& item, const Section& s, std::map<std::string, int>& names_seen, Model& model) {
  s.restrict_to(kFlexibleBodyKeys, "a flexible body (its mass and inertia come from the beam)");
  FlexibleBody f;
  const Value name = s.get("name");
  f.name = read_identifier(name);
  check_unique(name, f.name, "body", names_seen);
  if (const Value data = s.get("flexible"); data.node.IsMap() && data.node["file"]) {
    parse_modal_file_body(f.name, item, s, data, model);
    return;
  }
  const Section b(s.get("flexible"), kBeamKeys);
  const double length = read_positive(b.get("length"));
  f.elements = read_integer_at_least(b.get("elements"), 1);
  if (f.elements > 200) fail_expected(b.get("elements"), "at most 200 elements");
  const double rho_A = read_positive(b.get("rho_A"));
  const double rho_J = read_positive(b.get("rho_J"));
  BeamSection section;
  section.EA = read_positive(b.get("EA"));
  section.GJ = read_positive(b.get("GJ"));
  std::tie(section.EIy, section.EIz) = read_pair(b.get("EI"));
  // Shear stiffness: a solid section's kappa G A is about a third of E A.
  section.GAy = section.GAz = section.EA / 3;
  if (auto v = b.find("GA")) std::tie(section.GAy, section.GAz) = read_pair(*v);
  if (auto v = b.find("damping")) section.damping = read_non_negative(*v);
  const Placement placement = read_placement(s);  // position: the root
  if (auto modes = b.find("modes")) {
    // A modal body: one body, the beam's frame at its centre.
    if (auto v = b.find("GA")) fail(*v, "GA is a nodal beam's (a modal body's modes are Euler-Bernoulli); remove it or drop modes");
    ModalSource beam;
    beam.body = static_cast<int>(model.bodies.size());
    beam.modes = read_integer_at_least(*modes, 1);
    beam.length = length, beam.EA = section.EA, beam.GJ = section.GJ, beam.EIy = section.EIy, beam.EIz = section.EIz;
    beam.rho_A = rho_A, beam.rho_J = rho_J, beam.damping = section.damping, beam.elements = f.elements;
    if (beam.modes > kMaxModes) fail_expected(*modes, "at most " + std::to_string(kMaxModes) + " modes");
    if (auto v = b.find("static_loads")) beam.static_loads = read_static_loads(*v, beam, f.name);
    // Six modes converge long before; the modes' eigenproblem grows as the cube.
    if (beam.elements > 60) fail_expected(b.get("elements"), "at most 60 elements for a modal body");
    Body frame;
    frame.name = f.name;
    frame.where = item.where;
    frame.mass = rho_A * length;
    frame.inertia = Eigen::Vector3d(rho_J * length, frame.mass * length * length / 12, frame.mass * length * length / 12).asDiagonal();
    placement.place(frame, Eigen::Vector3d(length / 2, 0, 0));
    model.bodies.push_back(frame);
    model.modal.push_back(beam);
    return;
  }
  if (auto v = b.find("static_loads")) fail(*v, "static_loads shape a modal body's modes; give modes, or remove it for a nodal beam");
  const double l = length / f.elements;
  f.first_node = static_cast<int>(model.bodies.size());
  for (int k = 0; k <= f.elements; ++k) {
    Body node;
    node.name = f.name + "_n" + std::to_string(k);
    node.where = item.where;
    check_unique(name, node.name, "body", names_seen);
    const double slice = (k == 0 || k == f.elements) ? l / 2 : l;
    node.mass = rho_A * slice;
    const double bending = rho_J / 2 * slice + node.mass * slice * slice / 12;
    node.inertia = Eigen::Vector3d(rho_J * slice, bending, bending).asDiagonal();
    placement.place(node, Eigen::Vector3d(k * l, 0, 0));
    model.bodies.push_back(node);
  }
  for (int k = 0; k < f.elements; ++k) model.beam_elements.push_back({f.first_node + k, f.first_node + k + 1, placement.R().col(1), section});
  model.flexible.push_back(f);
}

// A rolling_disk, rolling_ball or knife_edge: a body on the ground plane.
Joint parse_contact(const Section& s, const Model& model, Joint& j) {
  j.body1 = kGround;
  const Value body = s.get("body");
  j.body2 = read_body_ref(body, model);
  if (j.body2 == kGround) fail(body, "the ground cannot touch itself; name a body");
  j.plane_normal = read_axis(s.get("plane_normal"));
  if (j.type == JointType::rolling_disk || j.type == JointType::rolling_ball) {
    j.radius = read_positive(s.get("radius"));
    j.plane_point = read_vector3(s.get("plane_point"));
  }
  if (j.type == JointType::rolling_disk) {
    j.axis = read_axis(s.get("axis"));
  } else if (j.type == JointType::rolling_ball) {
    const auto center = s.find("center");
    j.point = center ? read_vector3(*center) : model.bodies[static_cast<size_t>(j.body2)].position;
  } else {
    j.point = read_vector3(s.get("point"));
    const Value direction = s.get("direction");
    j.direction = read_axis(direction);
    if (!(std::abs(j.direction.dot(j.plane_normal)) < kPerpendicularTolerance)) {
      fail(direction, "the edge direction must lie in the plane (direction . plane_normal = " +
                          format_number(j.direction.dot(j.plane_normal)) + ")");
    }
  }
  return j;
}

// A joint's friction (docs/friction.md), one of three forms:
//   {torque: T} (revolute) or {force: F} (prismatic): constant;
//   {static_torque: Ts, kinetic_torque: Tk} ({static_force, kinetic_force}),
//   Ts >= Tk: constant, the static one at rest;
//   {static: mu_s, kinetic: mu_k, radius: r} (revolute) or {static, kinetic}
//   (prismatic), mu_s >= mu_k: proportional to the transverse reaction,
//   times the pin's radius for a revolute joint (after Lidstrom 2012, "On the
//   equations of motion in constrained multibody dynamics", eqs. 51-53).
JointFriction read_joint_friction(const Value& v, JointType type) {
  const Section s(v, kFrictionKeys);
  const bool revolute = type == JointType::revolute;
  const std::string unit = revolute ? "torque" : "force";
  for (const char* wrong : {"force", "static_force", "kinetic_force", "torque", "static_torque", "kinetic_torque"}) {
    if (std::string(wrong).find(unit) != std::string::npos) continue;
    if (auto x = s.find(wrong)) {
      fail(*x, std::string("a ") + (revolute ? "revolute joint's friction is a torque: friction: {torque: N m}"
                                             : "prismatic joint's friction is a force: friction: {force: N}"));
    }
  }
  // A static and a kinetic value, static >= kinetic >= 0, both given.
  const auto pair = [&](const std::string& static_key, const std::string& kinetic_key, double& stat, double& kin) {
    const auto given_static = s.find(static_key), given_kinetic = s.find(kinetic_key);
    if (!given_static || !given_kinetic) {
      fail(given_static ? *given_static : *given_kinetic, "give both " + static_key + " and " + kinetic_key);
    }
    kin = read_non_negative(*given_kinetic);
    stat = read_non_negative(*given_static);
    if (stat < kin) fail_expected(*given_static, "a number >= " + kinetic_key + " (" + format_number(kin) + ")");
  };
  const std::string static_key = "static_" + unit, kinetic_key = "kinetic_" + unit;
  const std::vector<std::string> forms[] = {{unit}, {static_key, kinetic_key}, {"static", "kinetic", "radius"}};
  int form = -1;
  std::string first_key;
  for (int f = 0; f < 3; ++f) {
    for (const std::string& key : forms[f]) {
      const auto x = s.find(key);
      if (!x) continue;
      if (form >= 0 && form != f) {
        fail(*x, "give one form of friction: " + unit + ", or " + static_key + " and " + kinetic_key +
                     ", or static and kinetic coefficients" + (revolute ? " and a radius" : "") + " (not " + first_key +
                     " and " + key + ")");
      }
      if (form < 0) first_key = key;
      form = f;
    }
  }
  JointFriction out;
  if (form == 0) {
    out.kinetic = out.static_limit = read_non_negative(s.get(unit));
  } else if (form == 1) {
    pair(static_key, kinetic_key, out.static_limit, out.kinetic);
  } else if (form == 2) {
    pair("static", "kinetic", out.static_per_load, out.kinetic_per_load);
    if (revolute) {
      const double radius = read_positive(s.get("radius"));
      out.static_per_load *= radius;
      out.kinetic_per_load *= radius;
    } else if (auto x = s.find("radius")) {
      fail(*x, "a prismatic joint's friction takes no radius: its limit is mu times the transverse reaction force");
    }
  } else {
    fail(v, "expected " + unit + ", or " + static_key + " and " + kinetic_key + ", or static and kinetic" +
                (revolute ? " and radius" : "") + " in the joint's friction");
  }
  return out;
}

// A joint's point: `point`, or where it holds a modal body's node, that
// node's place (both nodes': the same place).
Eigen::Vector3d joint_point(const Section& s, const Model& model, const Joint& j, const Value& body2) {
  if (const auto point = s.find("point")) return read_vector3(*point);
  if (j.node1 < 0 && j.node2 < 0) return read_vector3(s.get("point"));
  const Eigen::Vector3d place = j.node2 >= 0 ? modal_node_place(model, j.body2, j.node2) : modal_node_place(model, j.body1, j.node1);
  if (j.node1 >= 0 && j.node2 >= 0) {
    const double apart = (modal_node_place(model, j.body1, j.node1) - place).norm();
    if (apart > 1e-9 * std::max(1.0, place.norm())) {
      fail(body2, "a " + std::string(type_row(j.type).name) + " joint holds its two nodes together, but they start " +
                      format_number(apart) + " m apart; move the bodies so that they meet, or join them by a distance joint");
    }
  }
  return place;
}

Joint parse_joint(const Value& item, const Model& model, std::map<std::string, int>& names_seen) {
  const Section s(item, every_joint_key());
  Joint j;
  j.where = item.where;
  const Value type = s.get("type");
  Keys types = type_names(kJointTypeTable);
  types.insert(types.end(), kContactTypes.begin(), kContactTypes.end());
  j.type = *type_named(kJointTypeTable, read_choice(type, types));
  s.restrict_to(joint_keys(j.type), "a " + type.node.Scalar() + " joint");
  // A ground contact may go unnamed: it is then "<body>_<type>".
  const bool contact = type_row(j.type).ground_contact;
  const std::optional<Value> given = s.find("name");
  const Value name = given ? *given : contact ? s.get("body") : s.get("name");
  j.name = given ? read_identifier(name) : read_identifier(name) + "_" + type.node.Scalar();
  check_unique(name, j.name, "joint", names_seen);
  if (contact) return parse_contact(s, model, j);

  const Value body1 = s.get("body1");
  j.body1 = read_body_ref(body1, model, &j.node1);
  const Value body2 = s.get("body2");
  j.body2 = read_body_ref(body2, model, &j.node2);
  if (j.body1 == j.body2) {
    fail(body2, "a joint must connect two different bodies (both are '" +
                    model.body_name(j.body1) + "')");
  }
  // A joint holds a modal body's node where it deforms to, and one with axes
  // turns them with its section's small rotations (a prismatic, cylindrical,
  // screw or planar one slides along or across the section's turned axis).
  const bool point_joint = j.type == JointType::spherical || j.type == JointType::distance;
  for (const auto& [value, body, node] : {std::tuple{body1, j.body1, j.node1}, std::tuple{body2, j.body2, j.node2}}) {
    if (node < 0) continue;
    if (j.type == JointType::velocity_toward) {
      const bool beam = !modal_source(model, body)->structure;
      fail(value, "a " + type.node.Scalar() + " joint attaches to modal body '" + model.body_name(body) + "' " +
                      (beam ? "at its root" : "at one of its clamped nodes' places") +
                      ": name the body; a velocity_toward joint does not take one of its nodes");
    }
    if (!point_joint) check_node_turns(value, model, body, node, "a " + type.node.Scalar() + " joint's torque");
  }

  switch (j.type) {
    case JointType::revolute:
    case JointType::cylindrical:
    case JointType::prismatic:
    case JointType::planar:
      j.point = joint_point(s, model, j, body2);
      j.axis = read_axis(s.get("axis"));
      if (auto x = s.find("armature")) j.armature = read_non_negative(*x);
      if (auto x = s.find("friction")) {
        if (j.node1 >= 0 || j.node2 >= 0) {
          fail(*x, "joint '" + j.name + "' holds a modal body's node: friction there is not modelled; drop it, or put the "
                   "joint at the body's root");
        }
        j.friction = read_joint_friction(*x, j.type);
      }
      break;
    case JointType::screw: {
      j.point = joint_point(s, model, j, body2);
      j.axis = read_axis(s.get("axis"));
      const Value lead = s.get("lead");
      j.lead = read_number(lead);
      if (!(std::abs(j.lead) > 0.0)) fail_expected(lead, "a non-zero lead (m per turn)");
      break;
    }
    case JointType::universal: {
      j.point = joint_point(s, model, j, body2);
      j.axis1 = read_axis(s.get("axis1"));
      const Value axis2 = s.get("axis2");
      j.axis2 = read_axis(axis2);
      const double c = j.axis1.dot(j.axis2);
      if (!(std::abs(c) < kPerpendicularTolerance)) {
        fail(axis2, "axis1 and axis2 of a universal joint must be perpendicular (axis1 . axis2 = " +
                        format_number(c) + " after normalizing)");
      }
      break;
    }
    case JointType::distance: {
      // At a modal body's node, its place is the point's default.
      const bool at_node1 = j.node1 >= 0 && !s.find("point1"), at_node2 = j.node2 >= 0 && !s.find("point2");
      j.point1 = at_node1 ? modal_node_place(model, j.body1, j.node1) : read_vector3(s.get("point1"));
      const Value point2 = at_node2 ? body2 : s.get("point2");
      j.point2 = at_node2 ? modal_node_place(model, j.body2, j.node2) : read_vector3(point2);
      if (auto v = s.find("length")) {
        j.length = read_positive(*v);
      } else {
        j.length = (j.point2 - j.point1).norm();
        if (!(j.length > 0.0)) {
          fail(point2, "zero-length distance: point1 and point2 coincide "
                       "(move them apart or give a length > 0)");
        }
      }
      break;
    }
    case JointType::spherical:
    case JointType::fixed:
      j.point = joint_point(s, model, j, body2);
      break;
    case JointType::velocity_toward:
      j.point1 = read_vector3(s.get("point1"));
      j.point2 = read_vector3(s.get("point2"));
      j.plane_normal = read_axis(s.get("plane_normal"));
      break;
    case JointType::rolling_disk:
    case JointType::rolling_ball:
    case JointType::knife_edge:
      break;  // parse_contact
  }
  return j;
}

// A joints: entry that is a point_contact or sphere_contact.
bool is_contact_entry(const Value& item) {
  if (!item.node.IsMap()) return false;
  const YAML::Node type = item.node["type"];
  return type && type.IsScalar() && contains(kContactTypes, type.Scalar());
}

// A point_contact or sphere_contact (docs/contact.md). Unnamed, it is
// "<body>_<type>" like the ground contacts.
Contact parse_unilateral_contact(const Value& item, const Model& model, std::map<std::string, int>& names_seen) {
  Keys every_key = kSphereContactKeys;
  every_key.push_back("point");
  const Section s(item, every_key);
  const Value type = s.get("type");
  const bool sphere = type.node.Scalar() == "sphere_contact";
  s.restrict_to(sphere ? kSphereContactKeys : kPointContactKeys, "a " + type.node.Scalar());
  Contact c;
  c.where = item.where;
  c.type = sphere ? ContactType::sphere : ContactType::point;
  const Value body = s.get("body");
  c.body = read_body_ref(body, model);
  if (c.body == kGround) fail(body, "the ground cannot touch itself; name a body");
  const std::optional<Value> given = s.find("name");
  c.name = given ? read_identifier(*given) : read_identifier(body) + "_" + type.node.Scalar();
  check_unique(given ? *given : body, c.name, "joint", names_seen);
  const Body& b = model.bodies[static_cast<size_t>(c.body)];
  if (sphere) {
    c.radius = read_positive(s.get("radius"));
    const auto center = s.find("center");
    c.point = center ? read_vector3(*center) : b.position;
  } else {
    c.point = read_vector3(s.get("point"));
  }
  c.plane_point = read_vector3(s.get("plane_point"));
  c.plane_normal = read_axis(s.get("plane_normal"));
  if (auto f = s.find("friction")) {
    const Section fs(*f, kContactFrictionKeys);
    const auto given_static = fs.find("static"), given_kinetic = fs.find("kinetic");
    if (!given_static || !given_kinetic) {
      fail(given_static ? *given_static : given_kinetic ? *given_kinetic : *f,
           "give both static and kinetic friction coefficients (static >= kinetic >= 0)");
    }
    c.mu_kinetic = read_non_negative(*given_kinetic);
    c.mu_static = read_non_negative(*given_static);
    if (c.mu_static < c.mu_kinetic) {
      fail_expected(*given_static, "a number >= kinetic (" + format_number(c.mu_kinetic) + ")");
    }
  }
  if (auto e = s.find("restitution")) {
    c.restitution = read_non_negative(*e);
    if (!(c.restitution <= 1.0)) fail_expected(*e, "a number from 0 to 1");
  }
  if (b.particle && sphere) {
    fail(body, "a sphere_contact needs a rigid body ('" + b.name + "' is a particle); use a point_contact");
  }
  return c;
}

// A joint named by `v` whose type is one of `types`; returns its index.
int read_joint_ref(const Value& v, const Model& model, const std::vector<JointType>& types, const std::string& role) {
  const std::string joint_name = read_string(v, "a joint name");
  for (std::size_t i = 0; i < model.joints.size(); ++i) {
    const Joint& j = model.joints[i];
    if (j.name != joint_name) continue;
    if (std::find(types.begin(), types.end(), j.type) == types.end()) {
      std::string names;
      for (JointType t : types) names += (names.empty() ? "" : " or ") + std::string(type_row(t).name);
      fail(v, role + " needs a " + names + " joint; '" + joint_name + "' is not one");
    }
    return static_cast<int>(i);
  }
  fail(v, "unknown joint '" + excerpt(joint_name) + "'");
}

Force parse_force(const Value& item, const Model& model) {
  const Section s(item, every_force_key());
  Force f;
  f.where = item.where;
  const Value type = s.get("type");
  f.type = read_type(type, kForceTypeTable);
  const std::string& type_name = type.node.Scalar();
  s.restrict_to(force_keys(f.type), "a " + type_name + " force");

  if (f.type == ForceType::force) {
    const Value body = s.get("body");
    f.body = read_body_ref(body, model, &f.node);
    if (f.body == kGround) fail(body, "a force must act on a body, not on ground");
    f.point = f.node >= 0 ? modal_node_place(model, f.body, f.node) : model.bodies[static_cast<std::size_t>(f.body)].position;
    if (auto v = s.find("point")) f.point = read_vector3(*v);
    f.vector = read_vector3(s.get("vector"));
    return f;
  }
  if (f.type == ForceType::joint_spring) {
    f.joint = read_joint_ref(s.get("joint"), model, {JointType::revolute, JointType::prismatic}, "a joint_spring force");
    const Joint& j = model.joints[static_cast<std::size_t>(f.joint)];
    f.body1 = j.body1;
    f.body2 = j.body2;
    f.stiffness = read_non_negative(s.get("stiffness"));
    if (auto v = s.find("damping")) f.damping = read_non_negative(*v);
    if (auto v = s.find("rest")) f.rest = read_number(*v);
    return f;
  }

  // spring_damper and torque act between two bodies; on one body they
  // would cancel out, which is never what was meant.
  const bool spring = f.type == ForceType::spring_damper;
  const Value body1 = s.get("body1"), body2 = s.get("body2");
  f.body1 = read_body_ref(body1, model, &f.node1);
  f.body2 = read_body_ref(body2, model, &f.node2);
  if (!spring) check_node_turns(body1, model, f.body1, f.node1), check_node_turns(body2, model, f.body2, f.node2);
  if (f.body1 == f.body2) {
    fail(body2, "a " + type_name + " must connect two different bodies (both are '" +
                    model.body_name(f.body1) + "')");
  }
  if (spring) {
    // A modal body's node is its own place; a point, if given, must be it.
    f.point1 = f.node1 >= 0 ? modal_node_place(model, f.body1, f.node1) : read_vector3(s.get("point1"));
    f.point2 = f.node2 >= 0 ? modal_node_place(model, f.body2, f.node2) : read_vector3(s.get("point2"));
    if (auto v = s.find("point1"); v && f.node1 >= 0) f.point1 = read_vector3(*v);
    if (auto v = s.find("point2"); v && f.node2 >= 0) f.point2 = read_vector3(*v);
    f.stiffness = read_non_negative(s.get("stiffness"));
    if (auto v = s.find("damping")) f.damping = read_non_negative(*v);
    f.rest_length = read_non_negative(s.get("rest_length"));
  } else {
    f.axis = read_axis(s.get("axis"));
    f.value = read_number(s.get("value"));
  }
  return f;
}

std::vector<double> read_coefficients(const Value& v) {
  if (!v.node.IsSequence() || v.node.size() == 0) fail_expected(v, "a non-empty list of coefficients c0, c1, ...");
  std::vector<double> c;
  for (std::size_t i = 0; i < v.node.size(); ++i) c.push_back(read_number(element(v, i)));
  return c;
}

FunctionPiece parse_piece(const Value& v, bool last) {
  const Section s(v, kPieceKeys);
  FunctionPiece piece;
  if (auto until = s.find("until")) {
    if (last) fail(*until, "the last piece runs to the end of time: remove its 'until'");
    piece.until = read_number(*until);
  } else if (!last) {
    fail(v, "missing required key 'until' (every piece but the last ends at a time, s)");
  }
  const auto poly = s.find("polynomial");
  const auto harmonics = s.find("harmonics");
  if (!poly && !harmonics) fail_expected(v, "a piece with a polynomial, harmonics or both");
  if (poly) piece.polynomial = read_coefficients(*poly);
  if (harmonics) {
    if (!harmonics->node.IsSequence() || harmonics->node.size() == 0) {
      fail_expected(*harmonics, "a non-empty list of {amplitude, omega, phase}");
    }
    for (std::size_t i = 0; i < harmonics->node.size(); ++i) {
      const Section h(element(*harmonics, i), kHarmonicKeys);
      mbrt::Harmonic term{0.0, 0.0, 0.0};
      term.amplitude = read_number(h.get("amplitude"));
      term.omega = read_number(h.get("omega"));
      if (auto x = h.find("phase")) term.phase = read_number(*x);
      piece.harmonics.push_back(term);
    }
  }
  return piece;
}

// A driver's prescribed coordinate and its rate must not jump where one piece
// hands over to the next: the constraint would demand an infinite force.
void check_continuity(const Value& pieces, const std::vector<FunctionPiece>& p) {
  for (std::size_t i = 0; i + 1 < p.size(); ++i) {
    const double t = p[i].until;
    const mbrt::TimeValue a = evaluate(p[i], t), b = evaluate(p[i + 1], t);
    const auto differ = [](double x, double y) { return std::abs(x - y) > 1e-6 * std::max({1.0, std::abs(x), std::abs(y)}); };
    const char* what = differ(a.f, b.f) ? "value" : differ(a.df, b.df) ? "rate" : nullptr;
    if (what == nullptr) continue;
    std::ostringstream m;
    m.precision(10);
    m << "pieces " << i << " and " << i + 1 << " give different " << what << "s at t = " << t << " s ("
      << (what[0] == 'v' ? a.f : a.df) << " and " << (what[0] == 'v' ? b.f : b.df)
      << "): a driver's value and rate must be continuous";
    fail(element(pieces, i + 1), m.str());
  }
}

TimeFunction parse_function(const Value& v) {
  const Section s(v, kFunctionKeys);
  TimeFunction f;
  const auto poly = s.find("polynomial");
  const auto sine = s.find("sine");
  const auto pieces = s.find("pieces");
  if (int(poly.has_value()) + int(sine.has_value()) + int(pieces.has_value()) != 1) {
    fail_expected(v, "exactly one of: polynomial, sine, pieces");
  }
  if (poly) {
    f.polynomial = read_coefficients(*poly);
    return f;
  }
  if (pieces) {
    if (!pieces->node.IsSequence() || pieces->node.size() == 0) {
      fail_expected(*pieces, "a non-empty list of pieces {until, polynomial, harmonics}");
    }
    const std::size_t n = pieces->node.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Value item = element(*pieces, i);
      f.pieces.push_back(parse_piece(item, i + 1 == n));
      if (i > 0 && !(f.pieces[i].until > f.pieces[i - 1].until) && i + 1 < n) {
        fail(Section(item, kPieceKeys).get("until"), "pieces must end in increasing time (the piece before ends at " +
                                                         std::to_string(f.pieces[i - 1].until) + " s)");
      }
    }
    check_continuity(*pieces, f.pieces);
    return f;
  }
  const Section p(*sine, kSineKeys);
  f.is_sine = true;
  f.amplitude = read_number(p.get("amplitude"));
  f.omega = read_number(p.get("omega"));
  if (auto x = p.find("phase")) f.phase = read_number(*x);
  if (auto x = p.find("offset")) f.offset = read_number(*x);
  return f;
}

Driver parse_driver(const Value& item, const Model& model, std::map<std::string, int>& names_seen) {
  const Section s(item, every_driver_key());
  Driver d;
  d.where = item.where;
  const Value name = s.get("name");
  d.name = read_identifier(name);
  for (const Joint& j : model.joints) {
    if (j.name == d.name) fail(name, "the name '" + d.name + "' is already used by a joint");
  }
  check_unique(name, d.name, "driver", names_seen);
  const Value type = s.get("type");
  d.type = read_type(type, kDriverTypeTable);
  s.restrict_to(driver_keys(d.type), "a " + type.node.Scalar() + " driver");
  if (d.type == DriverType::distance) {
    d.body1 = read_body_ref(s.get("body1"), model);
    const Value body2 = s.get("body2");
    d.body2 = read_body_ref(body2, model);
    if (d.body1 == d.body2) fail(body2, "a driver must connect two different bodies");
    d.point1 = read_vector3(s.get("point1"));
    const Value point2 = s.get("point2");
    d.point2 = read_vector3(point2);
    if (!((d.point2 - d.point1).norm() > 0.0)) fail(point2, "point1 and point2 coincide: the distance has no direction");
  } else {
    const std::vector<JointType> joints = d.type == DriverType::joint_angle
                                              ? std::vector{JointType::revolute, JointType::cylindrical}
                                              : std::vector{JointType::prismatic, JointType::cylindrical};
    const Value joint = s.get("joint");
    d.joint = read_joint_ref(joint, model, joints, "a " + type.node.Scalar() + " driver");
  }
  d.function = parse_function(s.get("function"));
  return d;
}

Ali3pSettings parse_ali3p(const Value& v) {
  Ali3pSettings a;
  const Section s(v, kAli3pKeys);
  if (auto x = s.find("alpha")) a.alpha = read_positive(*x);
  if (auto x = s.find("relative_shift")) a.relative_shift = read_positive(*x);
  if (auto x = s.find("alpha_of")) {
    if (!x->node.IsMap()) fail_expected(*x, "a map from joint or driver names to penalties");
    a.alpha_of_where = x->where;
    for (const auto& entry : x->node) {
      const YAML::Node key = entry.first;
      const std::string name = key.IsScalar() ? key.Scalar() : "";
      const Value value{entry.second, x->key + "." + name, location(x->where.file, entry.second.Mark())};
      a.alpha_of.emplace_back(name, read_positive(value));
    }
  }
  if (auto x = s.find("newton_iterations")) a.newton_iterations = read_integer_at_least(*x, 1);
  if (auto x = s.find("projection")) a.cuadrado_projection = read_choice(*x, {"bayo", "cuadrado"}) == "cuadrado";
  if (auto x = s.find("projection_iterations")) a.projection_iterations = read_integer_at_least(*x, 1);
  if (auto x = s.find("integrator")) {
    a.generalized_alpha = read_choice(*x, {"trapezoidal", "generalized_alpha"}) == "generalized_alpha";
  }
  if (auto x = s.find("rho_inf")) {
    a.rho_inf = read_non_negative(*x);
    if (a.rho_inf > 1.0) fail_expected(*x, "a spectral radius in [0, 1]");
  }
  return a;
}

// Inputs and outputs share one namespace of signal names (they become
// message fields), which excludes the messages' own fields.
void check_signal_name(const Value& name_value, const std::string& name, std::map<std::string, int>& seen) {
  if (contains(kMessageFields, name)) {
    fail(name_value, "'" + name + "' is a field of every message (reserved: " + join(kMessageFields) + ")");
  }
  check_unique(name_value, name, "input or output", seen);
}

// The name and type every input and output starts with; returns the type as written.
template <typename Row, std::size_t N, typename Enum>
std::string read_signal_head(const Section& s, const std::array<Row, N>& types, std::map<std::string, int>& names_seen,
                             std::string& name, Enum& type) {
  const Value name_value = s.get("name");
  name = read_identifier(name_value);
  check_signal_name(name_value, name, names_seen);
  const Value type_value = s.get("type");
  type = read_type(type_value, types);
  return type_value.node.Scalar();
}

Input parse_input(const Value& item, const Model& model, std::map<std::string, int>& names_seen) {
  const Section s(item, every_input_key());
  Input in;
  in.where = item.where;
  const std::string type_name = read_signal_head(s, kInputTypeTable, names_seen, in.name, in.type);
  s.restrict_to(input_keys(in.type), "a " + type_name + " input");
  if (in.type == InputType::motor_torque) {
    const Value body1 = s.get("body1"), body2 = s.get("body2");
    in.body1 = read_body_ref(body1, model, &in.node1);
    in.body2 = read_body_ref(body2, model, &in.node2);
    check_node_turns(body1, model, in.body1, in.node1), check_node_turns(body2, model, in.body2, in.node2);
    if (in.body1 == in.body2) fail(body2, "a motor_torque must connect two different bodies");
    in.axis = read_axis(s.get("axis"));
  } else {
    const std::vector<JointType> joints = in.type == InputType::joint_torque
                                              ? std::vector{JointType::revolute, JointType::cylindrical}
                                              : std::vector{JointType::prismatic, JointType::cylindrical};
    in.joint = read_joint_ref(s.get("joint"), model, joints, "a " + type_name + " input");
  }
  in.min = read_number(s.get("min"));
  const Value max = s.get("max");
  in.max = read_number(max);
  if (!(in.max > in.min)) fail_expected(max, "a number > min (" + format_number(in.min) + ")");
  const Value safe = s.get("safe");
  in.safe = read_number(safe);
  if (!(in.safe >= in.min && in.safe <= in.max)) {
    fail_expected(safe, "a number within [min, max] = [" + format_number(in.min) + ", " + format_number(in.max) + "]");
  }
  return in;
}

Output parse_output(const Value& item, const Model& model, std::map<std::string, int>& names_seen) {
  const Section s(item, every_output_key());
  Output out;
  out.where = item.where;
  const std::string type_name = read_signal_head(s, kOutputTypeTable, names_seen, out.name, out.type);
  s.restrict_to(output_keys(out.type), "a " + type_name + " output");
  if (out.type == OutputType::joint_friction || out.type == OutputType::joint_stuck) {
    const Value joint = s.get("joint");
    out.joint = read_joint_ref(joint, model, {JointType::revolute, JointType::prismatic}, "a " + type_name + " output");
    const Joint& j = model.joints[static_cast<size_t>(out.joint)];
    if (!j.friction.any()) {
      fail(joint, "joint '" + j.name + "' has no friction; give it friction: {torque: N m} or {force: N} (docs/friction.md)");
    }
  } else if (out.type == OutputType::contact_force || out.type == OutputType::contact_stuck) {
    const Value contact = s.get("contact");
    const std::string contact_name = read_string(contact, "a contact's name");
    for (std::size_t i = 0; i < model.contacts.size(); ++i) {
      if (model.contacts[i].name == contact_name) out.contact = static_cast<int>(i);
    }
    if (out.contact < 0) {
      std::string names;
      for (const Contact& c : model.contacts) names += (names.empty() ? "" : ", ") + c.name;
      fail(contact, "unknown contact '" + excerpt(contact_name) + "' (point_contact and sphere_contact joints: " +
                        (names.empty() ? "none" : names) + ")");
    }
  } else if (out.type == OutputType::joint_position || out.type == OutputType::joint_velocity) {
    out.joint = read_joint_ref(s.get("joint"), model, {JointType::revolute, JointType::prismatic}, "a " + type_name + " output");
  } else {
    const Value body = s.get("body");
    out.body = read_body_ref(body, model, &out.node);  // a modal body's node too: NAME@K
    if (out.body == kGround) fail(body, "ground does not move; name a body");
  }
  return out;
}

SolverSettings parse_solver(const Value& v) {
  SolverSettings solver;
  if (v.node.IsNull()) return solver;  // "solver:" with nothing under it: defaults
  const Section s(v, kSolverKeys);
  if (auto x = s.find("scheme")) {
    solver.scheme = *mbrt::scheme_from_name(read_choice(*x, kSchemes));
    solver.scheme_given = true;
  }
  if (auto x = s.find("step")) solver.step = read_positive(*x);
  if (auto x = s.find("euler_updates")) solver.euler_updates = read_integer_at_least(*x, 1);
  if (auto x = s.find("penalty")) solver.penalty = read_non_negative(*x);
  if (auto x = s.find("stabilization")) solver.stabilization = read_non_negative(*x);
  if (auto x = s.find("baumgarte_alpha")) solver.baumgarte_alpha = read_non_negative(*x);
  if (auto x = s.find("baumgarte_beta")) solver.baumgarte_beta = read_non_negative(*x);
  if (auto x = s.find("corrections")) solver.corrections = read_integer_at_least(*x, 1);
  if (auto x = s.find("ali3p")) solver.ali3p = parse_ali3p(*x);
  if (auto x = s.find("parallel_parts")) {
    solver.parallel_parts = read_integer_at_least(*x, 1);
    solver.parallel_parts_where = x->where;
    if (solver.parallel_parts > 64) fail(*x, "expected at most 64 parts, got " + std::to_string(solver.parallel_parts));
  }
  if (auto x = s.find("parallel_min_rows")) solver.parallel_min_rows = read_integer_at_least(*x, 0);
  if (auto x = s.find("parallel_interface")) solver.parallel_interface = read_choice(*x, {"direct", "pcg"});
  if (auto x = s.find("pcg_iterations")) solver.pcg_iterations = read_integer_at_least(*x, 1);
  if (auto x = s.find("pcg_preconditioner")) solver.pcg_preconditioner = read_choice(*x, {"block", "diagonal"});
  if (auto x = s.find("body_states")) {
    solver.body_states_on_demand = read_choice(*x, {"each_step", "on_demand"}) == "on_demand";
    solver.body_states_where = x->where;
  }
  return solver;
}

Model build_model(const YAML::Node& root, const std::string& file) {
  if (!root.IsDefined() || root.IsNull()) {
    throw ModelError({file, 1, 1}, "",
                     "the model file is empty (expected a map with keys " + join(kTopKeys) + ")");
  }
  const Value top{root, "", location(file, root.Mark())};
  const Section s(top, kTopKeys);

  Model model;
  model.file = file;
  model.name = read_identifier(s.get("name"));
  if (auto v = s.find("gravity")) model.gravity = read_vector3(*v);

  // Bodies first, whatever the key order: joints and forces refer to them.
  const Value bodies = s.get("bodies");
  if (!bodies.node.IsSequence() || bodies.node.size() == 0) {
    fail_expected(bodies, "a non-empty list of bodies");
  }
  std::map<std::string, int> body_names;
  for (std::size_t i = 0; i < bodies.node.size(); ++i) {
    const Value item = element(bodies, i);
    const Section body(item, kBodyKeys);
    if (body.find("flexible")) parse_flexible_body(item, body, body_names, model);
    else model.bodies.push_back(parse_body(item, body_names));
  }

  if (auto joints = s.find("joints"); joints && !is_empty_or_list(*joints, "a list of joints")) {
    std::map<std::string, int> joint_names;
    for (std::size_t i = 0; i < joints->node.size(); ++i) {
      const Value item = element(*joints, i);
      if (is_contact_entry(item)) {
        model.contacts.push_back(parse_unilateral_contact(item, model, joint_names));
      } else {
        model.joints.push_back(parse_joint(item, model, joint_names));
      }
    }
  }

  if (auto forces = s.find("forces"); forces && !is_empty_or_list(*forces, "a list of forces")) {
    for (std::size_t i = 0; i < forces->node.size(); ++i) {
      model.forces.push_back(parse_force(element(*forces, i), model));
    }
  }

  if (auto drivers = s.find("drivers"); drivers && !is_empty_or_list(*drivers, "a list of drivers")) {
    std::map<std::string, int> driver_names;
    for (std::size_t i = 0; i < drivers->node.size(); ++i) {
      model.drivers.push_back(parse_driver(element(*drivers, i), model, driver_names));
    }
  }

  std::map<std::string, int> signal_names;
  if (auto inputs = s.find("inputs"); inputs && !is_empty_or_list(*inputs, "a list of inputs")) {
    for (std::size_t i = 0; i < inputs->node.size(); ++i) {
      model.inputs.push_back(parse_input(element(*inputs, i), model, signal_names));
    }
  }
  if (auto outputs = s.find("outputs"); outputs && !is_empty_or_list(*outputs, "a list of outputs")) {
    for (std::size_t i = 0; i < outputs->node.size(); ++i) {
      model.outputs.push_back(parse_output(element(*outputs, i), model, signal_names));
    }
  }

  if (auto v = s.find("solver")) model.solver = parse_solver(*v);
  if (auto tunable = s.find("tunable"); tunable && !is_empty_or_list(*tunable, "a list of tunable keys")) {
    for (std::size_t i = 0; i < tunable->node.size(); ++i) {
      const Value entry = element(*tunable, i);
      model.tunable.push_back({read_string(entry, "a tunable key (docs/parameters.md)"), entry.where});
    }
    parameters(model);  // every entry names something tunable
  }
  return model;
}

}  // namespace

Model parse_model(const std::string& yaml_text, const std::string& file_name) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw ModelError(location(file_name, e.mark), "", "invalid YAML: " + e.msg);
  }
  try {
    return build_model(root, file_name);
  } catch (const YAML::Exception& e) {
    // Not expected (all access is checked), but never let a raw yaml-cpp
    // exception reach the user.
    throw ModelError(location(file_name, e.mark), "", "cannot read model: " + e.msg);
  }
}

Model load_model(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw ModelError({path, 0, 0}, "",
                     "cannot read the model file '" + path + "': it is a directory");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw ModelError({path, 0, 0}, "",
                     "cannot open the model file '" + path + "' (" + std::strerror(errno) + ")");
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) {
    throw ModelError({path, 0, 0}, "", "cannot read the model file '" + path + "'");
  }
  return parse_model(text.str(), path);
}

}  // namespace mbrt::codegen
