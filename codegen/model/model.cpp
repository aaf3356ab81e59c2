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

const std::string& Model::body_name(int index) const {
  static const std::string ground = "ground";
  return index == kGround ? ground : bodies.at(static_cast<size_t>(index)).name;
}

std::string Model::file_name() const { return std::filesystem::path(file).filename().string(); }

}  // namespace mbrt::codegen
