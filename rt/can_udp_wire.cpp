#include "mbrt/rt/can_udp_wire.hpp"

#include <algorithm>
#include <cstring>

#include <mbrt/can_frames.hpp>

namespace mbrt::rt {

namespace {

// msgpack is big-endian.
std::uint8_t* put_be(std::uint8_t* p, std::uint64_t v, int bytes) noexcept {
  for (int i = bytes - 1; i >= 0; --i) *p++ = static_cast<std::uint8_t>(v >> (8 * i));
  return p;
}

std::uint8_t* put_key(std::uint8_t* p, const char* key) noexcept {
  const std::size_t n = std::strlen(key);  // all keys are fixstr (< 32 bytes)
  *p++ = static_cast<std::uint8_t>(0xa0 | n);
  std::memcpy(p, key, n);
  return p + n;
}

std::uint8_t* put_bool(std::uint8_t* p, const char* key, bool v) noexcept {
  p = put_key(p, key);
  *p++ = v ? 0xc3 : 0xc2;
  return p;
}

std::uint8_t* put_uint(std::uint8_t* p, const char* key, std::uint32_t v) noexcept {
  p = put_key(p, key);
  if (v < 0x80) {
    *p++ = static_cast<std::uint8_t>(v);
    return p;
  }
  *p++ = 0xce;
  return put_be(p, v, 4);
}

// A cursor over a msgpack datagram; any read past the end or of an
// unexpected type clears ok.
struct Reader {
  const std::uint8_t* p;
  const std::uint8_t* end;
  bool ok = true;

  std::uint64_t be(int bytes) noexcept {
    if (end - p < bytes) {
      ok = false;
      return 0;
    }
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v = v << 8 | *p++;
    return v;
  }
  std::uint8_t tag() noexcept { return static_cast<std::uint8_t>(be(1)); }

  // A string or binary: its bytes and length.
  const std::uint8_t* bytes(std::uint8_t t, std::size_t& n) noexcept {
    if ((t & 0xe0) == 0xa0) n = t & 0x1f;
    else if (t == 0xd9 || t == 0xc4) n = be(1);
    else if (t == 0xda || t == 0xc5) n = be(2);
    else ok = false;
    if (!ok || static_cast<std::size_t>(end - p) < n) {
      ok = false;
      return nullptr;
    }
    const std::uint8_t* b = p;
    p += n;
    return b;
  }

  // A scalar as a number (nil 0, bools 0/1, integers, floats); strings and
  // binaries are skipped (number 0) and reported through b and n.
  double value(const std::uint8_t*& b, std::size_t& n) noexcept {
    b = nullptr;
    const std::uint8_t t = tag();
    if (t < 0x80) return t;
    if (t >= 0xe0) return static_cast<std::int8_t>(t);
    switch (t) {
      case 0xc0: case 0xc2: return 0;
      case 0xc3: return 1;
      case 0xcc: return static_cast<double>(be(1));
      case 0xcd: return static_cast<double>(be(2));
      case 0xce: return static_cast<double>(be(4));
      case 0xcf: return static_cast<double>(be(8));
      case 0xd0: return static_cast<std::int8_t>(be(1));
      case 0xd1: return static_cast<std::int16_t>(be(2));
      case 0xd2: return static_cast<std::int32_t>(be(4));
      case 0xd3: return static_cast<double>(static_cast<std::int64_t>(be(8)));
      case 0xca: { const std::uint32_t u = static_cast<std::uint32_t>(be(4)); float x; std::memcpy(&x, &u, 4); return x; }
      case 0xcb: { const std::uint64_t u = be(8); double x; std::memcpy(&x, &u, 8); return x; }
      default: b = bytes(t, n); return 0;
    }
  }
};

bool is(const std::uint8_t* key, std::size_t n, const char* name) noexcept {
  return n == std::strlen(name) && std::memcmp(key, name, n) == 0;
}

}  // namespace

std::size_t encode_can_udp(const canfd_frame& f, double timestamp, std::uint8_t* out) noexcept {
  std::uint8_t* p = out;
  *p++ = 0x8b;  // map of 11
  p = put_key(p, "timestamp");
  *p++ = 0xcb;
  std::uint64_t bits;
  std::memcpy(&bits, &timestamp, 8);
  p = put_be(p, bits, 8);
  const bool extended = f.can_id & CAN_EFF_FLAG;
  p = put_uint(p, "arbitration_id", f.can_id & (extended ? CAN_EFF_MASK : CAN_SFF_MASK));
  p = put_bool(p, "is_extended_id", extended);
  p = put_bool(p, "is_remote_frame", f.can_id & CAN_RTR_FLAG);
  p = put_bool(p, "is_error_frame", f.can_id & CAN_ERR_FLAG);
  p = put_key(p, "channel");
  *p++ = 0xc0;
  const bool fd = mbrt::can::is_fd(f);
  const std::uint8_t len = std::min(f.len, static_cast<std::uint8_t>(fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN));
  p = put_uint(p, "dlc", len);
  p = put_key(p, "data");
  *p++ = 0xc4;
  *p++ = len;
  std::memcpy(p, f.data, len);
  p += len;
  p = put_bool(p, "is_fd", fd);
  p = put_bool(p, "bitrate_switch", fd && (f.flags & CANFD_BRS));
  p = put_bool(p, "error_state_indicator", fd && (f.flags & CANFD_ESI));
  return static_cast<std::size_t>(p - out);
}

bool decode_can_udp(const std::uint8_t* data, std::size_t size, canfd_frame& f) noexcept {
  Reader r{data, data + size};
  const std::uint8_t t = r.tag();
  std::size_t entries = 0;
  if ((t & 0xf0) == 0x80) entries = t & 0x0f;
  else if (t == 0xde) entries = r.be(2);
  else return false;
  f = canfd_frame{};
  double id = -1, dlc = -1;
  bool extended = false, remote = false, error = false, fd = false, brs = false, esi = false, has_data = false;
  std::size_t len = 0;
  for (std::size_t i = 0; i < entries && r.ok; ++i) {
    std::size_t key_size = 0;
    const std::uint8_t* key = r.bytes(r.tag(), key_size);
    const std::uint8_t* bytes = nullptr;
    std::size_t n = 0;
    const double v = r.value(bytes, n);
    if (!r.ok) return false;
    if (is(key, key_size, "arbitration_id")) id = v;
    else if (is(key, key_size, "is_extended_id")) extended = v != 0;
    else if (is(key, key_size, "is_remote_frame")) remote = v != 0;
    else if (is(key, key_size, "is_error_frame")) error = v != 0;
    else if (is(key, key_size, "is_fd")) fd = v != 0;
    else if (is(key, key_size, "bitrate_switch")) brs = v != 0;
    else if (is(key, key_size, "error_state_indicator")) esi = v != 0;
    else if (is(key, key_size, "dlc")) dlc = v;
    else if (is(key, key_size, "data")) {
      if (!bytes || n > CANFD_MAX_DLEN) return false;
      std::memcpy(f.data, bytes, n);
      len = n;
      has_data = true;
    }
  }
  const double max_id = extended ? CAN_EFF_MASK : CAN_SFF_MASK;
  const bool length_ok = fd ? mbrt::can::is_fd_length(static_cast<int>(len)) && !remote : len <= CAN_MAX_DLEN;
  if (!r.ok || r.p != r.end || !length_ok || !has_data || !(id >= 0 && id <= max_id) || dlc != static_cast<double>(len)) {
    return false;
  }
  if (fd) f.flags = CANFD_FDF | (brs ? CANFD_BRS : 0) | (esi ? CANFD_ESI : 0);
  f.can_id = static_cast<canid_t>(id) | (extended ? CAN_EFF_FLAG : 0) | (remote ? CAN_RTR_FLAG : 0) | (error ? CAN_ERR_FLAG : 0);
  f.len = static_cast<std::uint8_t>(len);
  return true;
}

}  // namespace mbrt::rt
