// Run time against error for every scheme and step size on reference
// problems, measured alternately in one process so machine noise hits all
// variants alike. Writes a CSV table on stdout.
//
// Errors are against independent references: A01, the bob position at every
// 0.5 s up to 20 s against the minimal-coordinate equation integrated by RK4;
// heavy top, the height of the centre of mass at 8 times up to 2 s against
// the closed-form Lagrange-top solution.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "reference_solutions.hpp"
#include "work_precision_variants.hpp"

namespace {

// A01 to 20 s, sampled every 0.5 s; RK4 reference at 1e-5 s.
const std::vector<mbrt::Vec3> kA01 = reference::a01_bob_positions(20.0, 0.5, 1e-5);

struct Result {
  std::string problem, name, scheme;
  double h = 0, error = 0, best_s = 1e300;
  long steps = 0;
};

using Clock = std::chrono::steady_clock;

template <class Model>
Result run_a01(const char* name) {
  typename Model::State s = Model::initial_state();
  Result r{"a01", name, Model::kScheme, Model::kStep};
  double stepping = 0;
  for (size_t k = 1; k < kA01.size(); ++k) {
    const double t = 0.5 * static_cast<double>(k);
    const auto t0 = Clock::now();
    while (s.t < t - 0.5 * Model::kStep) {
      Model::step(s);
      ++r.steps;
    }
    stepping += std::chrono::duration<double>(Clock::now() - t0).count();
    r.error = std::max(r.error, (s.particle[0].r - kA01[k]).norm());
  }
  r.best_s = stepping;
  return r;
}

template <class Model>
Result run_top(const char* name) {
  typename Model::State s = Model::initial_state();
  Result r{"heavy_top", name, Model::kScheme, Model::kStep};
  double stepping = 0;
  for (const reference::TimedValue& c : reference::kHeavyTopHeight) {
    const auto t0 = Clock::now();
    while (s.t < c.t - 0.5 * Model::kStep) {
      Model::step(s);
      ++r.steps;
    }
    stepping += std::chrono::duration<double>(Clock::now() - t0).count();
    r.error = std::max(r.error, std::abs(s.rigid[0].r.z() - c.value));
  }
  r.best_s = stepping;
  return r;
}

// Adapts a generated model's namespace to a type the templates above take.
#define MBRT_ADAPT(problem, ns)                                                 \
  struct ns##_model {                                                           \
    using State = mbrt::models::ns::State;                                      \
    static constexpr double kStep = mbrt::models::ns::kStep;                    \
    static constexpr const char* kScheme = mbrt::models::ns::kScheme;          \
    static State initial_state() { return mbrt::models::ns::initial_state(); } \
    static void step(State& s) { mbrt::models::ns::step(s); }                   \
  };
MBRT_VARIANTS(MBRT_ADAPT)

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  std::vector<Result> best;
  for (int rep = 0; rep < repeats; ++rep) {
    std::vector<Result> round;
#define MBRT_RUN(problem, ns)                                                                   \
  round.push_back(std::string(#problem) == "a01" ? run_a01<ns##_model>(#ns) : run_top<ns##_model>(#ns));
    MBRT_VARIANTS(MBRT_RUN)
#undef MBRT_RUN
    if (best.empty()) best = round;
    for (size_t i = 0; i < round.size(); ++i) best[i].best_s = std::min(best[i].best_s, round[i].best_s);
    std::fprintf(stderr, "round %d of %d done\n", rep + 1, repeats);
  }
  std::printf("problem,scheme,h,steps,max_error,run_s,ns_per_step\n");
  for (const Result& r : best) {
    std::printf("%s,%s,%.6g,%ld,%.6g,%.6g,%.1f\n", r.problem.c_str(), r.scheme.c_str(), r.h, r.steps, r.error,
                r.best_s, 1e9 * r.best_s / static_cast<double>(r.steps));
  }
  return 0;
}
