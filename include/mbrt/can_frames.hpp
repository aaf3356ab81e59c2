// A model's signals in classic CAN frames (linux/can.h `can_frame`), the
// layout `<name>.dbc` describes (docs/hil.md, "CAN"). Every value is a
// little-endian int32 with factor 1e-6 and offset 0, which any DBC decoder
// reads exactly; raw INT32_MIN marks a value that has no such
// representation (NaN, Inf, |x| > 2147.483647), so a non-finite command
// arrives non-finite and is refused. Allocation-free, noexcept.
//
// Frames, with the model's base IDs:
//   state   (state_id):          seq u16, command_seq u16, t u32 (1e-5 s)
//   outputs (state_id + 1 + k):  output values 2k and 2k+1 (DLC 4 for a lone last value)
//   command (command_id + i):    seq u16, state_seq u16, input i
#pragma once

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

struct StateHeader {
  std::uint16_t seq = 0;          // cycle number, modulo 2^16
  std::uint16_t command_seq = 0;  // sequence number of the command in use, modulo 2^16
  double t = 0.0;                 // simulation time, s
};

struct CommandSignal {
  int input = 0;                // which input
  std::uint16_t seq = 0;        // the command's sequence number, modulo 2^16
  std::uint16_t state_seq = 0;  // seq of the state it answers
  double value = 0.0;           // NaN if the frame carried the invalid marker
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

inline can_frame empty_frame(canid_t id, std::uint8_t len) noexcept {
  can_frame f{};
  f.can_id = id;
  f.len = len;
  return f;
}

// Frames with an extended ID, or error frames, are never ours; a remote
// frame or a wrong length with one of our IDs is malformed.
inline FrameCheck check(const can_frame& f, canid_t first, int count, std::uint8_t len_of_last, int& index) noexcept {
  if (f.can_id & (CAN_EFF_FLAG | CAN_ERR_FLAG)) return FrameCheck::unknown_id;
  const canid_t id = f.can_id & CAN_SFF_MASK;
  if (id < first || id >= first + static_cast<canid_t>(count)) return FrameCheck::unknown_id;
  index = static_cast<int>(id - first);
  const std::uint8_t len = index == count - 1 ? len_of_last : 8;
  if ((f.can_id & CAN_RTR_FLAG) || f.len != len) return FrameCheck::malformed;
  return FrameCheck::ok;
}

template <std::size_t N>
inline constexpr int output_frames = static_cast<int>((N + 1) / 2);

template <std::size_t N>
inline void pack_state(canid_t state_id, const std::array<double, N>& y, const StateHeader& h,
                       std::array<can_frame, 1 + output_frames<N>>& frames) noexcept {
  frames[0] = empty_frame(state_id, 8);
  put<std::uint16_t>(frames[0].data, h.seq);
  put<std::uint16_t>(frames[0].data + 2, h.command_seq);
  put<std::uint32_t>(frames[0].data + 4, static_cast<std::uint32_t>(std::llround(h.t / kTimeFactor)));
  for (std::size_t i = 0; i < N; ++i) {
    can_frame& f = frames[1 + i / 2];
    if (i % 2 == 0) f = empty_frame(state_id + 1 + static_cast<canid_t>(i / 2), i + 1 < N ? 8 : 4);
    put<std::int32_t>(f.data + 4 * (i % 2), to_raw(y[i]));
  }
}

// One state or output frame into h or y; other frames are left alone.
template <std::size_t N>
inline FrameCheck unpack_state(canid_t state_id, const can_frame& f, std::array<double, N>& y, StateHeader& h) noexcept {
  int k = 0;
  const FrameCheck c = check(f, state_id, 1 + output_frames<N>, N % 2 ? 4 : 8, k);
  if (c != FrameCheck::ok) return c;
  if (k == 0) {
    h.seq = get<std::uint16_t>(f.data);
    h.command_seq = get<std::uint16_t>(f.data + 2);
    h.t = get<std::uint32_t>(f.data + 4) * kTimeFactor;
    return c;
  }
  const std::size_t first = 2 * static_cast<std::size_t>(k - 1);
  y[first] = from_raw(get<std::int32_t>(f.data));
  if (first + 1 < N) y[first + 1] = from_raw(get<std::int32_t>(f.data + 4));
  return c;
}

template <std::size_t N>
inline void pack_command(canid_t command_id, std::uint16_t seq, std::uint16_t state_seq, const std::array<double, N>& u,
                         std::array<can_frame, N>& frames) noexcept {
  for (std::size_t i = 0; i < N; ++i) {
    frames[i] = empty_frame(command_id + static_cast<canid_t>(i), 8);
    put<std::uint16_t>(frames[i].data, seq);
    put<std::uint16_t>(frames[i].data + 2, state_seq);
    put<std::int32_t>(frames[i].data + 4, to_raw(u[i]));
  }
}

template <std::size_t N>
inline FrameCheck unpack_command(canid_t command_id, const can_frame& f, CommandSignal& s) noexcept {
  int i = 0;
  const FrameCheck c = check(f, command_id, static_cast<int>(N), 8, i);
  if (c != FrameCheck::ok) return c;
  s.input = i;
  s.seq = get<std::uint16_t>(f.data);
  s.state_seq = get<std::uint16_t>(f.data + 2);
  s.value = from_raw(get<std::int32_t>(f.data + 4));
  return c;
}

}  // namespace mbrt::can
