// mbrt::WorkerTeam: serial in order until started; started, every part once
// per run on its own thread, the parts' writes visible to the caller after
// run() and the caller's to the parts; stop(), a second start() and the
// destructor; workers idle long enough to yield; no allocation in run(). The
// _tsan build runs the same cases under ThreadSanitizer, without the malloc
// interposer (TSan replaces malloc). A run takes a microsecond while every
// part has a CPU; on a loaded machine, or with more parts than CPUs, it waits
// for the scheduler to switch threads (milliseconds: the caller spins without
// yielding), so the repeated runs stop early at a time budget.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <thread>
#include <vector>

#include <sched.h>

#include <mbrt/worker_team.hpp>

#ifndef MBRT_TEST_WITHOUT_ALLOCATION_COUNTER
#include "allocation_counter.hpp"
#endif

using mbrt::WorkerTeam;

namespace {

// The CPUs this process may run on.
int cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 1;
  return std::max(CPU_COUNT(&set), 1);
}

using Clock = std::chrono::steady_clock;

// Whether to run again after `done` runs: up to `runs`, at least 20, and no
// more once the deadline has passed.
bool more_runs(long done, long runs, Clock::time_point deadline) {
  return done < runs && (done < 20 || Clock::now() < deadline);
}

void report_short(long done, long runs) {
  if (done < runs) MESSAGE("a loaded machine: " << done << " of " << runs << " runs in the time budget");
}

// The threads of this process now.
int thread_count() {
  int n = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) ++n;
  return n;
}

// The same, given a second to reach `expected`: a joined thread leaves
// /proc/self/task a moment after pthread_join returns.
int thread_count_reaching(int expected) {
  const auto deadline = Clock::now() + std::chrono::seconds(1);
  int n = thread_count();
  while (n != expected && Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    n = thread_count();
  }
  return n;
}

// Which thread ran each part, in which order: for serial runs (one thread).
struct OrderRecorder {
  std::vector<int> order;
  std::vector<std::thread::id> threads;
  void operator()(int p) {
    order.push_back(p);
    threads.push_back(std::this_thread::get_id());
  }
};

void check_serial(WorkerTeam& team) {
  OrderRecorder recorder;
  recorder.order.reserve(WorkerTeam::kMaxParts);
  recorder.threads.reserve(WorkerTeam::kMaxParts);
  team.run(recorder);
  REQUIRE(recorder.order.size() == static_cast<std::size_t>(team.parts()));
  for (int p = 0; p < team.parts(); ++p) {
    CHECK(recorder.order[static_cast<std::size_t>(p)] == p);
    CHECK(recorder.threads[static_cast<std::size_t>(p)] == std::this_thread::get_id());
  }
}

// One cache line per part: parts write only their own.
struct alignas(64) PartSlot {
  long sum = 0;
  long calls = 0;
  std::thread::id thread;
};

}  // namespace

TEST_CASE("parts are clamped to [1, kMaxParts]") {
  CHECK(WorkerTeam(0).parts() == 1);
  CHECK(WorkerTeam(-3).parts() == 1);
  CHECK(WorkerTeam(5).parts() == 5);
  CHECK(WorkerTeam(1000).parts() == WorkerTeam::kMaxParts);
}

TEST_CASE("a team not started runs the parts in order on the caller's thread") {
  for (const int parts : {1, 2, 3, 4, 7}) {
    CAPTURE(parts);
    WorkerTeam team(parts);
    CHECK_FALSE(team.running());
    check_serial(team);
  }
}

TEST_CASE("a started team runs every part once per run, part p >= 1 on worker p") {
  for (const int parts : {2, 3, 4}) {
    CAPTURE(parts);
    WorkerTeam team(parts);
    team.start();
    REQUIRE(team.running());
    PartSlot slots[4];
    auto task = [&slots](int p) noexcept {
      PartSlot& s = slots[p];
      s.sum += p + 1;
      ++s.calls;
      s.thread = std::this_thread::get_id();
    };
    constexpr long kRuns = 10000;
    const Clock::time_point deadline = Clock::now() + std::chrono::milliseconds(1500);
    team.run(task);
    // Part 0 on the caller's thread, the others each on a thread of its own.
    const std::thread::id caller = std::this_thread::get_id();
    CHECK(slots[0].thread == caller);
    for (int p = 1; p < parts; ++p) {
      CHECK(slots[p].thread != caller);
      for (int q = 1; q < p; ++q) CHECK(slots[p].thread != slots[q].thread);
    }
    std::thread::id first[4];
    for (int p = 0; p < parts; ++p) first[p] = slots[p].thread;
    // Checked after each run (plain reads: run() returned, so every part has).
    long wrong_calls = 0;
    long wrong_thread = 0;
    long runs = 1;
    while (more_runs(runs, kRuns, deadline)) {
      team.run(task);
      ++runs;
      for (int p = 0; p < parts; ++p) {
        wrong_calls += slots[p].calls != runs;
        wrong_thread += slots[p].thread != first[p];
      }
    }
    report_short(runs, kRuns);
    CHECK(wrong_calls == 0);
    CHECK(wrong_thread == 0);
    long total = 0;
    for (int p = 0; p < parts; ++p) {
      CHECK(slots[p].calls == runs);
      CHECK(slots[p].sum == runs * (p + 1));
      total += slots[p].sum;
    }
    CHECK(total == runs * parts * (parts + 1) / 2);
  }
}

TEST_CASE("the parts see the caller's writes before run() and the caller sees theirs after it") {
  // Up to four parts, each filling its share of the array; at most a part per
  // CPU, so that the parts run at once and hand over through the atomics alone.
  const int parts = std::clamp(cpus(), 2, 4);
  CAPTURE(parts);
  const std::size_t size = 100000;
  const std::size_t share = size / static_cast<std::size_t>(parts);
  WorkerTeam team(parts);
  team.start();
  std::vector<double> values(size, -1.0);
  double offset = 0.0;  // the caller's write for this run, plain data
  auto fill = [&values, &offset, share](int p) noexcept {
    const std::size_t begin = static_cast<std::size_t>(p) * share;
    for (std::size_t i = begin; i < begin + share; ++i) values[i] = offset + static_cast<double>(i);
  };
  long wrong = 0;
  constexpr long kRuns = 300;
  const Clock::time_point deadline = Clock::now() + std::chrono::seconds(1);
  long run = 0;
  for (; more_runs(run, kRuns, deadline); ++run) {
    offset = 1e6 * static_cast<double>(run);
    team.run(fill);
    const double expected = 1e6 * static_cast<double>(run);
    for (std::size_t i = 0; i < size; ++i) wrong += values[i] != expected + static_cast<double>(i);
  }
  report_short(run, kRuns);
  CHECK(wrong == 0);
}

TEST_CASE("stop() makes run() serial again; start() twice is harmless; the destructor joins") {
  constexpr int kParts = 3;
  WorkerTeam team(kParts);
  team.start();
  const int started = thread_count();
  team.start();
  CHECK(team.running());
  CHECK(thread_count() == started);  // no second set of workers
  long calls[kParts] = {};
  auto count = [&calls](int p) noexcept { ++calls[p]; };
  for (int i = 0; i < 20; ++i) team.run(count);
  for (const long c : calls) CHECK(c == 20);

  team.stop();
  CHECK_FALSE(team.running());
  CHECK(thread_count_reaching(started - (kParts - 1)) == started - (kParts - 1));
  check_serial(team);
  team.stop();  // stopping a stopped team is harmless too
  check_serial(team);

  // Started again after a stop: parallel again, every part once.
  team.start();
  CHECK(thread_count() == started);
  for (int i = 0; i < 20; ++i) team.run(count);
  for (const long c : calls) CHECK(c == 40);

  const int before_scope = thread_count();
  {
    WorkerTeam scoped(4);
    scoped.start();
    CHECK(thread_count() == before_scope + 3);
    long scoped_calls[4] = {};
    auto scoped_count = [&scoped_calls](int p) noexcept { ++scoped_calls[p]; };
    scoped.run(scoped_count);
    for (const long c : scoped_calls) CHECK(c == 1);
  }
  CHECK(thread_count_reaching(before_scope) == before_scope);
}

TEST_CASE("workers idle long enough to yield their CPUs still take the next run") {
  WorkerTeam team(2);
  team.start();
  long calls[2][8] = {};  // part p writes only calls[p]
  auto task = [&calls](int p) noexcept { ++calls[p][0]; };
  for (int i = 1; i <= 3; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(30));  // past 2^16 pauses
    team.run(task);
    CHECK(calls[0][0] == i);
    CHECK(calls[1][0] == i);
  }
}

#ifndef MBRT_TEST_WITHOUT_ALLOCATION_COUNTER
TEST_CASE("run() on a started team allocates nothing") {
  {
    AllocationCounter counter;
    const std::vector<double> v(1000, 1.0);
    CHECK(counter.count() >= 1);  // the counter sees allocations
    CHECK(v.back() == 1.0);
  }
  WorkerTeam team(2);
  team.start();
  long calls[2][8] = {};  // part p writes only calls[p]
  auto task = [&calls](int p) noexcept { ++calls[p][0]; };
  team.run(task);  // warm up outside the counted region
  constexpr long kRuns = 1000;
  const Clock::time_point deadline = Clock::now() + std::chrono::seconds(1);
  long runs = 0;
  long seen = 0;
  {
    AllocationCounter counter;
    for (; more_runs(runs, kRuns, deadline); ++runs) team.run(task);
    seen = counter.count();
  }
  report_short(runs, kRuns);
  CHECK(seen == 0);
  CHECK(calls[0][0] == runs + 1);
  CHECK(calls[1][0] == runs + 1);
}
#endif
