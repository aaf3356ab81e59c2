#include "stable_step.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <mbrt/rotation.hpp>

#include "modal_body.hpp"

namespace mbrt::codegen {

namespace {

// Rotation per step (h * fastest rotation) each scheme keeps finite with a
// bounded energy, from the spinning-body stress runs (docs/stability.md):
// staggered-pcst's position stage and free rotation stay finite to about 0.7
// rad per step (energy within 1 % to 0.5, lost beyond 0.85); the schemes whose constraint forces are explicit in the position
// (staggered-nps, baumgarte, blajer) lose a fast pivoted body at about 0.1;
// ali3p stays finite but dissipates beyond about 0.3. staggered4's longest
// substep is 1.70 h (its middle one, backwards): staggered-pcst's 0.7 / 1.70.
// rk8-tree keeps the arm's tool spinning at 1000 rad/s within 0.16 % of its
// energy over 20 s at 3 rad per step, 0.43 % at 4 and 1.4 % at 5.
// A modal body lowers staggered-pcst's to about 0.09 rad per step: a 0.3 m
// tool of three modes pinned at its root and spun up by a constant torque
// failed at 91, 194 and 386 rad/s at steps of 1, 0.5 and 0.25 ms
// (docs/flexible.md); baumgarte and blajer kept it to 0.2 rad per step.
double rotation_per_step(mbrt::Scheme scheme, bool modal) {
  if (modal && scheme == mbrt::Scheme::staggered_pcst) return 0.08;
  switch (scheme) {
    case mbrt::Scheme::staggered4: return 0.7 / 1.70241438391931549;
    case mbrt::Scheme::staggered_pcst:
    case mbrt::Scheme::staggered_tree:
    case mbrt::Scheme::midpoint_tree:
    case mbrt::Scheme::rk4_tree: return 0.7;
    case mbrt::Scheme::rk8_tree: return 3.0;
    case mbrt::Scheme::ali3p:
    case mbrt::Scheme::rk4_projected: return 0.3;
    case mbrt::Scheme::staggered_nps:
    case mbrt::Scheme::blajer:
    case mbrt::Scheme::baumgarte: return 0.1;
  }
  return 0.1;
}

// Upper bounds of each body's distance from the ground point its chain hangs
// from, through the joints (rigid distances add up), and that point; bodies no
// joint path ties to the ground get none.
struct Reach {
  std::vector<double> distance;
  std::vector<Eigen::Vector3d> root;
  std::vector<Eigen::Vector3d> inboard;  // the joint point towards the ground
  std::vector<bool> tied;
};

Eigen::Vector3d joint_point(const Joint& j, int body) {
  if (j.type == JointType::distance) return body == j.body1 ? j.point1 : j.point2;
  return j.point;
}

Reach reach(const Model& m) {
  const size_t n = m.bodies.size();
  Reach r{std::vector<double>(n, 0.0), std::vector<Eigen::Vector3d>(n, Eigen::Vector3d::Zero()),
          std::vector<Eigen::Vector3d>(n, Eigen::Vector3d::Zero()), std::vector<bool>(n, false)};
  for (size_t pass = 0; pass <= n; ++pass) {  // relax along the joints until nothing changes
    bool changed = false;
    for (const Joint& j : m.joints) {
      for (const auto& [from, to] : {std::pair{j.body1, j.body2}, std::pair{j.body2, j.body1}}) {
        if (to == kGround) continue;
        const Eigen::Vector3d q = joint_point(j, to);
        const Eigen::Vector3d& c = m.bodies[static_cast<size_t>(to)].position;
        double d;
        Eigen::Vector3d root;
        if (from == kGround) {
          d = (c - joint_point(j, from)).norm();
          root = joint_point(j, from);
        } else if (r.tied[static_cast<size_t>(from)]) {
          const Eigen::Vector3d& cf = m.bodies[static_cast<size_t>(from)].position;
          d = r.distance[static_cast<size_t>(from)] + (joint_point(j, from) - cf).norm() + (c - q).norm();
          root = r.root[static_cast<size_t>(from)];
        } else {
          continue;
        }
        const size_t t = static_cast<size_t>(to);
        if (!r.tied[t] || d < r.distance[t] - 1e-12) {
          r.tied[t] = true;
          r.distance[t] = d;
          r.root[t] = root;
          r.inboard[t] = q;
          changed = true;
        }
      }
    }
    if (!changed) break;
  }
  return r;
}

// Rigid bodies that cannot turn: tied to the ground through prismatic and
// fixed joints only, which keep their orientation (other joints can only
// constrain them further).
std::vector<bool> rotation_locked(const Model& m) {
  std::vector<bool> locked(m.bodies.size(), false);
  for (size_t pass = 0; pass <= m.bodies.size(); ++pass) {
    bool changed = false;
    for (const Joint& j : m.joints) {
      if (j.type != JointType::prismatic && j.type != JointType::fixed) continue;
      for (const auto& [from, to] : {std::pair{j.body1, j.body2}, std::pair{j.body2, j.body1}}) {
        if (to == kGround || locked[static_cast<size_t>(to)]) continue;
        if (from == kGround || locked[static_cast<size_t>(from)]) changed = locked[static_cast<size_t>(to)] = true;
      }
    }
    if (!changed) break;
  }
  return locked;
}

// Bodies welded together (fixed joints between two bodies) turn as one: each
// body's group, by the index of its first member.
std::vector<size_t> welded_groups(const Model& m) {
  std::vector<size_t> group(m.bodies.size());
  for (size_t i = 0; i < group.size(); ++i) group[i] = i;
  const auto first = [&](size_t i) {
    while (group[i] != i) i = group[i];
    return i;
  };
  for (const Joint& j : m.joints) {
    if (j.type != JointType::fixed || j.body1 == kGround || j.body2 == kGround) continue;
    const size_t a = first(static_cast<size_t>(j.body1)), b = first(static_cast<size_t>(j.body2));
    group[std::max(a, b)] = std::min(a, b);
  }
  for (size_t i = 0; i < group.size(); ++i) group[i] = first(i);
  return group;
}

// Rigid bodies in no joint or driver with equal principal moments (a ball
// on contacts, docs/contact.md): no gyroscopic torque, and their rotation
// moves no joint, so its rate does not bound the step (every scheme turns
// the Euler parameters by an orthogonal map).
std::vector<bool> free_isotropic(const Model& m) {
  std::vector<bool> out(m.bodies.size(), false);
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    const Eigen::Matrix3d& inertia = m.bodies[i].inertia;
    out[i] = !m.bodies[i].particle && inertia.isApprox(inertia(0, 0) * Eigen::Matrix3d::Identity(), 1e-12);
  }
  const auto joined = [&](int b) {
    if (b != kGround) out[static_cast<size_t>(b)] = false;
  };
  for (const Joint& j : m.joints) joined(j.body1), joined(j.body2);
  for (const Driver& d : m.drivers) joined(d.body1), joined(d.body2);
  return out;
}

double kinetic_energy(const Body& b) {
  double t = 0.5 * b.mass * b.velocity.squaredNorm();
  if (!b.particle) t += 0.5 * b.angular_velocity.dot(b.inertia * b.angular_velocity);
  return t;
}

std::string format(double x) {
  std::ostringstream o;
  o.precision(3);
  o << x;
  return o.str();
}

}  // namespace

StableStep estimate_stable_step(const Model& m, const std::vector<ModalPlan>& modal_plans) {
  StableStep s;
  s.rotation_per_step = rotation_per_step(m.solver.scheme, !m.modal.empty());
  const Reach r = reach(m);
  double energy = 0.0;
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    const Body& b = m.bodies[i];
    energy += kinetic_energy(b);
    if (m.gravity && r.tied[i]) {
      const double g = m.gravity->norm();
      if (g > 0.0) {
        const Eigen::Vector3d down = *m.gravity / g;
        energy += b.mass * g * std::max(0.0, down.dot(r.root[i] - b.position) + r.distance[i]);
      }
    }
  }
  bool loads = false;
  auto inverse_mass = [&](int b) { return b == kGround ? 0.0 : 1.0 / m.bodies[static_cast<size_t>(b)].mass; };
  // 1 / (the body's moment of inertia about a world axis through its COM):
  // the pin's is larger, so the frequency below is an upper bound.
  auto inverse_moment = [&](int b, const Eigen::Vector3d& axis) {
    if (b == kGround) return 0.0;
    const Body& body = m.bodies[static_cast<size_t>(b)];
    const Eigen::Matrix3d r = mbrt::rotation_matrix(body.orientation);
    return 1.0 / axis.dot(r * body.inertia * r.transpose() * axis);
  };
  auto stiffest = [&](double w, const std::string& element) {
    if (w > s.stiffest_frequency) {
      s.stiffest_frequency = w;
      s.stiffest_element = element;
    }
  };
  for (const Force& f : m.forces) {
    switch (f.type) {
      case ForceType::spring_damper: {
        const double stretch = (f.point2 - f.point1).norm() - f.rest_length;  // points: world at t = 0
        energy += 0.5 * f.stiffness * stretch * stretch;
        stiffest(std::sqrt(f.stiffness * (inverse_mass(f.body1) + inverse_mass(f.body2))),
                 "spring_damper " + m.body_name(f.body1) + " - " + m.body_name(f.body2));
        break;
      }
      case ForceType::joint_spring: {
        const Joint& j = m.joints[static_cast<size_t>(f.joint)];
        energy += 0.5 * f.stiffness * f.rest * f.rest;  // the joint coordinate is 0 at t = 0
        const double compliance = j.type == JointType::revolute
                                      ? inverse_moment(j.body1, j.axis) + inverse_moment(j.body2, j.axis)
                                      : inverse_mass(j.body1) + inverse_mass(j.body2);
        stiffest(std::sqrt(f.stiffness * compliance), "joint_spring " + j.name);
        break;
      }
      case ForceType::torque:
      case ForceType::force: loads = true; break;
    }
  }
  // A beam element's stiffest mode, as for a chain of equal elements (twice a
  // single spring's square: a node between two): its stretch or shear
  // against the nodes' masses, its twist against their moments about the
  // element, its bending and the shear of a turned end against their
  // smaller bending moments of inertia.
  for (const BeamElementSpec& e : m.beam_elements) {
    const Body& b1 = m.bodies[static_cast<size_t>(e.body1)];
    const Body& b2 = m.bodies[static_cast<size_t>(e.body2)];
    const BeamSection& c = e.section;
    const double l = (b2.position - b1.position).norm();
    const double shear = std::max(c.GAy, c.GAz);
    const double translation = std::max(c.EA, shear) / l * (1 / b1.mass + 1 / b2.mass);
    const double twist = c.GJ / l * (1 / b1.inertia(0, 0) + 1 / b2.inertia(0, 0));
    const double bending = (std::max(c.EIy, c.EIz) / l + shear * l / 4) *
                           (1 / std::min(b1.inertia(1, 1), b1.inertia(2, 2)) + 1 / std::min(b2.inertia(1, 1), b2.inertia(2, 2)));
    // Explicit stiffness-proportional damping lowers the limit to
    // (2 / w) (sqrt(1 + z^2) - z), z = damping w / 2: as a higher frequency.
    const double w = std::sqrt(2 * std::max({translation, twist, bending})), z = c.damping * w / 2;
    stiffest(w / (std::sqrt(1 + z * z) - z), "beam element " + b1.name + " - " + b2.name);
  }
  // A modal body's highest mode: its elastic and damping forces are explicit
  // (central difference: h < 2 / w, with the damping as above). The modes
  // are clamped to the frame, but the frame moves with them: with the frame
  // free (what the body's joints can only lower) they are stiffer, by the
  // mass the frame takes, M0 = [M_rigid, S; S^T, I] against diag(0, w^2).
  for (size_t i = 0; i < m.modal.size(); ++i) {
    const ModalSource& beam = m.modal[i];
    const ModalPlan p = i < modal_plans.size() ? modal_plans[i] : plan_modal(beam);
    s.lowest_mode.push_back(p.omega[0]);
    const int n = p.modes;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(6 + n, 6 + n), K = Eigen::MatrixXd::Zero(6 + n, 6 + n);
    M.topLeftCorner<3, 3>() = p.m * Eigen::Matrix3d::Identity();
    M.block<3, 3>(3, 3) = p.J;
    M.topRightCorner(3, n) = p.St_T.transpose();
    M.block(3, 6, 3, n) = p.Sr_T.transpose();
    M.bottomLeftCorner(n, 6) = M.topRightCorner(6, n).transpose();
    M.bottomRightCorner(n, n) = Eigen::MatrixXd::Identity(n, n);
    K.bottomRightCorner(n, n) = p.omega.cwiseAbs2().asDiagonal();
    // A spring at a node stiffens the modes: k J^T J, J the node's motion
    // [I, -[x]x, Psi] in body axes, summed over the three directions (an
    // upper bound on the one it pulls along); a joint spring at a node, its
    // section's turn about the joint's axis a, a^T [0, I, Theta], or for a
    // prismatic joint the node's motion along it, a^T [I, -[x]x, Psi].
    const Eigen::Matrix3d to_body = mbrt::rotation_matrix(m.bodies[static_cast<size_t>(beam.body)].orientation).transpose();
    for (const Force& f : m.forces) {
      if (f.type == ForceType::joint_spring) {
        const Joint& j = m.joints[static_cast<size_t>(f.joint)];
        for (const auto& [body, node] : {std::pair{j.body1, j.node1}, std::pair{j.body2, j.node2}}) {
          if (body != beam.body || node < 0) continue;
          const Eigen::RowVector3d a = (to_body * j.axis).transpose();
          const ModalNode x = modal_node(p, node);
          Eigen::RowVectorXd J(6 + n);
          if (j.type == JointType::prismatic) {
            J << a, -a * mbrt::skew(x.point), a * x.displacement;
          } else {
            J << Eigen::RowVector3d::Zero(), a, a * x.rotation;
          }
          K += f.stiffness * J.transpose() * J;
        }
      }
      if (f.type != ForceType::spring_damper) continue;
      for (const auto& [body, node] : {std::pair{f.body1, f.node1}, std::pair{f.body2, f.node2}}) {
        if (body != beam.body || node < 0) continue;
        const ModalNode x = modal_node(p, node);
        Eigen::MatrixXd J(3, 6 + n);
        J << Eigen::Matrix3d::Identity(), -mbrt::skew(x.point), x.displacement;
        K += f.stiffness * J.transpose() * J;
      }
    }
    const double w = std::sqrt(Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd>(K, M).eigenvalues().maxCoeff());
    const double z = beam.structure ? beam.damping_ratio : beam.damping * w / 2;  // modal or stiffness-proportional
    stiffest(w / (std::sqrt(1 + z * z) - z), "modal body " + m.body_name(beam.body) + " (" + std::to_string(n) +
                                                 " modes, the highest " + std::to_string(p.omega.maxCoeff()) +
                                                 " rad/s clamped, " + std::to_string(w) + " with its frame free)");
  }
  s.energy_bound = energy;
  const std::vector<bool> locked = rotation_locked(m);
  const std::vector<bool> free_sphere = free_isotropic(m);
  // Each welded group's inertia about the joint it hangs from (parallel
  // axes), as if that joint stood still: a whipped tip link turns about it.
  // That joint is its member's nearest the ground along the joints (the
  // others' inboard joints are its welds); a group no joint ties to the
  // ground turns about its centre of mass.
  const std::vector<size_t> group = welded_groups(m);
  std::vector<size_t> hangs_from(m.bodies.size());
  std::vector<Eigen::Vector3d> centre(m.bodies.size(), Eigen::Vector3d::Zero());
  std::vector<double> mass(m.bodies.size(), 0.0);
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    const size_t g = group[i];
    size_t& k = hangs_from[g];
    if (g == i || (r.tied[i] && (!r.tied[k] || r.distance[i] < r.distance[k]))) k = i;
    centre[g] += m.bodies[i].mass * m.bodies[i].position;
    mass[g] += m.bodies[i].mass;
  }
  for (size_t g = 0; g < m.bodies.size(); ++g) {
    if (group[g] == g) centre[g] = r.tied[hangs_from[g]] ? r.inboard[hangs_from[g]] : Eigen::Vector3d(centre[g] / mass[g]);
  }
  std::vector<Eigen::Matrix3d> group_inertia(m.bodies.size(), Eigen::Matrix3d::Zero());
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    const Body& b = m.bodies[i];
    Eigen::Matrix3d& inertia = group_inertia[group[i]];
    if (!b.particle) {
      const Eigen::Quaterniond q(b.orientation[0], b.orientation[1], b.orientation[2], b.orientation[3]);
      const Eigen::Matrix3d rot = q.toRotationMatrix();
      inertia += rot * b.inertia * rot.transpose();
    }
    const Eigen::Vector3d d = b.position - centre[group[i]];
    inertia += b.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  s.rotation_bound.assign(m.bodies.size(), 0.0);
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    const Body& b = m.bodies[i];
    const bool modal = std::any_of(m.modal.begin(), m.modal.end(), [&](const ModalSource& x) { return x.body == static_cast<int>(i); });
    if (b.particle || locked[i] || (free_sphere[i] && !modal)) continue;
    const Eigen::Matrix3d& inertia = group_inertia[group[i]];
    const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(inertia).eigenvalues();
    const double bound = std::max(b.angular_velocity.norm(), std::sqrt(2.0 * energy / moments[1]));
    s.rotation_bound[i] = bound;
    if (bound > s.fastest_rotation) {
      s.fastest_rotation = bound;
      s.fastest_body = b.name;
    }
  }
  double step = 0.0;
  if (s.fastest_rotation > 0.0) step = s.rotation_per_step / s.fastest_rotation;
  if (s.stiffest_frequency > 0.0) {
    const double spring = 2.0 / s.stiffest_frequency;
    step = step > 0.0 ? std::min(step, spring) : spring;
  }
  s.stable_step = step;
  s.exceeded = step > 0.0 && m.solver.step > step;
  if (loads || !m.inputs.empty() || !m.drivers.empty()) {
    s.note = "torques, forces, inputs and drivers can add energy beyond this bound";
  }
  return s;
}

std::string stable_step_warning(const Model& m, const StableStep& s) {
  if (!s.exceeded) return "";
  std::ostringstream o;
  o << "warning: " << m.name << ": step " << format(m.solver.step) << " s is above the stable step "
    << format(s.stable_step) << " s that " << mbrt::scheme_name(m.solver.scheme) << " is estimated to allow: ";
  const bool rotation = s.fastest_rotation > 0.0 && s.rotation_per_step / s.fastest_rotation <= s.stable_step * 1.0000001;
  if (rotation) {
    o << "body " << s.fastest_body << " could turn at " << format(s.fastest_rotation) << " rad/s about the joint it hangs from"
      << " with the " << format(s.energy_bound) << " J the scene can release, and " << mbrt::scheme_name(m.solver.scheme)
      << " stays finite to about " << format(s.rotation_per_step) << " rad per step";
  } else {
    o << s.stiffest_element << " oscillates at " << format(s.stiffest_frequency)
      << " rad/s and the explicit stage needs h * omega < 2";
  }
  o << " (docs/stability.md)";
  const double pcst = rotation_per_step(mbrt::Scheme::staggered_pcst, !m.modal.empty());
  if (rotation && s.rotation_per_step < pcst) o << "; staggered-pcst allows about " << format(pcst) << " rad per step";
  return o.str();
}

std::string modal_spin_warning(const Model& m, const StableStep& s) {
  std::ostringstream o;
  for (size_t i = 0; i < m.modal.size(); ++i) {
    const ModalSource& source = m.modal[i];
    if (!source.structure || source.structure->spin_stiffens()) continue;
    const double spin = s.rotation_bound[static_cast<size_t>(source.body)], lowest = s.lowest_mode[i];
    if (spin <= kModalSpinLimit * lowest) continue;
    if (!o.str().empty()) o << "\n";
    o << "warning: " << m.name << ": modal body " << m.body_name(source.body) << " (from " << source.structure->file
      << ") has no geometric stiffness of spin, and with the " << format(s.energy_bound) << " J the scene can release it could turn at "
      << format(spin) << " rad/s, " << format(spin / lowest) << " of its lowest mode's " << format(lowest)
      << " rad/s: spin softens such modes where it should stiffen them, by about (spin / omega)^2; keep it below "
      << kModalSpinLimit << " of that, give its data file geometric_stiffness or model it as a beam (docs/flexible.md)";
  }
  return o.str();
}

// The figures are measured: docs/staggered-tree.md, "Energy".
std::string tree_energy_warning(const Model& m) {
  if (m.solver.scheme != mbrt::Scheme::staggered_tree || m.joints.size() < 2 || m.solver.step <= kTreeEnergyStep) {
    return "";
  }
  std::ostringstream o;
  o << "warning: " << m.name << ": staggered-tree at step " << format(m.solver.step)
    << " s: its kick-drift-kick in joint coordinates is not symplectic, so on trees of several links the energy"
    << " wanders: over 20 s at 1e-3 s it drifted 3 to 52 % on a 7-link arm and 28 % on a 32-link chain, and a"
    << " 30-link humanoid went non-finite after 17 s; at " << format(kTreeEnergyStep)
    << " s and below it holds 1 % (docs/staggered-tree.md). rk4-tree (the default for trees) holds them within 0.25 % over 20 s at 1e-3 s";
  return o.str();
}

}  // namespace mbrt::codegen
