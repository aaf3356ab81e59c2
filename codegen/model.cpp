#include "model.hpp"

#include <filesystem>

namespace mbrt::codegen {

namespace {
std::string format_error(const SourceLocation& where, const std::string& key, const std::string& message) {
  std::string s = where.file;
  if (where.line > 0) s += ":" + std::to_string(where.line) + ":" + std::to_string(where.column);
  s += ": ";
  if (!key.empty()) s += key + ": ";
  return s + message;
}
}  // namespace

ModelError::ModelError(const SourceLocation& where, const std::string& key, const std::string& message)
    : std::runtime_error(format_error(where, key, message)), where_(where), key_(key) {}

const char* input_type_name(InputType t) {
  switch (t) {
    case InputType::joint_torque: return "joint_torque";
    case InputType::joint_force: return "joint_force";
    case InputType::motor_torque: return "motor_torque";
  }
  return "?";
}

const char* output_type_name(OutputType t) {
  switch (t) {
    case OutputType::joint_position: return "joint_position";
    case OutputType::joint_velocity: return "joint_velocity";
    case OutputType::body_pose: return "body_pose";
    case OutputType::body_velocity: return "body_velocity";
  }
  return "?";
}

int output_count(OutputType t) {
  switch (t) {
    case OutputType::body_pose: return 7;
    case OutputType::body_velocity: return 6;
    default: return 1;
  }
}

const std::string& Model::body_name(int index) const {
  static const std::string ground = "ground";
  return index == kGround ? ground : bodies.at(static_cast<size_t>(index)).name;
}

std::string Model::file_name() const { return std::filesystem::path(file).filename().string(); }

}  // namespace mbrt::codegen
