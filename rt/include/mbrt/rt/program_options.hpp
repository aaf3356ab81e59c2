// The command lines of the HIL programs (`mbrt hil`'s loop and `mbrt stub`'s
// PD controller), read with CLI11: every option is known, every number parses
// completely and is checked, and a mistake exits with status 2 naming it.
// `mbrt hil` and `mbrt stub` check the same options with the same functions
// before they compile anything.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mbrt/rt/realtime_setup.hpp"

namespace mbrt::rt {

// Options both HIL programs take: the link (LCM, or a CAN bus and its
// optional candump log), their own rate and run time, the report file.
struct LinkOptions {
  std::string lcm_url;
  double rate_hz = 1000.0;
  double duration_s = 5.0;
  std::string report;
  std::string state_channel;
  std::string command_channel;
  std::string can_bus;  // udp://GROUP:PORT, udp://[IPv6 GROUP]:PORT or a SocketCAN interface
  std::string can_log;  // candump log of the frames sent and received
};

// The real-time loop's options.
struct HilOptions {
  LinkOptions link;
  double command_timeout_s = 0.05;
  double max_command_age_s = 0.05;
  long publish_every = 1;
  RealtimeOptions realtime;
  std::vector<std::string> set;  // --set KEY=VALUE: runtime parameters (docs/parameters.md)
};

// Probabilities of each fault per command the stub sends.
struct Faults {
  double drop = 0, duplicate = 0, reorder = 0, garbage = 0, nan = 0, out_of_range = 0;
};

// The PD controller stub's options.
struct StubOptions {
  StubOptions() { link.rate_hz = 500.0; }
  LinkOptions link;
  std::vector<double> kp{40.0}, kd{4.0};  // one gain for all joints, or one per controlled joint
  double amplitude = 0.5, frequency = 0.5;
  double settle_s = 1.0;
  double delay_us = 0.0, jitter_us = 0.0;
  unsigned seed = 1;
  double crash_after_s = -1.0;
  Faults faults;
};

// A check that a value parses completely as a finite number for which
// ok(x) holds; its message otherwise: "expected <what>, got '<text>'".
CLI::Validator number_check(const std::string& what, std::function<bool(double)> ok);

// --set's check: KEY=VALUE with a finite number (the key is the model's to check).
CLI::Validator setting_check();

void add_hil_options(CLI::App& app, HilOptions& options);
void add_stub_options(CLI::App& app, StubOptions& options);

// What is wrong with options that each parsed (a combination, or a rate that
// does not fit the model's step h), or "" when nothing is.
std::string check_link_options(const LinkOptions& link);
std::string check_rate(double rate_hz, double step);
std::string check_hil_options(const HilOptions& options, double step);  // both

// Parses argv into app's options; on a mistake prints it with the usage and
// exits with status 2 (with --help: the usage, status 0).
void parse_or_exit(CLI::App& app, int argc, char** argv);
[[noreturn]] void fail(const CLI::App& app, const std::string& why);

// Prints a program's JSON report on stdout and, if path is not empty, writes
// it there too. Returns false (after saying why) if the file cannot be written.
bool write_report(const std::string& json, const std::string& path);

}  // namespace mbrt::rt
