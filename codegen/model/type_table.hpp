// What the element type tables share (joint_types.hpp, driver_types.hpp,
// force_types.hpp, input_types.hpp, output_types.hpp): one row per type, in
// the order of the type's enum, so a type's row is table[type]; a row's name
// is the type as a model file writes it, its keys the ones the type takes
// besides those every element of the family takes.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mbrt::codegen {

using Keys = std::vector<std::string>;

// Checked by a static_assert under each table: a missing or misplaced row
// puts some type's row at another type's index.
template <typename Row, std::size_t N>
constexpr bool rows_in_enum_order(const std::array<Row, N>& table) {
  for (std::size_t i = 0; i < N; ++i) {
    if (static_cast<std::size_t>(table[i].type) != i) return false;
  }
  return true;
}

template <typename Row, std::size_t N, typename Enum>
constexpr const Row& row_of(const std::array<Row, N>& table, Enum type) {
  return table[static_cast<std::size_t>(type)];
}

// The type a model file names by `name`, if there is one.
template <typename Row, std::size_t N>
auto type_named(const std::array<Row, N>& table, std::string_view name) -> std::optional<decltype(Row::type)> {
  for (const Row& row : table) {
    if (name == row.name) return row.type;
  }
  return std::nullopt;
}

template <typename Row, std::size_t N>
Keys type_names(const std::array<Row, N>& table) {
  Keys names;
  for (const Row& row : table) names.emplace_back(row.name);
  return names;
}

// "body1 body2 point" as {"body1", "body2", "point"}.
Keys split_keys(std::string_view words);

// The keys every element of the family takes first (`leading`), the type's
// own, then the family's `trailing` ones.
Keys element_keys(const char* leading, const char* own, const char* trailing);

// Every key some type of the family takes, each once, in table order.
template <typename Row, std::size_t N>
Keys every_key(const std::array<Row, N>& table, const char* leading, const char* trailing) {
  Keys own;
  for (const Row& row : table) {
    for (std::string& key : split_keys(row.keys)) {
      if (std::find(own.begin(), own.end(), key) == own.end()) own.push_back(std::move(key));
    }
  }
  Keys keys = split_keys(leading);
  keys.insert(keys.end(), own.begin(), own.end());
  for (std::string& key : split_keys(trailing)) keys.push_back(std::move(key));
  return keys;
}

}  // namespace mbrt::codegen
