// The LCM bridge's I/O in the loop, liblcm included, makes no heap
// allocation once warmed up: publishing a message and taking the waiting
// ones, as every HIL cycle does. Needs a network with multicast on
// loopback: ctest runs it inside scripts/in-private-network.
#include <doctest/doctest.h>

#include <array>

#include <mbrt/rt/lcm_bridge.hpp>

#include "allocation_counter.hpp"

namespace {
void count_message(const void*, int, void* received) { ++*static_cast<long*>(received); }
}  // namespace

TEST_CASE("publishing and receiving through the LCM bridge allocates nothing") {
  mbrt::rt::LcmBridge bridge("udpm://239.255.76.67:7667?ttl=0", "mbrt_test_ALLOCATION");
  std::array<unsigned char, 200> message{};
  long received = 0;
  const auto cycle = [&](int timeout_ms) {
    REQUIRE(bridge.publish("mbrt_test_ALLOCATION", message.data(), static_cast<int>(message.size())));
    bridge.receive(&count_message, &received, 32, timeout_ms);
  };
  for (int i = 0; i < 100; ++i) cycle(10);  // warm up: liblcm's buffers
  received = 0;
  long seen = 0;
  {
    AllocationCounter counter;
    for (int i = 0; i < 10000; ++i) cycle(1);
    seen = counter.count();
  }
  MESSAGE(received << " of 10000 messages came back");
  CHECK(received > 1000);  // the receive path really ran
  CHECK(seen == 0);
}
