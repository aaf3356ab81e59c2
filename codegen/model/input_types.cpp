#include "input_types.hpp"

namespace mbrt::codegen {

namespace {
constexpr const char* kEveryInputTakesFirst = "name type";
constexpr const char* kEveryInputTakesLast = "min max safe";  // accepted range; value when commands are stale
}  // namespace

Keys input_keys(InputType type) {
  return element_keys(kEveryInputTakesFirst, type_row(type).keys, kEveryInputTakesLast);
}

Keys every_input_key() { return every_key(kInputTypeTable, kEveryInputTakesFirst, kEveryInputTakesLast); }

}  // namespace mbrt::codegen
