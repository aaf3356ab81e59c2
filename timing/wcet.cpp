// Worst-case timing of one generated model's step().
//   wcet warm N HIST.csv          per-step times of N consecutive steps
//   wcet cold N HIST.csv [MB=64]  the same, caches evicted before every step
//                                 by writing MB megabytes
//   wcet realtime N HIST.csv [PRIORITY=80] [CPU=last]
//                                 warm, at SCHED_FIFO PRIORITY, pinned to CPU,
//                                 memory locked (rt/realtime_setup), resting
//                                 between bursts of 1000 steps; fails if the
//                                 scheduler, pinning or locking is refused
//   wcet instructions N EVERY     under callgrind (--collect-atstart=no):
//                                 collects only inside every EVERY-th step and
//                                 dumps after it, one count per sampled step
// warm and cold print one CSV line (mode, steps, failed, timer_ns, min,
// median, p99, p99.99, max in ns, max/median, p99.99/median) and write a
// histogram of the step times (log-spaced bins: lo_ns, hi_ns, count).
// The model is chosen at build time (timing/CMakeLists.txt, MBRT_WCET_MODEL).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>
#include <valgrind/callgrind.h>

#include "mbrt/rt/realtime_setup.hpp"
#include "wcet_model.hpp"

namespace {

namespace model = mbrt::models::wcet_model;
using Clock = std::chrono::steady_clock;

// The step's working memory, owned here as a real-time loop owns it.
model::Workspace workspace;

double ns_between(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::nano>(b - a).count(); }

// Median cost of reading the clock twice, the floor under every figure.
double timer_ns() {
  std::vector<double> t(10000);
  for (double& x : t) {
    const auto a = Clock::now();
    x = ns_between(a, Clock::now());
  }
  std::nth_element(t.begin(), t.begin() + t.size() / 2, t.end());
  return t[t.size() / 2];
}

// Writes every byte of a buffer larger than the caches, evicting the state,
// the step's code and its constants.
class CacheEvictor {
 public:
  explicit CacheEvictor(size_t megabytes) : buffer_(megabytes << 20) {}
  void evict() {
    ++pass_;
    for (size_t i = 0; i < buffer_.size(); i += 64) buffer_[i] = pass_;
  }

 private:
  std::vector<unsigned char> buffer_;
  unsigned char pass_ = 0;
};

double quantile(const std::vector<double>& sorted, double q) {
  return sorted[std::min(sorted.size() - 1, static_cast<size_t>(q * static_cast<double>(sorted.size())))];
}

void write_histogram(const std::vector<double>& sorted, const char* path) {
  std::FILE* f = std::fopen(path, "w");
  if (!f) {
    std::perror(path);
    std::exit(1);
  }
  std::fprintf(f, "lo_ns,hi_ns,count\n");
  const double ratio = std::pow(10.0, 1.0 / 40.0);  // 40 bins a decade
  double lo = std::pow(10.0, std::floor(std::log10(std::max(1.0, sorted.front()))));
  size_t i = 0;
  while (i < sorted.size()) {
    const double hi = lo * ratio;
    size_t count = 0;
    while (i < sorted.size() && sorted[i] < hi) ++count, ++i;
    if (count > 0) std::fprintf(f, "%.4g,%.4g,%zu\n", lo, hi, count);
    lo = hi;
  }
  std::fclose(f);
}

// rest: after every 1000 steps, sleep as long as they took. A SCHED_FIFO
// thread that never sleeps is throttled by the kernel (sched_rt_runtime_us,
// 50 ms of every second by default), which a periodic loop never meets.
int timed(const char* mode, long n, const char* histogram, size_t evict_mb, bool rest = false) {
  std::vector<double> ns(static_cast<size_t>(n));
  CacheEvictor evictor(evict_mb);
  model::State s = model::initial_state();
  for (int i = 0; i < 10000; ++i) model::step(s, workspace);  // warm caches and branch predictors
  long failed = 0;
  auto burst = Clock::now();
  for (size_t i = 0; i < ns.size(); ++i) {
    if (rest && i % 1000 == 0) {
      const auto now = Clock::now();
      std::this_thread::sleep_for(now - burst);
      burst = Clock::now();
    }
    if (evict_mb > 0) evictor.evict();
    const auto a = Clock::now();
    failed += model::step(s, workspace) != mbrt::StepStatus::ok;
    ns[i] = ns_between(a, Clock::now());
  }
  std::sort(ns.begin(), ns.end());
  write_histogram(ns, histogram);
  const double median = quantile(ns, 0.5), p9999 = quantile(ns, 0.9999);
  std::printf("%s,%ld,%ld,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.2f,%.2f\n", mode, n, failed, timer_ns(), ns.front(), median,
              quantile(ns, 0.99), p9999, ns.back(), ns.back() / median, p9999 / median);
  return 0;
}

// The warm run as a HIL loop runs it: real-time scheduler, one CPU, locked
// memory. A refused step would make it the plain warm run under another
// name, so that is an error here rather than the loop's warning.
int realtime(long n, const char* histogram, int priority, int cpu) {
  const mbrt::rt::RealtimeStatus status = mbrt::rt::prepare_realtime({priority, cpu}, &workspace, model::kWorkspaceBytes);
  if (!status.fifo || !status.pinned || !status.memory_locked) {
    std::fprintf(stderr, "wcet realtime: not permitted here:\n%s", status.warnings.c_str());
    return 1;
  }
  return timed("realtime", n, histogram, 0, true);
}

int instructions(long n, long every) {
  model::State s = model::initial_state();
  for (long i = 0; i < n; ++i) {
    const bool sampled = i % every == 0;
    if (sampled) CALLGRIND_TOGGLE_COLLECT;
    model::step(s, workspace);
    if (sampled) {
      CALLGRIND_TOGGLE_COLLECT;
      CALLGRIND_DUMP_STATS;
    }
  }
  return 0;
}

int usage() {
  std::fprintf(stderr,
               "usage: wcet warm N HIST.csv | wcet cold N HIST.csv [MB] | wcet realtime N HIST.csv [PRIORITY] [CPU] |"
               " wcet instructions N EVERY\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) return usage();
  const std::string mode = argv[1];
  const long n = std::atol(argv[2]);
  if (n < 1) return usage();
  if (mode == "warm") return timed("warm", n, argv[3], 0);
  if (mode == "cold") return timed("cold", n, argv[3], argc > 4 ? std::strtoul(argv[4], nullptr, 10) : 64);
  if (mode == "realtime") {
    const int last_cpu = static_cast<int>(sysconf(_SC_NPROCESSORS_ONLN)) - 1;
    return realtime(n, argv[3], argc > 4 ? std::atoi(argv[4]) : 80, argc > 5 ? std::atoi(argv[5]) : last_cpu);
  }
  if (mode == "instructions") return instructions(n, std::max(1L, std::atol(argv[3])));
  return usage();
}
