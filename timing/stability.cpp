// Long runs: how far energy, angular momentum, the Euler-parameter norm and
// the constraints drift over many steps, every scheme, one model after the
// other (the heavy top, a body tumbling about its intermediate axis, the A01
// pendulum). Conserved quantities are computed here from the body states and
// the model files' inertias, not by mbrt.
//   stability [STEPS=1e7] [DIR=.] [MODELS=all] [SCHEMES=all]
// MODELS and SCHEMES are comma-separated names ("heavy_top,a01_pendulum",
// "staggered-pcst") choosing the runs. Writes DIR/stability_long_runs.csv
// (one line per model and scheme run) and
// DIR/stability_series_<model>_<scheme>.csv (1000 samples of the drifts).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>

#include <mbrt/rotation.hpp>

#include "model_adapter.hpp"
#include "stability_variants.hpp"

namespace {

// Angular momentum of the models' first rigid body (NaN where nothing is
// conserved): about the fixed point for the heavy top (only its vertical
// component is conserved), about the centre of mass for the free body.
mbrt::Vec3 momentum(const std::string& model, const mbrt::RigidState& b) {
  if (model == "heavy_top") {  // tests/models/heavy_top.yaml: m = 15, J = diag(0.234375, 0.46875, 0.234375)
    const mbrt::Vec3 j(0.234375, 0.46875, 0.234375);
    const mbrt::Vec3 l = mbrt::rotation_matrix(b.p) * j.cwiseProduct(b.w) + 15.0 * b.r.cross(b.v);
    return {0, 0, l.z()};
  }
  if (model == "tumbling_body") {  // timing/models/tumbling_body.yaml: J = diag(1, 2, 3)
    return mbrt::rotation_matrix(b.p) * mbrt::Vec3(1, 2, 3).cwiseProduct(b.w);
  }
  return mbrt::Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
}

struct Summary {
  long steps = 0, failed = 0, flips = 0;
  double energy_drift = 0, momentum_drift = 0, quaternion = 0, violation = 0, seconds = 0;
};

template <class Model>
Summary long_run(const std::string& model, long steps, const std::string& dir) {
  typename Model::State s = Model::initial_state();
  const bool rigid = !s.rigid.empty();
  const double e0 = Model::energy(s).total();
  const mbrt::Vec3 l0 = rigid ? momentum(model, s.rigid[0]) : momentum(model, {});
  const std::string series_path = dir + "/stability_series_" + model + "_" + Model::kScheme + ".csv";
  std::FILE* series = std::fopen(series_path.c_str(), "w");
  if (!series) {
    std::perror(series_path.c_str());
    std::exit(1);
  }
  std::fprintf(series, "t,energy_drift,momentum_drift,quaternion_norm_error,position_violation\n");
  Summary sum;
  const long every = std::max(1L, steps / 1000);
  double last_wy = rigid ? s.rigid[0].w.y() : 0.0;
  for (long done = 0; done < steps; done += every) {
    const auto start = std::chrono::steady_clock::now();
    for (long i = 0; i < every; ++i) sum.failed += Model::step(s) != mbrt::StepStatus::ok;
    sum.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    sum.steps += every;
    const double de = std::abs(Model::energy(s).total() - e0);
    const double dl = rigid ? (momentum(model, s.rigid[0]) - l0).norm() : std::numeric_limits<double>::quiet_NaN();
    const double dq = Model::quaternion_norm_error(s), phi = Model::violation(s).position;
    // Sign changes of the body-y rate, sampled: a lower bound on the flips.
    if (rigid && (s.rigid[0].w.y() < 0) != (last_wy < 0)) ++sum.flips;
    if (rigid) last_wy = s.rigid[0].w.y();
    sum.energy_drift = std::max(sum.energy_drift, de);
    sum.momentum_drift = std::max(sum.momentum_drift, dl);
    sum.quaternion = std::max(sum.quaternion, dq);
    sum.violation = std::max(sum.violation, phi);
    std::fprintf(series, "%.9g,%.4g,%.4g,%.4g,%.4g\n", s.t, de, dl, dq, phi);
  }
  std::fclose(series);
  if (!rigid) sum.momentum_drift = std::numeric_limits<double>::quiet_NaN();  // nothing conserved to compare
  return sum;
}

// Whether a comma-separated list names `name` ("all" names everything).
bool chosen(const std::string& list, const std::string& name) {
  return list == "all" || ("," + list + ",").find("," + name + ",") != std::string::npos;
}

#define MBRT_ADAPT(model, ns) BENCH_MODEL(ns##_model, ns);
MBRT_STABILITY_VARIANTS(MBRT_ADAPT)
#undef MBRT_ADAPT

}  // namespace

int main(int argc, char** argv) {
  const long steps = argc > 1 ? static_cast<long>(std::atof(argv[1])) : 10000000L;
  const std::string dir = argc > 2 ? argv[2] : ".";
  const std::string models = argc > 3 ? argv[3] : "all", schemes = argc > 4 ? argv[4] : "all";
  const std::string path = dir + "/stability_long_runs.csv";
  std::FILE* csv = std::fopen(path.c_str(), "w");
  if (!csv) {
    std::perror(path.c_str());
    return 1;
  }
  std::fprintf(csv, "model,scheme,h,steps,t_end,failed_steps,max_energy_drift_J,max_momentum_drift,"
                    "max_quaternion_norm_error,max_position_violation,intermediate_axis_flips,ns_per_step\n");
#define MBRT_LONG_RUN(model, ns)                                                                                  \
  if (chosen(models, #model) && chosen(schemes, ns##_model::kScheme)) {                                          \
    const Summary r = long_run<ns##_model>(#model, steps, dir);                                                   \
    std::fprintf(csv, "%s,%s,%g,%ld,%g,%ld,%.3g,%.3g,%.3g,%.3g,%ld,%.1f\n", #model, ns##_model::kScheme,           \
                 ns##_model::kStep, r.steps, static_cast<double>(r.steps) * ns##_model::kStep, r.failed,           \
                 r.energy_drift, r.momentum_drift, r.quaternion, r.violation, r.flips,             \
                 1e9 * r.seconds / static_cast<double>(r.steps));                                                 \
    std::fflush(csv);                                                                                             \
    std::fprintf(stderr, "%s %s done\n", #model, ns##_model::kScheme);                                           \
  }
  MBRT_STABILITY_VARIANTS(MBRT_LONG_RUN)
#undef MBRT_LONG_RUN
  std::fclose(csv);
  return 0;
}
