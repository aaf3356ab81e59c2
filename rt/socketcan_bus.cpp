#include <cstring>
#include <stdexcept>

#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include "mbrt/rt/can_backends.hpp"

namespace mbrt::rt {

namespace {

class SocketCanBus final : public CanBus {
 public:
  explicit SocketCanBus(const std::string& interface) : socket_(PF_CAN, SOCK_RAW, CAN_RAW) {
    ifreq request{};
    if (interface.size() >= sizeof request.ifr_name) throw std::runtime_error("interface name too long: " + interface);
    std::strncpy(request.ifr_name, interface.c_str(), sizeof request.ifr_name - 1);
    if (ioctl(socket_.fd, SIOCGIFINDEX, &request) != 0) throw_errno("CAN interface '" + interface + "'");
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = request.ifr_ifindex;
    if (bind(socket_.fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) throw_errno("bind " + interface);
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
  SocketFd socket_;
};

}  // namespace

std::unique_ptr<CanBus> open_socketcan_bus(const std::string& interface) {
  return std::make_unique<SocketCanBus>(interface);
}

}  // namespace mbrt::rt
