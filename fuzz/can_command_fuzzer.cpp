// libFuzzer entry point for the CAN command path: frames, assembler, gate (see fuzz/README.md).
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "take_any_can_frames.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (!mbrt::fuzz::take_any_can_frames(data, size)) std::abort();
  return 0;
}
