// Joint friction's part of a generated model (docs/friction.md) that both
// families share: the friction:: index names, the limits, the transverse
// loads; and the absolute-coordinate schemes' rows and columns
// (include/mbrt/schemes/joint_friction_absolute.hpp). The tree's recursion
// columns are in emit_tree.cpp.
#include <string>
#include <vector>

#include "emitter.hpp"

namespace mbrt::codegen {

std::vector<int> Emitter::friction_joints() const {
  std::vector<int> out;
  for (size_t j = 0; j < m_.joints.size(); ++j) {
    if (m_.joints[j].friction.any()) out.push_back(static_cast<int>(j));
  }
  return out;
}

std::string Emitter::friction_joint_names() const {
  std::string names;
  for (const int j : friction_joints()) names += (names.empty() ? "\"" : ", \"") + m_.joints[static_cast<size_t>(j)].name + "\"";
  return names;
}

void Emitter::friction_declarations(std::ostringstream& o) const {
  const std::vector<int> friction = friction_joints();
  o << "// The joints with Coulomb friction (docs/friction.md), friction:: indices\n"
    << "// into State::friction and State::stuck.\n"
    << "inline constexpr int kFrictionJoints = " << friction.size() << ";\nnamespace friction {\n";
  for (size_t c = 0; c < friction.size(); ++c) {
    o << "inline constexpr int " << m_.joints[static_cast<size_t>(friction[c])].name << " = " << c << ";\n";
  }
  o << "}  // namespace friction\n";
}

// The projected Gauss-Seidel sweeps of the friction impulses per step
// (include/mbrt/schemes/joint_friction.hpp): one is exact for one joint;
// for more, two per joint, warm-started from the last step's.
void Emitter::friction_limits(std::ostringstream& o) const {
  const std::vector<int> friction = friction_joints();
  std::string limits, static_limits, per_load, static_per_load;
  bool loads = false;
  for (size_t c = 0; c < friction.size(); ++c) {
    const JointFriction& f = m_.joints[static_cast<size_t>(friction[c])].friction;
    const std::string comma = c ? ", " : "";
    limits += comma + num(f.kinetic);
    static_limits += comma + num(f.static_limit);
    per_load += comma + num(f.kinetic_per_load);
    static_per_load += comma + num(f.static_per_load);
    loads = loads || f.load_dependent();
  }
  const size_t sweeps = friction.size() == 1 ? 1 : 2 * friction.size();
  o << "// Joint friction (docs/friction.md), by friction:: index: kinetic and static\n"
    << "// Coulomb limits (N m or N), each a constant plus a multiple of the joint's\n"
    << "// transverse reaction (m or 1); projected Gauss-Seidel sweeps a step.\n"
    << "static constexpr int kFrictionJoints = mbrt::models::" << m_.name << "::kFrictionJoints;\n"
    << "static constexpr std::array<double, kFrictionJoints> kFrictionLimit{{" << limits << "}};\n"
    << "static constexpr std::array<double, kFrictionJoints> kFrictionStaticLimit{{" << static_limits << "}};\n"
    << "static constexpr std::array<double, kFrictionJoints> kFrictionPerLoad{{" << per_load << "}};\n"
    << "static constexpr std::array<double, kFrictionJoints> kFrictionStaticPerLoad{{" << static_per_load << "}};\n"
    << "static constexpr bool kFrictionLoads = " << (loads ? "true" : "false") << ";\n"
    << "static constexpr int kFrictionSweeps = " << sweeps << ";\n";
}

// Where a friction limit depends on the load: each friction joint's
// transverse reaction force from the multipliers at the state (reactions();
// the tree's are its joints' constraint forces in absolute coordinates), 0
// for the others. The joint's axis is its frame's a1.
void Emitter::friction_loads_function(std::ostringstream& o) const {
  const std::vector<int> friction = friction_joints();
  bool loads = false;
  for (const int j : friction) loads = loads || m_.joints[static_cast<size_t>(j)].friction.load_dependent();
  if (!loads) return;
  o << "// (s" << (tree_scheme() ? " with its body states" : ", its multipliers")
    << ") => (load): each friction joint's transverse\n"
    << "// reaction force (N), where its limit depends on it; 0 elsewhere.\n"
    << "static void friction_loads(const State& s, std::array<double, kFrictionJoints>& load) noexcept {\n"
    << "  Reactions r;\n  reactions(s, r);\n";
  for (size_t c = 0; c < friction.size(); ++c) {
    const Joint& j = m_.joints[static_cast<size_t>(friction[c])];
    o << "  load[" << c << "] = ";
    if (j.friction.load_dependent()) {
      // sqrt of the sum of squares, not hypot: the same work whatever the load.
      o << "r[constraint::" << j.name << "].force_joint.tail<2>().norm();\n";
    } else {
      o << "0.0;\n";
    }
  }
  o << "}\n\n";
}

// The absolute-coordinate schemes' friction members of struct Model: the
// limits, each joint's bodies and kind, its coordinate's row at a state
// and the free response M^-1 g^T to a unit impulse along it.
void Emitter::absolute_friction_members(std::ostringstream& o) const {
  const std::vector<int> friction = friction_joints();
  if (friction.empty()) return;
  friction_limits(o);
  const auto index = [&](int b) { return b == kGround ? std::string("-1") : "body::" + body(b).name; };
  std::string bodies, revolute;
  for (size_t c = 0; c < friction.size(); ++c) {
    const Joint& j = m_.joints[static_cast<size_t>(friction[c])];
    const std::string comma = c ? ", " : "";
    bodies += comma + "{" + index(j.body1) + ", " + index(j.body2) + "}";
    revolute += comma + (j.type == JointType::revolute ? "true" : "false");
  }
  o << "// Each friction joint's bodies (-1: the ground) and whether it turns (else slides).\n"
    << "static constexpr std::array<std::array<int, 2>, kFrictionJoints> kFrictionBodies{{" << bodies << "}};\n"
    << "static constexpr std::array<bool, kFrictionJoints> kFrictionRevolute{{" << revolute << "}};\n"
    << "// Column c: the bodies' [dv; dw_body] for a unit impulse along friction joint c.\n"
    << "using FrictionColumns = std::array<BodyVectors, kFrictionJoints>;\n"
    << "// (s) => (r): where each friction joint is (a revolute joint's cos and sin of\n"
    << "// its angle, a prismatic joint's slide) and its rate's row over the two\n"
    << "// bodies' [v; w_body].\n"
    << "static void friction_rows(const State& s, std::array<mbrt::JointRow, kFrictionJoints>& r) noexcept {\n"
    << "  Kinematics k;\n  kinematics(s, k);\n";
  for (size_t c = 0; c < friction.size(); ++c) {
    const Joint& j = m_.joints[static_cast<size_t>(friction[c])];
    o << "  r[" << c << "] = mbrt::" << (j.type == JointType::revolute ? "revolute" : "prismatic") << "_row(" << j.name
      << "_frame, " << motion(j.body1) << ", " << motion(j.body2) << ");\n";
  }
  o << "}\n"
    << "// (s" << (a_.tunable_masses ? ", its masses" : "") << ", rows) => (x): M^-1 g^T per friction joint, without the joints.\n"
    << "static void friction_columns([[maybe_unused]] const State& s, const std::array<mbrt::JointRow, kFrictionJoints>& r,\n"
    << "                             FrictionColumns& x) noexcept {\n"
    << "  for (BodyVectors& column : x) {\n    for (mbrt::Vec6& e : column) e.setZero();\n  }\n";
  for (size_t c = 0; c < friction.size(); ++c) {
    const Joint& j = m_.joints[static_cast<size_t>(friction[c])];
    const std::string col = "x[" + std::to_string(c) + "]";
    if (j.body1 != kGround) {
      o << "  " << col << at(j.body1) << " = mbrt::inverse_mass_times_transpose(" << mass_of(j.body1) << ", r[" << c << "].J1);\n";
    }
    if (j.body2 != kGround) {
      o << "  " << col << at(j.body2) << " = mbrt::inverse_mass_times_transpose(" << mass_of(j.body2) << ", r[" << c << "].J2);\n";
    }
  }
  o << "}\n";
  friction_loads_function(o);
  if (!has_contacts()) displace_function(o);
}

}  // namespace mbrt::codegen
