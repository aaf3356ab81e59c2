#include "mbrt/rt/lcm_bridge.hpp"

#include <stdexcept>

#include <lcm/lcm.h>

namespace mbrt::rt {

namespace {

// Whether url asks LCM's udpm (or mpudpm) provider for an IPv6 group: a
// bracketed address or one with more colons than the port's. Those
// providers parse groups with inet_aton (lcm_udpm.c), IPv4 only, and would
// only say "Bad multicast IP address".
bool udpm_ipv6_group(const std::string& url) {
  const std::size_t scheme = url.find("://");
  if (scheme == std::string::npos) return false;
  const std::string provider = url.substr(0, scheme);
  if (provider != "udpm" && provider != "mpudpm") return false;
  const std::size_t start = scheme + 3;
  const std::string network = url.substr(start, url.find('?', start) - start);
  return network.find('[') != std::string::npos || network.find(':') != network.rfind(':');
}

}  // namespace

LcmBridge::LcmBridge(const std::string& url, const std::string& subscribe_channel) {
  if (udpm_ipv6_group(url)) {
    throw std::runtime_error("cannot open LCM at '" + url + "': LCM's udpm provider is IPv4-only; use an IPv4 group " +
                             "(udpm://239.255.76.67:7667?ttl=0), or CAN over UDP (--can udp://[GROUP]:PORT) for IPv6");
  }
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
