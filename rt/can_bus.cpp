#include "mbrt/rt/can_bus.hpp"

#include <cerrno>
#include <cstring>
#include <ctime>
#include <stdexcept>

#include <arpa/inet.h>
#include <net/if.h>
#include <netinet/in.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include "mbrt/rt/can_udp_wire.hpp"

namespace mbrt::rt {

namespace {

[[noreturn]] void fail(const std::string& what) {
  throw std::runtime_error(what + ": " + std::strerror(errno));
}

// Closes the socket if construction fails half-way.
struct Socket {
  int fd;
  explicit Socket(int domain, int type, int protocol) : fd(::socket(domain, type | SOCK_NONBLOCK, protocol)) {
    if (fd < 0) fail("socket");
  }
  ~Socket() { ::close(fd); }
};

class UdpMulticastBus final : public CanBus {
 public:
  UdpMulticastBus(const std::string& group, int port) : socket_(AF_INET, SOCK_DGRAM, 0) {
    const int yes = 1;
    const unsigned char ttl = 0, loop = 1;  // TTL 0: host only; loop: peers on this host hear us
    if (setsockopt(socket_.fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes) != 0) fail("SO_REUSEADDR");
    if (setsockopt(socket_.fd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl) != 0) fail("IP_MULTICAST_TTL");
    if (setsockopt(socket_.fd, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof loop) != 0) fail("IP_MULTICAST_LOOP");
    destination_.sin_family = AF_INET;
    destination_.sin_port = htons(static_cast<std::uint16_t>(port));
    if (inet_pton(AF_INET, group.c_str(), &destination_.sin_addr) != 1 || !IN_MULTICAST(ntohl(destination_.sin_addr.s_addr))) {
      throw std::runtime_error("'" + group + "' is not an IPv4 multicast group");
    }
    sockaddr_in any{};
    any.sin_family = AF_INET;
    any.sin_port = destination_.sin_port;
    any.sin_addr.s_addr = htonl(INADDR_ANY);
    if (bind(socket_.fd, reinterpret_cast<const sockaddr*>(&any), sizeof any) != 0) fail("bind");
    ip_mreq request{};
    request.imr_multiaddr = destination_.sin_addr;
    request.imr_interface.s_addr = htonl(INADDR_ANY);
    if (setsockopt(socket_.fd, IPPROTO_IP, IP_ADD_MEMBERSHIP, &request, sizeof request) != 0) fail("IP_ADD_MEMBERSHIP " + group);
  }

  bool send(const can_frame& f) noexcept override {
    timespec now;
    clock_gettime(CLOCK_REALTIME, &now);
    const std::size_t n = encode_can_udp(f, static_cast<double>(now.tv_sec) + now.tv_nsec * 1e-9, buffer_);
    return sendto(socket_.fd, buffer_, n, 0, reinterpret_cast<const sockaddr*>(&destination_), sizeof destination_) ==
           static_cast<ssize_t>(n);
  }

  int receive(can_frame* frames, int max) noexcept override {
    int n = 0;
    while (n < max) {
      const ssize_t size = recv(socket_.fd, buffer_, sizeof buffer_, MSG_DONTWAIT | MSG_TRUNC);
      if (size < 0) break;
      if (static_cast<std::size_t>(size) <= sizeof buffer_ && decode_can_udp(buffer_, static_cast<std::size_t>(size), frames[n])) ++n;
      else ++undecodable_;
    }
    return n;
  }

 private:
  Socket socket_;
  sockaddr_in destination_{};
  std::uint8_t buffer_[512];
};

class SocketCanBus final : public CanBus {
 public:
  explicit SocketCanBus(const std::string& interface) : socket_(PF_CAN, SOCK_RAW, CAN_RAW) {
    ifreq request{};
    if (interface.size() >= sizeof request.ifr_name) throw std::runtime_error("interface name too long: " + interface);
    std::strncpy(request.ifr_name, interface.c_str(), sizeof request.ifr_name - 1);
    if (ioctl(socket_.fd, SIOCGIFINDEX, &request) != 0) fail("CAN interface '" + interface + "'");
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = request.ifr_ifindex;
    if (bind(socket_.fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) fail("bind " + interface);
  }

  bool send(const can_frame& f) noexcept override {
    return write(socket_.fd, &f, sizeof f) == static_cast<ssize_t>(sizeof f);
  }

  int receive(can_frame* frames, int max) noexcept override {
    int n = 0;
    while (n < max) {
      const ssize_t size = recv(socket_.fd, &frames[n], sizeof(can_frame), MSG_DONTWAIT);
      if (size < 0) break;
      if (size == static_cast<ssize_t>(sizeof(can_frame))) ++n;
      else ++undecodable_;
    }
    return n;
  }

 private:
  Socket socket_;
};

}  // namespace

std::unique_ptr<CanBus> open_can_bus(const std::string& spec) {
  const std::string udp = "udp://";
  if (spec.rfind(udp, 0) != 0) return std::make_unique<SocketCanBus>(spec);
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
  return std::make_unique<UdpMulticastBus>(address.substr(0, colon), port);
}

}  // namespace mbrt::rt
