// Strict command-line reading for the HIL programs: every option is known,
// every number parses completely, and a mistake exits with status 2 naming it.
#pragma once

#include <string>

namespace mbrt::rt {

class ProgramOptions {
 public:
  ProgramOptions(int argc, char** argv, const char* usage) : argc_(argc), argv_(argv), usage_(usage) {}

  // Walks the options: next() is false at the end; name() is the current one.
  bool next() { return ++i_ < argc_; }
  std::string name() const { return argv_[i_]; }
  std::string text();  // the value after the current option
  double number();
  long integer();
  [[noreturn]] void fail(const std::string& why) const;

 private:
  int argc_;
  char** argv_;
  const char* usage_;
  int i_ = 0;
};

// Options both HIL programs take: the link (LCM, or a CAN bus and its
// optional candump log), their own rate and run time, the report file.
struct LinkOptions {
  std::string lcm_url;
  double rate_hz;
  double duration_s = 5.0;
  std::string report;
  std::string state_channel;
  std::string command_channel;
  std::string can_bus;  // udp://GROUP:PORT, udp://[IPv6 GROUP]:PORT or a SocketCAN interface
  std::string can_log;  // candump log of the frames sent and received
};

// Reads the current option into `link` if it is one of LinkOptions; false
// if it is not. check_link_options() then rejects missing or bad values.
bool read_link_option(ProgramOptions& args, LinkOptions& link);
void check_link_options(ProgramOptions& args, const LinkOptions& link);

// Prints a program's JSON report on stdout and, if path is not empty, writes
// it there too. Returns false (after saying why) if the file cannot be written.
bool write_report(const std::string& json, const std::string& path);

}  // namespace mbrt::rt
