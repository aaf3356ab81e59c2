// Run time against error for every mbrt scheme and step size, and for the
// peers' fixed-step integrators (MuJoCo, Simbody, DART, where found), on the same
// mechanisms against independent references (problems.hpp). All runs are
// measured alternately in one process, several rounds, the fastest round of
// each run kept, so machine noise hits every engine alike. The peers run
// the problems mbrt's models were built for (MBRT_TIMING_WP_PROBLEMS).
//   work_precision [ROUNDS=3] [CSV=work_precision.csv]
// Writes the CSV and prints a table with each run's time ratio at equal error
// to MuJoCo and (mbrt runs) to staggered-pcst.
#include <cstdio>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "equal_error.hpp"
#include "mbrt_engine.hpp"
#include "model_adapter.hpp"
#include "work_precision_variants.hpp"
#ifdef MBRT_WITH_MUJOCO
#include "mujoco_engine.hpp"
#endif
#ifdef MBRT_WITH_SIMBODY
#include "simbody_engine.hpp"
#endif
#ifdef MBRT_WITH_DART
#include "dart_engine.hpp"
#endif

namespace {

using timing::Measurement;
using Run = std::function<Measurement()>;

#define MBRT_ADAPT(name, ns, method) BENCH_MODEL(ns##_model, ns);
MBRT_VARIANTS(MBRT_ADAPT)
#undef MBRT_ADAPT

using PeerRun = Measurement (*)(const timing::Problem&, const std::string&, double);

// The problems built (timing/CMakeLists.txt's wp_problems, or a part of them).
const std::set<std::string>& built_problems() {
  static const std::set<std::string> names = {
#define MBRT_NAME(name, ns, method) #name,
      MBRT_VARIANTS(MBRT_NAME)
#undef MBRT_NAME
  };
  return names;
}

// A peer on the problems built that it builds too (builds: null for all).
void add_peer(std::vector<Run>& runs, const std::vector<std::string>& methods, PeerRun run,
              bool (*builds)(const timing::Problem&) = nullptr) {
  for (const timing::Problem& p : timing::problems())
    if (built_problems().count(p.name) && (!builds || builds(p)))
      for (const std::string& method : methods)
        for (double h : timing::peer_steps(p)) runs.push_back([&p, method, h, run] { return run(p, method, h); });
}

std::vector<Run> all_runs() {
  std::vector<Run> runs;
#define MBRT_RUN(name, ns, method) \
  runs.push_back([] { return timing::run_mbrt<ns##_model>(timing::problem(#name), method); });
  MBRT_VARIANTS(MBRT_RUN)
#undef MBRT_RUN
#ifdef MBRT_WITH_MUJOCO
  add_peer(runs, timing::mujoco_methods(), timing::run_mujoco);
#endif
#ifdef MBRT_WITH_SIMBODY
  add_peer(runs, timing::simbody_methods(), timing::run_simbody);
#endif
#ifdef MBRT_WITH_DART
  add_peer(runs, timing::dart_methods(), timing::run_dart, timing::dart_builds);
#endif
  return runs;
}

std::string ratio_text(const std::optional<double>& r) {
  if (!r) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", *r);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const char* csv_path = argc > 2 ? argv[2] : "work_precision.csv";
  const std::vector<Run> runs = all_runs();
  std::vector<Measurement> best;
  for (int round = 0; round < rounds; ++round) {
    for (size_t i = 0; i < runs.size(); ++i) {
      const Measurement m = runs[i]();
      if (best.size() <= i) {
        best.push_back(m);
      } else if (m.seconds < best[i].seconds) {
        best[i].seconds = m.seconds;
      }
    }
    std::fprintf(stderr, "round %d of %d done (%zu runs)\n", round + 1, rounds, runs.size());
  }
  std::FILE* csv = std::fopen(csv_path, "w");
  if (!csv) {
    std::perror(csv_path);
    return 1;
  }
  std::fprintf(csv,
               "problem,engine,method,h,steps,max_error,run_s,ns_per_step,allocations_per_step,failed,"
               "time_ratio_to_mujoco,time_ratio_to_staggered_pcst\n");
  std::printf("%-18s %-8s %-22s %10s %12s %12s %10s %8s %-10s %s\n", "problem", "engine", "method", "h", "max_error",
              "run_s", "ns/step", "allocs", "/MuJoCo", "/staggered-pcst (time at equal error)");
  for (const Measurement& m : best) {
    if (!m.failed && m.samples == 0) {
      std::fprintf(stderr, "%s %s %s at h = %g: no reference sample on its steps, left out\n", m.problem.c_str(),
                   m.engine.c_str(), m.method.c_str(), m.h);
      continue;
    }
    const double steps = static_cast<double>(std::max(1L, m.steps));
    const double ns = 1e9 * m.seconds / steps, allocs = static_cast<double>(m.allocations) / steps;
    const std::string to_mujoco = ratio_text(timing::ratio_to_mujoco(m, best));
    const std::string to_pcst = ratio_text(timing::ratio_to_staggered_pcst(m, best));
    std::fprintf(csv, "%s,%s,%s,%.6g,%ld,%.6g,%.6g,%.1f,%.3g,%d,%s,%s\n", m.problem.c_str(), m.engine.c_str(),
                 m.method.c_str(), m.h, m.steps, m.error, m.seconds, ns, allocs, m.failed ? 1 : 0, to_mujoco.c_str(),
                 to_pcst.c_str());
    std::printf("%-18s %-8s %-22s %10.4g %12.4g %12.4g %10.1f %8.3g %-10s %s\n", m.problem.c_str(), m.engine.c_str(),
                m.method.c_str(), m.h, m.error, m.seconds, ns, allocs, to_mujoco.c_str(), to_pcst.c_str());
  }
  std::fclose(csv);
  return 0;
}
