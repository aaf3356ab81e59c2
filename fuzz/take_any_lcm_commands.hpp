// The property the LCM command fuzzer checks, on the actuated test model
// (tests/models/actuated.yaml, three inputs with ranges): a run of messages
// on the command channel, each decoded and judged as `mbrt hil` does
// (on_command in rt/hil_driver.cpp) with one loop cycle after it, keeps the
// gate's property (watched_gate.hpp). So a message that does not decode is
// counted as malformed, and a NaN, Inf or out-of-range command never
// reaches the model.
//
// Input: records [advance of the clocks u8, ms][message size u8][message].
#pragma once

#include <cstddef>
#include <cstdint>

#include "actuated_lcm.hpp"
#include "byte_cursor.hpp"
#include "watched_gate.hpp"

namespace mbrt::fuzz {

// The wall clock (LCM utime, microseconds) at the first record.
inline constexpr std::int64_t kLcmStartUs = 1'700'000'000'000'000;

// True when the property holds for this run of messages.
inline bool take_any_lcm_commands(const std::uint8_t* data, std::size_t size) noexcept {
  namespace model = mbrt::models::actuated;
  ByteCursor in{data, data + size};
  WatchedGate<model::kInputs> gate(model::kInputInfo);
  model::CommandMessage m{};
  std::int64_t now_ns = 0;
  std::uint8_t advance_ms = 0, message_size = 0;
  while (in.take(advance_ms) && in.take(message_size)) {
    const std::uint8_t* message = in.take_bytes(message_size);
    if (!message) break;
    now_ns += advance_ms * kMs;
    if (model::decode_exactly(message, message_size, m)) {
      model::Inputs values;
      model::unpack_inputs(m, values);
      gate.offer(m.seq, rt::lcm_command_age_ns(kLcmStartUs + now_ns / 1000, m.utime, m.state_utime), values, now_ns);
    } else {
      gate.malformed();
    }
    if (!gate.cycle(now_ns)) return false;
  }
  return true;
}

}  // namespace mbrt::fuzz
