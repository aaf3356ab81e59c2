// The integration schemes a model can be generated with (solver.scheme).
#pragma once

#include <array>
#include <optional>
#include <string_view>

namespace mbrt {

enum class Scheme {
  staggered_pcst,  // docs/staggered-pcst.md
  staggered_nps,   // docs/staggered-nps.md
  ali3p,           // docs/ali3p.md
  blajer,          // docs/schemes.md
  baumgarte,       // docs/schemes.md
  staggered_tree,  // docs/staggered-tree.md
  midpoint_tree,   // docs/staggered-tree.md, "midpoint-tree"
  rk4_tree,        // docs/staggered-tree.md, "rk4-tree"
  rk4_projected,   // docs/schemes.md, "rk4-projected"
  staggered4,      // docs/schemes.md, "staggered4"
  rk8_tree,        // docs/staggered-tree.md, "rk8-tree"
};

// The names the model file and the command line use, one per Scheme in order.
inline constexpr std::array<std::string_view, 11> kSchemeNames{
    "staggered-pcst", "staggered-nps", "ali3p",    "blajer",        "baumgarte", "staggered-tree",
    "midpoint-tree",  "rk4-tree",      "rk4-projected", "staggered4", "rk8-tree"};

inline constexpr std::string_view scheme_name(Scheme s) noexcept { return kSchemeNames[static_cast<int>(s)]; }

// The schemes whose state is a tree's joint coordinates (include/mbrt/schemes/tree.hpp).
inline constexpr bool joint_space(Scheme s) noexcept {
  return s == Scheme::staggered_tree || s == Scheme::midpoint_tree || s == Scheme::rk4_tree ||
         s == Scheme::rk8_tree;
}

// The schemes whose steps are staggered-pcst's (staggered4 composes three of
// them into one step, include/mbrt/schemes/staggered4.hpp).
inline constexpr bool pcst_steps(Scheme s) noexcept { return s == Scheme::staggered_pcst || s == Scheme::staggered4; }

inline std::optional<Scheme> scheme_from_name(std::string_view name) noexcept {
  for (std::size_t i = 0; i < kSchemeNames.size(); ++i) {
    if (kSchemeNames[i] == name) return static_cast<Scheme>(i);
  }
  return std::nullopt;
}

}  // namespace mbrt
