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

// A multicast group and port as a socket address; the family comes from the
// group's spelling (IPv4 dotted quad or IPv6).
struct Group {
  int family;
  sockaddr_storage address{};
  socklen_t size;

  Group(const std::string& group, int port) {
    auto* v4 = reinterpret_cast<sockaddr_in*>(&address);
    auto* v6 = reinterpret_cast<sockaddr_in6*>(&address);
    if (inet_pton(AF_INET, group.c_str(), &v4->sin_addr) == 1) {
      if (!IN_MULTICAST(ntohl(v4->sin_addr.s_addr))) throw std::runtime_error("'" + group + "' is not an IPv4 multicast group");
      family = v4->sin_family = AF_INET;
      v4->sin_port = htons(static_cast<std::uint16_t>(port));
      size = sizeof *v4;
    } else if (inet_pton(AF_INET6, group.c_str(), &v6->sin6_addr) == 1) {
      if (!IN6_IS_ADDR_MULTICAST(&v6->sin6_addr)) throw std::runtime_error("'" + group + "' is not an IPv6 multicast group");
      family = v6->sin6_family = AF_INET6;
      v6->sin6_port = htons(static_cast<std::uint16_t>(port));
      size = sizeof *v6;
    } else {
      throw std::runtime_error("'" + group + "' is not an IPv4 or IPv6 multicast group");
    }
  }
};

class UdpMulticastBus final : public CanBus {
 public:
  UdpMulticastBus(const std::string& name, const Group& group)
      : socket_(group.family, SOCK_DGRAM, 0), destination_(group.address), destination_size_(group.size) {
    const int yes = 1;
    if (setsockopt(socket_.fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes) != 0) throw_errno("SO_REUSEADDR");
    if (group.family == AF_INET) join_ipv4(name);
    else join_ipv6(name);
  }

  bool send(const canfd_frame& f) noexcept override {
    timespec now;
    clock_gettime(CLOCK_REALTIME, &now);
    const std::size_t n = encode_can_udp(f, static_cast<double>(now.tv_sec) + now.tv_nsec * 1e-9, buffer_);
    return sendto(socket_.fd, buffer_, n, 0, reinterpret_cast<const sockaddr*>(&destination_), destination_size_) ==
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
  // Binds the group's port on every address and joins the group on the
  // interface the kernel routes it to (index 0 or INADDR_ANY), as python-can
  // does. TTL or hop limit 0: datagrams stay on the host; loop on: peers on
  // this host hear us.
  void join_ipv4(const std::string& name) {
    const auto& group = reinterpret_cast<const sockaddr_in&>(destination_);
    const unsigned char ttl = 0, loop = 1;
    if (setsockopt(socket_.fd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl) != 0) throw_errno("IP_MULTICAST_TTL");
    if (setsockopt(socket_.fd, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof loop) != 0) throw_errno("IP_MULTICAST_LOOP");
    sockaddr_in any{};
    any.sin_family = AF_INET;
    any.sin_port = group.sin_port;
    any.sin_addr.s_addr = htonl(INADDR_ANY);
    if (bind(socket_.fd, reinterpret_cast<const sockaddr*>(&any), sizeof any) != 0) throw_errno("bind");
    ip_mreq request{};
    request.imr_multiaddr = group.sin_addr;
    request.imr_interface.s_addr = htonl(INADDR_ANY);
    if (setsockopt(socket_.fd, IPPROTO_IP, IP_ADD_MEMBERSHIP, &request, sizeof request) != 0) throw_errno("IP_ADD_MEMBERSHIP " + name);
  }

  void join_ipv6(const std::string& name) {
    const auto& group = reinterpret_cast<const sockaddr_in6&>(destination_);
    const int hops = 0;
    const unsigned loop = 1;
    if (setsockopt(socket_.fd, IPPROTO_IPV6, IPV6_MULTICAST_HOPS, &hops, sizeof hops) != 0) throw_errno("IPV6_MULTICAST_HOPS");
    if (setsockopt(socket_.fd, IPPROTO_IPV6, IPV6_MULTICAST_LOOP, &loop, sizeof loop) != 0) throw_errno("IPV6_MULTICAST_LOOP");
    sockaddr_in6 any{};
    any.sin6_family = AF_INET6;
    any.sin6_port = group.sin6_port;
    any.sin6_addr = in6addr_any;
    if (bind(socket_.fd, reinterpret_cast<const sockaddr*>(&any), sizeof any) != 0) throw_errno("bind");
    ipv6_mreq request{};
    request.ipv6mr_multiaddr = group.sin6_addr;
    request.ipv6mr_interface = 0;
    if (setsockopt(socket_.fd, IPPROTO_IPV6, IPV6_JOIN_GROUP, &request, sizeof request) != 0) throw_errno("IPV6_JOIN_GROUP " + name);
  }

  SocketFd socket_;
  sockaddr_storage destination_;
  socklen_t destination_size_;
  std::uint8_t buffer_[512];
};

}  // namespace

std::unique_ptr<CanBus> open_udp_multicast_bus(const std::string& group, int port) {
  return std::make_unique<UdpMulticastBus>(group, Group(group, port));
}

}  // namespace mbrt::rt
