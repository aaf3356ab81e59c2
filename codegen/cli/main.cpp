// mbrt: generate a model's allocation-free step, or generate, compile and run
// it; import a URDF or MJCF file as a model file. The command line is read
// with CLI11; every value is checked before anything is generated or
// compiled, and a mistake exits with status 2 naming the option.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "generate.hpp"
#include "import_command.hpp"
#include "parameters.hpp"
#include "mbrt/rt/program_options.hpp"
#include "sim_runner.hpp"
#include "step_report.hpp"

namespace {

using mbrt::rt::number_check;

constexpr const char* kDescription = R"(mbrt: a multibody model's fixed-step, allocation-free step() as C++.
  gen     writes DIR/<name>.hpp and DIR/<name>.cpp, the C interface DIR/<name>_c.h and
          DIR/<name>_c.cpp (docs/c_interface.md) and, for models with inputs and outputs,
          DIR/<name>.lcm, DIR/<name>_lcm.hpp, DIR/<name>.dbc and DIR/<name>_can.hpp;
          --report prints, as JSON, the specializations that applied, the step's floating-point
          operations and instructions, its code size and predicted time (docs/specializations.md)
  sim     generates, compiles (cached by content hash under $MBRT_CACHE_DIR or ~/.cache/mbrt) and
          runs the model; its last line on stdout is a JSON summary
  hil     runs the model in a real-time loop that publishes its outputs and takes commands over
          LCM or a CAN bus; stub runs a PD controller for it; both print a JSON report (docs/hil.md)
  build   compiles (or takes from the cache) the sim, hil or stub program and prints its path
  sweep   runs the model's sim program over a grid or random samples of its tunable parameters,
          on local processes, Dask or Slurm, into one table (docs/sweeps.md)
  import  writes a URDF or MJCF file as a model file (docs/import.md)
`mbrt COMMAND --help` lists a command's options.)";

// The generation options every command but import takes.
void add_generate_options(CLI::App& app, mbrt::codegen::GenerateOptions& gen, std::vector<std::string>& no_specialize) {
  app.add_option_function<std::string>("--scheme", [&gen](const std::string& s) { gen.scheme = s; },
                                       "the scheme, overriding solver.scheme");
  // Any number parses here; check_generate_options says what a step must be.
  app.add_option_function<double>("--h", [&gen](double h) { gen.step = h; }, "the step, s, overriding solver.step")
      ->check(CLI::Validator(
          [](const std::string& text) {
            char* end = nullptr;
            std::strtod(text.c_str(), &end);
            return !text.empty() && *end == '\0' ? std::string() : "expected a number, got '" + text + "'";
          },
          "NUMBER"));
  app.add_option_function<double>("--euler-updates", [&gen](double k) { gen.euler_updates = static_cast<int>(k); },
                                  "Euler-parameter updates per step, overriding solver.euler_updates")
      ->check(number_check("an integer", [](double k) { return k == std::floor(k) && std::abs(k) < 1e9; }));
  app.add_option_function<double>("--parallel-parts", [&gen](double k) { gen.parallel_parts = static_cast<int>(k); },
                                  "subsystems stepped on their own threads, overriding solver.parallel_parts")
      ->check(number_check("an integer", [](double k) { return k == std::floor(k) && std::abs(k) < 1e9; }));
  app.add_option_function<double>("--parallel-min-rows",
                                  [&gen](double k) { gen.parallel_min_rows = static_cast<int>(k); },
                                  "constraint rows per part below which the step stays serial, overriding "
                                  "solver.parallel_min_rows (0: always split)")
      ->check(number_check("an integer", [](double k) { return k == std::floor(k) && std::abs(k) < 1e9; }));
  app.add_option_function<std::string>("--parallel-interface", [&gen](const std::string& m) { gen.parallel_interface = m; },
                                       "direct or pcg: the parallel step's interface, overriding solver.parallel_interface");
  app.add_option_function<double>("--pcg-iterations", [&gen](double k) { gen.pcg_iterations = static_cast<int>(k); },
                                  "conjugate-gradient iterations on the interface, overriding solver.pcg_iterations")
      ->check(number_check("an integer", [](double k) { return k == std::floor(k) && std::abs(k) < 1e9; }));
  app.add_option_function<std::string>("--pcg-preconditioner", [&gen](const std::string& m) { gen.pcg_preconditioner = m; },
                                       "block or diagonal, overriding solver.pcg_preconditioner");
  app.add_option_function<std::string>("--body-states", [&gen](const std::string& m) { gen.body_states = m; },
                                       "each_step or on_demand (tree schemes): when the bodies' world states are "
                                       "formed, overriding solver.body_states");
  app.add_flag("--project-initial", gen.project_initial, "project the initial state onto the constraints");
  app.add_flag("--can-fd", gen.can_fd, "the CAN layout in CAN FD frames of up to 64 bytes");
  app.add_option_function<std::string>("--name", [&gen](const std::string& n) { gen.name = n; },
                                       "rename the model and its C++ namespace");
  app.add_option_function<std::string>("--ali3p-projection", [&gen](const std::string& p) { gen.ali3p_projection = p; },
                                       "bayo or cuadrado");
  app.add_option_function<std::string>("--ali3p-integrator", [&gen](const std::string& i) { gen.ali3p_integrator = i; },
                                       "trapezoidal or generalized_alpha");
  app.add_flag("--no-specialize{all}", no_specialize,
               "generate the general step; =NAME,... only without those specializations (principal_axes, isotropic, "
               "single_stage, gravity_free, folded_weights, unloaded_bodies, no_drivers, sparse_factor, planar)");
}

// --no-specialize (given as "all") or --no-specialize=NAME,...: clears the flags named.
void turn_off(const std::vector<std::string>& given, mbrt::codegen::Specializations& s) {
  for (const std::string& names : given) {
    if (names == "all") {
      s = mbrt::codegen::Specializations::none();
      continue;
    }
    std::stringstream list(names);
    for (std::string name; std::getline(list, name, ',');) {
      bool known = false;
      for (const auto& [n, flag] : mbrt::codegen::kSpecializationNames) {
        if (name != n) continue;
        s.*flag = false;
        known = true;
      }
      if (!known) throw CLI::ValidationError("--no-specialize", "unknown specialization '" + name + "'");
    }
  }
}

// The options a compiled program (hil's loop, the stub) reads again: given
// ones are passed on as written.
std::vector<std::string> given_options(const CLI::App& app, const std::set<const CLI::Option*>& program) {
  std::vector<std::string> args;
  for (const CLI::Option* o : app.get_options()) {
    if (!program.count(o)) continue;
    for (const std::string& value : o->results()) args.insert(args.end(), {o->get_name(), value});
  }
  return args;
}

// `mbrt sweep ...`: the Python tool python/mbrt/sweep with the remaining
// arguments, told this executable in $MBRT.
[[noreturn]] void exec_sweep(int argc, char** argv) {
  const std::string package = mbrt::codegen::python_package_dir();
  const char* old_path = std::getenv("PYTHONPATH");
  setenv("PYTHONPATH", (package + (old_path && *old_path ? ":" + std::string(old_path) : "")).c_str(), 1);
  setenv("MBRT", std::filesystem::read_symlink("/proc/self/exe").c_str(), 1);
  // Debian's interpreter, which has python3-numpy and python3-distributed, before any other on PATH.
  const char* python = std::getenv("MBRT_PYTHON");
  if (!python || !*python) python = std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  std::vector<char*> args = {const_cast<char*>(python), const_cast<char*>("-m"), const_cast<char*>("mbrt.sweep")};
  args.insert(args.end(), argv + 2, argv + argc);
  args.push_back(nullptr);
  execvp(python, args.data());
  std::fprintf(stderr, "error: cannot run %s for mbrt sweep: %s\n", python, std::strerror(errno));
  std::exit(1);
}

[[noreturn]] void usage_error(const CLI::App& app, const std::string& why) {
  std::fprintf(stderr, "error: %s\n\n%s", why.c_str(), app.help().c_str());
  std::exit(2);
}

int run(int argc, char** argv) {
  using mbrt::codegen::Program;
  if (argc > 1 && argv[1] == std::string("sweep")) exec_sweep(argc, argv);
  CLI::App app(kDescription, "mbrt");
  app.require_subcommand(1);

  mbrt::codegen::SimOptions sim;
  mbrt::codegen::GenerateOptions& gen = sim.generate;
  std::string model_path, out_dir;
  bool report = false;
  std::vector<std::string> no_specialize;
  mbrt::rt::HilOptions hil;
  mbrt::rt::StubOptions stub;
  std::set<const CLI::Option*> program_options;  // hil's or the stub's, checked here and by the program

  CLI::App* gen_cmd = app.add_subcommand("gen", "generate a model's step");
  CLI::App* sim_cmd = app.add_subcommand("sim", "generate, compile and run a model");
  CLI::App* hil_cmd = app.add_subcommand("hil", "run a model in a real-time loop over LCM or CAN");
  CLI::App* stub_cmd = app.add_subcommand("stub", "run a PD controller with fault injection for a model in hil");
  CLI::App* build_cmd = app.add_subcommand("build", "compile a model's program (cached like sim) and print its path");
  app.add_subcommand("sweep", "parameter sweeps and Monte Carlo runs (mbrt sweep --help)");
  for (CLI::App* cmd : {gen_cmd, sim_cmd, hil_cmd, stub_cmd, build_cmd}) {
    cmd->add_option("MODEL", model_path, "the model file (.yaml)")->required();
    add_generate_options(*cmd, gen, no_specialize);
  }
  gen_cmd->add_option("-o", out_dir, "the directory to write into")->required();
  gen_cmd->add_flag("--report", report, "print what the step costs and what was left out, as JSON");
  std::string built = "sim";
  build_cmd->add_option("--program", built, "the program: sim (default), hil or stub")
      ->check(CLI::IsMember({"sim", "hil", "stub"}));

  // sim's run options, checked here; the program gets the text as given, at full precision.
  const auto forward = [&sim](const std::string& flag) {
    return [&sim, flag](const std::string& value) { sim.driver_args.insert(sim.driver_args.end(), {flag, value}); };
  };
  sim_cmd->add_option_function<std::string>("--t-end", forward("--t-end"), "run to this time, s (default 1)")
      ->check(number_check("a finite time >= 0 s", [](double t) { return t >= 0.0; }));
  sim_cmd->add_option_function<std::string>("--every", forward("--every"), "write every N-th step (default 1)")
      ->check(number_check("an integer", [](double n) { return n == std::floor(n); }) &
              number_check("an integer >= 1 (steps)", [](double n) { return n >= 1.0; }));
  sim_cmd->add_option_function<std::string>("--out", forward("--out"), "write the trajectory to this CSV file")
      ->check(CLI::Validator(
          [](const std::string& file) {
            const std::filesystem::path dir = std::filesystem::absolute(file).parent_path();
            return std::filesystem::is_directory(dir) ? std::string()
                                                      : "no directory " + dir.string() + " for '" + file + "'";
          },
          "FILE"));
  for (const char* flag : {"--velocities", "--reactions", "--outputs", "--serial"}) {
    const std::string f = flag;
    sim_cmd->add_flag_callback(flag, [&sim, flag]() { sim.driver_args.push_back(flag); },
                               f == "--velocities"  ? "add the velocities to the CSV"
                               : f == "--reactions" ? "add the joints' reactions to the CSV"
                               : f == "--outputs"   ? "add the model's outputs to the CSV (NAME.0, NAME.1, ...)"
                                                    : "run a parallel step's parts on one thread (docs/parallel.md)");
  }
  std::vector<std::string> set;  // --set KEY=VALUE: runtime parameters (docs/parameters.md), checked against the model
  sim_cmd->add_option("--set", set, "set a tunable parameter before the run (repeatable)")
      ->take_all()
      ->check(mbrt::rt::setting_check());
  for (CLI::App* cmd : {sim_cmd, hil_cmd, stub_cmd, build_cmd}) cmd->add_flag("--verbose", sim.verbose, "show the compiler's command");

  const auto add_program_options = [&program_options](CLI::App& cmd, const auto& add) {
    const size_t before = cmd.get_options().size();
    add();
    const std::vector<const CLI::Option*> all = std::as_const(cmd).get_options();
    program_options.insert(all.begin() + static_cast<std::ptrdiff_t>(before), all.end());
  };
  add_program_options(*hil_cmd, [&] { mbrt::rt::add_hil_options(*hil_cmd, hil); });
  add_program_options(*stub_cmd, [&] { mbrt::rt::add_stub_options(*stub_cmd, stub); });

  CLI::App* import_cmd = app.add_subcommand("import", "write a URDF (.urdf) or MJCF (.xml) file as a model file");
  std::string import_source, import_out;
  import_cmd->add_option("SOURCE", import_source, "ROBOT.urdf or MODEL.xml")->required();
  import_cmd->add_option("-o", import_out, "the model file to write (.yaml)")->required();

  for (CLI::App* cmd : app.get_subcommands({})) cmd->allow_extras();  // named below, one at a time
  try {
    const std::vector<CLI::App*> commands = app.get_subcommands({});
    const auto named = [&](CLI::App* c) { return c->get_name() == argv[1]; };
    if (argc > 1 && argv[1][0] != '-' && std::none_of(commands.begin(), commands.end(), named)) {
      throw CLI::ParseError("unknown command '" + std::string(argv[1]) + "'", CLI::ExitCodes::ExtrasError);
    }
    app.parse(argc, argv);
    const std::vector<std::string> extra = app.get_subcommands().front()->remaining();
    if (!extra.empty()) {
      throw CLI::ParseError((extra[0].rfind('-', 0) == 0 ? "unknown option '" : "unexpected argument '") + extra[0] +
                                "' for " + app.get_subcommands().front()->get_name(),
                            CLI::ExitCodes::ExtrasError);
    }
    turn_off(no_specialize, gen.specialize);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const std::vector<CLI::App*> used = app.get_subcommands();
    usage_error(used.empty() ? app : *used.front(), e.what());
  }

  if (import_cmd->parsed()) return mbrt::codegen::run_import(import_source, import_out);
  CLI::App& cmd = *app.get_subcommands().front();
  try {
    mbrt::codegen::check_generate_options(gen);
  } catch (const std::invalid_argument& e) {
    usage_error(cmd, e.what());
  }
  const mbrt::rt::LinkOptions& link = hil_cmd->parsed() ? hil.link : stub.link;
  if (hil_cmd->parsed() || stub_cmd->parsed()) {
    if (const std::string why = mbrt::rt::check_link_options(link); !why.empty()) usage_error(cmd, why);
  }
  const mbrt::codegen::Generated g = mbrt::codegen::generate(model_path, gen);
  if (gen_cmd->parsed()) {
    mbrt::codegen::write_generated(g.code, out_dir);
    if (report) std::puts(mbrt::codegen::report_json(mbrt::codegen::report_step(g, sim)).c_str());
    return 0;
  }
  if (build_cmd->parsed()) {
    const Program p = built == "sim" ? Program::sim : built == "hil" ? Program::hil : Program::pd_controller;
    std::puts(mbrt::codegen::build_program(p, g, sim).c_str());
    return 0;
  }
  if (hil_cmd->parsed()) {
    if (const std::string why = mbrt::rt::check_rate(hil.link.rate_hz, g.model.solver.step); !why.empty()) usage_error(cmd, why);
  }
  if (sim_cmd->parsed() && g.model.outputs.empty() &&
      std::find(sim.driver_args.begin(), sim.driver_args.end(), "--outputs") != sim.driver_args.end()) {
    usage_error(cmd, "--outputs: model " + g.model.name + " has no outputs (give it an outputs: list)");
  }
  // --set keys checked against the model before compiling; hil's go to the
  // loop with its other options.
  const std::vector<std::string> tunable = mbrt::codegen::tunable_names(g.model);
  for (const std::string& pair : hil_cmd->parsed() ? hil.set : set) {
    const std::string key = pair.substr(0, pair.find('='));
    if (std::find(tunable.begin(), tunable.end(), key) != tunable.end()) {
      if (sim_cmd->parsed()) sim.driver_args.insert(sim.driver_args.end(), {"--set", pair});
      continue;
    }
    std::string names;
    for (const std::string& n : tunable) names += (names.empty() ? "" : ", ") + n;
    usage_error(cmd, "--set: '" + key + "' is not a tunable parameter of " + g.model.name +
                         (names.empty() ? " (it marks none: docs/parameters.md)" : "; the tunable ones are " + names));
  }
  const std::vector<std::string> program_args = given_options(cmd, program_options);
  sim.driver_args.insert(sim.driver_args.end(), program_args.begin(), program_args.end());
  const Program program = sim_cmd->parsed() ? Program::sim : hil_cmd->parsed() ? Program::hil : Program::pd_controller;
  return mbrt::codegen::run_program(program, g, sim);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
