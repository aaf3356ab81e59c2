#include "force_types.hpp"

namespace mbrt::codegen {

namespace {
constexpr const char* kEveryForceTakes = "type";  // forces have no names
}  // namespace

Keys force_keys(ForceType type) { return element_keys(kEveryForceTakes, type_row(type).keys, ""); }

Keys every_force_key() { return every_key(kForceTypeTable, kEveryForceTakes, ""); }

}  // namespace mbrt::codegen
