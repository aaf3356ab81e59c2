// Writes CAN frames as candump log lines, `(SECONDS.MICROS) IFACE ID#DATA`,
// CAN FD frames `ID##FDATA` with F their CANFD_BRS | CANFD_ESI flags in
// one hex digit (can-utils `candump -l`, read by python-can's
// CanutilsLogReader). The
// file is opened at start-up (throws there); write() formats into a fixed
// buffer and goes to a stdio stream with its own fixed buffer, unlocked (only
// the loop writes), so the loop allocates nothing and takes no lock; a full
// buffer costs one write(2).
#pragma once

#include <cstdio>
#include <string>

#include <linux/can.h>

namespace mbrt::rt {

// One line, NUL-terminated, into out (at least kCandumpLineSize bytes); returns its length.
inline constexpr int kCandumpLineSize = 192;
int format_candump_line(const canfd_frame& f, double timestamp, const char* interface, char* out) noexcept;

class CandumpLog {
 public:
  CandumpLog(const std::string& path, const std::string& interface);
  ~CandumpLog();
  CandumpLog(const CandumpLog&) = delete;
  CandumpLog& operator=(const CandumpLog&) = delete;

  void write(const canfd_frame& f, double timestamp) noexcept;

 private:
  std::FILE* file_;
  std::string interface_;
  char buffer_[1 << 16];
};

}  // namespace mbrt::rt
