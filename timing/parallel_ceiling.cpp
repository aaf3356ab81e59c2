// What two threads of this machine give on arithmetic alone: a loop of
// independent multiply-adds over a private, L1-resident array per part, on
// one thread and on a started mbrt::WorkerTeam of two, in the same process.
// On two physical cores the second thread halves the time; on two hardware
// threads of one core (the usual two-vCPU virtual machine) it saves little.
// timing/parallel_speedup prints it beside the step's speed-ups.
//   parallel_ceiling [REGIONS=2000]
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include <mbrt/worker_team.hpp>

int main(int argc, char** argv) {
  const int regions = argc > 1 ? std::atoi(argv[1]) : 2000;
  alignas(64) static double data[2][4096];
  for (auto& part : data) {
    for (double& x : part) x = 1.0;
  }
  auto task = [&](int p) noexcept {
    for (int sweep = 0; sweep < 50; ++sweep) {
      for (double& x : data[p]) x = x * 0.9999999 + 1e-7;
    }
  };
  mbrt::WorkerTeam team(2);
  double seconds[2] = {0.0, 0.0};
  for (int mode = 0; mode < 2; ++mode) {
    if (mode == 1) team.start();
    const auto start = std::chrono::steady_clock::now();
    for (int r = 0; r < regions; ++r) team.run(task);
    seconds[mode] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  std::printf("{\"one_thread_us\": %.3f, \"two_threads_us\": %.3f, \"speedup\": %.3f, \"check\": %g}\n",
              1e6 * seconds[0] / regions, 1e6 * seconds[1] / regions, seconds[0] / seconds[1], data[0][0] + data[1][0]);
  return 0;
}
