// The property the CAN-over-UDP wire fuzzer checks: any datagram either
// does not decode, or decodes to a classic CAN frame (at most 8 data bytes,
// an identifier inside its format's range) that encodes to a datagram
// decoding to the same frame. Anything else, a crash or a sanitizer report
// included, is a bug.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include <mbrt/rt/can_udp_wire.hpp>

namespace mbrt::fuzz {

inline bool same_frame(const can_frame& a, const can_frame& b) noexcept {
  return a.can_id == b.can_id && a.len == b.len && std::memcmp(a.data, b.data, a.len) == 0;
}

// True when the property holds for this datagram.
inline bool decode_any_datagram(const std::uint8_t* data, std::size_t size) noexcept {
  can_frame f;
  if (!rt::decode_can_udp(data, size, f)) return true;
  const canid_t id_range = f.can_id & CAN_EFF_FLAG ? CAN_EFF_MASK : CAN_SFF_MASK;
  if (f.len > CAN_MAX_DLEN || (f.can_id & CAN_EFF_MASK) > id_range) return false;
  std::uint8_t wire[rt::kCanUdpMaxDatagram];
  can_frame back;
  return rt::decode_can_udp(wire, rt::encode_can_udp(f, 0.0, wire), back) && same_frame(back, f);
}

}  // namespace mbrt::fuzz
