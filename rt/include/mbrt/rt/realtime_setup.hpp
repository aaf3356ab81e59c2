// Process set-up for a real-time loop: lock memory, prefault the stack,
// optionally SCHED_FIFO and CPU pinning. Each step that is not permitted
// (no CAP_SYS_NICE, a small RLIMIT_MEMLOCK, ...) is skipped with a warning on
// stderr; the loop then runs, with less protection from the rest of the machine.
#pragma once

#include <string>

namespace mbrt::rt {

struct RealtimeOptions {
  int fifo_priority = 0;  // 0: keep the default scheduler
  int cpu = -1;           // -1: no pinning
};

struct RealtimeStatus {
  bool memory_locked = false;
  bool fifo = false;
  bool pinned = false;
  std::string warnings;  // one line per step that was skipped
};

RealtimeStatus prepare_realtime(const RealtimeOptions& options);

}  // namespace mbrt::rt
