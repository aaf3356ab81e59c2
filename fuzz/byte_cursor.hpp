// Fuzz inputs made of records: a cursor that takes fixed-size values and
// byte runs off the front of the input (memcpy: any alignment), until the
// input runs out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace mbrt::fuzz {

struct ByteCursor {
  const std::uint8_t* p;
  const std::uint8_t* end;

  template <class T>
  bool take(T& v) noexcept {
    if (static_cast<std::size_t>(end - p) < sizeof v) return false;
    std::memcpy(&v, p, sizeof v);
    p += sizeof v;
    return true;
  }

  // n bytes, or nullptr when fewer are left.
  const std::uint8_t* take_bytes(std::size_t n) noexcept {
    if (static_cast<std::size_t>(end - p) < n) return nullptr;
    const std::uint8_t* b = p;
    p += n;
    return b;
  }
};

}  // namespace mbrt::fuzz
