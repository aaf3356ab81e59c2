#include "step_report.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "toolchain.hpp"

namespace fs = std::filesystem;

namespace mbrt::codegen {

namespace {

// Steps counted: enough that the difference of N and 2N steps is exact
// (fixed work per step) and short under valgrind.
constexpr int kCountedSteps = 200;

std::string json_string(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

// ns_per_flop from the calibration file's first data row
// (header model,scheme,flops_per_step,ns_per_step,ns_per_flop). The report
// names the file relative to the source tree, the same from every checkout.
void read_calibration(StepReport& r) {
  const std::string file = "timing/results/flop_calibration.csv";
  std::ifstream in(fs::path(toolchain::kSourceRoot) / file);
  std::string header, row;
  if (!std::getline(in, header) || !std::getline(in, row)) {
    r.calibration = "none: run timing/flop_calibration to write " + file;
    return;
  }
  std::istringstream fields(row);
  std::string field, model;
  for (int i = 0; i < 5 && std::getline(fields, field, ','); ++i) {
    if (i == 0) model = field;
    if (i == 4) r.ns_per_flop = std::stod(field);
  }
  r.calibration = file + " (model " + model + ")";
}

}  // namespace

StepReport report_step(const Generated& g, const SimOptions& options) {
  StepReport r;
  r.model = g.model.name;
  r.scheme = mbrt::scheme_name(g.model.solver.scheme);
  for (const auto& [name, flag] : kSpecializationNames) {
    if (!(options.generate.specialize.*flag)) r.turned_off.push_back(name);
  }
  r.skipped = g.analysis.skipped;
  if (!g.analysis.planar.refusal.empty()) r.not_applied.push_back({"planar", g.analysis.planar.refusal});
  r.source_bytes = g.code.header.size() + g.code.source.size();
  const std::string executable = build_program(Program::sim, g, options);
  r.executable_bytes = fs::file_size(executable);
  r.per_step = count_step(executable, g.model.solver.step, kCountedSteps);
  read_calibration(r);
  r.stable = g.stable;
  return r;
}

std::string report_json(const StepReport& r) {
  std::ostringstream o;
  o << "{\n  \"model\": " << json_string(r.model) << ",\n  \"scheme\": " << json_string(r.scheme)
    << ",\n  \"turned_off\": [";
  for (size_t i = 0; i < r.turned_off.size(); ++i) o << (i ? ", " : "") << json_string(r.turned_off[i]);
  o << "],\n  \"skipped\": [";
  for (size_t i = 0; i < r.skipped.size(); ++i) {
    o << (i ? "," : "") << "\n    {\"specialization\": " << json_string(r.skipped[i].specialization)
      << ", \"removed\": " << json_string(r.skipped[i].removed) << "}";
  }
  o << (r.skipped.empty() ? "" : "\n  ") << "],\n  \"not_applied\": [";
  for (size_t i = 0; i < r.not_applied.size(); ++i) {
    o << (i ? "," : "") << "\n    {\"specialization\": " << json_string(r.not_applied[i].specialization)
      << ", \"reason\": " << json_string(r.not_applied[i].reason) << "}";
  }
  o << (r.not_applied.empty() ? "" : "\n  ") << "],\n  \"source_bytes\": " << r.source_bytes
    << ",\n  \"executable_bytes\": " << r.executable_bytes << ",\n  \"flops_per_step\": " << r.per_step.flops
    << ",\n  \"instructions_per_step\": " << r.per_step.instructions << ",\n  \"ns_per_flop\": ";
  if (r.ns_per_flop) o << *r.ns_per_flop; else o << "null";
  o << ",\n  \"predicted_ns_per_step\": ";
  if (r.ns_per_flop) o << *r.ns_per_flop * r.per_step.flops; else o << "null";
  o << ",\n  \"calibration\": " << json_string(r.calibration) << ",\n  \"stable_step\": " << stable_step_json(r.stable)
    << "\n}";
  return o.str();
}

}  // namespace mbrt::codegen
