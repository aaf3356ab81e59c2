// Whole commands from CAN command frames (mbrt/can_frames.hpp): one frame
// per input in classic CAN, one per 15 inputs in CAN FD, each carrying the
// command's 16-bit sequence number and the 16-bit seq of the state it
// answers. A command is whole when the frames of every input with the same
// sequence number have arrived; a frame of another
// sequence number starts over (the unfinished command is lost, and the
// command gate counts the gap as missing). Sequence numbers are unwrapped
// to 64 bits around the last whole command, so the gate orders them as it
// does LCM's. Pure logic, no allocation.
#pragma once

#include <array>
#include <cstdint>

#include <mbrt/can_frames.hpp>

namespace mbrt::rt {

// The 64-bit counter nearest to `near` whose low 16 bits are `low`.
inline std::int64_t unwrap16(std::int64_t near, std::uint16_t low) noexcept {
  return near + static_cast<std::int16_t>(static_cast<std::uint16_t>(low - static_cast<std::uint16_t>(near)));
}

template <std::size_t N>
class CanCommandAssembler {
 public:
  // True when p completes a command; then sequence(), state_seq() and values() describe it.
  bool add(const mbrt::can::CommandPart& p) noexcept {
    if (count_ == 0 || p.seq != seq_) {
      seq_ = p.seq;
      state_seq_ = p.state_seq;
      have_.fill(false);
      count_ = 0;
    }
    const std::size_t first = static_cast<std::size_t>(p.first_input);
    if (have_[first]) return false;  // a repeated frame within one command
    for (std::size_t i = 0; i < static_cast<std::size_t>(p.count); ++i) {
      have_[first + i] = true;
      values_[first + i] = p.values[i];
    }
    count_ += static_cast<std::size_t>(p.count);
    if (count_ < N) return false;
    count_ = 0;  // a repeat of the whole command is assembled again, and judged a duplicate
    last_ = unwrap16(last_, seq_);
    return true;
  }

  std::int64_t sequence() const noexcept { return last_; }
  std::uint16_t state_seq() const noexcept { return state_seq_; }
  const std::array<double, N>& values() const noexcept { return values_; }

 private:
  std::array<bool, N> have_{};
  std::array<double, N> values_{};
  std::size_t count_ = 0;
  std::uint16_t seq_ = 0, state_seq_ = 0;
  std::int64_t last_ = 0;
};

}  // namespace mbrt::rt
