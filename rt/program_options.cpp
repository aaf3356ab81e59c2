#include "mbrt/rt/program_options.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace mbrt::rt {

std::string ProgramOptions::text() {
  const std::string option = name();
  if (i_ + 1 >= argc_) fail(option + ": missing value");
  return argv_[++i_];
}

double ProgramOptions::number() {
  const std::string option = name(), value = text();
  try {
    std::size_t used = 0;
    const double x = std::stod(value, &used);
    if (used == value.size()) return x;
  } catch (const std::exception&) {
  }
  fail(option + ": expected a number, got '" + value + "'");
}

long ProgramOptions::integer() {
  const std::string option = name(), value = text();
  try {
    std::size_t used = 0;
    const long x = std::stol(value, &used);
    if (used == value.size()) return x;
  } catch (const std::exception&) {
  }
  fail(option + ": expected an integer, got '" + value + "'");
}

void ProgramOptions::fail(const std::string& why) const {
  std::fprintf(stderr, "error: %s\n\n%s", why.c_str(), usage_);
  std::exit(2);
}

bool write_report(const std::string& json, const std::string& path) {
  std::fputs(json.c_str(), stdout);
  if (path.empty()) return true;
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f && std::fputs(json.c_str(), f) >= 0 && std::fclose(f) == 0) return true;
  std::fprintf(stderr, "error: cannot write %s\n", path.c_str());
  return false;
}

}  // namespace mbrt::rt
