// The property the CAN command fuzzer checks, on the actuated test model
// (tests/models/actuated.yaml, three inputs with ranges): a run of CAN
// frames, each unpacked, assembled into commands and judged as `mbrt hil`
// does (receive_can_commands in rt/hil_driver.cpp) with one loop cycle
// after it, keeps the gate's property (watched_gate.hpp); a frame taken as
// a command frame's inputs are inputs of the model. So a frame with our ID
// but a wrong length or the remote flag is counted as malformed, other
// traffic is ignored, and a NaN, Inf or out-of-range command never reaches
// the model.
//
// Input: records [advance of the clock u8, ms][age of a command it
// completes u8, ms][struct canfd_frame, 72 bytes].
#pragma once

#include <cstddef>
#include <cstdint>

#include <mbrt/rt/can_command_assembler.hpp>

#include "actuated_can.hpp"
#include "byte_cursor.hpp"
#include "watched_gate.hpp"

namespace mbrt::fuzz {

// True when the property holds for this run of frames.
inline bool take_any_can_frames(const std::uint8_t* data, std::size_t size) noexcept {
  namespace model = mbrt::models::actuated;
  ByteCursor in{data, data + size};
  WatchedGate<model::kInputs> gate(model::kInputInfo);
  rt::CanCommandAssembler<model::kInputs> assembler;
  std::int64_t now_ns = 0;
  std::uint8_t advance_ms = 0, age_ms = 0;
  canfd_frame f;
  while (in.take(advance_ms) && in.take(age_ms) && in.take(f)) {
    now_ns += advance_ms * kMs;
    can::CommandPart p;
    const can::FrameCheck c = model::can::unpack_command(f, p);
    if (c == can::FrameCheck::malformed) {
      gate.malformed();
    } else if (c == can::FrameCheck::ok) {
      if (p.first_input < 0 || p.count < 1 || p.first_input + p.count > static_cast<int>(model::kInputs)) return false;
      if (assembler.add(p)) gate.offer(assembler.sequence(), age_ms * kMs, assembler.values(), now_ns);
    }
    if (!gate.cycle(now_ns)) return false;
  }
  return true;
}

}  // namespace mbrt::fuzz
