#include "driver_types.hpp"

namespace mbrt::codegen {

namespace {
constexpr const char* kEveryDriverTakesFirst = "name type";
constexpr const char* kEveryDriverTakesLast = "function";
}  // namespace

Keys driver_keys(DriverType type) {
  return element_keys(kEveryDriverTakesFirst, type_row(type).keys, kEveryDriverTakesLast);
}

Keys every_driver_key() { return every_key(kDriverTypeTable, kEveryDriverTakesFirst, kEveryDriverTakesLast); }

}  // namespace mbrt::codegen
