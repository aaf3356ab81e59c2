#include "generate.hpp"

#include <cmath>
#include <cstdio>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "emit_c.hpp"
#include "emit_can.hpp"
#include "emit_lcm.hpp"
#include "initial_conditions.hpp"

namespace mbrt::codegen {

namespace {

bool valid_name(const std::string& n) {
  return !n.empty() && n[0] >= 'a' && n[0] <= 'z' &&
         std::all_of(n.begin(), n.end(), [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; });
}

// The options, checked by check_generate_options.
void apply_overrides(Model& model, const GenerateOptions& options) {
  if (options.scheme) {
    model.solver.scheme = *mbrt::scheme_from_name(*options.scheme);
    model.solver.scheme_given = true;
  }
  if (options.name) model.name = *options.name;
  if (options.step) model.solver.step = *options.step;
  if (options.euler_updates) model.solver.euler_updates = *options.euler_updates;
  if (options.parallel_parts) {
    model.solver.parallel_parts = *options.parallel_parts;
    model.solver.parallel_parts_where = {model.file, 0, 0};
  }
  if (options.parallel_min_rows) model.solver.parallel_min_rows = *options.parallel_min_rows;
  if (options.parallel_interface) model.solver.parallel_interface = *options.parallel_interface;
  if (options.pcg_iterations) model.solver.pcg_iterations = *options.pcg_iterations;
  if (options.pcg_preconditioner) model.solver.pcg_preconditioner = *options.pcg_preconditioner;
  if (options.body_states) {
    model.solver.body_states_on_demand = *options.body_states == "on_demand";
    model.solver.body_states_where = {model.file, 0, 0};
  }
  Ali3pSettings& ali3p = model.solver.ali3p;
  if (options.ali3p_projection) ali3p.cuadrado_projection = *options.ali3p_projection == "cuadrado";
  if (options.ali3p_integrator) ali3p.generalized_alpha = *options.ali3p_integrator == "generalized_alpha";
}

void check_initial_state(const Model& model, const Analysis& analysis) {
  const InitialResidual r = initial_residual(model, analysis);
  const auto report = [&](int block, double residual, const char* level, const char* what) {
    const ConstraintBlock& b = analysis.constraints[static_cast<size_t>(block)];
    const bool driver = b.source == ConstraintSource::driver;
    std::ostringstream m;
    m << "initial " << level << " violate " << (driver ? "driver" : "joint") << " '" << b.name << "' by " << residual
      << " (tolerance " << kInitialTolerance << "); fix the " << what << " or pass --project-initial";
    throw ModelError(b.where, driver ? "drivers" : "joints", m.str());
  };
  if (r.position > kInitialTolerance) report(r.position_block, r.position, "positions", "positions");
  if (r.velocity > kInitialTolerance) report(r.velocity_block, r.velocity, "velocities", "velocities");
}

}  // namespace

void check_generate_options(const GenerateOptions& options) {
  const auto bad = [](const std::string& flag, const std::string& why) { throw std::invalid_argument(flag + ": " + why); };
  if (options.scheme && !mbrt::scheme_from_name(*options.scheme)) {
    std::string names;
    for (std::string_view n : mbrt::kSchemeNames) names += (names.empty() ? "" : ", ") + std::string(n);
    bad("--scheme", "expected one of: " + names + ", got '" + *options.scheme + "'");
  }
  if (options.name && !valid_name(*options.name))
    bad("--name", "expected a name matching [a-z][a-z0-9_]*, got '" + *options.name + "'");
  if (options.step && !(*options.step > 0.0 && std::isfinite(*options.step))) bad("--h", "expected a finite step > 0 s");
  if (options.euler_updates && *options.euler_updates < 1) bad("--euler-updates", "expected an integer >= 1");
  if (options.parallel_parts && (*options.parallel_parts < 1 || *options.parallel_parts > 64))
    bad("--parallel-parts", "expected an integer from 1 to 64");
  if (options.parallel_min_rows && *options.parallel_min_rows < 0) bad("--parallel-min-rows", "expected an integer >= 0");
  if (options.parallel_interface && *options.parallel_interface != "direct" && *options.parallel_interface != "pcg")
    bad("--parallel-interface", "expected direct or pcg, got '" + *options.parallel_interface + "'");
  if (options.pcg_iterations && *options.pcg_iterations < 1) bad("--pcg-iterations", "expected an integer >= 1");
  if (options.pcg_preconditioner && *options.pcg_preconditioner != "block" && *options.pcg_preconditioner != "diagonal")
    bad("--pcg-preconditioner", "expected block or diagonal, got '" + *options.pcg_preconditioner + "'");
  if (options.body_states && *options.body_states != "each_step" && *options.body_states != "on_demand")
    bad("--body-states", "expected each_step or on_demand, got '" + *options.body_states + "'");
  if (options.ali3p_projection && *options.ali3p_projection != "bayo" && *options.ali3p_projection != "cuadrado")
    bad("--ali3p-projection", "expected bayo or cuadrado, got '" + *options.ali3p_projection + "'");
  if (options.ali3p_integrator && *options.ali3p_integrator != "trapezoidal" &&
      *options.ali3p_integrator != "generalized_alpha")
    bad("--ali3p-integrator", "expected trapezoidal or generalized_alpha, got '" + *options.ali3p_integrator + "'");
}

Generated generate(const std::string& model_path, const GenerateOptions& options) {
  check_generate_options(options);
  Generated g{load_model(model_path), {}, {}, {}};
  apply_overrides(g.model, options);
  if (!g.model.solver.scheme_given) g.model.solver.scheme = default_scheme(g.model);
  g.analysis = analyse(g.model, options.specialize);
  if (options.project_initial) project_initial_state(g.model, g.analysis);
  check_initial_state(g.model, g.analysis);
  g.stable = estimate_stable_step(g.model, g.analysis.modal);
  if (const std::string w = stable_step_warning(g.model, g.stable); !w.empty()) std::fprintf(stderr, "%s\n", w.c_str());
  if (const std::string w = tree_energy_warning(g.model); !w.empty()) std::fprintf(stderr, "%s\n", w.c_str());
  if (const std::string w = modal_spin_warning(g.model, g.stable); !w.empty()) std::fprintf(stderr, "%s\n", w.c_str());
  g.code = emit_cpp(g.model, g.analysis);
  g.code.interface_files = emit_c(g.model, g.analysis);
  if (!g.model.inputs.empty() && !g.model.outputs.empty()) {
    for (GeneratedFile& f : emit_lcm(g.model)) g.code.interface_files.push_back(std::move(f));
    for (GeneratedFile& f : emit_can(g.model, options.can_fd)) g.code.interface_files.push_back(std::move(f));
  }
  return g;
}

void write_generated(const GeneratedCode& code, const std::string& dir) {
  std::filesystem::create_directories(dir);
  std::vector<GeneratedFile> files = {{code.header_name, code.header}, {code.source_name, code.source}};
  files.insert(files.end(), code.interface_files.begin(), code.interface_files.end());
  for (const auto& [name, text] : files) {
    const std::filesystem::path path = std::filesystem::path(dir) / name;
    std::ifstream in(path);
    std::stringstream old;
    old << in.rdbuf();
    if (in && old.str() == text) continue;
    std::ofstream out(path);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + path.string());
  }
}

}  // namespace mbrt::codegen
