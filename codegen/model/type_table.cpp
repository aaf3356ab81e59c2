#include "type_table.hpp"

namespace mbrt::codegen {

Keys split_keys(std::string_view words) {
  Keys keys;
  while (!words.empty()) {
    const std::size_t end = std::min(words.find(' '), words.size());
    if (end > 0) keys.emplace_back(words.substr(0, end));
    words.remove_prefix(std::min(end + 1, words.size()));
  }
  return keys;
}

Keys element_keys(const char* leading, const char* own, const char* trailing) {
  Keys keys = split_keys(leading);
  for (const char* part : {own, trailing}) {
    for (std::string& key : split_keys(part)) keys.push_back(std::move(key));
  }
  return keys;
}

}  // namespace mbrt::codegen
