// libFuzzer entry point for the LCM command path: decode, gate (see fuzz/README.md).
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "take_any_lcm_commands.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (!mbrt::fuzz::take_any_lcm_commands(data, size)) std::abort();
  return 0;
}
