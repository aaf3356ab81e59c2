// A model's signals in CAN frames, classic or CAN FD, the layout
// `<name>.dbc` describes (docs/hil.md, "CAN"). Frames are linux/can.h
// `canfd_frame`s either way: a CAN FD frame has CANFD_FDF in its flags, a
// classic one has no flags and at most 8 bytes (the kernel's dual use of
// `struct canfd_frame`). Every value is a little-endian int32 with factor
// 1e-6 and offset 0, which any DBC decoder reads exactly; raw INT32_MIN
// marks a value that has no such representation (NaN, Inf, |x| >
// 2147.483647), so a non-finite command arrives non-finite and is refused.
// Allocation-free, noexcept.
//
// Frames, with the model's base IDs, P payload bytes (classic 8, FD 64):
//   state   (state_id):          seq u16, command_seq u16, t u32 (1e-5 s),
//                                then output values 0.. while they fit (none in classic CAN)
//   outputs (state_id + 1 + k):  the next P/4 output values each
//   command (command_id + k):    seq u16, state_seq u16, then the next (P-4)/4 inputs
//                                (one in classic CAN)
// A frame is as long as its content: classic frames 4 or 8 bytes, FD frames
// rounded up to the next FD length (8, 12, 16, 20, 24, 32, 48, 64), zero-padded.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <linux/can.h>

namespace mbrt::can {

inline constexpr double kValueFactor = 1e-6;
inline constexpr double kTimeFactor = 1e-5;
inline constexpr std::int32_t kInvalidRaw = std::numeric_limits<std::int32_t>::min();
inline constexpr double kMaxValue = 2147.483647;
inline constexpr int kHeaderBytes = 8;   // state frame: seq, command_seq, t
inline constexpr int kCommandHeaderBytes = 4;  // command frame: seq, state_seq
inline constexpr int kValueBytes = 4;

// The data lengths a CAN FD frame may have (its DLC codes 0 to 15).
inline constexpr bool is_fd_length(int len) noexcept {
  return (len >= 0 && len <= 8) || len == 12 || len == 16 || len == 20 || len == 24 || len == 32 || len == 48 || len == 64;
}

// The frame counts and lengths of one model's layout.
struct Layout {
  bool fd;
  int outputs, inputs;

  constexpr int payload() const noexcept { return fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN; }
  // Shortest frame that holds `bytes`: classic frames take any length up to 8, FD frames the next FD length.
  constexpr std::uint8_t length(int bytes) const noexcept {
    int len = bytes;
    while (fd && !is_fd_length(len)) ++len;
    return static_cast<std::uint8_t>(len);
  }

  constexpr int values_in_header() const noexcept { return (payload() - kHeaderBytes) / kValueBytes; }
  constexpr int values_per_frame() const noexcept { return payload() / kValueBytes; }
  constexpr int state_frames() const noexcept {
    const int rest = std::max(0, outputs - values_in_header());
    return 1 + (rest + values_per_frame() - 1) / values_per_frame();
  }
  // State frame k: its first output's index, how many it carries, the byte of its i-th.
  constexpr int first_output(int k) const noexcept { return k == 0 ? 0 : values_in_header() + (k - 1) * values_per_frame(); }
  constexpr int output_count(int k) const noexcept {
    return std::min(outputs - first_output(k), k == 0 ? values_in_header() : values_per_frame());
  }
  constexpr int output_byte(int k, int i) const noexcept { return (k == 0 ? kHeaderBytes : 0) + kValueBytes * i; }
  constexpr std::uint8_t state_length(int k) const noexcept { return length(output_byte(k, output_count(k))); }

  constexpr int inputs_per_frame() const noexcept { return (payload() - kCommandHeaderBytes) / kValueBytes; }
  constexpr int command_frames() const noexcept { return (inputs + inputs_per_frame() - 1) / inputs_per_frame(); }
  constexpr int first_input(int k) const noexcept { return k * inputs_per_frame(); }
  constexpr int input_count(int k) const noexcept { return std::min(inputs - first_input(k), inputs_per_frame()); }
  // The byte of a command frame's i-th input.
  constexpr int input_byte(int i) const noexcept { return kCommandHeaderBytes + kValueBytes * i; }
  constexpr std::uint8_t command_length(int k) const noexcept { return length(input_byte(input_count(k))); }
};

// Inputs one command frame carries at most (a CAN FD one).
inline constexpr int kMaxInputsPerFrame = Layout{true, 0, 0}.inputs_per_frame();

struct StateHeader {
  std::uint16_t seq = 0;          // cycle number, modulo 2^16
  std::uint16_t command_seq = 0;  // sequence number of the command in use, modulo 2^16
  double t = 0.0;                 // simulation time, s
};

// What one command frame carries: inputs first_input .. first_input + count - 1.
struct CommandPart {
  int first_input = 0;
  int count = 0;
  std::uint16_t seq = 0;        // the command's sequence number, modulo 2^16
  std::uint16_t state_seq = 0;  // seq of the state it answers
  std::array<double, kMaxInputsPerFrame> values{};  // NaN where the frame carried the invalid marker
};

enum class FrameCheck { ok, unknown_id, malformed };

inline std::int32_t to_raw(double x) noexcept {
  if (!(std::abs(x) <= kMaxValue)) return kInvalidRaw;
  return static_cast<std::int32_t>(std::lround(x / kValueFactor));
}
inline double from_raw(std::int32_t raw) noexcept {
  return raw == kInvalidRaw ? std::numeric_limits<double>::quiet_NaN() : raw * kValueFactor;
}

template <class T>
inline void put(std::uint8_t* at, T v) noexcept {  // little-endian hosts (x86-64, aarch64)
  std::memcpy(at, &v, sizeof v);
}
template <class T>
inline T get(const std::uint8_t* at) noexcept {
  T v;
  std::memcpy(&v, at, sizeof v);
  return v;
}

inline bool is_fd(const canfd_frame& f) noexcept { return f.flags & CANFD_FDF; }

inline canfd_frame empty_frame(const Layout& l, canid_t id, std::uint8_t len) noexcept {
  canfd_frame f{};
  f.can_id = id;
  f.len = len;
  if (l.fd) f.flags = CANFD_FDF;
  return f;
}

// Frames with an extended ID, or error frames, are never ours; a remote
// frame, a frame of the other kind (classic for FD, FD for classic) or a
// wrong length with one of our IDs is malformed.
template <class LengthOf>
inline FrameCheck check(const Layout& l, const canfd_frame& f, canid_t first, int count, LengthOf length_of,
                        int& index) noexcept {
  if (f.can_id & (CAN_EFF_FLAG | CAN_ERR_FLAG)) return FrameCheck::unknown_id;
  const canid_t id = f.can_id & CAN_SFF_MASK;
  if (id < first || id >= first + static_cast<canid_t>(count)) return FrameCheck::unknown_id;
  index = static_cast<int>(id - first);
  if ((f.can_id & CAN_RTR_FLAG) || is_fd(f) != l.fd || f.len != length_of(index)) return FrameCheck::malformed;
  return FrameCheck::ok;
}

// y has l.outputs values; frames has l.state_frames() frames.
inline void pack_state(const Layout& l, canid_t state_id, const double* y, const StateHeader& h, canfd_frame* frames) noexcept {
  for (int k = 0; k < l.state_frames(); ++k) {
    canfd_frame& f = frames[k];
    f = empty_frame(l, state_id + static_cast<canid_t>(k), l.state_length(k));
    for (int i = 0; i < l.output_count(k); ++i) put<std::int32_t>(f.data + l.output_byte(k, i), to_raw(y[l.first_output(k) + i]));
  }
  put<std::uint16_t>(frames[0].data, h.seq);
  put<std::uint16_t>(frames[0].data + 2, h.command_seq);
  put<std::uint32_t>(frames[0].data + 4, static_cast<std::uint32_t>(std::llround(h.t / kTimeFactor)));
}

// One state or output frame into h (the state frame) and y; other frames are left alone.
inline FrameCheck unpack_state(const Layout& l, canid_t state_id, const canfd_frame& f, double* y, StateHeader& h) noexcept {
  int k = 0;
  const FrameCheck c = check(l, f, state_id, l.state_frames(), [&](int i) { return l.state_length(i); }, k);
  if (c != FrameCheck::ok) return c;
  if (k == 0) {
    h.seq = get<std::uint16_t>(f.data);
    h.command_seq = get<std::uint16_t>(f.data + 2);
    h.t = get<std::uint32_t>(f.data + 4) * kTimeFactor;
  }
  for (int i = 0; i < l.output_count(k); ++i) y[l.first_output(k) + i] = from_raw(get<std::int32_t>(f.data + l.output_byte(k, i)));
  return c;
}

// u has l.inputs values; frames has l.command_frames() frames.
inline void pack_command(const Layout& l, canid_t command_id, std::uint16_t seq, std::uint16_t state_seq, const double* u,
                         canfd_frame* frames) noexcept {
  for (int k = 0; k < l.command_frames(); ++k) {
    canfd_frame& f = frames[k];
    f = empty_frame(l, command_id + static_cast<canid_t>(k), l.command_length(k));
    put<std::uint16_t>(f.data, seq);
    put<std::uint16_t>(f.data + 2, state_seq);
    for (int i = 0; i < l.input_count(k); ++i) put<std::int32_t>(f.data + l.input_byte(i), to_raw(u[l.first_input(k) + i]));
  }
}

inline FrameCheck unpack_command(const Layout& l, canid_t command_id, const canfd_frame& f, CommandPart& p) noexcept {
  int k = 0;
  const FrameCheck c = check(l, f, command_id, l.command_frames(), [&](int i) { return l.command_length(i); }, k);
  if (c != FrameCheck::ok) return c;
  p.first_input = l.first_input(k);
  p.count = l.input_count(k);
  p.seq = get<std::uint16_t>(f.data);
  p.state_seq = get<std::uint16_t>(f.data + 2);
  for (int i = 0; i < p.count; ++i) p.values[static_cast<std::size_t>(i)] = from_raw(get<std::int32_t>(f.data + l.input_byte(i)));
  return c;
}

}  // namespace mbrt::can
