#include "tree_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace timing::tree {

Mat3 rotation(const Eigen::Vector4d& e) { return Eigen::Quaterniond(e[0], e[1], e[2], e[3]).toRotationMatrix(); }

Vec3 gravity(const Model& m) { return m.gravity.value_or(Vec3::Zero()); }

std::vector<BodyState> model_states(const Model& m) {
  std::vector<BodyState> out;
  for (const Body& b : m.bodies) {
    const Mat3 R = rotation(b.orientation);
    out.push_back({b.position, b.velocity, R * b.angular_velocity, R});
  }
  return out;
}

Energy energy(const Model& m, const std::vector<BodyState>& s) {
  Energy e;
  const Vec3 g = gravity(m);
  for (std::size_t i = 0; i < m.bodies.size(); ++i) {
    const Body& b = m.bodies[i];
    const Vec3 w_body = s[i].R.transpose() * s[i].w;
    e.kinetic += 0.5 * b.mass * s[i].v.squaredNorm() + 0.5 * w_body.dot(b.inertia * w_body);
    e.potential -= b.mass * g.dot(s[i].r);
  }
  return e;
}

std::vector<Link> links(const Model& m) {
  if (!m.forces.empty() || !m.drivers.empty())
    throw std::runtime_error("only bodies, joints and gravity are supported (the model has forces or drivers)");
  for (const Body& b : m.bodies)
    if (b.particle) throw std::runtime_error("body " + b.name + " is a particle; only rigid bodies are supported");
  for (const Joint& j : m.joints) {
    if (j.type != JointType::revolute && j.type != JointType::spherical)
      throw std::runtime_error("joint " + j.name + ": only revolute and spherical joints are supported");
    if (j.armature != 0.0) throw std::runtime_error("joint " + j.name + ": armature is not supported");
  }
  if (m.joints.size() != m.bodies.size())
    throw std::runtime_error("the joints do not form a tree from ground (one joint per body needed)");
  // Breadth first from ground; a joint may name the parent as body1 or body2.
  std::vector<Link> out;
  std::vector<bool> placed(m.bodies.size(), false);
  std::vector<int> frontier{kGround};
  for (std::size_t k = 0; k < frontier.size(); ++k) {
    for (const Joint& j : m.joints) {
      const int child = j.body1 == frontier[k] ? j.body2 : j.body2 == frontier[k] ? j.body1 : kGround - 1;
      if (child < 0 || placed[static_cast<std::size_t>(child)]) continue;
      placed[static_cast<std::size_t>(child)] = true;
      out.push_back({child, frontier[k], &j});
      frontier.push_back(child);
    }
  }
  if (out.size() != m.bodies.size())
    throw std::runtime_error("the joints do not form a tree from ground (a loop, or a body not connected to ground)");
  return out;
}

Vec3 relative_angular_velocity(const std::vector<BodyState>& s, const Link& l) {
  return s[static_cast<std::size_t>(l.body)].w - (l.parent == kGround ? Vec3::Zero() : s[static_cast<std::size_t>(l.parent)].w);
}

std::string initial_mismatch(const Model& m, const std::vector<BodyState>& engine) {
  const std::vector<BodyState> model = model_states(m);
  double length = 1, speed = 1, dr = 0, dR = 0, dv = 0;
  for (std::size_t i = 0; i < model.size(); ++i) {
    length = std::max(length, model[i].r.norm());
    speed = std::max({speed, model[i].v.norm(), model[i].w.norm()});
    dr = std::max(dr, (engine[i].r - model[i].r).norm());
    dR = std::max(dR, (engine[i].R - model[i].R).cwiseAbs().maxCoeff());
    dv = std::max({dv, (engine[i].v - model[i].v).norm(), (engine[i].w - model[i].w).norm()});
  }
  const Energy e_model = energy(m, model);
  const double dE = std::abs(energy(m, engine).total() - e_model.total());
  const double energy_scale = std::max(std::abs(e_model.total()), e_model.kinetic + std::abs(e_model.potential));
  char text[400];
  std::snprintf(text, sizeof text,
                "COM position %.3g m, orientation %.3g, velocity %.3g (m/s or rad/s), energy %.3g J (relative %.3g)",
                dr, dR, dv, dE, energy_scale > 0 ? dE / energy_scale : 0.0);
  const bool ok = dr <= 1e-9 * length && dR <= 1e-9 && dv <= 1e-9 * speed && dE <= 1e-9 * energy_scale;
  return ok ? "" : text;
}

}  // namespace timing::tree
