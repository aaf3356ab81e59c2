#include "mbrt/rt/realtime_setup.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>

namespace mbrt::rt {

namespace {

constexpr std::size_t kPage = 4096;

// Touch the stack the loop will use, so its pages are mapped (and, with
// mlockall, locked) before the first cycle rather than faulted in during one.
// The step keeps its large data in the caller's workspace; on the stack are
// its per-body vectors and the loop's own frames.
void prefault_stack() {
  constexpr std::size_t kBytes = 512 * 1024;
  unsigned char stack[kBytes];
  volatile unsigned char* const page = stack;  // writes the compiler must keep
  for (std::size_t i = 0; i < kBytes; i += kPage) page[i] = 0;
}

// Write every page of the workspace once (its contents do not matter: the
// step overwrites what it reads).
void prefault(void* memory, std::size_t bytes) {
  auto* p = static_cast<volatile unsigned char*>(memory);
  for (std::size_t i = 0; i < bytes; i += kPage) p[i] = 0;
  if (bytes > 0) p[bytes - 1] = 0;
}

void warn(RealtimeStatus& status, const std::string& what) {
  status.warnings += what + "\n";
  std::fprintf(stderr, "warning: %s\n", what.c_str());
}

}  // namespace

RealtimeStatus prepare_realtime(const RealtimeOptions& options, void* workspace, std::size_t bytes) {
  RealtimeStatus status;
  // Stack first: grown after mlockall(MCL_FUTURE), it must stay within
  // RLIMIT_MEMLOCK or the process dies of SIGSEGV; before, mlockall counts
  // it and fails cleanly if the limit is too small.
  prefault_stack();
  prefault(workspace, bytes);
  status.memory_locked = mlockall(MCL_CURRENT | MCL_FUTURE) == 0;
  if (!status.memory_locked) {
    const std::string why = std::strerror(errno);
    rlimit limit{};
    getrlimit(RLIMIT_MEMLOCK, &limit);
    const std::string allowed =
        limit.rlim_cur == RLIM_INFINITY ? "unlimited" : std::to_string(limit.rlim_cur / 1024) + " KiB";
    warn(status, "mlockall failed (" + why + "; RLIMIT_MEMLOCK " + allowed +
                     "): pages may be swapped or faulted in during the loop; raise it with ulimit -l");
  }
  if (options.cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(options.cpu, &set);
    status.pinned = sched_setaffinity(0, sizeof set, &set) == 0;
    if (!status.pinned) warn(status, "cannot pin to CPU " + std::to_string(options.cpu) + " (" + std::strerror(errno) + ")");
  }
  if (options.fifo_priority > 0) {
    const sched_param p{options.fifo_priority};
    status.fifo = sched_setscheduler(0, SCHED_FIFO, &p) == 0;
    if (!status.fifo) {
      warn(status, std::string("SCHED_FIFO refused (") + std::strerror(errno) +
                       "): running with the default scheduler; needs CAP_SYS_NICE or an rtprio limit");
    }
  }
  return status;
}

}  // namespace mbrt::rt
