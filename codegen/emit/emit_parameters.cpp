// Runtime parameters (docs/parameters.md): the header's Parameters and its
// name table, and the model values the step reads from State::params.
#include <algorithm>

#include "emitter.hpp"

namespace mbrt::codegen {

namespace {

std::string function_name(const ConstraintBlock& b) {
  return b.name + (b.function->piecewise() ? "_function" : b.function->is_sine ? "_sine" : "_polynomial");
}

// A piecewise function: each piece's polynomial and harmonic terms, and a
// function that picks the piece by time.
void piecewise_function(std::ostringstream& o, const ConstraintBlock& b) {
  const std::vector<FunctionPiece>& pieces = b.function->pieces;
  for (size_t i = 0; i < pieces.size(); ++i) {
    const FunctionPiece& p = pieces[i];
    const std::string n = b.name + "_piece" + std::to_string(i);
    o << "constexpr std::array<double, " << p.polynomial.size() << "> " << n << "_polynomial{";
    for (size_t k = 0; k < p.polynomial.size(); ++k) o << (k ? ", " : "") << num(p.polynomial[k]);
    o << "};\nconstexpr std::array<mbrt::Harmonic, " << p.harmonics.size() << "> " << n << "_harmonics{{";
    for (size_t k = 0; k < p.harmonics.size(); ++k) {
      const mbrt::Harmonic& h = p.harmonics[k];
      o << (k ? ", " : "") << "{" << num(h.amplitude) << ", " << num(h.omega) << ", " << num(h.phase) << "}";
    }
    o << "}};  // amplitude sin(omega t + phase)\n";
  }
  o << "inline mbrt::TimeValue " << function_name(b) << "(double t) noexcept {\n";
  for (size_t i = 0; i < pieces.size(); ++i) {
    const std::string n = b.name + "_piece" + std::to_string(i);
    const std::string value = "mbrt::polynomial_and_harmonics(" + n + "_polynomial, " + n + "_harmonics, t);\n";
    if (i + 1 < pieces.size()) o << "  if (t < " << num(pieces[i].until) << ") return " << value;
    else o << "  return " << value;
  }
  o << "}\n";
}

}  // namespace

const Parameter* Emitter::tunable(ParameterTarget target, int index, int component) const {
  const auto it = std::find_if(params_.begin(), params_.end(), [&](const Parameter& p) {
    return p.target == target && p.index == index && p.component == component;
  });
  return it == params_.end() ? nullptr : &*it;
}

std::string Emitter::value_of(ParameterTarget target, int index, int component, double folded,
                              const std::string& p) const {
  const Parameter* t = tunable(target, index, component);
  return t ? p + ".value[parameter::" + parameter_identifier(t->name) + "]" : num(folded);
}

std::string Emitter::vec3_of(ParameterTarget target, int index, const Eigen::Vector3d& folded,
                             const std::string& p) const {
  return "mbrt::Vec3(" + value_of(target, index, 0, folded.x(), p) + ", " + value_of(target, index, 1, folded.y(), p) +
         ", " + value_of(target, index, 2, folded.z(), p) + ")";
}

bool Emitter::tunable_gravity() const {
  return std::any_of(params_.begin(), params_.end(), [](const Parameter& p) { return p.target == ParameterTarget::gravity; });
}

bool Emitter::tunable_force(int model_index) const {
  return std::any_of(params_.begin(), params_.end(), [&](const Parameter& p) {
    return p.index == model_index && (p.target == ParameterTarget::spring_stiffness ||
                                      p.target == ParameterTarget::spring_damping || p.target == ParameterTarget::spring_rest);
  });
}

std::string Emitter::force_name(int e) const {
  const std::string n = "force_" + std::to_string(e);
  return tunable_force(a_.forces[static_cast<size_t>(e)].model_index) ? n + "(s.params)" : n;
}

void Emitter::parameter_declarations(std::ostringstream& o) const {
  o << "// Runtime parameters (docs/parameters.md): the keys the model file marks\n"
    << "// tunable, defaults from the file. The step reads them from State::params;\n"
    << "// set them by name (set_parameter) or index (parameter::NAME) before or\n"
    << "// between runs, then initial_state(p) for a run from the start.\n"
    << "inline constexpr int kParameters = " << params_.size() << ";\n"
    << "inline constexpr std::array<mbrt::ParameterInfo, kParameters> kParameterInfo{{\n";
  for (const Parameter& p : params_) o << "    {\"" << p.name << "\", " << num(p.value) << "},\n";
  o << "}};\n\nnamespace parameter {\n";
  for (size_t i = 0; i < params_.size(); ++i) {
    o << "inline constexpr int " << parameter_identifier(params_[i].name) << " = " << i << ";\n";
  }
  o << "}  // namespace parameter\n\n"
    << "struct Parameters {\n  std::array<double, kParameters> value;  // by parameter::NAME\n};\n\n"
    << "inline constexpr Parameters kDefaultParameters{mbrt::default_values(kParameterInfo)};\n\n"
    << "// Sets the parameter named name (kParameterInfo); false, p unchanged, if there is none.\n"
    << "inline bool set_parameter(Parameters& p, std::string_view name, double value) noexcept {\n"
    << "  return mbrt::set_parameter(kParameterInfo, p.value, name, value);\n}\n\n";
}

void Emitter::gravity_constant(std::ostringstream& o) const {
  const Eigen::Vector3d g = m_.gravity.value_or(Eigen::Vector3d::Zero());
  if (!tunable_gravity()) {
    o << "const mbrt::Vec3 kGravity = " << vec3(g) << ";\n";
    return;
  }
  o << "mbrt::Vec3 gravity(const Parameters& p) noexcept { return " << vec3_of(ParameterTarget::gravity, -1, g, "p")
    << "; }\n";
}

void Emitter::mass_constant(std::ostringstream& o, int i) const {
  const Body& b = body(i);
  const std::string m = value_of(ParameterTarget::mass, i, 0, b.mass, "p");
  if (!plan(i).tunable_mass) {
    o << (plan(i).rigid ? "const " : "constexpr ");
  }
  std::string type, value;
  if (!plan(i).rigid) {
    type = "mbrt::PointMass";
    value = "{" + m + "}";
  } else if (plan(i).principal_axes) {
    type = "mbrt::PrincipalInertia";
    value = "{" + m + ", " + vec3_of(ParameterTarget::inertia, i, b.inertia.diagonal(), "p") + "}";
  } else {
    const PrincipalFrame f = principal_frame(b.inertia);
    type = "mbrt::FullInertia";
    value = "{" + m + ", " + mat3(b.inertia) + ", " + mat3(b.inertia.inverse()) + ",\n    " + vec3(f.moments) + ", " +
            vec4(f.axes) + "}";
  }
  if (plan(i).tunable_mass) {
    o << type << " " << body(i).name << "_mass(const Parameters& p) noexcept { return " << value << "; }\n";
  } else {
    o << type << " " << body(i).name << "_mass" << value << ";\n";
  }
}

void Emitter::spring_constant(std::ostringstream& o, const Force& f, const ForcePlan& p, const std::string& n) const {
  const int e = p.model_index;
  const bool spring = f.type == ForceType::spring_damper;
  const std::string values =
      value_of(ParameterTarget::spring_stiffness, e, 0, spring ? p.spring.stiffness : p.joint_spring.stiffness, "p") +
      ", " + value_of(ParameterTarget::spring_damping, e, 0, spring ? p.spring.damping : p.joint_spring.damping, "p") +
      ", " + value_of(ParameterTarget::spring_rest, e, 0, spring ? p.spring.rest_length : p.joint_spring.rest, "p");
  const std::string type = spring ? "mbrt::SpringDamper" : "mbrt::JointSpring";
  const std::string init = spring ? vec3(axes(p.spring.s1)) + ", " + vec3(axes(p.spring.s2)) + ", " + values : values;
  const std::string comment = spring ? "spring_damper " + m_.body_name(f.body1) + " - " + m_.body_name(f.body2)
                                     : "joint_spring " + jname(f.joint) + ": stiffness, damping, rest";
  if (tunable_force(e)) {
    o << type << " " << n << "(const Parameters& p) noexcept { return {" << init << "}; }  // " << comment << "\n";
  } else {
    o << "const " << type << " " << n << "{" << init << "};  // " << comment << "\n";
  }
}

bool Emitter::piecewise_drivers() const {
  return std::any_of(m_.drivers.begin(), m_.drivers.end(), [](const Driver& d) { return d.function.piecewise(); });
}

bool Emitter::tunable_driver(int driver) const {
  return std::any_of(params_.begin(), params_.end(), [&](const Parameter& p) {
    return p.target == ParameterTarget::driver_coefficient && p.index == driver;
  });
}

void Emitter::driver_function_constant(std::ostringstream& o, const ConstraintBlock& b) const {
  const TimeFunction& fn = *b.function;
  if (fn.piecewise()) {
    piecewise_function(o, b);
    return;
  }
  const auto coefficient = [&](int k, double folded) {
    return value_of(ParameterTarget::driver_coefficient, b.driver, k, folded, "p");
  };
  std::string type, values, comment;
  if (fn.is_sine) {
    type = "mbrt::Sine";
    values = coefficient(0, fn.amplitude) + ", " + coefficient(1, fn.omega) + ", " + coefficient(2, fn.phase) + ", " +
             coefficient(3, fn.offset);
    comment = "offset + amplitude sin(omega t + phase)";
  } else {
    type = "std::array<double, " + std::to_string(fn.polynomial.size()) + ">";
    for (size_t k = 0; k < fn.polynomial.size(); ++k) {
      values += (k ? ", " : "") + coefficient(static_cast<int>(k), fn.polynomial[k]);
    }
    comment = "c0 + c1 t + ...";
  }
  const std::string n = function_name(b);
  if (tunable_driver(b.driver)) {
    o << type << " " << n << "(const Parameters& p) noexcept { return {" << values << "}; }  // " << comment << "\n";
  } else {
    o << (fn.is_sine ? "const " : "constexpr ") << type << " " << n << "{" << values << "};  // " << comment << "\n";
  }
}

std::string Emitter::driver_function_value(const ConstraintBlock& b) const {
  if (b.function->piecewise()) return function_name(b) + "(s.t)";
  return std::string(b.function->is_sine ? "mbrt::sine(" : "mbrt::polynomial(") + function_name(b) +
         (tunable_driver(b.driver) ? "(s.params)" : "") + ", s.t)";
}

}  // namespace mbrt::codegen
