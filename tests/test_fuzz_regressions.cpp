// Every input a fuzzer once failed on (tests/fuzz_regressions/, see
// fuzz/README.md) is given to its target again, by file extension: model
// files (.yaml) must yield a model or a ModelError; CAN-over-UDP datagrams
// (.can_udp), runs of CAN frames (.can_frames) and runs of LCM command
// messages (.lcm_commands) must keep their fuzzer's property.
#include <doctest/doctest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "decode_any_datagram.hpp"
#include "parse_any_text.hpp"
#include "take_any_can_frames.hpp"
#include "take_any_lcm_commands.hpp"

namespace {

// The regression files with this extension, each with its bytes.
std::vector<std::pair<std::string, std::string>> inputs(const std::string& extension) {
  std::vector<std::pair<std::string, std::string>> found;
  for (const auto& entry : std::filesystem::directory_iterator(MBRT_FUZZ_REGRESSIONS)) {
    if (entry.path().extension() != extension) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    found.emplace_back(entry.path().filename().string(), std::string(std::istreambuf_iterator<char>(in), {}));
  }
  return found;
}

const std::uint8_t* bytes(const std::string& s) { return reinterpret_cast<const std::uint8_t*>(s.data()); }

}  // namespace

TEST_CASE("model files the fuzzer failed on are rejected cleanly") {
  for (const auto& [name, text] : inputs(".yaml")) {
    INFO(name);
    CHECK_NOTHROW(mbrt::fuzz::parse_any_text(text));
  }
}

TEST_CASE("CAN-over-UDP datagrams the fuzzer failed on decode to a classic frame or not at all") {
  for (const auto& [name, data] : inputs(".can_udp")) {
    INFO(name);
    CHECK(mbrt::fuzz::decode_any_datagram(bytes(data), data.size()));
  }
}

TEST_CASE("runs of CAN frames the fuzzer failed on never apply a bad command") {
  for (const auto& [name, data] : inputs(".can_frames")) {
    INFO(name);
    CHECK(mbrt::fuzz::take_any_can_frames(bytes(data), data.size()));
  }
}

TEST_CASE("runs of LCM commands the fuzzer failed on never apply a bad command") {
  for (const auto& [name, data] : inputs(".lcm_commands")) {
    INFO(name);
    CHECK(mbrt::fuzz::take_any_lcm_commands(bytes(data), data.size()));
  }
}
