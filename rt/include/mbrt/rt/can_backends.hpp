// The CAN bus backends behind open_can_bus() (can_bus.hpp), and the socket
// they both own. Start-up only: these throw on failure.
#pragma once

#include <memory>
#include <string>

#include <mbrt/rt/can_bus.hpp>

namespace mbrt::rt {

// CAN over UDP multicast in python-can's udp_multicast format (can_udp_bus.cpp).
std::unique_ptr<CanBus> open_udp_multicast_bus(const std::string& group, int port);
// Raw SocketCAN on an interface such as vcan0 (socketcan_bus.cpp); fd as for open_can_bus().
std::unique_ptr<CanBus> open_socketcan_bus(const std::string& interface, bool fd);

// A non-blocking socket, closed with its owner.
class SocketFd {
 public:
  SocketFd(int domain, int type, int protocol);
  ~SocketFd();
  SocketFd(const SocketFd&) = delete;
  SocketFd& operator=(const SocketFd&) = delete;
  const int fd;
};

// Throws "<what>: <strerror(errno)>".
[[noreturn]] void throw_errno(const std::string& what);

}  // namespace mbrt::rt
