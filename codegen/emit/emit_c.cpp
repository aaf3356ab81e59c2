// The C interface of a generated model: <name>_c.h, a C11 header (sizes,
// index constants, name tables, the state as a plain struct, the functions),
// and <name>_c.cpp, its implementation over the C++ interface of <name>.hpp.
// The state's members are the C++ State's (Emitter::state_fields), copied
// member by member (include/mbrt/c_interface.hpp). docs/c_interface.md.
#include "emit_c.hpp"

#include <cctype>

#include "emitter.hpp"

namespace mbrt::codegen {

namespace {

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// The C++ declaration's comment lines as one C comment.
std::string c_comment(const std::string& declaration) {
  std::istringstream in(declaration);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("  // ", 0) == 0) out += (out.empty() ? "  /* " : "\n   * ") + line.substr(5);
  }
  return out.empty() ? out : out + " */\n";
}

}  // namespace

std::vector<GeneratedFile> Emitter::c_interface() const {
  const std::string n = m_.name, N = upper(m_.name);
  const std::string state = n + "_state", work = n + "_work";
  const int body_count = static_cast<int>(m_.bodies.size());
  const std::vector<StateField> fields = state_fields();

  std::ostringstream h;
  h << "/* mbrt generated model '" << n << "' from " << m_.file_name() << ": its C interface (docs/c_interface.md).\n"
    << " * Plain C11 over the C++ step of " << n << ".hpp, implemented in " << n << "_c.cpp.\n"
    << " * Generated code: regenerate, do not edit. */\n"
    << "#ifndef MBRT_MODEL_" << N << "_C_H\n#define MBRT_MODEL_" << N << "_C_H\n\n"
    << "#include <stddef.h>\n\n#include <mbrt/model_c.h>\n\n"
    << "#ifdef __cplusplus\nextern \"C\" {\n#endif\n\n"
    << "#define " << N << "_NAME \"" << n << "\"\n"
    << "#define " << N << "_SCHEME \"" << mbrt::scheme_name(scheme_kind()) << "\"\n"
    << "#define " << N << "_STEP " << num(m_.solver.step) << " /* s, the time step */\n"
    << "#define " << N << "_BODIES " << body_count << "\n"
    << "#define " << N << "_RIGID_BODIES " << a_.rigid_count << "\n"
    << "#define " << N << "_PARTICLES " << a_.particle_count << "\n"
    << "#define " << N << "_CONSTRAINT_BLOCKS " << blocks() << " /* joints, then drivers */\n"
    << "#define " << N << "_CONSTRAINT_ROWS " << a_.constraint_rows << "\n";
  if (tree_scheme()) h << "#define " << N << "_DOFS " << tree_dofs() << " /* joint coordinates, in body order */\n";
  if (!friction_joints().empty()) {
    h << "#define " << N << "_FRICTION_JOINTS " << friction_joints().size() << " /* joints with friction, docs/friction.md */\n";
  }
  if (modal()) h << "#define " << N << "_MODAL_BODIES " << a_.modal.size() << " /* docs/flexible.md */\n";
  if (has_contacts()) h << "#define " << N << "_CONTACTS " << a_.contacts.size() << " /* docs/contact.md */\n";
  if (has_inputs()) h << "#define " << N << "_INPUTS " << m_.inputs.size() << "\n";
  if (has_outputs()) h << "#define " << N << "_OUTPUTS " << output_value_count() << " /* values */\n";
  if (a_.tunable) h << "#define " << N << "_PARAMETERS " << params_.size() << " /* runtime parameters, docs/parameters.md */\n";

  h << "\n/* Indices by name: BODY_ into the body names, RIGID_ and PARTICLE_ into the\n"
    << " * state's rigid and particle arrays, CONSTRAINT_ into the constraint names and\n"
    << " * reactions, INPUT_ into the state's inputs, OUTPUT_ into the outputs. */\nenum {\n";
  for (int i = 0; i < body_count; ++i) {
    h << "  " << N << "_BODY_" << upper(body(i).name) << " = " << i << ",\n"
      << "  " << N << (plan(i).rigid ? "_RIGID_" : "_PARTICLE_") << upper(body(i).name) << " = " << plan(i).slot << ",\n";
  }
  for (int j = 0; j < blocks(); ++j) h << "  " << N << "_CONSTRAINT_" << upper(jname(j)) << " = " << j << ",\n";
  for (size_t i = 0; i < m_.inputs.size(); ++i) h << "  " << N << "_INPUT_" << upper(m_.inputs[i].name) << " = " << i << ",\n";
  int first = 0;
  for (const Output& out : m_.outputs) {
    h << "  " << N << "_OUTPUT_" << upper(out.name) << " = " << first << ", /* " << output_layout(out) << " */\n";
    first += type_row(out.type).values;
  }
  h << "};\n\n";

  h << "/* Names in index order. */\n"
    << "extern const char* const " << n << "_body_names[" << N << "_BODIES];\n";
  if (blocks() > 0) h << "extern const char* const " << n << "_constraint_names[" << N << "_CONSTRAINT_BLOCKS];\n";
  if (has_inputs()) h << "extern const char* const " << n << "_input_names[" << N << "_INPUTS];\n";

  h << "\n/* Everything that changes from step to step, member for member the C++\n"
    << " * State of " << n << ".hpp; the caller owns it. */\ntypedef struct " << state << " {\n";
  for (const StateField& f : fields) {
    if (f.count == 0) continue;
    h << c_comment(f.declaration) << "  " << f.c_type << " " << f.name
      << (f.c_length.empty() ? "" : "[" + N + "_" + f.c_length + "]") << f.c_inner << ";\n";
  }
  h << "} " << state << ";\n\n"
    << "/* What a step works on: caller-owned memory of " << n << "_work_size() bytes\n"
    << " * aligned to " << n << "_work_align(), prepared by " << n << "_init(). Allocate it\n"
    << " * before a real-time loop; nothing in it carries over between steps. */\n"
    << "typedef struct " << work << " " << work << ";\n"
    << "size_t " << n << "_work_size(void) MBRT_C_NOEXCEPT;\n"
    << "size_t " << n << "_work_align(void) MBRT_C_NOEXCEPT;\n\n"
    << "/* Sets *s to the model file's initial state and prepares *w. */\n"
    << "void " << n << "_init(" << state << "* s, " << work << "* w) MBRT_C_NOEXCEPT;\n"
    << "/* Advances *s by " << N << "_STEP. Allocates nothing, fixed work. On a status\n"
    << " * other than MBRT_STEP_OK *s keeps its old value. */\n"
    << "mbrt_step_status " << n << "_step(" << state << "* s, " << work << "* w) MBRT_C_NOEXCEPT;\n"
    << (!tree_scheme()            ? "/* Nothing to do here: the step advances s->rigid itself. */\n"
        : body_states_on_demand() ? "/* Forms s->rigid from the joint coordinates: the step does not\n"
                                    " * (solver.body_states: on_demand). */\n"
                                  : "/* Forms s->rigid from the joint coordinates, as the step does. */\n")
    << "void " << n << "_refresh_bodies(" << state << "* s) MBRT_C_NOEXCEPT;\n";
  if (tree_scheme()) {
    h << "/* Sets s->rigid_acceleration and s->lambda from the joint coordinates (the\n"
      << " * step does not need them; the reactions do). */\n"
      << "void " << n << "_set_multipliers(" << state << "* s) MBRT_C_NOEXCEPT;\n";
  }
  h << "mbrt_energy " << n << "_energy(const " << state << "* s) MBRT_C_NOEXCEPT;\n"
    << "mbrt_constraint_violation " << n << "_constraint_violation(const " << state << "* s) MBRT_C_NOEXCEPT;\n";
  if (blocks() > 0) {
    h << "/* Force and torque of every joint and driver on its body2, from the\n"
      << " * multipliers " << (tree_scheme() ? "at the state" : "of the last step") << ". */\n"
      << "void " << n << "_reactions(const " << state << "* s, mbrt_joint_reaction r[" << N
      << "_CONSTRAINT_BLOCKS]) MBRT_C_NOEXCEPT;\n";
  }
  if (has_outputs()) {
    h << "void " << n << "_outputs(const " << state << "* s, double y[" << N << "_OUTPUTS]) MBRT_C_NOEXCEPT;\n";
  }
  h << "\n#ifdef __cplusplus\n}\n#endif\n\n#endif /* MBRT_MODEL_" << N << "_C_H */\n";

  const auto names = [&](const std::string& table, const std::string& length, auto&& name_of, int count) {
    std::string s = "const char* const " + n + "_" + table + "[" + N + "_" + length + "] = {";
    for (int i = 0; i < count; ++i) s += std::string(i ? ", " : "") + "\"" + name_of(i) + "\"";
    return s + "};\n";
  };
  std::ostringstream c;
  c << "// mbrt generated model '" << n << "' from " << m_.file_name() << ": the C interface of " << n
    << "_c.h over the C++\n// one of " << n << ".hpp. Generated code: regenerate, do not edit.\n"
    << "#include \"" << n << "_c.h\"\n\n#include <new>\n\n#include <mbrt/c_interface.hpp>\n\n"
    << "#include \"" << n << ".hpp\"\n\n"
    << names("body_names", "BODIES", [&](int i) { return body(i).name; }, body_count);
  if (blocks() > 0) c << names("constraint_names", "CONSTRAINT_BLOCKS", [&](int j) { return jname(j); }, blocks());
  if (has_inputs()) {
    c << names("input_names", "INPUTS", [&](int i) { return m_.inputs[static_cast<size_t>(i)].name; },
               static_cast<int>(m_.inputs.size()));
  }
  c << "\nnamespace {\n\nnamespace model = mbrt::models::" << n << ";\n"
    << "using mbrt::c_interface::from_c;\nusing mbrt::c_interface::to_c;\n\n";
  if (a_.tunable) {
    c << "void to_c(const model::Parameters& p, double (&c)[" << N << "_PARAMETERS]) noexcept { to_c(p.value, c); }\n"
      << "void from_c(const double (&c)[" << N << "_PARAMETERS], model::Parameters& p) noexcept { from_c(c, p.value); }\n\n";
  }
  c
    << "// What " << work << " holds: the C++ workspace and the state it steps.\n"
    << "struct Work {\n  model::State s;\n  model::Workspace w;\n};\n\n"
    << "Work& work_of(" << work << "* w) noexcept { return *std::launder(reinterpret_cast<Work*>(w)); }\n\n"
    << "void copy(const model::State& s, " << state << "& c) noexcept {\n";
  for (const StateField& f : fields) {
    if (f.count > 0) c << "  to_c(s." << f.name << ", c." << f.name << ");\n";
  }
  c << "}\n\nvoid copy(const " << state << "& c, model::State& s) noexcept {\n";
  for (const StateField& f : fields) {
    if (f.count > 0) c << "  from_c(c." << f.name << ", s." << f.name << ");\n";
  }
  c << "}\n\nmodel::State state_of(const " << state << "& c) noexcept {\n  model::State s;\n  copy(c, s);\n"
    << "  return s;\n}\n\n}  // namespace\n\n"
    << "size_t " << n << "_work_size(void) noexcept { return sizeof(Work); }\n"
    << "size_t " << n << "_work_align(void) noexcept { return alignof(Work); }\n\n"
    << "void " << n << "_init(" << state << "* s, " << work << "* w) noexcept {\n"
    << "  Work* k = new (w) Work;\n  k->s = model::initial_state();\n  copy(k->s, *s);\n}\n\n"
    << "mbrt_step_status " << n << "_step(" << state << "* s, " << work << "* w) noexcept {\n"
    << "  Work& k = work_of(w);\n  copy(*s, k.s);\n  const mbrt::StepStatus status = model::step(k.s, k.w);\n"
    << "  copy(k.s, *s);\n  return to_c(status);\n}\n\n"
    << "void " << n << "_refresh_bodies(" << state << "* s) noexcept {\n"
    << "  model::State cpp = state_of(*s);\n  model::refresh_bodies(cpp);\n  copy(cpp, *s);\n}\n\n";
  if (tree_scheme()) {
    c << "void " << n << "_set_multipliers(" << state << "* s) noexcept {\n"
      << "  model::State cpp = state_of(*s);\n  model::set_multipliers(cpp);\n  copy(cpp, *s);\n}\n\n";
  }
  c << "mbrt_energy " << n << "_energy(const " << state << "* s) noexcept { return to_c(model::energy(state_of(*s))); }\n\n"
    << "mbrt_constraint_violation " << n << "_constraint_violation(const " << state << "* s) noexcept {\n"
    << "  return to_c(model::constraint_violation(state_of(*s)));\n}\n";
  if (blocks() > 0) {
    c << "\nvoid " << n << "_reactions(const " << state << "* s, mbrt_joint_reaction r[" << N
      << "_CONSTRAINT_BLOCKS]) noexcept {\n  model::Reactions cpp;\n  model::reactions(state_of(*s), cpp);\n"
      << "  for (int j = 0; j < " << N << "_CONSTRAINT_BLOCKS; ++j) to_c(cpp[static_cast<size_t>(j)], r[j]);\n}\n";
  }
  if (has_outputs()) {
    c << "\nvoid " << n << "_outputs(const " << state << "* s, double y[" << N << "_OUTPUTS]) noexcept {\n"
      << "  model::Outputs cpp;\n  model::outputs(state_of(*s), cpp);\n"
      << "  for (int i = 0; i < " << N << "_OUTPUTS; ++i) y[i] = cpp[static_cast<size_t>(i)];\n}\n";
  }
  return {{n + "_c.h", h.str()}, {n + "_c.cpp", c.str()}};
}

std::vector<GeneratedFile> emit_c(const Model& model, const Analysis& analysis) {
  return Emitter(model, analysis).c_interface();
}

}  // namespace mbrt::codegen
