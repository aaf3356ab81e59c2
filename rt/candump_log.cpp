#include "mbrt/rt/candump_log.hpp"

#include <cmath>
#include <stdexcept>

#include <mbrt/can_frames.hpp>

namespace mbrt::rt {

int format_candump_line(const canfd_frame& f, double timestamp, const char* interface, char* out) noexcept {
  static constexpr char kHex[] = "0123456789ABCDEF";
  const double whole = std::floor(timestamp);
  const long micros = std::lround((timestamp - whole) * 1e6);
  const bool extended = f.can_id & CAN_EFF_FLAG;
  int n = std::snprintf(out, kCandumpLineSize, extended ? "(%ld.%06ld) %.16s %08X#" : "(%ld.%06ld) %.16s %03X#",
                        static_cast<long>(whole) + micros / 1000000, micros % 1000000, interface,
                        f.can_id & (extended ? CAN_EFF_MASK : CAN_SFF_MASK));
  const bool fd = mbrt::can::is_fd(f);
  if (fd) {
    out[n++] = '#';
    out[n++] = kHex[f.flags & (CANFD_BRS | CANFD_ESI)];
  }
  if (f.can_id & CAN_RTR_FLAG) {
    out[n++] = 'R';
  } else {
    for (int i = 0; i < f.len && i < (fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN); ++i) {
      out[n++] = kHex[f.data[i] >> 4];
      out[n++] = kHex[f.data[i] & 15];
    }
  }
  out[n++] = '\n';
  out[n] = '\0';
  return n;
}

CandumpLog::CandumpLog(const std::string& path, const std::string& interface)
    : file_(std::fopen(path.c_str(), "w")), interface_(interface) {
  if (!file_) throw std::runtime_error("cannot write the CAN log " + path);
  std::setvbuf(file_, buffer_, _IOFBF, sizeof buffer_);
}

CandumpLog::~CandumpLog() { std::fclose(file_); }

void CandumpLog::write(const canfd_frame& f, double timestamp) noexcept {
  char line[kCandumpLineSize];
  const int n = format_candump_line(f, timestamp, interface_.c_str(), line);
  // Only the loop writes: no need for stdio's stream lock.
  fwrite_unlocked(line, 1, static_cast<std::size_t>(n), file_);
}

}  // namespace mbrt::rt
