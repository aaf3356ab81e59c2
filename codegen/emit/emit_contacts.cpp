// The contacts' part of a generated model (docs/contact.md): index names,
// State's contact fields, and the data and body views struct Model hands to
// mbrt::contact_step (include/mbrt/contacts.hpp).
#include <algorithm>
#include <functional>
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

// The contacts of each mechanism (a free body, or bodies joined by joints
// or drivers), in order of their first contact.
static std::vector<std::vector<int>> contacts_by_mechanism(const std::vector<ContactPlan>& contacts) {
  std::map<int, size_t> slot;
  std::vector<std::vector<int>> groups;
  for (size_t i = 0; i < contacts.size(); ++i) {
    const auto [at, added] = slot.emplace(contacts[i].mechanism, groups.size());
    if (added) groups.emplace_back();
    groups[at->second].push_back(static_cast<int>(i));
  }
  return groups;
}

// Gauss-Seidel sweeps per step, for mechanisms neither the stick nor the
// slide trial holds (some contacts stick, others slide): half with the
// static limits, half with the kinetic ones; two per contact of the
// mechanism with the most, at least four, warm-started from the last step
// (docs/contact.md).
int Emitter::contact_sweeps() const {
  size_t most = 0;
  for (const auto& group : contacts_by_mechanism(a_.contacts)) most = std::max(most, group.size());
  return std::max(4, 2 * static_cast<int>(most));
}

// Each mechanism's contacts, padded with -1 to the most any has: the trials
// solve them together (include/mbrt/contact_trials.hpp).
std::string Emitter::contact_groups() const {
  const auto by_mechanism = contacts_by_mechanism(a_.contacts);
  size_t most = 0;
  for (const auto& group : by_mechanism) most = std::max(most, group.size());
  std::string groups;
  for (std::vector<int> members : by_mechanism) {
    const int first = a_.contacts[static_cast<size_t>(members[0])].body;
    members.resize(most, -1);
    std::string list;
    for (const int m : members) list += (list.empty() ? "" : ", ") + std::to_string(m);
    groups += "    {{" + list + "}},  // " + m_.bodies[static_cast<size_t>(first)].name +
              (a_.contacts[static_cast<size_t>(members[0])].jointed ? "'s mechanism" : "") + "\n";
  }
  return "static constexpr std::array<mbrt::ContactGroup<" + std::to_string(most) + ">, " + std::to_string(by_mechanism.size()) +
         "> kContactGroups{{  // each mechanism's contacts\n" + groups + "}};\n";
}

void Emitter::contact_members(std::ostringstream& o) const {
  const double g = m_.gravity ? m_.gravity->norm() : 0.0;
  const bool jointed = std::any_of(a_.contacts.begin(), a_.contacts.end(), [](const ContactPlan& p) { return p.jointed; });
  o << "static constexpr int kContacts = mbrt::models::" << m_.name << "::kContacts;\n"
    << "static constexpr int kContactSweeps = " << contact_sweeps() << ";  // Gauss-Seidel sweeps per step\n"
    << contact_groups()
    << "// A contact's body is in a joint or driver: its impulses move the mechanism.\n"
    << "static constexpr bool kJointedContacts = " << (jointed ? "true" : "false") << ";\n"
    << "// Approach speeds below 2 |g| h do not bounce: a resting body settles.\n"
    << "static constexpr double kBounceSpeed = " << num(2.0 * g * m_.solver.step) << ";\n"
    << "// body, jointed, offset (body axes), radius, plane point, normal, tangents, 1/m, J^-1 (body axes), mu_s, mu_k, e\n"
    << "static inline const std::array<mbrt::ContactPoint, kContacts> kContactPoints{{\n";
  for (const ContactPlan& p : a_.contacts) {
    const Contact& c = m_.contacts[static_cast<size_t>(p.model_index)];
    o << "    {body::" << m_.bodies[static_cast<size_t>(p.body)].name << ", " << (p.jointed ? "true" : "false") << ", " << vec3(p.offset) << ", " << num(c.radius) << ", " << vec3(c.plane_point) << ",\n     "
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
  displace_function(o);
  if (jointed) mechanism_kernels(o);
}

void Emitter::displace_function(std::ostringstream& o) const {
  o << "// (dq, s) => (s): positions moved by dq = [dr; body-axes rotation vector] per body.\n"
    << "static void displace(const BodyVectors& dq, State& s) noexcept {\n";
  for (size_t i = 0; i < m_.bodies.size(); ++i) {
    const std::string st = state_of(static_cast<int>(i));
    o << "  " << st << ".r += dq" << at(static_cast<int>(i)) << ".head<3>();\n";
    if (a_.bodies[i].rigid) {
      o << "  " << st << ".p = mbrt::quaternion_product(" << st << ".p, mbrt::cayley_increment(dq" << at(static_cast<int>(i))
        << ".tail<3>()));\n";
    }
  }
  o << "}\n";
}

// B u, S^-1 x and u -= scale M^-1 B^T lambda over one contact mechanism's
// joints (a kContactGroups index): a contact's impulse moves only its own
// mechanism, so its columns of K need only its rows of S.
void Emitter::mechanism_kernels(std::ostringstream& o) const {
  const auto groups = contacts_by_mechanism(a_.contacts);
  std::vector<std::vector<bool>> blocks_of(groups.size());
  for (size_t g = 0; g < groups.size(); ++g) {
    const int mechanism = a_.contacts[static_cast<size_t>(groups[g][0])].mechanism;
    for (int j = 0; j < blocks(); ++j) {
      const auto moving = moving_bodies(j);
      blocks_of[g].push_back(!moving.empty() && a_.mechanism[static_cast<size_t>(moving[0])] == mechanism);
    }
  }
  const auto cases = [&](const std::function<std::string(const std::vector<bool>&)>& lines) {
    std::string text = "  switch (group) {\n";
    for (size_t g = 0; g < groups.size(); ++g) {
      const std::string body = lines(blocks_of[g]);
      if (!body.empty()) text += "    case " + std::to_string(g) + ":\n" + body + "      break;\n";
    }
    return text + "    default: break;  // a free body's group: no joints\n  }\n";
  };
  o << "// One contact mechanism's joints (kContactGroups index): B u, S^-1 x and\n"
    << "// u -= scale M^-1 B^T lambda over its own rows; the other rows stay zero.\n"
    << "static Rows jacobian_times_in(int group, const ConstraintSystem& c, const BodyVectors& u) noexcept {\n"
    << "  Rows y = Rows::Zero();\n"
    << cases([&](const std::vector<bool>& in) { return jacobian_lines(in, "      "); }) << "  return y;\n}\n"
    << "static void solve_in(int group, const ConstraintSystem& c, Rows& x) noexcept {\n"
    << cases([&](const std::vector<bool>& in) { return solve_lines(in, "      ", nullptr); }) << "}\n"
    << "static void subtract_constraint_forces_in(int group, const ConstraintSystem& c, const Rows& lambda, double scale,\n"
    << "                                          BodyVectors& u) noexcept {\n"
    << cases([&](const std::vector<bool>& in) { return constraint_force_lines(in, "      "); }) << "}\n";
}

}  // namespace mbrt::codegen
