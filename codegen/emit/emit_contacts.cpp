// The contacts' part of a generated model (docs/contact.md): index names,
// State's contact fields, and the data and body views struct Model hands to
// mbrt::contact_step (include/mbrt/contacts.hpp).
#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "emitter.hpp"

namespace mbrt::codegen {

void Emitter::contact_declarations(std::ostringstream& o) const {
  o << "// The contacts (docs/contact.md), contact:: indices into State's contact fields.\n"
    << "inline constexpr int kContacts = " << a_.contacts.size() << ";\nnamespace contact {\n";
  for (size_t i = 0; i < a_.contacts.size(); ++i) {
    o << "inline constexpr int " << m_.contacts[i].name << " = " << i << ";\n";
  }
  o << "}  // namespace contact\n\n";
}

std::string Emitter::contact_names() const {
  std::string names;
  for (const Contact& c : m_.contacts) names += (names.empty() ? "\"" : ", \"") + c.name + "\"";
  return names;
}

// Gauss-Seidel sweeps per step, for bodies neither the stick nor the slide
// trial holds (some contacts stick, others slide): half with the static
// limits, half with the kinetic ones; two per contact of the body with the
// most, at least four, warm-started from the last step (docs/contact.md).
int Emitter::contact_sweeps() const {
  std::map<int, int> per_body;
  int most = 0;
  for (const ContactPlan& c : a_.contacts) most = std::max(most, ++per_body[c.body]);
  return std::max(4, 2 * most);
}

// Each body's contacts, padded with -1 to the most any body has: the
// trials solve them together (include/mbrt/contact_trials.hpp).
std::string Emitter::contact_groups() const {
  std::map<int, std::vector<int>> by_body;
  std::vector<int> order;  // bodies in order of their first contact
  for (size_t i = 0; i < a_.contacts.size(); ++i) {
    const int body = a_.contacts[i].body;
    if (by_body.find(body) == by_body.end()) order.push_back(body);
    by_body[body].push_back(static_cast<int>(i));
  }
  size_t most = 0;
  for (const auto& entry : by_body) most = std::max(most, entry.second.size());
  std::string groups;
  for (const int body : order) {
    std::vector<int> members = by_body[body];
    members.resize(most, -1);
    std::string list;
    for (const int m : members) list += (list.empty() ? "" : ", ") + std::to_string(m);
    groups += "    {{" + list + "}},  // " + m_.bodies[static_cast<size_t>(body)].name + "\n";
  }
  return "static constexpr std::array<mbrt::ContactGroup<" + std::to_string(most) + ">, " + std::to_string(order.size()) +
         "> kContactGroups{{  // each body's contacts\n" + groups + "}};\n";
}

void Emitter::contact_members(std::ostringstream& o) const {
  const double g = m_.gravity ? m_.gravity->norm() : 0.0;
  o << "static constexpr int kContacts = mbrt::models::" << m_.name << "::kContacts;\n"
    << "static constexpr int kContactSweeps = " << contact_sweeps() << ";  // Gauss-Seidel sweeps per step\n"
    << contact_groups()
    << "// Approach speeds below 2 |g| h do not bounce: a resting body settles.\n"
    << "static constexpr double kBounceSpeed = " << num(2.0 * g * m_.solver.step) << ";\n"
    << "// offset (body axes), radius, plane point, normal, tangents, 1/m, J^-1 (body axes), mu_s, mu_k, e\n"
    << "static inline const std::array<mbrt::ContactPoint, kContacts> kContactPoints{{\n";
  for (const ContactPlan& p : a_.contacts) {
    const Contact& c = m_.contacts[static_cast<size_t>(p.model_index)];
    o << "    {" << vec3(p.offset) << ", " << num(c.radius) << ", " << vec3(c.plane_point) << ",\n     "
      << vec3(c.plane_normal) << ", " << vec3(p.tangent1) << ", " << vec3(p.tangent2) << ",\n     "
      << num(1.0 / m_.bodies[static_cast<size_t>(p.body)].mass) << ", " << mat3(p.inverse_inertia) << ",\n     "
      << num(c.mu_static) << ", " << num(c.mu_kinetic) << ", " << num(c.restitution) << "},  // " << c.name << "\n";
  }
  o << "}};\n"
    << "static std::array<mbrt::ContactBody, kContacts> contact_bodies(State& s) noexcept {\n  return {{\n";
  for (const ContactPlan& p : a_.contacts) {
    const std::string st = state_of(p.body);
    if (plan(p.body).rigid) {
      o << "      {&" << st << ".r, &" << st << ".p, &" << st << ".v, &" << st << ".w},\n";
    } else {
      o << "      {&" << st << ".r, nullptr, &" << st << ".v, nullptr},\n";
    }
  }
  o << "  }};\n}\n";
}

}  // namespace mbrt::codegen
