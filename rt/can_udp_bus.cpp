#include <cstring>
#include <ctime>
#include <stdexcept>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include "mbrt/rt/can_backends.hpp"
#include "mbrt/rt/can_udp_wire.hpp"

namespace mbrt::rt {

namespace {

class UdpMulticastBus final : public CanBus {
 public:
  UdpMulticastBus(const std::string& group, int port) : socket_(AF_INET, SOCK_DGRAM, 0) {
    const int yes = 1;
    const unsigned char ttl = 0, loop = 1;  // TTL 0: host only; loop: peers on this host hear us
    if (setsockopt(socket_.fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes) != 0) throw_errno("SO_REUSEADDR");
    if (setsockopt(socket_.fd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl) != 0) throw_errno("IP_MULTICAST_TTL");
    if (setsockopt(socket_.fd, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof loop) != 0) throw_errno("IP_MULTICAST_LOOP");
    destination_.sin_family = AF_INET;
    destination_.sin_port = htons(static_cast<std::uint16_t>(port));
    if (inet_pton(AF_INET, group.c_str(), &destination_.sin_addr) != 1 || !IN_MULTICAST(ntohl(destination_.sin_addr.s_addr))) {
      throw std::runtime_error("'" + group + "' is not an IPv4 multicast group");
    }
    sockaddr_in any{};
    any.sin_family = AF_INET;
    any.sin_port = destination_.sin_port;
    any.sin_addr.s_addr = htonl(INADDR_ANY);
    if (bind(socket_.fd, reinterpret_cast<const sockaddr*>(&any), sizeof any) != 0) throw_errno("bind");
    ip_mreq request{};
    request.imr_multiaddr = destination_.sin_addr;
    request.imr_interface.s_addr = htonl(INADDR_ANY);
    if (setsockopt(socket_.fd, IPPROTO_IP, IP_ADD_MEMBERSHIP, &request, sizeof request) != 0) throw_errno("IP_ADD_MEMBERSHIP " + group);
  }

  bool send(const canfd_frame& f) noexcept override {
    timespec now;
    clock_gettime(CLOCK_REALTIME, &now);
    const std::size_t n = encode_can_udp(f, static_cast<double>(now.tv_sec) + now.tv_nsec * 1e-9, buffer_);
    return sendto(socket_.fd, buffer_, n, 0, reinterpret_cast<const sockaddr*>(&destination_), sizeof destination_) ==
           static_cast<ssize_t>(n);
  }

  int receive(canfd_frame* frames, int max) noexcept override {
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
  SocketFd socket_;
  sockaddr_in destination_{};
  std::uint8_t buffer_[512];
};

}  // namespace

std::unique_ptr<CanBus> open_udp_multicast_bus(const std::string& group, int port) {
  return std::make_unique<UdpMulticastBus>(group, port);
}

}  // namespace mbrt::rt
