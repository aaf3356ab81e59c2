// One argument of a shell command line, quoted for /bin/sh.
#pragma once

#include <string>

namespace mbrt::codegen {

inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace mbrt::codegen
