// Process set-up for a real-time loop: lock memory, prefault the stack and
// the step's workspace,
// optionally SCHED_FIFO and CPU pinning. Each step that is not permitted
// (no CAP_SYS_NICE, a small RLIMIT_MEMLOCK, ...) is skipped with a warning on
// stderr; the loop then runs, with less protection from the rest of the machine.
#pragma once

#include <cstddef>
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

// workspace, bytes: memory the loop's step works on (a generated model's
// Workspace, kWorkspaceBytes), touched page by page before memory is locked so
// the first cycles do not fault it in.
RealtimeStatus prepare_realtime(const RealtimeOptions& options, void* workspace, std::size_t bytes);

}  // namespace mbrt::rt
