// libFuzzer entry point for the model-file parser (see fuzz/README.md).
#include <cstddef>
#include <cstdint>
#include <string>

#include "parse_any_text.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mbrt::fuzz::parse_any_text(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
