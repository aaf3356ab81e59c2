// The parallel step's phases (docs/parallel.md): a kernel whose statements
// fall into the partition's parts runs them as one fork and join of the
// model's WorkerTeam (include/mbrt/worker_team.hpp), part p on worker p. The
// statements and their order within a part are the serial kernel's, so the
// team's results equal its serial run's bit for bit.
#include "emitter.hpp"

namespace mbrt::codegen {

int Emitter::phase_part(int j) const {
  const Partition& p = a_.partition;
  if (!p.interface(j)) return p.block_part[static_cast<size_t>(j)];
  // Interface blocks have no part; in phases without coupling any part may
  // take them: one each in turn.
  int before = 0;
  for (int i = 0; i < j; ++i) before += p.interface(i) ? 1 : 0;
  return before % p.parts;
}

std::string Emitter::parallel_region(const std::vector<std::string>& part_lines, const std::string& enter,
                                     const std::string& leave) const {
  const auto indented = [](const std::string& lines, const std::string& by) {
    std::string out;
    size_t start = 0;
    while (start < lines.size()) {
      const size_t end = lines.find('\n', start);
      const std::string line = lines.substr(start, end == std::string::npos ? std::string::npos : end - start);
      out += (line.empty() ? "" : by) + line + "\n";
      if (end == std::string::npos) break;
      start = end + 1;
    }
    return out;
  };
  std::string o = "  {\n    auto phase = [&](int part) noexcept {\n" + indented(enter, "    ") + "      switch (part) {\n";
  for (size_t p = 0; p < part_lines.size(); ++p) {
    o += "        case " + std::to_string(p) + ":\n" + indented(part_lines[p], "      ") + "          break;\n";
  }
  o += "      }\n" + indented(leave, "    ") + "    };\n    team.run(phase);\n  }\n";
  return o;
}

void Emitter::worker_team_definition(std::ostringstream& o) const {
  if (!parallel()) return;
  o << "// The threads the step's phases run on (docs/parallel.md); start_workers()\n"
    << "// starts them, and until then the step runs every part on the caller's thread.\n"
    << "mbrt::WorkerTeam team{kParts};\n\n";
}

std::string Emitter::worker_declarations() const {
  if (!parallel()) {
    return "// The serial step: no worker threads to start (docs/parallel.md).\n"
           "inline void start_workers() {}\ninline void stop_workers() noexcept {}\n\n";
  }
  return "// Starts the kParts - 1 worker threads the step shares its phases with,\n"
         "// pinned to their own cores where permitted: call once before the loop (it\n"
         "// allocates). Until then, and after stop_workers(), step() runs the parts\n"
         "// one after the other on the caller's thread, with the same results.\n"
         "void start_workers();\nvoid stop_workers() noexcept;\n\n";
}

std::string Emitter::worker_functions() const {
  if (!parallel()) return "";
  return "void start_workers() { team.start(); }\n\nvoid stop_workers() noexcept { team.stop(); }\n\n";
}

}  // namespace mbrt::codegen
