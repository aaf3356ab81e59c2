// An mbrt model file run in a peer engine at a fixed step, for the long-run
// stability comparison (timing/stability_stress): MuJoCo's, Simbody's or DART's
// fixed-step integrators on the same bodies, joints, gravity and initial
// state, with the energy computed here from the engine's body states by the
// definition mbrt uses, so the drifts of all engines and of mbrt compare.
//
//   peer_stability MODEL.yaml --engine ENGINE --h H --t-end T [--series F.csv] [--samples N=1000]
//   peer_stability --list          the engines built in, one a line
//
// ENGINE: mujoco-euler (semi-implicit Euler), mujoco-rk4, simbody-rk3,
// simbody-rk-merson, simbody-semiexplicit-euler, simbody-semiexplicit-euler2
// (two half steps per step), dart-euler, all at the fixed step H
// (peers/tree_engine.hpp).
//
// Models: rigid bodies on revolute and spherical joints forming a tree from
// ground, gravity; nothing else (no springs, forces, drivers, particles).
// Before stepping, the engine's initial state is checked against the model's
// (COM positions, orientations, COM and angular velocities, energy); a
// mismatch is an error (exit 1), so the two runs really start alike.
//
// Prints one JSON line: engine, model, h, steps, finite, t_nonfinite,
// energy_initial, energy_final, max_abs_energy_drift, relative_drift
// (max |E - E0| / |E0|; these three null when the run did not stay finite),
// energy_samples, wall_s, ns_per_step. The energy is sampled every
// max(1, steps / N) steps, at t = 0 and at the last step too; wall_s times the
// steps only, not the sampling. --series writes t,energy per sample.
// Exit status: 0 for a run (finite or not), 1 for a model this cannot run or
// an initial-state mismatch, 2 for a bad command line.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tree_engine.hpp"

namespace {

using namespace timing::tree;

// ---- The run -----------------------------------------------------------------

struct Options {
  std::string model, engine, series;
  double h = 0, t_end = 0;
  long samples = 1000;
};

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr,
               "peer_stability: %s\nusage: peer_stability MODEL.yaml --engine ENGINE --h H --t-end T "
               "[--series F.csv] [--samples N=1000]\n       peer_stability --list\n",
               why.c_str());
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(a + " needs a value");
      return argv[++i];
    };
    if (a == "--engine") o.engine = value();
    else if (a == "--h") o.h = std::atof(value().c_str());
    else if (a == "--t-end") o.t_end = std::atof(value().c_str());
    else if (a == "--series") o.series = value();
    else if (a == "--samples") o.samples = std::atol(value().c_str());
    else if (a.rfind("--", 0) == 0 || !o.model.empty()) usage("unexpected " + a);
    else o.model = a;
  }
  if (o.model.empty() || o.engine.empty()) usage("a model file and --engine are needed");
  const std::vector<std::string> built = engines();
  if (std::find(built.begin(), built.end(), o.engine) == built.end())
    usage("no engine " + o.engine + " built in (peer_stability --list)");
  if (!(o.h > 0) || !(o.t_end > 0) || o.samples < 1) usage("--h and --t-end must be positive, --samples at least 1");
  return o;
}

struct Result {
  long steps = 0;  // taken with a finite result
  bool finite = true;
  double t_nonfinite = NAN;
  double e0 = 0, e_final = 0, max_drift = 0;
  long samples = 0;
  double wall_s = 0;
};

// Steps to t_end, sampling the energy every `every` steps (not timed).
Result run(Engine& engine, const Model& m, const Options& o) {
  const long steps = std::max(1L, std::lround(o.t_end / o.h));
  const long every = std::max(1L, steps / o.samples);
  std::ofstream series;
  if (!o.series.empty()) {
    series.open(o.series);
    if (!series) throw std::runtime_error("cannot write " + o.series);
    series << "t,energy\n";
    series.precision(17);
  }
  Result r;
  const auto sample = [&](long k) {
    const double e = energy(m, engine.states()).total();
    if (k == 0) r.e0 = e;
    r.e_final = e;
    r.max_drift = std::max(r.max_drift, std::abs(e - r.e0));
    ++r.samples;
    if (series.is_open()) series << k * o.h << ',' << e << '\n';
    return std::isfinite(e);
  };
  sample(0);
  std::chrono::steady_clock::duration wall{};
  while (r.steps < steps) {
    const long chunk = std::min(every, steps - r.steps);
    const auto start = std::chrono::steady_clock::now();
    long done = 0;
    while (done < chunk && engine.step()) ++done;
    wall += std::chrono::steady_clock::now() - start;
    r.steps += done;
    if (done < chunk || !sample(r.steps)) {
      r.finite = false;
      r.t_nonfinite = (r.steps + (done < chunk ? 1 : 0)) * o.h;
      break;
    }
  }
  r.wall_s = std::chrono::duration<double>(wall).count();
  return r;
}

void print_json(const Options& o, const Model& m, const Result& r) {
  // A run that blew up has no final energy, and its drift is unbounded
  // (MuJoCo has even reset the state): null, not the drift of the samples
  // before, which may be none. nlohmann-json writes non-finite numbers as null.
  const double end = r.finite ? r.e_final : NAN, drift = r.finite ? r.max_drift : NAN;
  const nlohmann::ordered_json j = {{"engine", o.engine},
                                    {"model", m.name},
                                    {"h", o.h},
                                    {"steps", r.steps},
                                    {"finite", r.finite},
                                    {"t_nonfinite", r.t_nonfinite},
                                    {"energy_initial", r.e0},
                                    {"energy_final", end},
                                    {"max_abs_energy_drift", drift},
                                    {"relative_drift", r.e0 != 0 ? drift / std::abs(r.e0) : NAN},
                                    {"energy_samples", r.samples},
                                    {"wall_s", r.wall_s},
                                    {"ns_per_step", r.steps > 0 ? 1e9 * r.wall_s / static_cast<double>(r.steps) : NAN}};
  std::printf("%s\n", j.dump().c_str());
}

int main_checked(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "--list") {
    for (const std::string& e : engines()) std::printf("%s\n", e.c_str());
    return 0;
  }
  const Options o = parse(argc, argv);
  const Model m = mbrt::codegen::load_model(o.model);
  links(m);  // an unsupported model is refused before any engine sees it
  const std::unique_ptr<Engine> engine = make_engine(o.engine, m, o.h);
  const std::string mismatch = initial_mismatch(m, engine->states());
  if (!mismatch.empty()) {
    std::fprintf(stderr, "peer_stability: %s in %s does not start where the model does: %s\n", o.model.c_str(),
                 o.engine.c_str(), mismatch.c_str());
    return 1;
  }
  print_json(o, m, run(*engine, m, o));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return main_checked(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "peer_stability: %s\n", e.what());
    return 1;
  }
}
