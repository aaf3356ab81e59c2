#include "analysis.hpp"

#include <Eigen/LU>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseQR>

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>

#include <amd.h>
#include <camd.h>

#include <mbrt/modal_body.hpp>

#include "constraint_evaluation.hpp"
#include "parameters.hpp"
#include "planar_scene.hpp"

namespace mbrt::codegen {

namespace {

struct Pose {
  Eigen::Vector3d r;
  Eigen::Matrix3d R;
};

Pose initial_pose(const Model& model, int index) {
  if (index == kGround) return {Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity()};
  const Body& b = model.bodies[static_cast<size_t>(index)];
  return {b.position, b.particle ? Eigen::Matrix3d::Identity() : mbrt::rotation_matrix(b.orientation)};
}

bool is_particle(const Model& model, int index) {
  return index != kGround && model.bodies[static_cast<size_t>(index)].particle;
}

// Body-frame offset of a world point; particles can only carry their own position.
Eigen::Vector3d body_point(const Model& model, int index, const Eigen::Vector3d& world,
                           const SourceLocation& where, const std::string& key) {
  const Pose pose = initial_pose(model, index);
  const Eigen::Vector3d s = pose.R.transpose() * (world - pose.r);
  if (is_particle(model, index) && s.norm() > 1e-9 * std::max(1.0, world.norm())) {
    throw ModelError(where, key,
                     "particle '" + model.body_name(index) +
                         "' has no extent: the point must be its position (off by " + std::to_string(s.norm()) + ")");
  }
  return is_particle(model, index) ? Eigen::Vector3d::Zero() : s;
}

// Two unit vectors completing a to a right-handed orthonormal triad (a, b, c).
void complete_triad(const Eigen::Vector3d& a, Eigen::Vector3d& b, Eigen::Vector3d& c) {
  Eigen::Index least;
  a.cwiseAbs().minCoeff(&least);
  b = a.cross(Eigen::Vector3d::Unit(least)).normalized();
  c = a.cross(b);
}

mbrt::JointFrame joint_frame(const Model& model, const Joint& j, const std::string& key) {
  for (int body : {j.body1, j.body2}) {
    if (type_row(j.type).rigid_bodies && is_particle(model, body)) {
      throw ModelError(j.where, key,
                       std::string("a ") + type_row(j.type).name + " joint needs rigid bodies; '" +
                           model.body_name(body) + "' is a particle (use spherical or distance)");
    }
  }
  const Pose p1 = initial_pose(model, j.body1);
  const Pose p2 = initial_pose(model, j.body2);
  mbrt::JointFrame f{};
  if (j.type == JointType::velocity_toward) {
    f.s1 = body_point(model, j.body1, j.point1, j.where, key + ".point1");
    f.s2 = body_point(model, j.body2, j.point2, j.where, key + ".point2");
    f.c1 = j.plane_normal;  // a world direction, whatever body 1 does
    return f;
  }
  if (type_row(j.type).ground_contact) {
    // Body 1 is the ground: its "body axes" are world axes.
    f.c1 = j.plane_normal;
    complete_triad(f.c1, f.a1, f.b1);
    f.s1 = j.plane_point;
    f.a2 = p2.R.transpose() * (j.type == JointType::rolling_disk ? j.axis : j.direction);
    // Reactions are taken about the disk's centre, the ball's centre or the knife edge's point.
    if (j.type != JointType::rolling_disk) f.s2 = body_point(model, j.body2, j.point, j.where, key + ".point");
    f.length = j.radius;
    return f;
  }
  if (j.type == JointType::distance) {
    f.s1 = body_point(model, j.body1, j.point1, j.where, key + ".point1");
    f.s2 = body_point(model, j.body2, j.point2, j.where, key + ".point2");
    f.length = j.length;
    return f;
  }
  f.s1 = body_point(model, j.body1, j.point, j.where, key + ".point");
  f.s2 = body_point(model, j.body2, j.point, j.where, key + ".point");
  Eigen::Vector3d a = j.type == JointType::universal ? j.axis1 : j.axis;
  if (j.type == JointType::fixed || j.type == JointType::spherical) a = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d b, c;
  complete_triad(a, b, c);
  f.a1 = p1.R.transpose() * a;
  f.b1 = p1.R.transpose() * b;
  f.c1 = p1.R.transpose() * c;
  f.a2 = p2.R.transpose() * (j.type == JointType::universal ? j.axis2 : a);
  f.b2 = p2.R.transpose() * b;
  f.c2 = p2.R.transpose() * c;
  f.length = 0.0;
  f.pitch = j.lead / (2.0 * M_PI);
  return f;
}

// Blocks coupled through a shared moving body (ground couples nothing).
std::vector<std::vector<int>> coupling(const std::vector<ConstraintBlock>& blocks) {
  const size_t n = blocks.size();
  std::vector<std::vector<int>> out(n);
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < n; ++k) {
      if (i == k) continue;
      const ConstraintBlock& a = blocks[i];
      const ConstraintBlock& b = blocks[k];
      const auto shares = [](int x, const ConstraintBlock& j) { return x != kGround && (x == j.body1 || x == j.body2); };
      if (shares(a.body1, b) || shares(a.body2, b)) out[i].push_back(static_cast<int>(k));
    }
  }
  return out;
}

// The general pattern: every block of S taken as non-zero.
std::vector<std::vector<int>> every_pair(size_t n) {
  std::vector<std::vector<int>> out(n);
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < n; ++k) if (i != k) out[i].push_back(static_cast<int>(k));
  }
  return out;
}

FactorPattern factor_pattern(const std::vector<std::vector<int>>& coupled, const Partition& partition) {
  const int n = static_cast<int>(coupled.size());
  FactorPattern p;
  p.coupled = coupled;
  p.order.resize(static_cast<size_t>(n));
  if (n > 0) {
    std::vector<int> Ap{0}, Ai;
    for (const auto& col : coupled) {
      Ai.insert(Ai.end(), col.begin(), col.end());
      Ap.push_back(static_cast<int>(Ai.size()));
    }
    double control[AMD_CONTROL], info[AMD_INFO];
    amd_defaults(control);
    int status = AMD_OK;
    if (partition.parts > 1) {
      // The parallel step's arrowhead form: the parts' blocks in constraint
      // sets 0 to parts - 1, eliminated in that order, the interface's last.
      double camd_control[CAMD_CONTROL], camd_info[CAMD_INFO];
      camd_defaults(camd_control);
      status = camd_order(n, Ap.data(), Ai.empty() ? nullptr : Ai.data(), p.order.data(), camd_control, camd_info,
                          partition.block_part.data());
    } else {
      status = amd_order(n, Ap.data(), Ai.empty() ? nullptr : Ai.data(), p.order.data(), control, info);
    }
    if (status < AMD_OK) {
      for (int i = 0; i < n; ++i) p.order[static_cast<size_t>(i)] = i;  // keep the natural order
    }
  }
  // Symbolic elimination on the block graph: eliminating k joins its
  // remaining neighbours pairwise (the fill).
  std::vector<std::set<int>> graph(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) graph[static_cast<size_t>(i)].insert(coupled[static_cast<size_t>(i)].begin(), coupled[static_cast<size_t>(i)].end());
  std::vector<bool> eliminated(static_cast<size_t>(n), false);
  p.lower.assign(static_cast<size_t>(n), {});
  for (int k : p.order) {
    std::vector<int> rest;
    for (int i : graph[static_cast<size_t>(k)]) if (!eliminated[static_cast<size_t>(i)]) rest.push_back(i);
    for (int i : rest) {
      for (int m : rest) {
        if (i != m && graph[static_cast<size_t>(i)].insert(m).second && i < m) ++p.fill_blocks;
      }
    }
    p.lower[static_cast<size_t>(k)] = rest;
    eliminated[static_cast<size_t>(k)] = true;
  }
  return p;
}

// The parallel step's parts (docs/parallel.md): the schemes whose step is a
// sequence of the phases the emitter splits, and models large enough to pay.
Partition plan_partition(const Model& model, const Analysis& a, const Specializations& specialize) {
  const int asked = model.solver.parallel_parts;
  const auto serial = [&](const std::string& why) {
    Partition p = partition_blocks(a.constraints, static_cast<int>(model.bodies.size()), 1);
    p.requested = asked;
    p.serial_reason = why;
    return p;
  };
  if (asked <= 1) return serial("");
  const mbrt::Scheme scheme = model.solver.scheme;
  if (scheme != mbrt::Scheme::staggered_pcst && scheme != mbrt::Scheme::baumgarte && scheme != mbrt::Scheme::blajer) {
    throw ModelError(model.solver.parallel_parts_where, "solver.parallel_parts",
                     "the parallel step is built for staggered-pcst, baumgarte and blajer; the scheme is " +
                         std::string(mbrt::scheme_name(scheme)) +
                         (model.solver.scheme_given ? "" : " (the default for this model: give solver.scheme)"));
  }
  if (!model.contacts.empty() || std::any_of(model.joints.begin(), model.joints.end(),
                                             [](const Joint& j) { return j.friction.any(); })) {
    throw ModelError(model.solver.parallel_parts_where, "solver.parallel_parts",
                     "the parallel step does not take contacts or joint friction yet; remove parallel_parts");
  }
  if (!specialize.sparse_factor) return serial("without the sparse_factor specialization S has no arrowhead form");
  Partition p = partition_blocks(a.constraints, static_cast<int>(model.bodies.size()), asked);
  const int fewest = p.part_rows.empty() ? 0 : *std::min_element(p.part_rows.begin(), p.part_rows.end());
  const int least = model.solver.parallel_min_rows >= 0 ? model.solver.parallel_min_rows : kMinRowsPerPart;
  if (p.parts < asked || fewest < std::max(1, least)) {
    return serial(std::to_string(asked) + " parts would hold " + std::to_string(fewest) +
                  " constraint rows in the smallest; below " + std::to_string(least) +
                  " per part (solver.parallel_min_rows) the fork and join of the step's phases would be a large share of "
                  "its work");
  }
  p.pcg = model.solver.parallel_interface == "pcg" && p.interface_rows > 0;
  p.pcg_iterations = model.solver.pcg_iterations > 0 ? model.solver.pcg_iterations : p.interface_rows;
  p.block_preconditioner = model.solver.pcg_preconditioner == "block";
  return p;
}

// Chung and Hulbert's generalized-alpha with spectral radius rho_inf, or
// the trapezoidal rule; the default penalty puts the tangent's shift
// 1/(c alpha) at relative_shift times the largest diagonal entry of S
// (docs/ali3p.md).
Ali3pPlan ali3p_plan(const Model& model, const std::vector<ConstraintBlock>& blocks, const Eigen::VectorXd& s_diagonal) {
  const Ali3pSettings& set = model.solver.ali3p;
  Ali3pPlan p;
  if (set.generalized_alpha) {
    const double r = set.rho_inf;
    p.delta_m = (2.0 * r - 1.0) / (r + 1.0);
    p.delta_f = r / (r + 1.0);
    p.gamma = 0.5 - p.delta_m + p.delta_f;
    p.beta = 0.25 * (1.0 - p.delta_m + p.delta_f) * (1.0 - p.delta_m + p.delta_f);
  }
  const double h = model.solver.step;
  const double c = (1.0 - p.delta_f) / (1.0 - p.delta_m) * p.beta * h * h;
  const double s_max = s_diagonal.size() > 0 ? s_diagonal.maxCoeff() : 0.0;
  p.alpha.assign(blocks.size(), set.alpha > 0.0 ? set.alpha : 1.0 / (c * set.relative_shift * s_max));
  for (const std::pair<std::string, double>& given : set.alpha_of) {
    const std::string& name = given.first;
    const auto it = std::find_if(blocks.begin(), blocks.end(), [&](const ConstraintBlock& b) { return b.name == name; });
    if (it == blocks.end()) {
      throw ModelError(set.alpha_of_where, "solver.ali3p.alpha_of." + name, "no joint or driver named '" + name + "'");
    }
    p.alpha[static_cast<size_t>(it - blocks.begin())] = given.second;
  }
  return p;
}

// The specializations that applied and the code each left out.
std::vector<Skipped> skipped_code(const Model& model, const Analysis& a) {
  const Specializations& on = a.specialize;
  std::vector<Skipped> out;
  const auto count = [&](auto predicate) {
    return static_cast<int>(std::count_if(a.bodies.begin(), a.bodies.end(), predicate));
  };
  const int principal = count([](const BodyPlan& b) { return b.rigid && b.principal_axes; });
  const int isotropic = count([](const BodyPlan& b) { return b.rigid && b.isotropic; });
  const int unloaded = count([](const BodyPlan& b) { return !b.loaded; });
  if (a.particle_count > 0) {
    out.push_back({"particles", std::to_string(a.particle_count) +
                                    " particle(s): no rotational state (the model's contract, also without specializations)"});
  }
  if (principal > 0) {
    out.push_back({"principal_axes", std::to_string(principal) +
                                         " principal-axis bodies: inertia products in M^-1 and the gyroscopic torques"});
  }
  if (isotropic > 0) out.push_back({"isotropic", std::to_string(isotropic) + " isotropic bodies: their gyroscopic torques"});
  if (on.single_stage && !a.velocity_dependent_forces) {
    out.push_back({"single_stage", "no velocity-dependent loads: the second implicit stage"});
  }
  if (on.gravity_free && !a.gravity) out.push_back({"gravity_free", "no gravity: the gravity term of every load"});
  if (on.folded_weights && model.gravity) {
    out.push_back({"folded_weights", "gravity: the products m g, one constant weight per body"});
  }
  if (unloaded > 0) {
    out.push_back({"unloaded_bodies", std::to_string(unloaded) + " bodies without applied loads: their M^-1 F products"});
  }
  if (!a.rheonomic) out.push_back({"no_drivers", "no drivers: the explicit time terms phi_t"});
  const size_t n = a.constraints.size();
  size_t formed = 0;
  for (const auto& col : a.pattern.lower) formed += col.size();
  if (on.sparse_factor && formed < n * (n - 1) / 2) {
    out.push_back({"sparse_factor", std::to_string(n * (n - 1) / 2 - formed) + " of " + std::to_string(n * (n - 1) / 2) +
                                        " off-diagonal blocks of S's factor: zero, never formed"});
  }
  if (a.planar.applies) {
    const Plane plane{a.planar.normal};
    out.push_back({"planar", "motion in the " + plane.name() + " plane: two coordinates and the angle about " +
                                 plane.axis_name() + " per body, " +
                                 std::to_string(a.planar.constraint_rows) + " of " + std::to_string(a.constraint_rows) +
                                 " constraint rows (the in-plane ones)"});
  }
  return out;
}

// The joints' and drivers' constraint blocks, rows numbered in file order.
std::vector<ConstraintBlock> constraint_blocks(const Model& model) {
  std::vector<ConstraintBlock> blocks;
  int rows = 0;
  for (size_t i = 0; i < model.joints.size(); ++i) {
    const Joint& j = model.joints[i];
    const std::string key = "joints[" + std::to_string(i) + "]";
    const JointTypeRow& type = type_row(j.type);
    ConstraintBlock block{.name = j.name,
                          .where = j.where,
                          .source = ConstraintSource::joint,
                          .joint_type = j.type,
                          .kernel = type.kernel,
                          .body1 = j.body1,
                          .body2 = j.body2,
                          .rows = type.rows,
                          .first_row = rows,
                          .frame = joint_frame(model, j, key),
                          .holonomic_rows = type.holonomic_rows,
                          .node1 = j.node1,
                          .node2 = j.node2};
    rows += block.rows;
    blocks.push_back(block);
  }
  for (size_t i = 0; i < model.drivers.size(); ++i) {
    const Driver& d = model.drivers[i];
    const std::string key = "drivers[" + std::to_string(i) + "]";
    const DriverTypeRow& type = type_row(d.type);
    ConstraintBlock block{.name = d.name,
                          .where = d.where,
                          .source = ConstraintSource::driver,
                          .driver_type = d.type,
                          .kernel = type.kernel,
                          .body1 = d.body1,
                          .body2 = d.body2,
                          .rows = type.rows,
                          .first_row = rows,
                          .frame = {},
                          .function = &d.function,
                          .driver = static_cast<int>(i),
                          .holonomic_rows = type.rows};
    if (d.type == DriverType::distance) {
      block.frame.s1 = body_point(model, d.body1, d.point1, d.where, key + ".point1");
      block.frame.s2 = body_point(model, d.body2, d.point2, d.where, key + ".point2");
    } else {
      // The driven joint's own frame: angle and slide are measured from t = 0.
      const size_t joint = static_cast<size_t>(d.joint);
      block.body1 = model.joints[joint].body1;
      block.body2 = model.joints[joint].body2;
      block.node1 = model.joints[joint].node1;
      block.node2 = model.joints[joint].node2;
      block.frame = blocks[joint].frame;
    }
    rows += block.rows;
    blocks.push_back(block);
  }
  return blocks;
}

bool body_state(const Parameter& p) {
  return p.target == ParameterTarget::position || p.target == ParameterTarget::velocity ||
         p.target == ParameterTarget::angular_velocity;
}

// Refuses a runtime parameter the scheme cannot read (docs/parameters.md):
// each scheme's initial state is in its own coordinates.
void check_parameters(const Model& model, const std::vector<Parameter>& params) {
  const mbrt::Scheme scheme = model.solver.scheme;
  const bool tree = mbrt::joint_space(scheme);
  for (const Parameter& p : params) {
    const bool joint_state = p.target == ParameterTarget::joint_coordinate || p.target == ParameterTarget::joint_rate;
    std::string why;
    if (tree && body_state(p)) {
      why = "the tree schemes start from joint coordinates: mark JOINT.coordinate and JOINT.rate instead";
    } else if (!tree && joint_state) {
      why = "joint coordinates are the initial state of the tree schemes (staggered-tree, midpoint-tree, rk4-tree, rk8-tree); "
            "in absolute coordinates mark BODY.position and BODY.velocity instead";
    }
    if (why.empty()) continue;
    throw ModelError(p.where, "tunable", "'" + p.entry + "': scheme " + std::string(mbrt::scheme_name(scheme)) +
                                             " cannot take " + p.name + " at run time; " + why + " (docs/parameters.md)");
  }
}

StepPlan plan_step(const Model& model, const Analysis& a, const std::vector<Parameter>& params) {
  StepPlan p;
  p.scheme = model.solver.scheme;
  const bool pcst = mbrt::pcst_steps(p.scheme);
  const bool baumgarte = p.scheme == mbrt::Scheme::baumgarte && a.constraint_rows > 0;
  p.stages = a.velocity_dependent_forces || baumgarte || !a.specialize.single_stage ? 2 : 1;
  p.position_stage = pcst && !a.constraints.empty();
  p.free_rotation = pcst;
  if (p.scheme == mbrt::Scheme::staggered_tree) {
    // The recursion holds the gyroscopic terms; only dampers make a second
    // pass over the end-of-step rates pay.
    p.stages = 1;
    for (const Force& f : model.forces) p.stages = f.damping != 0.0 ? 2 : p.stages;
    for (const Parameter& t : params) p.stages = t.target == ParameterTarget::spring_damping ? 2 : p.stages;
  }
  // Three fixed-point iterations from the last midpoint's accelerations keep
  // the energy of arms, chains and a 30-link tree within 1.5 % over 20 s at
  // 1 kHz; two let it wander to 8 % (docs/staggered-tree.md, "midpoint-tree").
  if (p.scheme == mbrt::Scheme::midpoint_tree) p.stages = 3;
  if (p.scheme == mbrt::Scheme::rk4_tree || p.scheme == mbrt::Scheme::rk4_projected) p.stages = 4;  // the classical Runge-Kutta method's four
  if (p.scheme == mbrt::Scheme::rk8_tree) p.stages = 12;  // Dormand and Prince's method of order eight
  return p;
}

}  // namespace

mbrt::Scheme default_scheme(const Model& model) {
  if (!model.modal.empty()) return mbrt::Scheme::staggered_pcst;  // the schemes that take modal bodies
  // A tunable body state is the absolute schemes' initial state.
  for (const Parameter& p : parameters(model)) {
    if (body_state(p)) return mbrt::Scheme::staggered_pcst;
  }
  return plan_tree_frames(model, constraint_blocks(model)).refusal.empty() ? mbrt::Scheme::rk4_tree
                                                                          : mbrt::Scheme::staggered_pcst;
}

namespace {

// The contacts in body axes. A contact's body moves freely: the impulses
// act on its mass alone, after the scheme's step, which the constraint forces
// of a joint would have to share (docs/contact.md).
// Mechanisms: bodies joined by joints or drivers (union-find over the
// blocks, ground excluded), each named by its first body.
std::vector<int> mechanisms(const Model& model, const std::vector<ConstraintBlock>& constraints) {
  std::vector<int> root(model.bodies.size());
  for (size_t b = 0; b < root.size(); ++b) root[b] = static_cast<int>(b);
  const auto find = [&](int b) {
    while (root[static_cast<size_t>(b)] != b) b = root[static_cast<size_t>(b)];
    return b;
  };
  for (const ConstraintBlock& block : constraints) {
    if (block.body1 >= 0 && block.body2 >= 0) {
      const int r1 = find(block.body1), r2 = find(block.body2);
      root[static_cast<size_t>(std::max(r1, r2))] = std::min(r1, r2);
    }
  }
  for (size_t b = 0; b < root.size(); ++b) root[b] = find(static_cast<int>(b));
  return root;
}

// A contact's impulse moves its body's whole mechanism (docs/contact.md).
std::vector<ContactPlan> contact_plans(const Model& model, const Analysis& a) {
  std::vector<const ConstraintBlock*> first_block(model.bodies.size(), nullptr);  // a body's first joint or driver
  for (const ConstraintBlock& block : a.constraints) {
    for (const int b : {block.body1, block.body2}) {
      if (b >= 0 && !first_block[static_cast<size_t>(b)]) first_block[static_cast<size_t>(b)] = &block;
    }
  }
  std::vector<ContactPlan> plans;
  for (size_t i = 0; i < model.contacts.size(); ++i) {
    const Contact& c = model.contacts[i];
    const std::string key = "joints." + c.name;
    if (mbrt::joint_space(model.solver.scheme)) {
      throw ModelError(c.where, key,
                       "contacts need a scheme in absolute coordinates, e.g. staggered-pcst (the scheme is " +
                           std::string(mbrt::scheme_name(model.solver.scheme)) + ", whose bodies all hang from joints)");
    }
    // Its middle substep runs backwards in time, where an impact would
    // have to be undone: dissipation is not reversible.
    if (model.solver.scheme == mbrt::Scheme::staggered4) {
      throw ModelError(c.where, key,
                       "contacts need a scheme that steps forward in time, e.g. staggered-pcst (staggered4's middle "
                       "substep runs backwards; docs/schemes.md)");
    }
    const ConstraintBlock* block = first_block[static_cast<size_t>(c.body)];
    const bool in_joint = block != nullptr;
    // Their impulses need S = B M^-1 B^T factorized at the step's end, which
    // staggered-nps (a tree elimination) and ali3p (a leading matrix with
    // M) do not keep.
    if (in_joint && (model.solver.scheme == mbrt::Scheme::staggered_nps || model.solver.scheme == mbrt::Scheme::ali3p)) {
      throw ModelError(c.where, key + ".body",
                       "body '" + model.body_name(c.body) + "' is in " + (block->source == ConstraintSource::joint ? "joint" : "driver") +
                           " '" + block->name + "': contacts on bodies in joints need staggered-pcst, baumgarte, blajer or " +
                           "rk4-projected (the scheme is " + std::string(mbrt::scheme_name(model.solver.scheme)) + "; docs/contact.md)");
    }
    const BodyPlan& body = a.bodies[static_cast<size_t>(c.body)];
    if (body.tunable_mass) {
      throw ModelError(c.where, key + ".body",
                       "body '" + model.body_name(c.body) + "' has a tunable mass or inertia: a contact's body takes the file's values");
    }
    ContactPlan plan{static_cast<int>(i), c.body, Eigen::Vector3d::Zero(), {}, {}, Eigen::Matrix3d::Zero(), a.mechanism[static_cast<size_t>(c.body)], in_joint};
    plan.offset = body_point(model, c.body, c.point, c.where, key + (c.type == ContactType::sphere ? ".center" : ".point"));
    complete_triad(c.plane_normal, plan.tangent1, plan.tangent2);
    if (body.rigid) plan.inverse_inertia = model.bodies[static_cast<size_t>(c.body)].inertia.inverse();
    plans.push_back(plan);
  }
  return plans;
}

}  // namespace

// Joint friction in the absolute-coordinate schemes (docs/friction.md):
// its impulses need S factorized at the step's end, which staggered-nps and
// ali3p do not keep; staggered4's middle substep runs backwards, where
// dissipation cannot; a joint a driver turns does not slip.
static void check_absolute_friction(const Model& model) {
  const mbrt::Scheme scheme = model.solver.scheme;
  if (mbrt::joint_space(scheme)) return;
  for (const Joint& j : model.joints) {
    if (!j.friction.any()) continue;
    const std::string key = "joints." + j.name + ".friction";
    if (scheme == mbrt::Scheme::staggered_nps || scheme == mbrt::Scheme::ali3p) {
      throw ModelError(j.where, key,
                       "joint friction needs staggered-pcst, baumgarte, blajer, rk4-projected or a tree scheme "
                       "(rk4-tree, rk8-tree, midpoint-tree, staggered-tree); the scheme is " +
                           std::string(mbrt::scheme_name(scheme)) + ", which does not keep S's factor (docs/friction.md)");
    }
    if (scheme == mbrt::Scheme::staggered4) {
      throw ModelError(j.where, key,
                       "joint friction needs a scheme that steps forward in time, e.g. staggered-pcst (staggered4's "
                       "middle substep runs backwards; docs/schemes.md)");
    }
    for (const Driver& d : model.drivers) {
      if (d.joint >= 0 && model.joints[static_cast<size_t>(d.joint)].name == j.name) {
        throw ModelError(j.where, key,
                         "joint '" + j.name + "' is driven by '" + d.name + "': a driven joint does not slip, so its friction "
                         "does nothing (docs/friction.md)");
      }
    }
  }
}

// Modal bodies (docs/flexible.md): their modes are clamped at the root, so
// joints attach there or at a node (NAME@K), as do forces and outputs.
// The staggered schemes that step the frame with its reduced mass and the
// modes' momentum take them.
// The modal columns of the constraint Jacobian at t = 0 (undeformed): a
// joint at a modal body's node moves with the node's modes and turns with
// its section's, J_v R (Psi + [s]x Theta) + J_w Theta
// (include/mbrt/modal_body.hpp, modal_node_rows), N columns per modal body.
static Eigen::MatrixXd node_columns(const Model& model, const Analysis& a, const Eigen::MatrixXd& B) {
  std::vector<int> first_column;
  int columns = 0;
  for (const ModalPlan& p : a.modal) first_column.push_back(columns), columns += p.modes;
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(B.rows(), columns);
  for (const ConstraintBlock& c : a.constraints) {
    for (const auto& [body, node] : {std::pair{c.body1, c.node1}, std::pair{c.body2, c.node2}}) {
      if (node < 0) continue;
      const int m = a.bodies[static_cast<size_t>(body)].modal;
      const ModalPlan& p = a.modal[static_cast<size_t>(m)];
      const Eigen::Matrix3d R = mbrt::rotation_matrix(model.bodies[static_cast<size_t>(body)].orientation);
      const ModalNode n = modal_node(p, node);
      out.block(c.first_row, first_column[static_cast<size_t>(m)], c.rows, p.modes) =
          B.block(c.first_row, 6 * body, c.rows, 3) * R * (n.displacement + mbrt::skew(n.point) * n.rotation) +
          B.block(c.first_row, 6 * body + 3, c.rows, 3) * n.rotation;
    }
  }
  // Round-off leaves traces where a bending mode moves a node along the beam
  // (1e-9 of its transverse motion), which would hide the repeats below.
  if (out.size() == 0) return out;
  const double largest = out.cwiseAbs().maxCoeff();
  return (out.array().abs() < 1e-8 * largest).select(0.0, out);
}

// Redundant rows that hold at second order where joints hold modal
// nodes. A repeat among the rows at t = 0 (B^T n = 0) is harmless where, along
// every motion the joints allow (B z = 0), the rows' second-order change
// d2 = z^T Phi'' z is one a first-order correction can cancel (n . d2 = 0):
// a clamped beam propped at its tip, a planar loop. Where it is not (a beam
// of bending modes held at two places along its axis, its frame free to turn:
// turning it to follow the deflection moves the far end along the axis by
// theta^2 L / 2, which its modes cannot), the body could not bend without
// breaking the joints; the step would lock it or fail. d2 comes from the
// rows at +-eps z, the node joints' points moved and axes turned with the modes.
static void refuse_inconsistent_node_joints(const Model& model, const Analysis& a, const Eigen::MatrixXd& B) {
  const auto kernel = [](const Eigen::MatrixXd& m) {
    Eigen::FullPivLU<Eigen::MatrixXd> lu(m);
    lu.setThreshold(1e-10);  // as the rank count's
    return Eigen::MatrixXd(lu.kernel());
  };
  const Eigen::MatrixXd motions = kernel(B), repeats = kernel(B.transpose());
  if (motions.isZero(0.0) || repeats.isZero(0.0)) return;
  const int bodies = static_cast<int>(model.bodies.size());
  std::vector<int> first_column;
  int columns = 6 * bodies;
  for (const ModalPlan& p : a.modal) first_column.push_back(columns), columns += p.modes;
  const auto rows_at = [&](const Eigen::VectorXd& x) {
    Model moved = model;
    for (int i = 0; i < bodies; ++i) {
      Body& b = moved.bodies[static_cast<size_t>(i)];
      b.position += x.segment<3>(6 * i);
      if (!b.particle) b.orientation = mbrt::quaternion_product(b.orientation, mbrt::cayley_increment(x.segment<3>(6 * i + 3)));
    }
    std::vector<ConstraintBlock> blocks = a.constraints;
    for (ConstraintBlock& c : blocks) {
      for (const auto& [body, node, side] : {std::tuple{c.body1, c.node1, 1}, std::tuple{c.body2, c.node2, 2}}) {
        if (node < 0) continue;
        const int m = a.bodies[static_cast<size_t>(body)].modal;
        const ModalPlan& p = a.modal[static_cast<size_t>(m)];
        const ModalNode n = modal_node(p, node);
        const Eigen::VectorXd q = x.segment(first_column[static_cast<size_t>(m)], p.modes);
        (side == 1 ? c.frame.s1 : c.frame.s2) = n.point + n.displacement * q;
        c.frame = mbrt::turned_joint_frame(c.frame, side, mbrt::section_turn(n.rotation * q).C);
      }
    }
    return evaluate_constraints(moved, blocks, 0.0).phi;
  };
  // Along each allowed motion and a few mixtures of them (a quadratic form
  // can vanish on a basis and not between), by differences at +-eps: their
  // error, eps^2 of the rows' fourth derivative plus round-off over eps^2
  // (1e-10 of the model's size), is far below what is taken as a part.
  double size = 1.0;
  for (const Body& b : model.bodies) size = std::max(size, b.position.norm());
  for (const ModalPlan& p : a.modal)
    for (const Eigen::Vector3d& x : p.node_points) size = std::max(size, x.norm());
  Eigen::MatrixXd mixtures(motions.cols(), 4);  // fixed, generic weights: the same answer each run
  for (Eigen::Index j = 0; j < mixtures.rows(); ++j)
    for (Eigen::Index k = 0; k < mixtures.cols(); ++k) mixtures(j, k) = std::sin(1.0 + 0.7 * static_cast<double>((j + 1) * (k + 2)));
  Eigen::MatrixXd along(motions.rows(), motions.cols() + mixtures.cols());
  along << motions, motions * mixtures;
  const double eps = 1e-3;
  const Eigen::VectorXd still = rows_at(Eigen::VectorXd::Zero(columns));
  for (Eigen::Index k = 0; k < along.cols(); ++k) {
    const Eigen::VectorXd z = along.col(k).normalized();
    const Eigen::VectorXd d2 = (rows_at(eps * z) + rows_at(-eps * z) - 2 * still) / (eps * eps);
    for (Eigen::Index r = 0; r < repeats.cols(); ++r) {
      const Eigen::VectorXd n = repeats.col(r).normalized();
      if (std::abs(n.dot(d2)) <= 1e-4 * d2.cwiseAbs().maxCoeff() + 1e-7 * size) continue;
      // The node joint the repeat leans on most.
      const ConstraintBlock* worst = nullptr;
      double weight = 0.0;
      for (const ConstraintBlock& c : a.constraints) {
        const double w = n.segment(c.first_row, c.rows).norm();
        if ((c.node1 >= 0 || c.node2 >= 0) && w > weight) worst = &c, weight = w;
      }
      if (!worst || weight < 1e-9) continue;  // among rigid joints only: not a modal body's
      const int body = worst->node1 >= 0 ? worst->body1 : worst->body2;
      const bool driver = worst->source == ConstraintSource::driver;
      throw ModelError(worst->where, (driver ? "drivers." : "joints.") + worst->name,
                       "its rows repeat the other joints' at t = 0, and part at second order as the bodies move: it holds "
                       "modal body '" + model.body_name(body) + "' at a node along a direction its modes do not move that "
                       "node in (a beam of bending modes held at two places along its axis, free to turn), so it could "
                       "not bend without breaking the joints; free that direction (a distance joint across it instead of "
                       "a spherical one, a revolute instead of a fixed one) or keep a mode that moves the node along it");
    }
  }
}

static std::vector<ModalPlan> modal_plans(const Model& model, Analysis& a) {
  std::vector<ModalPlan> plans;
  for (size_t i = 0; i < model.modal.size(); ++i) {
    const ModalSource& beam = model.modal[i];
    const Body& body = model.bodies[static_cast<size_t>(beam.body)];
    const std::string key = "bodies." + body.name + ".flexible.modes";
    const mbrt::Scheme scheme = model.solver.scheme;
    if (scheme != mbrt::Scheme::staggered_pcst && scheme != mbrt::Scheme::baumgarte && scheme != mbrt::Scheme::blajer) {
      throw ModelError(body.where, key,
                       "a modal body needs staggered-pcst, baumgarte or blajer (the scheme is " +
                           std::string(mbrt::scheme_name(scheme)) + "); or drop modes for a nodal beam");
    }
    if (model.solver.parallel_parts > 1) throw ModelError(body.where, key, "a modal body needs the serial step; remove solver.parallel_parts");
    if (!model.contacts.empty() || std::any_of(model.joints.begin(), model.joints.end(), [](const Joint& j) { return j.friction.any(); })) {
      throw ModelError(body.where, key, "modal bodies do not take contacts or joint friction in the model yet");
    }
    BodyPlan& frame = a.bodies[static_cast<size_t>(beam.body)];
    if (frame.tunable_mass) throw ModelError(body.where, key, "a modal body's mass comes from its beam; it cannot be tunable");
    ModalPlan plan;
    try {
      plan = plan_modal(beam);
    } catch (const std::exception& e) {
      const bool loads = std::string(e.what()).starts_with("static_loads:");
      throw ModelError(body.where, loads ? "bodies." + body.name + ".flexible.static_loads" : key, e.what());
    }
    if (!plan.reduced_inverse.allFinite() || !plan.omega.allFinite() || !plan.St_T.allFinite() || !plan.Sr_T.allFinite()) {
      throw ModelError(body.where, key, "the beam's modes are not finite numbers; check its properties' magnitudes");
    }
    plan.body = beam.body;
    frame.modal = static_cast<int>(i);
    frame.loaded = true;
    frame.isotropic = false;
    a.velocity_dependent_forces = true;  // its centrifugal, Coriolis and gyroscopic terms
    // Attachments: joints where the modes are clamped (a beam's root), which
    // the modes leave moving with the frame; forces there or at the node they name.
    double size = 0.0;
    for (const Eigen::Vector3d& x : plan.node_points) size = std::max(size, x.norm());
    const double tolerance = 1e-6 * size;  // a place copied from a message (6 decimals) must pass
    const auto place = [&](const Eigen::Vector3d& point) {
      const Eigen::Vector3d world = body.position + mbrt::rotation_matrix(body.orientation) * point;
      return "(" + std::to_string(world.x()) + ", " + std::to_string(world.y()) + ", " + std::to_string(world.z()) + " at t = 0)";
    };
    const auto at_root = [&](const Eigen::Vector3d& point, const SourceLocation& where, const std::string& what) {
      std::string mounts;
      for (const int k : plan.clamped) {
        const Eigen::Vector3d& mount = plan.node_points[static_cast<size_t>(k)];
        if ((point - mount).norm() <= tolerance) return;
        mounts += (mounts.empty() ? "" : ", ") + body.name + "@" + plan.node_names[static_cast<size_t>(k)] + " " + place(mount);
      }
      if (!beam.structure) {
        throw ModelError(where, what,
                         "attaches to modal body '" + body.name + "' away from its root; put it at the root " +
                             place(plan.node_points[0]) + ", name a node (" + body.name +
                             "@K) for a force, or use a nodal beam (drop modes)");
      }
      throw ModelError(where, what,
                       "attaches to modal body '" + body.name + "' away from where its modes are clamped" +
                           (mounts.empty() ? std::string(" (its file clamps none: only loads and outputs at its nodes attach to it)")
                                           : "; put it at " + mounts) +
                           ", or name a node (" + body.name + "@NODE) for a force");
    };
    const auto at_node = [&](int node, const Eigen::Vector3d& point, const SourceLocation& where, const std::string& what) {
      if (node < 0) return at_root(point, where, what);
      const Eigen::Vector3d node_point = modal_node(plan, node).point;
      if ((point - node_point).norm() > tolerance) {
        throw ModelError(where, what,
                         "acts at node " + std::to_string(node) + " of modal body '" + body.name + "', which is at " +
                             place(node_point) + "; drop the point or give that one");
      }
    };
    for (const ConstraintBlock& c : a.constraints) {
      if (c.source != ConstraintSource::joint) continue;
      if (c.body1 == beam.body) at_node(c.node1, c.frame.s1, c.where, "joints." + c.name);
      if (c.body2 == beam.body) at_node(c.node2, c.frame.s2, c.where, "joints." + c.name);
    }
    for (const ForcePlan& f : a.forces) {
      const Force& force = model.forces[static_cast<size_t>(f.model_index)];
      const std::string what = "forces[" + std::to_string(f.model_index) + "]";
      if (force.type == ForceType::force && force.body == beam.body) at_node(force.node, f.point, force.where, what + ".point");
      if (force.type == ForceType::spring_damper && force.body1 == beam.body) at_node(force.node1, f.spring.s1, force.where, what + ".point1");
      if (force.type == ForceType::spring_damper && force.body2 == beam.body) at_node(force.node2, f.spring.s2, force.where, what + ".point2");
    }
    plans.push_back(std::move(plan));
  }
  return plans;
}

Analysis analyse(const Model& model, const Specializations& specialize) {
  Analysis a;
  a.specialize = specialize;
  a.gravity = model.gravity.has_value() || !specialize.gravity_free;
  for (size_t i = 0; i < model.bodies.size(); ++i) {
    const Body& b = model.bodies[i];
    BodyPlan plan{static_cast<int>(i), !b.particle, b.particle ? a.particle_count++ : a.rigid_count++, false, false,
                  a.gravity};
    if (plan.rigid) {
      const Eigen::Matrix3d off = b.inertia - Eigen::Matrix3d(b.inertia.diagonal().asDiagonal());
      plan.principal_axes = specialize.principal_axes && off.cwiseAbs().maxCoeff() == 0.0;
      const Eigen::Vector3d d = b.inertia.diagonal();
      plan.isotropic = specialize.isotropic && d.x() == d.y() && d.y() == d.z() && off.cwiseAbs().maxCoeff() == 0.0;
      // staggered-pcst carries the gyroscopic torque in the free rotation of
      // its drift; the other schemes apply it as a load.
      if (!plan.isotropic && !mbrt::pcst_steps(model.solver.scheme)) a.velocity_dependent_forces = plan.loaded = true;
    }
    a.bodies.push_back(plan);
  }
  a.constraints = constraint_blocks(model);
  for (const ConstraintBlock& block : a.constraints) {
    a.nonholonomic = a.nonholonomic || block.holonomic_rows < block.rows;
    a.constraint_rows += block.rows;
  }
  a.rheonomic = !model.drivers.empty() || !specialize.no_drivers;
  const std::vector<Parameter> params = parameters(model);
  check_parameters(model, params);
  a.tunable = !params.empty();
  for (const Parameter& p : params) {
    switch (p.target) {
      case ParameterTarget::gravity: a.specialize.folded_weights = false; break;
      case ParameterTarget::inertia:
        a.bodies[static_cast<size_t>(p.index)].tunable_inertia = true;
        a.bodies[static_cast<size_t>(p.index)].isotropic = false;
        a.bodies[static_cast<size_t>(p.index)].principal_axes = true;  // its moments are the parameters
        [[fallthrough]];
      case ParameterTarget::mass:
        a.bodies[static_cast<size_t>(p.index)].tunable_mass = a.tunable_masses = true;
        a.specialize.folded_weights = false;
        break;
      case ParameterTarget::spring_damping: a.velocity_dependent_forces = true; break;
      case ParameterTarget::position:
      case ParameterTarget::velocity:
      case ParameterTarget::angular_velocity:
      case ParameterTarget::spring_stiffness:
      case ParameterTarget::spring_rest:
      case ParameterTarget::joint_coordinate:
      case ParameterTarget::joint_rate:
      case ParameterTarget::driver_coefficient: break;
    }
  }
  // A tunable inertia may lose its isotropy: its gyroscopic torque is a load
  // where the scheme applies it so (as for any non-isotropic body above).
  for (BodyPlan& b : a.bodies) {
    if (b.tunable_inertia && !mbrt::pcst_steps(model.solver.scheme)) a.velocity_dependent_forces = b.loaded = true;
  }
  for (size_t i = 0; i < model.forces.size(); ++i) {
    const Force& f = model.forces[i];
    const std::string key = "forces[" + std::to_string(i) + "]";
    ForcePlan plan{static_cast<int>(i), {}, {}, {}, Eigen::Vector3d::Zero()};
    switch (f.type) {
      case ForceType::spring_damper:
        plan.spring = {body_point(model, f.body1, f.point1, f.where, key + ".point1"),
                       body_point(model, f.body2, f.point2, f.where, key + ".point2"), f.stiffness, f.damping,
                       f.rest_length};
        if (f.damping != 0.0) a.velocity_dependent_forces = true;
        break;
      case ForceType::torque:
        if (is_particle(model, f.body1) || is_particle(model, f.body2)) {
          throw ModelError(f.where, key, "a torque needs rigid bodies; a particle cannot take one");
        }
        plan.torque = {initial_pose(model, f.body1).R.transpose() * f.axis, f.value};
        break;
      case ForceType::force:
        plan.point = body_point(model, f.body, f.point, f.where, key + ".point");
        break;
      case ForceType::joint_spring:
        plan.joint_spring = {f.stiffness, f.damping, f.rest};
        if (f.damping != 0.0) a.velocity_dependent_forces = true;
        break;
    }
    a.forces.push_back(plan);
  }
  for (const BeamElementSpec& e : model.beam_elements) {
    const Body& b1 = model.bodies[static_cast<size_t>(e.body1)];
    const Body& b2 = model.bodies[static_cast<size_t>(e.body2)];
    Eigen::Matrix3d axes;  // the element's, world at t = 0
    axes.col(0) = (b2.position - b1.position).normalized();
    axes.col(1) = (e.normal - e.normal.dot(axes.col(0)) * axes.col(0)).normalized();
    axes.col(2) = axes.col(0).cross(axes.col(1));
    const BeamSection& c = e.section;
    a.beams.push_back({Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                       mbrt::rotation_matrix(b1.orientation).transpose() * axes,
                       mbrt::rotation_matrix(b2.orientation).transpose() * axes, (b2.position - b1.position).norm(), c.EA,
                       c.GAy, c.GAz, c.GJ, c.EIy, c.EIz, c.damping});
    if (c.damping != 0.0) a.velocity_dependent_forces = true;
  }
  for (size_t i = 0; i < model.inputs.size(); ++i) {
    const Input& in = model.inputs[i];
    if (in.type == InputType::motor_torque) {
      if (is_particle(model, in.body1) || is_particle(model, in.body2)) {
        throw ModelError(in.where, "inputs[" + std::to_string(i) + "]", "a motor_torque needs rigid bodies; a particle cannot take one");
      }
      a.inputs.push_back({in.body1, in.body2, initial_pose(model, in.body1).R.transpose() * in.axis});
      continue;
    }
    // Joint inputs act along the joint's own axis, at its points.
    const Joint& j = model.joints[static_cast<size_t>(in.joint)];
    const mbrt::JointFrame& f = a.constraints[static_cast<size_t>(in.joint)].frame;
    a.inputs.push_back({j.body1, j.body2, f.a1, f.s1, f.s2});
  }
  // Bodies an applied load acts on (gravity and gyroscopic torques marked above).
  const auto load = [&](int body) {
    if (body != kGround) a.bodies[static_cast<size_t>(body)].loaded = true;
  };
  for (const Force& f : model.forces) {
    if (f.type == ForceType::force) load(f.body);
    else load(f.body1), load(f.body2);
  }
  for (const BeamElementSpec& e : model.beam_elements) load(e.body1), load(e.body2);
  for (const InputPlan& in : a.inputs) load(in.body1), load(in.body2);
  if (!specialize.unloaded_bodies) {
    for (BodyPlan& b : a.bodies) b.loaded = true;
  }
  a.modal = modal_plans(model, a);  // before S's diagonal and rank: joints at nodes add columns
  a.partition = plan_partition(model, a, specialize);
  a.pattern = factor_pattern(specialize.sparse_factor ? coupling(a.constraints) : every_pair(a.constraints.size()),
                             a.partition);

  // Scheme parameters (docs/staggered-pcst.md, docs/schemes.md).
  const double h = model.solver.step;
  a.stabilization = model.solver.stabilization > 0.0 ? model.solver.stabilization : 1.0 / h;
  a.baumgarte_alpha = model.solver.baumgarte_alpha > 0.0 ? model.solver.baumgarte_alpha : 0.1 / h;
  a.baumgarte_beta = model.solver.baumgarte_beta > 0.0 ? model.solver.baumgarte_beta : 0.1 / h;
  Eigen::VectorXd s_diagonal;  // of S at t = 0
  if (a.constraint_rows > 0) {
    const StackedConstraints c = evaluate_constraints(model, a.constraints, 0.0);
    // diag(B M^-1 B^T), row by row: B's rows are sparse and M^-1 block-diagonal.
    const Eigen::SparseMatrix<double> rigid = c.B.sparseView();
    const Eigen::SparseMatrix<double> b_m_inv = rigid * inverse_mass_matrix(model);
    const Eigen::MatrixXd modal_columns = node_columns(model, a, c.B);  // unit modal masses
    s_diagonal = b_m_inv.cwiseProduct(rigid) * Eigen::VectorXd::Ones(rigid.cols()) + modal_columns.rowwise().squaredNorm();
    Eigen::MatrixXd every_column(c.B.rows(), c.B.cols() + modal_columns.cols());
    every_column << c.B, modal_columns;
    const Eigen::SparseMatrix<double> b = every_column.sparseView();
    a.regularization = model.solver.penalty * s_diagonal.maxCoeff();
    // Redundant rows (closed planar loops, Bricard's mechanism) leave S singular
    // but for the regularization.
    Eigen::SparseMatrix<double> bt = b.transpose();
    bt.makeCompressed();
    Eigen::SparseQR<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> qr;
    qr.setPivotThreshold(1e-10 * std::max(1.0, b.norm()));
    qr.compute(bt);
    a.redundant_rows = a.constraint_rows - static_cast<int>(qr.rank());
    if (a.redundant_rows > 0 && std::any_of(a.constraints.begin(), a.constraints.end(), [](const ConstraintBlock& c) {
          return c.node1 >= 0 || c.node2 >= 0;
        })) {
      refuse_inconsistent_node_joints(model, a, every_column);
    }
    // The position stage's matrix B(q*) M^-1 B(q(t))^T is not symmetric: with
    // redundant rows, its left and right null spaces differ and a shift as small
    // as S's lets the unreachable part of phi grow. 1e-2 of S's diagonal keeps
    // it bounded (measured on the four-bar and Bricard's mechanism; docs/stability.md).
    // staggered4's six Newton steps need no more than S's shift: with 1e-2 of
    // the diagonal they stall (the four-bar's abs(Phi) at 5e-6, its energy
    // drifting 1.3e-3 J/s); with S's, abs(Phi) stays at 2e-15 over 1000 s.
    const bool small_shift = a.redundant_rows == 0 || model.solver.scheme == mbrt::Scheme::staggered4;
    a.newton_shift = small_shift ? a.regularization : 1e-2 * s_diagonal.maxCoeff();
  }
  if (model.solver.scheme == mbrt::Scheme::ali3p) a.ali3p = ali3p_plan(model, a.constraints, s_diagonal);
  if (model.solver.scheme == mbrt::Scheme::staggered_nps) a.tree = plan_tree(model, a.constraints);
  for (const Joint& j : model.joints) {
    if (j.armature > 0.0 && !mbrt::joint_space(model.solver.scheme)) {
      throw ModelError(j.where, "joints." + j.name + ".armature",
                       "armature needs solver.scheme midpoint-tree or staggered-tree (the scheme is " +
                           std::string(mbrt::scheme_name(model.solver.scheme)) +
                           "): in absolute coordinates a rotor's inertia would couple the two bodies' mass blocks");
    }
  }
  a.mechanism = mechanisms(model, a.constraints);
  a.contacts = contact_plans(model, a);
  check_absolute_friction(model);
  if (model.solver.body_states_on_demand && !mbrt::joint_space(model.solver.scheme)) {
    throw ModelError(model.solver.body_states_where, "solver.body_states",
                     "on_demand needs a tree scheme (rk4-tree, rk8-tree, midpoint-tree, staggered-tree), whose step "
                     "advances joint coordinates; the scheme is " + std::string(mbrt::scheme_name(model.solver.scheme)) +
                         (model.solver.scheme_given ? "" : " (the default for this model: give solver.scheme)") +
                         ", whose step advances the bodies' states themselves (remove solver.body_states or "
                         "--body-states)");
  }
  if (mbrt::joint_space(model.solver.scheme)) {
    a.tree_frames = plan_tree_frames(model, a.constraints);
    if (!a.tree_frames.refusal.empty()) {
      throw ModelError({model.file, 0, 0}, "solver.scheme",
                       std::string(mbrt::scheme_name(model.solver.scheme)) + " needs bodies hanging from ground by revolute and prismatic joints: " +
                           a.tree_frames.refusal + " (use staggered-pcst or staggered-nps)");
    }
  }

  a.step = plan_step(model, a, params);
  a.planar = plan_planar(model, a);
  a.skipped = skipped_code(model, a);
  return a;
}

}  // namespace mbrt::codegen
