#include "step_report.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "toolchain.hpp"

namespace fs = std::filesystem;

namespace mbrt::codegen {

namespace {

// Steps counted: enough that the difference of N and 2N steps is exact
// (fixed work per step) and short under valgrind.
constexpr int kCountedSteps = 200;

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
  r.bodies = g.model.bodies.size();
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
  r.partition = g.analysis.partition;
  return r;
}

std::string report_json(const StepReport& r) {
  using Json = nlohmann::ordered_json;
  Json skipped = Json::array(), not_applied = Json::array();
  for (const Skipped& k : r.skipped) skipped.push_back({{"specialization", k.specialization}, {"removed", k.removed}});
  for (const NotApplied& k : r.not_applied) not_applied.push_back({{"specialization", k.specialization}, {"reason", k.reason}});
  const StableStep& st = r.stable;
  const Json stable = {{"stable_step", st.stable_step},
                       {"exceeded", st.exceeded},
                       {"energy_bound", st.energy_bound},
                       {"fastest_rotation", st.fastest_rotation},
                       {"fastest_body", st.fastest_body},
                       {"rotation_per_step", st.rotation_per_step},
                       {"stiffest_frequency", st.stiffest_frequency},
                       {"stiffest_element", st.stiffest_element},
                       {"note", st.note}};
  const Partition& p = r.partition;
  const Json parallel = {{"parts", p.parts},
                         {"requested", p.requested},
                         {"part_rows", p.part_rows},
                         {"interface_blocks", p.interface_blocks},
                         {"interface_rows", p.interface_rows},
                         {"interface_solve", p.parts == 1    ? "none"
                                             : !p.pcg        ? "direct"
                                                             : "pcg, " + std::to_string(p.pcg_iterations) + " iterations, " +
                                                                   (p.block_preconditioner ? "block" : "diagonal") +
                                                                   " preconditioner"},
                         {"serial_reason", p.serial_reason}};
  const Json predicted = r.ns_per_flop ? Json(*r.ns_per_flop * static_cast<double>(r.per_step.flops)) : Json(nullptr);
  const Json j = {{"model", r.model},
                  {"scheme", r.scheme},
                  {"turned_off", r.turned_off},
                  {"skipped", skipped},
                  {"not_applied", not_applied},
                  {"bodies", r.bodies},
                  {"source_bytes", r.source_bytes},
                  {"executable_bytes", r.executable_bytes},
                  {"flops_per_step", r.per_step.flops},
                  {"flops_per_body", r.bodies ? static_cast<double>(r.per_step.flops) / static_cast<double>(r.bodies) : 0.0},
                  {"instructions_per_step", r.per_step.instructions},
                  {"ns_per_flop", r.ns_per_flop ? Json(*r.ns_per_flop) : Json(nullptr)},
                  {"predicted_ns_per_step", predicted},
                  {"calibration", r.calibration},
                  {"stable_step", stable},
                  {"parallel", parallel}};
  return j.dump(4);
}

}  // namespace mbrt::codegen
