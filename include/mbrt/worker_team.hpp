// A fixed team of worker threads that a step shares its work with, one phase
// at a time (fork-join): run(task) calls task(p) for every part p, part 0 on
// the caller's thread and part p >= 1 on worker p, and returns when all parts
// have returned. A phase of a step lasts microseconds, about what waking a
// sleeping thread takes, so the workers wait for work by spinning, and run()
// hands the work over and collects it through atomics alone: it allocates
// nothing, takes no lock, makes no system call and throws nothing, so it
// runs on the loop path. start() creates the threads (it allocates: call it
// before the loop); until then, and after stop(), run() calls the parts in
// order on the caller's thread.
//
// Give every part a CPU of its own (parts <= the CPUs the loop may use, none
// busy with other work): a worker the scheduler has preempted holds up run(),
// whose caller spins without yielding, for the scheduler's time slice, which
// is milliseconds.
//
// One phase at a time, from one thread: start(), run() and stop() are called
// by the thread that owns the team, and a task must not call run() itself.
// A task is called noexcept: one that throws terminates the program.
// Linux only (pthread affinity, sched_yield).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <thread>
#include <vector>

#include <pthread.h>
#include <sched.h>
#include <unistd.h>

namespace mbrt {

class WorkerTeam {
 public:
  static constexpr int kMaxParts = 64;

  // 1 <= parts <= kMaxParts (clamped); no threads yet.
  explicit WorkerTeam(int parts) noexcept : parts_(parts < 1 ? 1 : parts > kMaxParts ? kMaxParts : parts) {}
  WorkerTeam(const WorkerTeam&) = delete;
  WorkerTeam& operator=(const WorkerTeam&) = delete;
  ~WorkerTeam() { stop(); }

  // Creates parts - 1 worker threads, worker p pinned to CPU p % (online
  // CPUs) where the process may (failures are ignored: the worker then runs
  // wherever the scheduler puts it). Idempotent; with one part there are no
  // workers and run() stays serial. May throw std::system_error (a thread
  // could not be created) or std::bad_alloc; the team is then stopped and
  // still runs serially.
  void start() {
    if (running_) return;
    threads_.reserve(static_cast<std::size_t>(parts_ - 1));
    const long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    const std::uint64_t now = generation_.load(std::memory_order_relaxed);
    try {
      for (int p = 1; p < parts_; ++p) {
        threads_.emplace_back(&WorkerTeam::work, this, p, now);
        if (cpus > 0) {
          cpu_set_t cpu;
          CPU_ZERO(&cpu);
          CPU_SET(static_cast<std::size_t>(p % cpus), &cpu);
          pthread_setaffinity_np(threads_.back().native_handle(), sizeof cpu, &cpu);
        }
      }
    } catch (...) {
      join_workers();
      throw;
    }
    running_ = true;
  }

  // Tells the workers to finish and joins them; afterwards run() is serial again.
  void stop() noexcept {
    join_workers();
    running_ = false;
  }

  bool running() const noexcept { return running_; }
  int parts() const noexcept { return parts_; }

  // Calls task(p) once for every p in [0, parts()) and returns when all have
  // returned (their writes are then visible to the caller, and the caller's
  // writes before run() to every part).
  template <class Task>
  void run(Task& task) noexcept {
    if (threads_.empty()) {
      for (int p = 0; p < parts_; ++p) task(p);
      return;
    }
    // A plain function pointer and the task's address, no std::function: nothing to allocate.
    call_ = [](void* t, int p) noexcept { (*static_cast<Task*>(t))(p); };
    task_ = const_cast<void*>(static_cast<const void*>(std::addressof(task)));
    const std::uint64_t g = generation_.load(std::memory_order_relaxed) + 1;
    generation_.store(g, std::memory_order_release);  // publishes call_ and task_
    task(0);
    for (int p = 1; p < parts_; ++p) {
      while (done_[p].generation.load(std::memory_order_acquire) != g) pause();
    }
  }

 private:
  // How long a worker spins without work before it yields between spins:
  // 2^16 pauses, about 0.2 to 2 ms on x86 (a pause takes 10 to 140 cycles).
  // A running loop's next phase normally comes sooner; one that comes later
  // finds the worker at most a sched_yield() away (microseconds on a CPU of
  // its own).
  static constexpr unsigned kSpinsBeforeYield = 1u << 16;

  static void pause() noexcept {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  }

  void work(int p, std::uint64_t seen) noexcept {
    for (;;) {
      std::uint64_t g;
      unsigned spins = 0;
      while ((g = generation_.load(std::memory_order_acquire)) == seen) {
        // An idle team (the loop stopped, or a team started long before its
        // loop) would otherwise keep its CPUs busy and starve the other
        // processes of a shared machine: after a long idle, give the CPU
        // away between spins. Only this wait yields, never the caller's.
        if (spins < kSpinsBeforeYield) {
          ++spins;
          pause();
        } else {
          sched_yield();
        }
      }
      seen = g;
      if (call_ == nullptr) return;  // stop()
      call_(task_, p);
      done_[p].generation.store(g, std::memory_order_release);  // publishes the part's writes
    }
  }

  void join_workers() noexcept {
    if (threads_.empty()) return;
    call_ = nullptr;
    generation_.store(generation_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
    for (std::thread& t : threads_) t.join();
    threads_.clear();
  }

  // Each worker writes its own slot, on a cache line of its own: no worker's
  // store evicts the line another worker or the caller is reading.
  struct alignas(64) Done {
    std::atomic<std::uint64_t> generation{0};
  };

  int parts_;
  bool running_ = false;
  // Written by the caller only, read by the workers: the work of the current
  // generation. call_ and task_ are plain data published by the release
  // store of generation_, and rewritten only after every worker's done slot
  // shows that it has finished reading them. One cache line: a worker that
  // sees the new generation finds its work beside it.
  alignas(64) std::atomic<std::uint64_t> generation_{0};
  void (*call_)(void*, int) = nullptr;
  void* task_ = nullptr;
  Done done_[kMaxParts];
  std::vector<std::thread> threads_;
};

}  // namespace mbrt
