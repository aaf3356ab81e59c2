#include "joint_types.hpp"

namespace mbrt::codegen {

namespace {
constexpr const char* kEveryJointTakes = "name type";  // a ground contact's name is optional
}  // namespace

Keys joint_keys(JointType type) { return element_keys(kEveryJointTakes, type_row(type).keys, ""); }

Keys every_joint_key() { return every_key(kJointTypeTable, kEveryJointTakes, ""); }

}  // namespace mbrt::codegen
