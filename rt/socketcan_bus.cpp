#include <cstring>
#include <stdexcept>

#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include "mbrt/rt/can_backends.hpp"

#include <mbrt/can_frames.hpp>

namespace mbrt::rt {

namespace {

class SocketCanBus final : public CanBus {
 public:
  SocketCanBus(const std::string& interface, bool fd) : socket_(PF_CAN, SOCK_RAW, CAN_RAW) {
    ifreq request{};
    if (interface.size() >= sizeof request.ifr_name) throw std::runtime_error("interface name too long: " + interface);
    std::strncpy(request.ifr_name, interface.c_str(), sizeof request.ifr_name - 1);
    if (ioctl(socket_.fd, SIOCGIFINDEX, &request) != 0) throw_errno("CAN interface '" + interface + "'");
    if (fd) {
      if (ioctl(socket_.fd, SIOCGIFMTU, &request) != 0) throw_errno("MTU of '" + interface + "'");
      if (request.ifr_mtu != static_cast<int>(CANFD_MTU)) {
        throw std::runtime_error("CAN interface '" + interface + "' does not carry CAN FD frames (MTU " +
                                 std::to_string(request.ifr_mtu) + "; e.g. ip link set " + interface + " mtu 72)");
      }
    }
    // Classic frames arrive as can_frame (CAN_MTU bytes), CAN FD ones as canfd_frame (CANFD_MTU).
    const int yes = 1;
    if (setsockopt(socket_.fd, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &yes, sizeof yes) != 0) throw_errno("CAN_RAW_FD_FRAMES");
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = request.ifr_ifindex;
    if (bind(socket_.fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) throw_errno("bind " + interface);
  }

  // The size written tells the kernel the kind: a classic frame goes as a
  // can_frame (its padding and len8_dlc zero), a CAN FD frame as canfd_frame.
  bool send(const canfd_frame& f) noexcept override {
    if (mbrt::can::is_fd(f)) return write(socket_.fd, &f, CANFD_MTU) == static_cast<ssize_t>(CANFD_MTU);
    can_frame classic{};
    classic.can_id = f.can_id;
    classic.len = f.len;
    std::memcpy(classic.data, f.data, sizeof classic.data);
    return write(socket_.fd, &classic, CAN_MTU) == static_cast<ssize_t>(CAN_MTU);
  }

  int receive(canfd_frame* frames, int max) noexcept override {
    int n = 0;
    while (n < max) {
      canfd_frame& f = frames[n];
      const ssize_t size = recv(socket_.fd, &f, sizeof f, MSG_DONTWAIT);
      if (size < 0) break;
      if (size == static_cast<ssize_t>(CANFD_MTU) && mbrt::can::is_fd_length(f.len)) {
        f.flags |= CANFD_FDF;  // older kernels leave it unset
        ++n;
      } else if (size == static_cast<ssize_t>(CAN_MTU) && f.len <= CAN_MAX_DLEN) {
        f.flags = 0;  // can_frame's padding byte
        ++n;
      } else {
        ++undecodable_;
      }
    }
    return n;
  }

 private:
  SocketFd socket_;
};

}  // namespace

std::unique_ptr<CanBus> open_socketcan_bus(const std::string& interface, bool fd) {
  return std::make_unique<SocketCanBus>(interface, fd);
}

}  // namespace mbrt::rt
