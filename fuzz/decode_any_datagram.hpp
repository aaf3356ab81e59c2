// The property the CAN-over-UDP wire fuzzer checks: any datagram either
// does not decode, or decodes to a valid frame (a classic one with at most 8
// data bytes, or a CAN FD one with a CAN FD length; an identifier inside its
// format's range) that encodes to a datagram decoding to the same frame. Anything else, a crash or a sanitizer report
// included, is a bug.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include <mbrt/can_frames.hpp>
#include <mbrt/rt/can_udp_wire.hpp>

namespace mbrt::fuzz {

inline bool same_frame(const canfd_frame& a, const canfd_frame& b) noexcept {
  return a.can_id == b.can_id && a.len == b.len && a.flags == b.flags && std::memcmp(a.data, b.data, a.len) == 0;
}

// True when the property holds for this datagram.
inline bool decode_any_datagram(const std::uint8_t* data, std::size_t size) noexcept {
  canfd_frame f;
  if (!rt::decode_can_udp(data, size, f)) return true;
  const canid_t id_range = f.can_id & CAN_EFF_FLAG ? CAN_EFF_MASK : CAN_SFF_MASK;
  const bool length_ok = can::is_fd(f) ? can::is_fd_length(f.len) : f.len <= CAN_MAX_DLEN;
  if (!length_ok || (f.can_id & CAN_EFF_MASK) > id_range) return false;
  std::uint8_t wire[rt::kCanUdpMaxDatagram];
  canfd_frame back;
  return rt::decode_can_udp(wire, rt::encode_can_udp(f, 0.0, wire), back) && same_frame(back, f);
}

}  // namespace mbrt::fuzz
