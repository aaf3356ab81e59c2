// One LCM connection: publishes encoded messages and delivers those of one
// subscribed channel to a handler, without blocking unless asked to. The
// connection is made at start-up (and throws there); publish and receive
// never throw and, once warmed up, allocate nothing, liblcm included
// (test_lcm_allocates_nothing). LCM's udpm provider takes IPv4 groups only:
// a URL with an IPv6 group is refused, saying so.
#pragma once

#include <string>

struct _lcm_t;
struct _lcm_recv_buf_t;

namespace mbrt::rt {

class LcmBridge {
 public:
  using Handler = void (*)(const void* data, int size, void* context);

  LcmBridge(const std::string& url, const std::string& subscribe_channel);
  ~LcmBridge();
  LcmBridge(const LcmBridge&) = delete;
  LcmBridge& operator=(const LcmBridge&) = delete;

  bool publish(const char* channel, const void* data, int size) noexcept;

  // Hands up to max_messages waiting messages to handler; waits up to
  // timeout_ms for the first one (0: never blocks). Returns how many.
  int receive(Handler handler, void* context, int max_messages, int timeout_ms = 0) noexcept;

 private:
  static void dispatch(const _lcm_recv_buf_t* buffer, const char* channel, void* self);

  _lcm_t* lcm_ = nullptr;
  Handler handler_ = nullptr;
  void* context_ = nullptr;
};

}  // namespace mbrt::rt
