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

bool read_link_option(ProgramOptions& args, LinkOptions& link) {
  const std::string a = args.name();
  if (a == "--lcm") link.lcm_url = args.text();
  else if (a == "--rate") link.rate_hz = args.number();
  else if (a == "--duration") link.duration_s = args.number();
  else if (a == "--report") link.report = args.text();
  else if (a == "--state-channel") link.state_channel = args.text();
  else if (a == "--command-channel") link.command_channel = args.text();
  else if (a == "--can") link.can_bus = args.text();
  else if (a == "--can-log") link.can_log = args.text();
  else return false;
  return true;
}

void check_link_options(ProgramOptions& args, const LinkOptions& link) {
  if (link.lcm_url.empty() == link.can_bus.empty()) args.fail("one of --lcm URL or --can BUS is required");
  if (!link.can_log.empty() && link.can_bus.empty()) args.fail("--can-log needs --can");
  if (!(link.rate_hz > 0.0)) args.fail("--rate must be > 0");
  if (!(link.duration_s >= 0.0)) args.fail("--duration must be >= 0");
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
