// The kernels of staggered-pcst, baumgarte or blajer in planar coordinates
// (docs/specializations.md, "planar"): the same scheme template
// (include/mbrt/schemes/staggered.hpp) runs over a second struct Model in
// namespace `planar`, emitted by an Emitter whose constraint blocks are the
// in-plane rows. The spatial kernels stay for initial_state(), energy(),
// constraint_violation(), reactions() and outputs().
#include <algorithm>

#include "emitter.hpp"

namespace mbrt::codegen {

void Emitter::planar_stages(std::ostringstream& o) const {
  const Emitter e = planar_emitter();
  o << "// The step in planar coordinates: motion in one plane, per body two\n"
    << "// coordinates and the rotation about the normal, the in-plane constraint rows only.\n"
    << "namespace planar {\n\n";
  e.planar_constants(o);
  e.model_members(o);
  e.velocity_helpers(o);
  e.kinematics_function(o);
  e.loads_stage(o);
  e.constraint_stage(o);
  e.mass_products(o);
  store_multipliers(o);
  e.staggered_stages(o);
  o << "};\n\n}  // namespace planar\n\n";
}

// The planar step's types, in the header's detail::planar.
void Emitter::planar_types(std::ostringstream& o) const {
  const Emitter e = planar_emitter();
  o << "namespace planar {\n\n"
    << "inline constexpr int kPlanarRows = " << a_.planar.constraint_rows << ";  // of kConstraintRows\n";
  e.workspace_types(o);
  if (e.rattle()) e.newton_matrix_type(o);
  o << "}  // namespace planar\n\n";
}

void Emitter::planar_constants(std::ostringstream& o) const {
  // A body turning about the normal, a principal axis, has no gyroscopic torque:
  // without dampers (and Baumgarte's velocity term) one implicit stage.
  const Plane plane{a_.planar.normal};
  o << "constexpr int kNormal = " << plane.normal << ";  // the plane " << plane.name() << ", normal to world "
    << plane.axis_name() << "\n";
  if (rattle()) position_stage_constants(o);
  if (a_.gravity && !folded_weights()) {
    const Eigen::Vector3d g = axes(m_.gravity.value_or(Eigen::Vector3d::Zero()));
    o << "const mbrt::Vec2 kGravity(" << num(g.x()) << ", " << num(g.y()) << ");\n";
  }
  o << "const mbrt::PlanarPose kGroundPose = mbrt::planar_ground_pose();\n"
    << "const mbrt::PlanarVelocity kGroundVelocity = mbrt::planar_ground_velocity();\n\n"
    << "// Masses and the moments of inertia about the normal (particles keep their PointMass).\n";
  for (size_t i = 0; i < m_.bodies.size(); ++i) {
    const Body& b = m_.bodies[i];
    if (a_.bodies[i].rigid) {
      o << "const mbrt::PlanarInertia " << mass_of(static_cast<int>(i)) << "{" << num(b.mass) << ", "
        << num(b.inertia(plane.normal, plane.normal)) << "};\n";
    }
    if (folded_weights()) {
      const Eigen::Vector3d w = axes(b.mass * *m_.gravity);
      o << "const mbrt::Vec2 " << weight_of(static_cast<int>(i)) << "(" << num(w.x()) << ", " << num(w.y()) << ");\n";
    }
  }
  // Plane coordinates are world ones in the x-y plane; in another, the
  // frames and loads are given again in them, hiding the spatial constants.
  if (plane.normal != 2) frame_constants(o);
  o << "\n";
}

void Emitter::planar_velocity_helpers(std::ostringstream& o) const {
  o << "// (s) => (u): (vx, vy, omega_z) per body.\n"
    << "static BodyVectors generalized_velocities(const State& s) noexcept {\n  BodyVectors u;\n";
  for (size_t i = 0; i < m_.bodies.size(); ++i) {
    o << "  u" << at(static_cast<int>(i)) << " = mbrt::planar_velocities<kNormal>(" << state_of(static_cast<int>(i)) << ");\n";
  }
  o << "  return u;\n}\n\n"
    << "// (u) => (s): the in-plane velocities; the others stay zero.\n"
    << "static void set_velocities(const BodyVectors& u, State& s) noexcept {\n";
  for (size_t i = 0; i < m_.bodies.size(); ++i) {
    o << "  mbrt::set_planar_velocities<kNormal>(u" << at(static_cast<int>(i)) << ", " << state_of(static_cast<int>(i)) << ");\n";
  }
  o << "}\n\n";
  o << "// (a) => (s): accelerations kept for the next step.\n"
    << "static void set_accelerations(const BodyVectors& a, State& s) noexcept {\n";
  for (int i = 0; i < static_cast<int>(m_.bodies.size()); ++i) {
    o << "  mbrt::set_planar_accelerations<kNormal>(a" << at(i) << ", " << acceleration_of(i) << ");\n";
  }
  o << "}\n\n"
    << "static BodyVectors accelerations_of(const State& s) noexcept {\n  BodyVectors a;\n";
  for (int i = 0; i < static_cast<int>(m_.bodies.size()); ++i) {
    o << "  a" << at(i) << " = mbrt::planar_accelerations<kNormal>(" << acceleration_of(i) << ");\n";
  }
  o << "  return a;\n}\n\n";
}

void Emitter::planar_explicit_stage(std::ostringstream& o) const {
  o << R"(// (s, accelerations at t) => (s): half kick of the velocities in the plane
// (docs/staggered-pcst.md, eq. 1).
static void kick(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) mbrt::planar_kick<kNormal>(s.rigid[b], s.rigid_acceleration[b], h);
  for (int b = 0; b < kParticles; ++b) mbrt::planar_kick<kNormal>(s.particle[b], s.particle_acceleration[b], h);
}

// (s) => (s): positions to t + h with the half-step velocities (eqs. 2-3); the
// rotation about the normal by the spatial step's Cayley updates.
static void drift(State& s) noexcept {
  for (int b = 0; b < kRigidBodies; ++b) mbrt::planar_drift<kNormal>(s.rigid[b], h, kEulerUpdates);
  for (int b = 0; b < kParticles; ++b) mbrt::planar_drift<kNormal>(s.particle[b], h);
  s.t += h;
}

)";
}

// Loads of loads_stage in the plane: torques about the normal, forces and springs
// whose points lie in their bodies' planes (codegen/plan/planar_scene.cpp).
void Emitter::planar_force_load(std::ostringstream& o, const Force& f, const std::string& n) const {
  switch (f.type) {
    case ForceType::spring_damper:
      o << "  {  // spring_damper " << m_.body_name(f.body1) << " - " << m_.body_name(f.body2) << "\n"
        << "    const mbrt::PlanarSpringDamperForce e = mbrt::planar_spring_damper(" << n << ", " << motion(f.body1)
        << ", " << motion(f.body2) << ");\n";
      if (f.body2 != kGround) o << "    mbrt::add_point_force(l.w" << at(f.body2) << ", " << pose(f.body2) << ", " << n << ".s2, e.f2);\n";
      if (f.body1 != kGround) o << "    mbrt::add_point_force(l.w" << at(f.body1) << ", " << pose(f.body1) << ", " << n << ".s1, -e.f2);\n";
      o << "    l.elastic_energy += e.energy;\n  }\n";
      break;
    case ForceType::torque:
      o << "  // torque about the normal on " << m_.body_name(f.body2) << ", reaction on " << m_.body_name(f.body1) << "\n";
      if (f.body2 != kGround) o << "  l.w" << at(f.body2) << ".tau += " << n << ".value * " << n << ".axis1.z();\n";
      if (f.body1 != kGround) o << "  l.w" << at(f.body1) << ".tau -= " << n << ".value * " << n << ".axis1.z();\n";
      break;
    case ForceType::force:
      o << "  mbrt::add_point_force(l.w" << at(f.body) << ", " << pose(f.body) << ", " << n << "_point, mbrt::Vec2("
        << n << "_vector.head<2>()));  // force on " << m_.body_name(f.body) << "\n";
      break;
    case ForceType::joint_spring: joint_spring_load(o, f, n); break;
  }
}

// Each planar row is one row of its spatial block (ConstraintBlock::spatial_rows);
// the spatial block's other (out-of-plane) multipliers are zero in a planar scene.
void Emitter::store_multipliers(std::ostringstream& o) const {
  o << "// (lambda) => (s.lambda): the in-plane rows of every spatial block.\n"
    << "static void store_multipliers(const Rows& lambda, State& s) noexcept {\n";
  if (blocks() == 0) o << "  (void)lambda;\n  (void)s;\n";
  for (int j = 0; j < blocks(); ++j) {
    const ConstraintBlock& p = a_.planar.constraints[static_cast<size_t>(j)];
    const std::vector<int>& rows = p.spatial_rows;
    bool leading = true;  // the spatial block's first rows, in order
    for (size_t r = 0; r < rows.size(); ++r) leading = leading && rows[r] == static_cast<int>(r);
    if (leading) {
      o << "  s.lambda.segment<" << p.rows << ">(" << first_row(j) << ") = lambda.segment<" << p.rows << ">("
        << p.first_row << ");  // " << jname(j) << "\n";
      continue;
    }
    for (size_t r = 0; r < rows.size(); ++r) {
      o << "  s.lambda[" << first_row(j) + rows[r] << "] = lambda[" << p.first_row + static_cast<int>(r) << "];  // "
        << jname(j) << "\n";
    }
  }
  o << "}\n\n";
}

}  // namespace mbrt::codegen
