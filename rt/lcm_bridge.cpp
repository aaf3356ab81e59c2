#include "mbrt/rt/lcm_bridge.hpp"

#include <stdexcept>

#include <lcm/lcm.h>

namespace mbrt::rt {

LcmBridge::LcmBridge(const std::string& url, const std::string& subscribe_channel) {
  lcm_ = lcm_create(url.c_str());
  if (!lcm_) throw std::runtime_error("cannot open LCM at '" + url + "'");
  if (!lcm_subscribe(lcm_, subscribe_channel.c_str(), &LcmBridge::dispatch, this)) {
    lcm_destroy(lcm_);
    throw std::runtime_error("cannot subscribe to LCM channel '" + subscribe_channel + "'");
  }
}

LcmBridge::~LcmBridge() { lcm_destroy(lcm_); }

bool LcmBridge::publish(const char* channel, const void* data, int size) noexcept {
  return lcm_publish(lcm_, channel, data, static_cast<unsigned>(size)) == 0;
}

int LcmBridge::receive(Handler handler, void* context, int max_messages, int timeout_ms) noexcept {
  handler_ = handler;
  context_ = context;
  int n = 0;
  while (n < max_messages && lcm_handle_timeout(lcm_, n == 0 ? timeout_ms : 0) > 0) ++n;
  return n;
}

void LcmBridge::dispatch(const lcm_recv_buf_t* buffer, const char*, void* self) {
  auto* bridge = static_cast<LcmBridge*>(self);
  bridge->handler_(buffer->data, static_cast<int>(buffer->data_size), bridge->context_);
}

}  // namespace mbrt::rt
