#include "output_types.hpp"

namespace mbrt::codegen {

namespace {
constexpr const char* kEveryOutputTakes = "name type";
}  // namespace

Keys output_keys(OutputType type) { return element_keys(kEveryOutputTakes, type_row(type).keys, ""); }

Keys every_output_key() { return every_key(kOutputTypeTable, kEveryOutputTakes, ""); }

}  // namespace mbrt::codegen
