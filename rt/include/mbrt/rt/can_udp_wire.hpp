// The datagram python-can's `udp_multicast` bus exchanges (python-can 4.1,
// can/interfaces/udp_multicast/utils.py): one msgpack map per CAN message
// with the keys timestamp, arbitration_id, is_extended_id, is_remote_frame,
// is_error_frame, channel, dlc, data (bin), is_fd, bitrate_switch,
// error_state_indicator. Classic and CAN FD frames (is_fd, with
// bitrate_switch and error_state_indicator as CANFD_BRS and CANFD_ESI in the
// frame's flags). No allocation, no throw.
#pragma once

#include <cstddef>
#include <cstdint>

#include <linux/can.h>

namespace mbrt::rt {

// Largest datagram encode() writes.
inline constexpr std::size_t kCanUdpMaxDatagram = 256;

// Writes f (timestamp in s) into out; returns the number of bytes.
std::size_t encode_can_udp(const canfd_frame& f, double timestamp, std::uint8_t* out) noexcept;

// Reads a datagram into f: false for anything that is not a complete
// msgpack map of a CAN message (bad msgpack, more than 8 data bytes in a
// classic frame, a CAN FD length that is none of 0-8, 12, 16, 20, 24, 32, 48,
// 64, a remote CAN FD frame, dlc not the data length, trailing bytes).
bool decode_can_udp(const std::uint8_t* data, std::size_t size, canfd_frame& f) noexcept;

}  // namespace mbrt::rt
