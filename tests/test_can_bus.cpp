// The CAN buses: over UDP multicast (loopback, TTL 0) a classic or CAN FD
// frame sent arrives whole, a datagram that is not a CAN message (or not a
// well-formed CAN FD one) is counted, and sending and
// receiving allocate nothing, on an IPv4 group as on an IPv6 one; a bad
// group or port, or a SocketCAN interface that does not exist, is refused at
// start-up. Needs a network with multicast on loopback: ctest runs it inside
// scripts/in-private-network, the "IPv6:" cases with IPv6 multicast there too.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <stdexcept>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <mbrt/rt/can_bus.hpp>
#include <mbrt/rt/can_udp_wire.hpp>

#include "allocation_counter.hpp"

namespace {
constexpr const char* kBus = "udp://239.74.163.2:43114";
constexpr const char* kBus6 = "udp://[ff15:7079:7468:6f6e:6465:6d6f:6d63:6173]:43114";  // python-can's IPv6 group

canfd_frame test_frame(canid_t id, std::uint8_t len = 5, std::uint8_t flags = 0) {
  canfd_frame f{};
  f.can_id = id;
  f.len = len;
  f.flags = flags;
  for (int i = 0; i < len; ++i) f.data[i] = static_cast<__u8>(0x10 * i + 1);
  return f;
}

// Waits (up to ~1 s) for a frame on bus.
int receive_some(mbrt::rt::CanBus& bus, canfd_frame* frames, int max) {
  for (int i = 0; i < 1000; ++i) {
    const int n = bus.receive(frames, max);
    if (n > 0) return n;
    usleep(1000);
  }
  return 0;
}
}  // namespace

namespace {
void check_frames_cross(const char* spec) {
  auto a = mbrt::rt::open_can_bus(spec, false), b = mbrt::rt::open_can_bus(spec, false);
  for (const canid_t id : {canid_t{0x123}, canid_t{0x1abcdef | CAN_EFF_FLAG}, canid_t{0x7ff | CAN_RTR_FLAG}}) {
    const canfd_frame sent = test_frame(id);
    REQUIRE(a->send(sent));
    std::array<canfd_frame, 4> got{};
    REQUIRE(receive_some(*b, got.data(), 4) >= 1);
    CHECK(got[0].can_id == sent.can_id);
    CHECK(got[0].len == sent.len);
    CHECK(std::memcmp(got[0].data, sent.data, sent.len) == 0);
    while (a->receive(got.data(), 4) > 0) {  // a hears itself (multicast loop): drain
    }
  }
}
}  // namespace

TEST_CASE("a frame crosses the UDP bus whole; extended and remote flags included") { check_frames_cross(kBus); }

TEST_CASE("IPv6: a frame crosses the UDP bus whole; extended and remote flags included") { check_frames_cross(kBus6); }

TEST_CASE("a CAN FD frame crosses the UDP bus whole, its flags included") {
  auto a = mbrt::rt::open_can_bus(kBus, true), b = mbrt::rt::open_can_bus(kBus, true);
  for (const std::uint8_t len : {std::uint8_t{12}, std::uint8_t{64}}) {
    const canfd_frame sent = test_frame(0x101, len, CANFD_FDF | CANFD_BRS | CANFD_ESI);
    REQUIRE(a->send(sent));
    std::array<canfd_frame, 4> got{};
    REQUIRE(receive_some(*b, got.data(), 4) >= 1);
    CHECK(got[0].can_id == sent.can_id);
    CHECK(got[0].len == len);
    CHECK(got[0].flags == sent.flags);
    CHECK(std::memcmp(got[0].data, sent.data, len) == 0);
    while (a->receive(got.data(), 4) > 0) {
    }
  }
}

namespace {
void send_datagram(const void* data, std::size_t size) {
  const int s = socket(AF_INET, SOCK_DGRAM, 0);
  REQUIRE(s >= 0);
  const unsigned char ttl = 0;
  setsockopt(s, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(43114);
  inet_pton(AF_INET, "239.74.163.2", &to.sin_addr);
  REQUIRE(sendto(s, data, size, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to) > 0);
  close(s);
}

// Waits (up to ~1 s) until bus has counted `expected` undecodable datagrams; no frame may arrive.
void expect_undecodable(mbrt::rt::CanBus& bus, long expected) {
  std::array<canfd_frame, 4> got{};
  for (int i = 0; i < 1000 && bus.undecodable() < expected; ++i) {
    CHECK(bus.receive(got.data(), 4) == 0);
    usleep(1000);
  }
  CHECK(bus.receive(got.data(), 4) == 0);
  CHECK(bus.undecodable() == expected);
}
}  // namespace

TEST_CASE("a datagram that is not a CAN message is counted, not delivered") {
  auto bus = mbrt::rt::open_can_bus(kBus, false);
  const char garbage[] = "\x81\xa4" "data" "\xc4\x09";  // a map whose data claims 9 bytes
  send_datagram(garbage, sizeof garbage - 1);
  expect_undecodable(*bus, 1);
}

TEST_CASE("malformed CAN FD datagrams are counted, not delivered") {
  auto bus = mbrt::rt::open_can_bus(kBus, false);
  std::uint8_t datagram[mbrt::rt::kCanUdpMaxDatagram];
  // 13 data bytes: no CAN FD length (encode writes what it is given).
  send_datagram(datagram, mbrt::rt::encode_can_udp(test_frame(0x200, 13, CANFD_FDF), 1.0, datagram));
  // A well-formed CAN FD datagram cut short.
  send_datagram(datagram, mbrt::rt::encode_can_udp(test_frame(0x200, 16, CANFD_FDF), 1.0, datagram) - 5);
  // 12 data bytes in a classic frame (encode caps classic frames at 8: clear is_fd by hand).
  const std::uint8_t is_fd_true[] = {0xa5, 'i', 's', '_', 'f', 'd', 0xc3};
  const std::size_t n = mbrt::rt::encode_can_udp(test_frame(0x200, 12, CANFD_FDF), 1.0, datagram);
  std::uint8_t* at = std::search(datagram, datagram + n, std::begin(is_fd_true), std::end(is_fd_true));
  REQUIRE(at != datagram + n);
  at[6] = 0xc2;
  send_datagram(datagram, n);
  expect_undecodable(*bus, 3);
}

namespace {
void check_no_allocations(const char* spec) {
  auto a = mbrt::rt::open_can_bus(spec, false), b = mbrt::rt::open_can_bus(spec, false);
  std::array<canfd_frame, 32> got{};
  const canfd_frame f = test_frame(0x200);
  long received = 0, seen = 0;
  {
    AllocationCounter counter;
    for (int i = 0; i < 10000; ++i) {
      a->send(f);
      received += b->receive(got.data(), 32);
      a->receive(got.data(), 32);
    }
    seen = counter.count();
  }
  MESSAGE(received << " of 10000 frames came back");
  CHECK(received > 1000);  // the receive path really ran
  CHECK(seen == 0);
}
}  // namespace

TEST_CASE("sending and receiving on the UDP bus allocates nothing") { check_no_allocations(kBus); }

TEST_CASE("IPv6: sending and receiving on the UDP bus allocates nothing") { check_no_allocations(kBus6); }

TEST_CASE("bad bus names are refused at start-up") {
  for (const bool fd : {false, true}) {
    CHECK_THROWS_AS(mbrt::rt::open_can_bus("no_such_can9", fd), std::runtime_error);
    CHECK_THROWS_AS(mbrt::rt::open_can_bus("udp://10.0.0.1:43114", fd), std::runtime_error);  // not multicast
    CHECK_THROWS_AS(mbrt::rt::open_can_bus("udp://239.74.163.2", fd), std::runtime_error);
    CHECK_THROWS_AS(mbrt::rt::open_can_bus("udp://239.74.163.2:x", fd), std::runtime_error);
    // IPv6 groups: refused before any socket is opened, each message naming what is wrong.
    CHECK_THROWS_WITH_AS(mbrt::rt::open_can_bus("udp://[2001:db8::1]:43114", fd),
                         "'2001:db8::1' is not an IPv6 multicast group", std::runtime_error);
    CHECK_THROWS_WITH_AS(mbrt::rt::open_can_bus("udp://[ff15::x]:43114", fd),
                         "'ff15::x' is not an IPv4 or IPv6 multicast group", std::runtime_error);
    CHECK_THROWS_WITH_AS(mbrt::rt::open_can_bus("udp://ff15::1:43114", fd),
                         doctest::Contains("an IPv6 group goes in brackets"), std::runtime_error);
    CHECK_THROWS_WITH_AS(mbrt::rt::open_can_bus("udp://[ff15::1]", fd),
                         doctest::Contains("expected udp://GROUP:PORT"), std::runtime_error);
    CHECK_THROWS_WITH_AS(mbrt::rt::open_can_bus("udp://[ff15::1]:x", fd),
                         "bad port in 'udp://[ff15::1]:x'", std::runtime_error);
  }
}
