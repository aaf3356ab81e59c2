// Modal bodies (docs/flexible.md): the constants of include/mbrt/modal_body.hpp
// per body, its loads, the modal coordinates' kick and drift, its energy and
// tip outputs. State::modal_q and modal_p hold each body's coordinates and
// momenta in the first N entries of a Vec6; the momenta ride in BodyVectors
// after the bodies, where constraint forces leave them alone.
#include <algorithm>
#include <tuple>

#include "emitter.hpp"

namespace mbrt::codegen {

namespace {

std::string matrix(const Eigen::MatrixXd& m) {
  std::string s;
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) s += (s.empty() ? "" : ", ") + num(m(i, j));
  return s;
}

}  // namespace

std::string Emitter::modal_coordinates(int k, const std::string& field) const {
  return "s." + field + modal_slot(k) + ".head<" + std::to_string(a_.modal[static_cast<size_t>(k)].modes) + ">()";
}

void Emitter::modal_constants(std::ostringstream& o) const {
  if (!modal()) return;
  o << "\n// Modal bodies: the frame's reduced inverse mass, the modes' coupling, stiffness,\n"
    << "// damping, geometric stiffness and inertia invariants (include/mbrt/modal_body.hpp).\n";
  for (const ModalPlan& p : a_.modal) {
    const std::string n = body(p.body).name, N = std::to_string(p.modes);
    o << "const mbrt::ModalBody<" << N << "> " << n << "_modal = [] {\n  mbrt::ModalBody<" << N << "> b;\n"
      << "  b.St_T << " << matrix(p.St_T) << ";\n  b.Sr_T << " << matrix(p.Sr_T) << ";\n"
      << "  b.stiffness << " << matrix(p.omega.cwiseAbs2()) << ";  // omega^2: " << matrix(p.omega) << " rad/s\n"
      << "  b.damping << " << matrix(p.damping) << ";\n";
    unsigned cases = 0;
    for (size_t k = 0; k < p.kg.size(); ++k) {
      const Eigen::MatrixXd kg = step_geometric_stiffness(p, k);
      if (kg.isZero(0.0)) {
        o << "  b.kg[" << k << "].setZero();\n";
      } else {
        o << "  b.kg[" << k << "] << " << matrix(kg) << ";\n";
        cases |= 1u << k;
      }
    }
    o << "  b.kg_cases = " << cases << "u;  // the cases above that are not zero\n";
    if (p.axial_moment > 0.0) {
      o << "  b.stretch << " << matrix(p.stretch) << ";  // the spin's cases, in the mass\n  b.axial_moment = " << num(p.axial_moment)
        << ";\n";
    } else {
      o << "  b.stretch.setZero();\n";
    }
    for (int i = 0; i < 9; ++i) {
      o << "  b.E[" << i << "] << " << matrix(p.E[static_cast<size_t>(i)]) << ";\n"
        << "  b.G[" << i << "] << " << matrix(p.G[static_cast<size_t>(i)]) << ";\n";
    }
    o << "  b.J = " << mat3(p.J) << ";\n  b.m = " << num(p.m) << ";\n  return b;\n}();\n";
    for (const int k : modal_nodes(p.body)) {
      const ModalNode node = modal_node(p, k);
      o << "const mbrt::ModalPoint<" << N << "> " << modal_node_constant(p.body, k) << " = [] {  // " << modal_node_label(p.body, k)
        << "\n  mbrt::ModalPoint<" << N << "> c;\n"
        << "  c.point = " << vec3(node.point) << ";\n  c.displacement << " << matrix(node.displacement) << ";\n"
        << "  c.rotation << " << matrix(node.rotation) << ";\n  return c;\n}();\n";
    }
  }
}

std::string Emitter::modal_node_label(int i, int k) const {
  return body(i).name + "@" + a_.modal[static_cast<size_t>(plan(i).modal)].node_names[static_cast<size_t>(k)];
}

std::vector<int> Emitter::modal_nodes(int i) const {
  std::vector<int> nodes;
  const auto use = [&](int b, int k) {
    if (b == i && k >= 0 && std::find(nodes.begin(), nodes.end(), k) == nodes.end()) nodes.push_back(k);
  };
  for (const Output& out : m_.outputs) use(out.body, out.node);
  for (const Force& f : m_.forces) use(f.body, f.node), use(f.body1, f.node1), use(f.body2, f.node2);
  for (const Input& in : m_.inputs) use(in.body1, in.node1), use(in.body2, in.node2);
  for (int j = 0; j < blocks(); ++j) use(block(j).body1, block(j).node1), use(block(j).body2, block(j).node2);
  std::sort(nodes.begin(), nodes.end());
  return nodes;
}

std::string Emitter::node_force(int b, int k, const std::string& force) const {
  const int m = plan(b).modal;
  const std::string N = "<" + std::to_string(a_.modal[static_cast<size_t>(m)].modes) + ">";
  return "    l.modal" + modal_slot(m) + ".head" + N + "() += mbrt::modal_point_force" + N + "(" + modal_node_constant(b, k) +
         ", " + pose(b) + ".R, " + modal_coordinates(m, "modal_q") + ", " + force + ", l.w" + at(b) + ");\n";
}

// A force or spring_damper acting at a modal body's node: the node's place
// and velocity from the modal coordinates, the frame's load at that place,
// and the modes' share in l.modal, which modal_loads takes as applied.
void Emitter::modal_force_load(std::ostringstream& o, const Force& f, const std::string& n) const {
  if (f.type == ForceType::force) {
    o << "  {  // force at " << modal_node_label(f.body, f.node) << "\n" << node_force(f.body, f.node, n + "_vector") << "  }\n";
    return;
  }
  o << "  {  // spring_damper " << (f.node1 >= 0 ? modal_node_label(f.body1, f.node1) : m_.body_name(f.body1)) << " - "
    << (f.node2 >= 0 ? modal_node_label(f.body2, f.node2) : m_.body_name(f.body2)) << "\n"
    << "    mbrt::SpringDamper spring = " << n << ";\n";
  std::string motions[2];
  const int bodies[2] = {f.body1, f.body2}, nodes[2] = {f.node1, f.node2};
  for (int e = 0; e < 2; ++e) {
    const int b = bodies[e], k = nodes[e];
    motions[e] = motion(b);
    if (k < 0) continue;
    const int m = plan(b).modal;
    const std::string N = "<" + std::to_string(a_.modal[static_cast<size_t>(m)].modes) + ">", x = "node" + std::to_string(e + 1);
    o << "    const mbrt::ModalPointMotion" << N << " " << x << " = mbrt::modal_point_motion" << N << "(" << body(b).name << "_modal, "
      << modal_node_constant(b, k) << ", " << pose(b) << ", k.vel" << at(b) << ", " << modal_coordinates(m, "modal_q") << ", "
      << modal_coordinates(m, "modal_p") << ");\n"
      << "    spring.s" << (e + 1) << " = " << x << ".point;\n";
    motions[e] = "mbrt::BodyMotion{" + pose(b) + ", " + x + ".velocity}";
  }
  o << "    const mbrt::SpringDamperForce e = mbrt::spring_damper(spring, " << motions[0] << ", " << motions[1] << ");\n";
  for (int e = 0; e < 2; ++e) {
    const int b = bodies[e];
    if (b == kGround) continue;
    const std::string force = e == 0 ? "-e.f2" : "e.f2";
    if (nodes[e] >= 0) o << node_force(b, nodes[e], force);
    else o << "    mbrt::add_point_force(l.w" << at(b) << ", " << pose(b) << ", spring.s" << (e + 1) << ", " << force << ");\n";
  }
  o << "    l.elastic_energy += e.energy;\n  }\n";
}

// The kernel sees a rigid body carrying the node's deformed place and its
// section's axes at their velocities; modal_node_rows then splits its
// columns between the frame and the modal momenta and adds the node's
// deformation terms to quad. Point joints (spherical, distance) have no axes
// to turn.
bool Emitter::turns_axes(const ConstraintBlock& b) {
  return b.source == ConstraintSource::driver ||
         (b.joint_type != JointType::spherical && b.joint_type != JointType::distance);
}

Emitter::NodeJointView Emitter::node_joint_view(const std::string& frame, int body1, int node1, int body2, int node2, bool turns,
                                                const std::string& indent) const {
  NodeJointView view{indent + "mbrt::JointFrame f = " + frame + ";\n", {motion(body1), motion(body2)}};
  const int bodies[2] = {body1, body2}, nodes[2] = {node1, node2};
  for (int e = 0; e < 2; ++e) {
    const int i = bodies[e], k = nodes[e];
    if (k < 0) continue;
    const int m = plan(i).modal;
    const std::string N = std::to_string(modes_of(i)), x = "node" + std::to_string(e + 1);
    view.code += indent + "const mbrt::ModalPointMotion<" + N + "> " + x + " = mbrt::modal_point_motion<" + N + ">(" + body(i).name +
                 "_modal, " + modal_node_constant(i, k) + ", " + pose(i) + ", k.vel" + at(i) + ", " + modal_coordinates(m, "modal_q") +
                 ", " + modal_coordinates(m, "modal_p") + ");\n" + indent + "f.s" + std::to_string(e + 1) + " = " + x + ".point;\n";
    if (turns) view.code += indent + "f = mbrt::turned_joint_frame(f, " + std::to_string(e + 1) + ", " + x + ".turn.C);\n";
    view.motions[static_cast<size_t>(e)] = "mbrt::BodyMotion{" + pose(i) + ", " + x + ".velocity}";
  }
  return view;
}

std::string Emitter::modal_node_block(int j) const {
  const ConstraintBlock& b = block(j);
  const auto label = [&](int body, int node) { return node >= 0 ? modal_node_label(body, node) : m_.body_name(body); };
  const NodeJointView view = node_joint_view(b.name + "_frame", b.body1, b.node1, b.body2, b.node2, turns_axes(b), "    ");
  std::string columns;
  const int bodies[2] = {b.body1, b.body2}, nodes[2] = {b.node1, b.node2};
  for (int e = 0; e < 2; ++e) {
    const int i = bodies[e];
    if (nodes[e] < 0) continue;
    const std::string N = std::to_string(modes_of(i));
    columns += "    " + jq(j, i) + " = mbrt::modal_node_rows<" + N + ", " + std::to_string(rows(j)) + ">(" + body(i).name + "_modal, " +
               modal_node_constant(i, nodes[e]) + ", " + pose(i) + ", k.vel" + at(i) + ", " + modal_coordinates(plan(i).modal, "modal_q") +
               ", node" + std::to_string(e + 1) + ", " + rows_of(j) + "." + (e == 0 ? "J1" : "J2") + ", " + rows_of(j) + ".quad, " + jp(j, i) +
               ");\n";
  }
  const std::string target = b.function ? ",\n        " + driver_function_value(b) : "";
  return "  {  // " + b.kernel + " " + label(b.body1, b.node1) + " - " + label(b.body2, b.node2) + "\n" + view.code + "    " + rows_of(j) +
         " = mbrt::" + b.kernel + "(f, " + view.motions[0] + ", " + view.motions[1] + target + ");\n" + columns + "  }\n";
}

std::string Emitter::reaction_frame(int j) const {
  const ConstraintBlock& b = block(j);
  const std::string frame = b.name + "_frame";
  if (b.node1 < 0 || !turns_axes(b)) return frame;
  const std::string N = std::to_string(modes_of(b.body1));
  return "mbrt::turned_joint_frame(" + frame + ", 1, mbrt::modal_section_turn<" + N + ">(" + modal_node_constant(b.body1, b.node1) + ", " +
         modal_coordinates(plan(b.body1).modal, "modal_q") + "))";
}

std::string Emitter::modal_node_place(int b, int k) const {
  const int m = plan(b).modal;
  const std::string c = modal_node_constant(b, k);
  return pose(b) + ".r + " + pose(b) + ".R * (" + c + ".point + " + c + ".displacement * " + modal_coordinates(m, "modal_q") + ")";
}

void Emitter::modal_loads(std::ostringstream& o) const {
  for (size_t k = 0; k < a_.modal.size(); ++k) {
    const int i = a_.modal[k].body, n = static_cast<int>(k);
    const std::string N = std::to_string(a_.modal[k].modes), b = body(i).name + "_modal";
    o << "  {  // modal body " << body(i).name << ": inertia terms of the deformed body, elastic and damping loads,\n"
      << "     // and the frame's M^-1 at its deformation for the loads' accelerations\n"
      << "    const mbrt::ModalMass<" << N << "> mass = mbrt::modal_mass<" << N << ">(" << b << ", " << modal_coordinates(n, "modal_q")
      << ");\n"
      << "    const auto e = mbrt::modal_loads<" << N << ">(" << b << ", mass, " << pose(i) << ".R, k.vel" << at(i) << ".v, k.vel"
      << at(i) << ".w,\n        " << (a_.gravity ? gravity() : "mbrt::Vec3::Zero()") << ", "
      << modal_coordinates(n, "modal_q") << ", " << modal_coordinates(n, "modal_p") << ", l.modal" << modal_slot(n) << ".head<"
      << N << ">(), l.w" << at(i) << ");\n"
      << "    l.modal" << modal_slot(n) << ".head<" << N << ">() = e.momentum_rate;\n"
      << "    l.modal_inverse" << modal_slot(n) << " = mbrt::modal_inverse_mass<" << N << ">(" << b << ", mass, " << pose(i) << ".R);\n"
      << "    l.elastic_energy += e.potential;\n  }\n";
  }
}

void Emitter::modal_kick(std::ostringstream& o) const {
  if (modal()) o << "  for (int b = 0; b < kModalBodies; ++b) s.modal_p[b] += (0.5 * h) * s.modal_rate[b];\n";
}

// The modal coordinates' drift at the half-step velocities, with the frame's
// turn over the step averaged (the body-axes velocity it couples to is at
// mid-step) and q's own coupling at mid-step.
void Emitter::modal_drift(std::ostringstream& o) const {
  for (size_t k = 0; k < a_.modal.size(); ++k) {
    const int i = a_.modal[k].body, n = static_cast<int>(k);
    const std::string st = state_of(i);
    o << "  " << modal_coordinates(n, "modal_q") << " += mbrt::modal_drift<" << a_.modal[k].modes << ">(" << body(i).name
      << "_modal, 0.5 * (" << body(i).name << "_start + mbrt::rotation_matrix(" << st << ".p)), " << st << ".v, " << st
      << ".w, " << modal_coordinates(n, "modal_q") << ", " << modal_coordinates(n, "modal_p") << ", h);\n";
  }
}

void Emitter::modal_initial_momenta(std::ostringstream& o) const {
  if (!modal()) return;
  o << "  s.modal_q.fill(mbrt::Vec6::Zero());  // undeformed, at rest in the frame\n  s.modal_p.fill(mbrt::Vec6::Zero());\n"
    << "  s.modal_rate.fill(mbrt::Vec6::Zero());\n";
  for (size_t k = 0; k < a_.modal.size(); ++k) {
    const int i = a_.modal[k].body, n = static_cast<int>(k);
    const std::string st = state_of(i), b = body(i).name + "_modal";
    o << "  " << modal_coordinates(n, "modal_p") << " = " << b << ".St_T * (mbrt::rotation_matrix(" << st << ".p).transpose() * "
      << st << ".v) + " << b << ".Sr_T * " << st << ".w;\n"
      << "  " << acceleration_of(i) << " = {mbrt::Vec3::Zero(), mbrt::Vec3::Zero()};  // the loads' last accelerations at the start\n";
  }
}

void Emitter::modal_energy(std::ostringstream& o) const {
  for (size_t k = 0; k < a_.modal.size(); ++k) {
    const int i = a_.modal[k].body, n = static_cast<int>(k);
    const std::string st = state_of(i);
    o << "  e.kinetic += mbrt::modal_kinetic_energy<" << a_.modal[k].modes << ">(" << body(i).name << "_modal, " << pose(i) << ".R, " << st << ".v, "
      << st << ".w, " << modal_coordinates(n, "modal_q") << ", " << modal_coordinates(n, "modal_p") << ");\n";
  }
}

std::string Emitter::modal_node_output(const Output& out, const std::string& at) const {
  const int i = out.body;
  const int k = plan(i).modal;
  const std::string n = body(i).name, N = "<" + std::to_string(a_.modal[static_cast<size_t>(k)].modes) + ">";
  const std::string node = modal_node_constant(i, out.node);
  if (out.type == OutputType::body_pose) {
    return "  mbrt::modal_point_pose" + N + "(" + node + ", " + state_of(i) + ", " + modal_coordinates(k, "modal_q") + ", " + at + ");\n";
  }
  return "  mbrt::modal_point_velocity" + N + "(" + n + "_modal, " + node + ", " + state_of(i) + ", " + modal_coordinates(k, "modal_q") +
         ", " + modal_coordinates(k, "modal_p") + ", " + at + ");\n";
}

void Emitter::torque_on_ends(std::ostringstream& o, int body1, int node1, int body2, int node2) const {
  for (const auto& [b, k, sign] : {std::tuple{body2, node2, "+"}, std::tuple{body1, node1, "-"}}) {
    if (b == kGround) continue;
    if (k < 0) {
      o << "    l.w" << at(b) << ".tau " << sign << "= " << pose(b) << ".R.transpose() * t;\n";
      continue;
    }
    const int m = plan(b).modal;
    const std::string N = "<" + std::to_string(a_.modal[static_cast<size_t>(m)].modes) + ">";
    o << "    l.modal" << modal_slot(m) << ".head" << N << "() += mbrt::modal_point_torque" << N << "(" << modal_node_constant(b, k)
      << ", " << pose(b) << ".R, " << (sign[0] == '-' ? "-t" : "t") << ", l.w" << at(b) << ");\n";
  }
}

}  // namespace mbrt::codegen
