// A CAN bus the HIL programs send and receive classic and CAN FD frames on:
// raw SocketCAN (`vcan0`, `can0`: any interface name) or CAN over UDP
// multicast in python-can's `udp_multicast` format (`udp://GROUP:PORT` or
// `udp://[GROUP]:PORT` for an IPv6 group; TTL or hop limit 0, so datagrams
// never leave the host). Frames are `canfd_frame`s, CAN FD
// ones marked by CANFD_FDF in their flags (mbrt/can_frames.hpp). Opened at
// start-up (throws there); send and receive never block, never throw and
// allocate nothing.
#pragma once

#include <memory>
#include <string>

#include <linux/can.h>

namespace mbrt::rt {

class CanBus {
 public:
  virtual ~CanBus() = default;
  virtual bool send(const canfd_frame& f) noexcept = 0;
  // Fills up to max frames with those waiting; returns how many. A datagram
  // or frame that is not a well-formed CAN or CAN FD frame counts in undecodable().
  virtual int receive(canfd_frame* frames, int max) noexcept = 0;
  long undecodable() const noexcept { return undecodable_; }

 protected:
  long undecodable_ = 0;
};

// "udp://GROUP:PORT" (IPv4 multicast group), "udp://[GROUP]:PORT" (IPv6
// multicast group) or a SocketCAN interface name.
// fd: CAN FD frames will be sent, so a SocketCAN interface must have the CAN
// FD MTU (refused at start-up otherwise, rather than every send failing).
std::unique_ptr<CanBus> open_can_bus(const std::string& spec, bool fd);

}  // namespace mbrt::rt
