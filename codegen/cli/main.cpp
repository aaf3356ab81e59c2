// mbrt: generate a model's allocation-free step, or generate, compile and run it.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "generate.hpp"
#include "sim_runner.hpp"
#include "step_report.hpp"

namespace {

constexpr const char* kUsage = R"(usage:
  mbrt gen MODEL.yaml -o DIR [--scheme S] [--h H] [--euler-updates K] [--project-initial] [--name N]
                      [--ali3p-projection bayo|cuadrado] [--ali3p-integrator trapezoidal|generalized_alpha] [--can-fd]
                      [--no-specialize[=NAME,...]] [--report]
  mbrt sim MODEL.yaml [--scheme S] [--h H] [--euler-updates K] [--project-initial] [--name N]
                      [--ali3p-projection P] [--ali3p-integrator I] [--can-fd] [--no-specialize[=NAME,...]]
                      [--t-end T] [--out F.csv] [--every N] [--velocities] [--reactions] [--verbose]
  mbrt hil MODEL.yaml [generation options] (--lcm URL | --can BUS [--can-log F])
                      [--rate HZ] [--duration S] [--report F.json] [--state-channel C] [--command-channel C]
                      [--command-timeout S] [--max-command-age S] [--publish-every N] [--fifo PRIORITY] [--cpu N]
  mbrt stub MODEL.yaml [generation options] (--lcm URL | --can BUS) [--rate HZ] [--duration S] [--report F.json]
                      [--kp K] [--kd K] [--amplitude A] [--frequency F] [--settle S]
                      [--delay-us D] [--jitter-us J] [--seed N] [--crash-after S]
                      [--drop P] [--duplicate P] [--reorder P] [--garbage P] [--nan P] [--out-of-range P]

gen writes DIR/<name>.hpp and DIR/<name>.cpp, the C interface DIR/<name>_c.h and
DIR/<name>_c.cpp (docs/c_interface.md) and, for models with inputs and
outputs, DIR/<name>.lcm, DIR/<name>_lcm.hpp, DIR/<name>.dbc and DIR/<name>_can.hpp.
--no-specialize generates the general step, without the specializations the
scene would allow; --no-specialize=NAME,... turns off only those named
(principal_axes, isotropic, single_stage, gravity_free, folded_weights,
unloaded_bodies, no_drivers, sparse_factor, planar). gen --report prints, as JSON,
the specializations that applied, the step's floating-point operations and
instructions, its code size and predicted time (docs/specializations.md).
sim generates, compiles (cached by content hash under $MBRT_CACHE_DIR or
~/.cache/mbrt) and runs the model; its last line on stdout is a JSON summary.
hil runs the model in a real-time loop that publishes its outputs and takes
commands over LCM or a CAN bus (BUS: udp://GROUP:PORT, udp://[IPv6 GROUP]:PORT
or a SocketCAN interface such as vcan0; --can-fd: CAN FD frames of up to 64 bytes, which hil and stub
must both be given); stub runs a PD controller for it; both print a JSON report.
See docs/hil.md.
)";

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

double parse_number(const std::string& flag, const std::string& text) {
  try {
    size_t used = 0;
    const double x = std::stod(text, &used);
    if (used == text.size()) return x;
  } catch (const std::exception&) {
  }
  throw UsageError(flag + ": expected a number, got '" + text + "'");
}

int parse_integer(const std::string& flag, const std::string& text) {
  try {
    size_t used = 0;
    const int x = std::stoi(text, &used);
    if (used == text.size()) return x;
  } catch (const std::exception&) {
  }
  throw UsageError(flag + ": expected an integer, got '" + text + "'");
}

// sim's run options, checked before anything is generated or compiled; the
// driver gets the text as given, at full precision.
const std::string& run_time(const std::string& flag, const std::string& text) {
  const double x = parse_number(flag, text);
  if (!(x >= 0.0 && std::isfinite(x))) throw UsageError(flag + ": expected a finite time >= 0 s, got '" + text + "'");
  return text;
}

const std::string& output_interval(const std::string& flag, const std::string& text) {
  if (parse_integer(flag, text) < 1) throw UsageError(flag + ": expected an integer >= 1 (steps), got '" + text + "'");
  return text;
}

const std::string& output_file(const std::string& flag, const std::string& text) {
  const std::filesystem::path dir = std::filesystem::absolute(text).parent_path();
  if (!std::filesystem::is_directory(dir)) throw UsageError(flag + ": no directory " + dir.string() + " for '" + text + "'");
  return text;
}

// --no-specialize=NAME,...: clears the flags named.
void turn_off(const std::string& names, mbrt::codegen::Specializations& s) {
  std::stringstream list(names);
  for (std::string name; std::getline(list, name, ',');) {
    bool known = false;
    for (const auto& [n, flag] : mbrt::codegen::kSpecializationNames) {
      if (name != n) continue;
      s.*flag = false;
      known = true;
    }
    if (!known) throw UsageError("--no-specialize: unknown specialization '" + name + "'");
  }
}

int run(const std::vector<std::string>& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::fputs(kUsage, args.empty() ? stderr : stdout);
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  if (command != "gen" && command != "sim" && command != "hil" && command != "stub") {
    throw UsageError("unknown command '" + command + "'");
  }
  const bool program_options = command == "hil" || command == "stub";  // checked by the program itself
  std::string model_path, out_dir;
  bool report = false;
  mbrt::codegen::SimOptions sim;
  mbrt::codegen::GenerateOptions& gen = sim.generate;
  for (size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    const auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw UsageError(a + ": missing value");
      return args[++i];
    };
    if (a == "--scheme") gen.scheme = value();
    else if (a == "--h") gen.step = parse_number(a, value());
    else if (a == "--euler-updates") gen.euler_updates = parse_integer(a, value());
    else if (a == "--project-initial") gen.project_initial = true;
    else if (a == "--can-fd") gen.can_fd = true;
    else if (a == "--name") gen.name = value();
    else if (a == "--ali3p-projection") gen.ali3p_projection = value();
    else if (a == "--ali3p-integrator") gen.ali3p_integrator = value();
    else if (a == "--no-specialize") gen.specialize = mbrt::codegen::Specializations::none();
    else if (a.rfind("--no-specialize=", 0) == 0) turn_off(a.substr(16), gen.specialize);
    else if (command == "gen" && a == "--report") report = true;
    else if (command == "gen" && a == "-o") out_dir = value();
    else if (command == "sim" && a == "--t-end") sim.driver_args.insert(sim.driver_args.end(), {a, run_time(a, value())});
    else if (command == "sim" && a == "--every") sim.driver_args.insert(sim.driver_args.end(), {a, output_interval(a, value())});
    else if (command == "sim" && a == "--out") sim.driver_args.insert(sim.driver_args.end(), {a, output_file(a, value())});
    else if (command == "sim" && (a == "--velocities" || a == "--reactions")) sim.driver_args.push_back(a);
    else if (command != "gen" && a == "--verbose") sim.verbose = true;
    else if (program_options && a.rfind("--", 0) == 0) {
      sim.driver_args.push_back(a);  // every program option takes a value
      if (i + 1 < args.size() && args[i + 1].rfind("--", 0) != 0) sim.driver_args.push_back(args[++i]);
    }
    else if (!a.empty() && a[0] == '-') throw UsageError("unknown option '" + a + "' for " + command);
    else if (model_path.empty()) model_path = a;
    else throw UsageError("unexpected argument '" + a + "'");
  }
  if (model_path.empty()) throw UsageError(command + ": missing MODEL.yaml");
  try {
    mbrt::codegen::check_generate_options(gen);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  if (command == "gen") {
    if (out_dir.empty()) throw UsageError("gen: missing -o DIR");
    const mbrt::codegen::Generated g = mbrt::codegen::generate(model_path, gen);
    mbrt::codegen::write_generated(g.code, out_dir);
    if (report) std::puts(mbrt::codegen::report_json(mbrt::codegen::report_step(g, sim)).c_str());
    return 0;
  }
  using mbrt::codegen::Program;
  const Program program = command == "sim" ? Program::sim : command == "hil" ? Program::hil : Program::pd_controller;
  return mbrt::codegen::run_program(program, model_path, sim);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const UsageError& e) {
    std::fprintf(stderr, "error: %s\n\n%s", e.what(), kUsage);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
