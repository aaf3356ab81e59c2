#include "mbrt/rt/can_bus.hpp"

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <sys/socket.h>
#include <unistd.h>

#include "mbrt/rt/can_backends.hpp"

namespace mbrt::rt {

void throw_errno(const std::string& what) { throw std::runtime_error(what + ": " + std::strerror(errno)); }

SocketFd::SocketFd(int domain, int type, int protocol) : fd(::socket(domain, type | SOCK_NONBLOCK, protocol)) {
  if (fd < 0) throw_errno("socket");
}

SocketFd::~SocketFd() { ::close(fd); }

std::unique_ptr<CanBus> open_can_bus(const std::string& spec, bool fd) {
  const std::string udp = "udp://";
  if (spec.rfind(udp, 0) != 0) return open_socketcan_bus(spec, fd);
  const std::string address = spec.substr(udp.size());
  // An IPv6 group is bracketed, as in URLs: its own colons would hide the port's.
  const bool bracketed = !address.empty() && address[0] == '[';
  const std::size_t colon = bracketed ? address.find("]:") + 1 : address.rfind(':');
  if (colon == std::string::npos || colon == 0) {
    throw std::runtime_error("expected udp://GROUP:PORT or udp://[IPv6 GROUP]:PORT, got '" + spec + "'");
  }
  const std::string group = bracketed ? address.substr(1, colon - 2) : address.substr(0, colon);
  if (!bracketed && group.find(':') != std::string::npos) {
    throw std::runtime_error("an IPv6 group goes in brackets, udp://[GROUP]:PORT; got '" + spec + "'");
  }
  std::size_t used = 0;
  int port = -1;
  try {
    port = std::stoi(address.substr(colon + 1), &used);
  } catch (const std::exception&) {
  }
  if (port <= 0 || port > 65535 || used != address.size() - colon - 1) throw std::runtime_error("bad port in '" + spec + "'");
  return open_udp_multicast_bus(group, port);
}

}  // namespace mbrt::rt
