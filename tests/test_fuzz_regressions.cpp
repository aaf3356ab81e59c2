// Every input the model-file fuzzer once crashed on (tests/fuzz_regressions/,
// see fuzz/README.md) is parsed again: it must yield a model or a ModelError.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "parse_any_text.hpp"

TEST_CASE("inputs the fuzzer crashed on are rejected cleanly") {
  for (const auto& entry : std::filesystem::directory_iterator(MBRT_FUZZ_REGRESSIONS)) {
    if (entry.path().extension() != ".yaml") continue;
    std::ifstream in(entry.path(), std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    INFO(entry.path().filename().string());
    CHECK_NOTHROW(mbrt::fuzz::parse_any_text(text.str()));
  }
}
