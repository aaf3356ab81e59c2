// libFuzzer entry point for the CAN-over-UDP datagram decoder (see fuzz/README.md).
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "decode_any_datagram.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (!mbrt::fuzz::decode_any_datagram(data, size)) std::abort();
  return 0;
}
