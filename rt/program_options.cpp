#include "mbrt/rt/program_options.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "mbrt/parameter_settings.hpp"

namespace mbrt::rt {

// CLI11's own checks would take "nan" and "inf", and word their errors by the
// type's limits.
CLI::Validator number_check(const std::string& what, std::function<bool(double)> ok) {
  return CLI::Validator(
      [what, ok](const std::string& text) {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        const bool parsed = !text.empty() && *end == '\0' && std::isfinite(x);
        return parsed && ok(x) ? std::string() : "expected " + what + ", got '" + text + "'";
      },
      what);
}

namespace {

const CLI::Validator kFinite = number_check("a finite number", [](double) { return true; });
const CLI::Validator kPositive = number_check("a finite number > 0", [](double x) { return x > 0.0; });
const CLI::Validator kNonNegative = number_check("a finite number >= 0", [](double x) { return x >= 0.0; });
const CLI::Validator kProbability = number_check("a probability in [0, 1]", [](double x) { return x >= 0.0 && x <= 1.0; });
const CLI::Validator kCount = number_check("a whole number >= 1", [](double x) { return x >= 1.0 && x == std::floor(x); });
const CLI::Validator kIndex = number_check("a whole number >= 0", [](double x) { return x >= 0.0 && x == std::floor(x); });

void add_link_options(CLI::App& app, LinkOptions& link) {
  app.add_option("--lcm", link.lcm_url, "LCM URL, e.g. udpm://239.255.76.67:7667?ttl=0");
  app.add_option("--can", link.can_bus, "CAN bus: udp://GROUP:PORT, udp://[IPv6 GROUP]:PORT or a SocketCAN interface");
  app.add_option("--can-log", link.can_log, "candump log of the frames sent and received");
  app.add_option("--rate", link.rate_hz, "cycles per second")->check(kPositive);
  app.add_option("--duration", link.duration_s, "run time, s")->check(kNonNegative);
  app.add_option("--report", link.report, "also write the JSON report here");
  app.add_option("--state-channel", link.state_channel, "LCM channel of the states");
  app.add_option("--command-channel", link.command_channel, "LCM channel of the commands");
}

}  // namespace

CLI::Validator setting_check() {
  return CLI::Validator(
      [](const std::string& text) {
        std::string key;
        double value = 0.0;
        return parse_setting(text, key, value);
      },
      "KEY=VALUE");
}

void add_hil_options(CLI::App& app, HilOptions& o) {
  add_link_options(app, o.link);
  app.add_option("--command-timeout", o.command_timeout_s, "a command older than this is stale, s")
      ->check(kPositive);
  app.add_option("--max-command-age", o.max_command_age_s, "a command answering an older state is refused, s")
      ->check(kPositive);
  app.add_option("--publish-every", o.publish_every, "publish the state every N cycles")->check(kCount);
  app.add_option("--fifo", o.realtime.fifo_priority, "SCHED_FIFO priority, 1 to 99 (0: keep the default scheduler)")
      ->check(number_check("a whole number in [0, 99]", [](double x) { return x >= 0.0 && x <= 99.0 && x == std::floor(x); }));
  app.add_option("--cpu", o.realtime.cpu, "pin the loop to this CPU")->check(kIndex);
  app.add_option("--set", o.set, "set a tunable parameter before the run (repeatable)")->take_all()->check(setting_check());
}

void add_stub_options(CLI::App& app, StubOptions& o) {
  add_link_options(app, o.link);
  app.add_option("--kp", o.kp, "proportional gain: one, or one per joint separated by commas")
      ->delimiter(',')
      ->check(kFinite);
  app.add_option("--kd", o.kd, "derivative gain: one, or one per joint separated by commas")
      ->delimiter(',')
      ->check(kFinite);
  app.add_option("--amplitude", o.amplitude, "reference amplitude, rad or m")->check(kFinite);
  app.add_option("--frequency", o.frequency, "reference frequency, Hz")->check(kFinite);
  app.add_option("--settle", o.settle_s, "hold the start for this long, s")->check(kNonNegative);
  app.add_option("--delay-us", o.delay_us, "added latency per command, us")->check(kNonNegative);
  app.add_option("--jitter-us", o.jitter_us, "random extra latency, us")->check(kNonNegative);
  app.add_option("--seed", o.seed, "fault and jitter random seed")->check(kIndex);
  app.add_option("--crash-after", o.crash_after_s, "exit without a report after this long, s")->check(kFinite);
  app.add_option("--drop", o.faults.drop, "probability a command is dropped")->check(kProbability);
  app.add_option("--duplicate", o.faults.duplicate, "probability a command is sent twice")->check(kProbability);
  app.add_option("--reorder", o.faults.reorder, "probability a command is held back one cycle")->check(kProbability);
  app.add_option("--garbage", o.faults.garbage, "probability a command is garbled")->check(kProbability);
  app.add_option("--nan", o.faults.nan, "probability a command carries NaN")->check(kProbability);
  app.add_option("--out-of-range", o.faults.out_of_range, "probability a command is out of range")->check(kProbability);
}

std::string check_link_options(const LinkOptions& link) {
  if (link.lcm_url.empty() == link.can_bus.empty()) return "one of --lcm URL or --can BUS is required";
  if (!link.can_log.empty() && link.can_bus.empty()) return "--can-log needs --can";
  return "";
}

std::string check_rate(double rate_hz, double step) {
  const double steps = 1.0 / (rate_hz * step);
  if (std::abs(steps - std::round(steps)) > 1e-9 * steps || std::round(steps) < 1) {
    return "--rate " + std::to_string(rate_hz) + " Hz is not 1 / (k h) for the model's step h = " +
           std::to_string(step) + " s; pick a rate that divides 1/h, or regenerate with --h";
  }
  return "";
}

std::string check_hil_options(const HilOptions& o, double step) {
  const std::string why = check_link_options(o.link);
  return why.empty() ? check_rate(o.link.rate_hz, step) : why;
}

void parse_or_exit(CLI::App& app, int argc, char** argv) {
  app.allow_extras();  // named below, one at a time, in the order given
  try {
    app.parse(argc, argv);
    const std::vector<std::string> extra = app.remaining();
    if (!extra.empty()) {
      fail(app, extra[0].rfind('-', 0) == 0 ? "unknown option '" + extra[0] + "'" : "unexpected argument '" + extra[0] + "'");
    }
  } catch (const CLI::CallForHelp&) {
    std::fputs(app.help().c_str(), stdout);
    std::exit(0);
  } catch (const CLI::ParseError& e) {
    fail(app, e.what());
  }
}

void fail(const CLI::App& app, const std::string& why) {
  std::fprintf(stderr, "error: %s\n\n%s", why.c_str(), app.help().c_str());
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
