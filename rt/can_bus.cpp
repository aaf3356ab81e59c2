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
  const std::size_t colon = address.rfind(':');
  if (colon == std::string::npos) throw std::runtime_error("expected udp://GROUP:PORT, got '" + spec + "'");
  std::size_t used = 0;
  int port = -1;
  try {
    port = std::stoi(address.substr(colon + 1), &used);
  } catch (const std::exception&) {
  }
  if (port <= 0 || port > 65535 || used != address.size() - colon - 1) throw std::runtime_error("bad port in '" + spec + "'");
  return open_udp_multicast_bus(address.substr(0, colon), port);
}

}  // namespace mbrt::rt
