// Main program of `mbrt hil`: runs one generated model in a fixed-period
// loop and exchanges states and commands over LCM. Compiled by `mbrt hil`
// together with the model and its LCM types, with
//   -DMBRT_MODEL_LCM_HEADER="<name>_lcm.hpp" -DMBRT_MODEL_NAMESPACE=mbrt::models::<name>
//
// Each cycle: wait for the release, take the waiting commands (validated by
// the command gate), step the model, publish its outputs. The cycle
// allocates nothing after start-up (test_step_allocates_nothing,
// test_lcm_allocates_nothing); the report is written after the loop.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <mbrt/runtime.hpp>
#include <mbrt/rt/command_gate.hpp>
#include <mbrt/rt/hil_report.hpp>
#include <mbrt/rt/lcm_bridge.hpp>
#include <mbrt/rt/periodic_clock.hpp>
#include <mbrt/rt/program_options.hpp>
#include <mbrt/rt/realtime_setup.hpp>

#include MBRT_MODEL_LCM_HEADER

namespace model = MBRT_MODEL_NAMESPACE;
using namespace mbrt::rt;

namespace {

constexpr const char* kUsage = R"(usage: hil --lcm URL [--rate HZ] [--duration S] [--report F.json]
           [--state-channel C] [--command-channel C] [--command-timeout S] [--max-command-age S]
           [--publish-every N] [--fifo PRIORITY] [--cpu N]
)";

// Commands taken per cycle at most: a flood cannot stretch a cycle unboundedly.
constexpr int kMaxCommandsPerCycle = 32;

struct Options {
  LinkOptions link{"", 1000.0, 5.0, "", model::kStateChannel, model::kCommandChannel};
  double command_timeout_s = 0.05;
  double max_command_age_s = 0.05;
  long publish_every = 1;
  RealtimeOptions realtime;
};

Options parse(int argc, char** argv) {
  Options o;
  ProgramOptions args(argc, argv, kUsage);
  while (args.next()) {
    const std::string a = args.name();
    if (read_link_option(args, o.link)) continue;
    if (a == "--command-timeout") o.command_timeout_s = args.number();
    else if (a == "--max-command-age") o.max_command_age_s = args.number();
    else if (a == "--publish-every") o.publish_every = args.integer();
    else if (a == "--fifo") o.realtime.fifo_priority = static_cast<int>(args.integer());
    else if (a == "--cpu") o.realtime.cpu = static_cast<int>(args.integer());
    else args.fail("unknown option '" + a + "'");
  }
  check_link_options(args, o.link);
  if (!(o.command_timeout_s > 0.0) || !(o.max_command_age_s > 0.0)) args.fail("command timeouts must be > 0");
  if (o.publish_every < 1) args.fail("--publish-every must be >= 1");
  const double steps = 1.0 / (o.link.rate_hz * model::kStep);
  if (std::abs(steps - std::round(steps)) > 1e-9 * steps || std::round(steps) < 1) {
    args.fail("--rate " + std::to_string(o.link.rate_hz) + " Hz is not 1 / (k h) for the model's step h = " +
              std::to_string(model::kStep) + " s; pick a rate that divides 1/h, or regenerate with --h");
  }
  return o;
}

std::int64_t seconds_to_ns(double s) { return std::llround(s * 1e9); }

bool finite(const model::State& s) {
  bool ok = std::isfinite(s.t);
  for (const mbrt::RigidState& x : s.rigid) ok = ok && mbrt::all_finite(x.r) && mbrt::all_finite(x.p) && mbrt::all_finite(x.v) && mbrt::all_finite(x.w);
  for (const mbrt::ParticleState& x : s.particle) ok = ok && mbrt::all_finite(x.r) && mbrt::all_finite(x.v);
  return ok;
}

// The loop's data, all allocated before the first cycle.
struct Loop {
  model::State state = model::initial_state();
  model::Outputs outputs{};
  model::StateMessage state_message{};
  model::CommandMessage command_message{};
  CommandGate<model::kInputs> gate;
  HilRunStats stats;
  std::vector<unsigned char> buffer;

  explicit Loop(GateTimes times) : gate(model::kInputInfo, times) {}
};

// A command arrived: decode it (the whole message, fingerprint included),
// then let the gate judge it.
void on_command(const void* data, int size, void* context) {
  Loop& loop = *static_cast<Loop*>(context);
  if (!model::decode_exactly(data, size, loop.command_message)) {
    loop.gate.reject_malformed();
    return;
  }
  const model::CommandMessage& m = loop.command_message;
  model::Inputs values;
  model::unpack_inputs(m, values);
  // Its age counts from the state it answers: a command computed from old
  // data is late however quickly it was sent.
  const std::int64_t now_us = realtime_us();
  const std::int64_t born_us = m.state_utime > 0 ? m.state_utime : m.utime;
  const CommandVerdict v = loop.gate.offer(m.seq, (now_us - born_us) * 1000, values, monotonic_ns());
  if (v == CommandVerdict::applied && m.state_utime > 0) loop.stats.command_rtt_ns.record((now_us - m.state_utime) * 1000);
}

void publish_state(Loop& loop, LcmBridge& bridge, const std::string& channel, std::int64_t cycle) {
  model::outputs(loop.state, loop.outputs);
  model::StateMessage& m = loop.state_message;
  model::pack_outputs(loop.outputs, m);
  m.utime = realtime_us();
  m.seq = cycle;
  m.command_seq = loop.gate.on_safe_values() ? -1 : loop.gate.last_sequence();
  m.t = loop.state.t;
  const int size = m.encode(loop.buffer.data(), 0, static_cast<int>(loop.buffer.size()));
  bridge.publish(channel.c_str(), loop.buffer.data(), size);
}

int run(const Options& opt) {
  Loop loop({seconds_to_ns(opt.command_timeout_s), seconds_to_ns(opt.max_command_age_s)});
  HilRunStats& stats = loop.stats;
  stats.model = model::kName;
  stats.transport = "lcm " + opt.link.lcm_url;
  stats.rate_hz = opt.link.rate_hz;
  stats.steps_per_cycle = static_cast<int>(std::lround(1.0 / (opt.link.rate_hz * model::kStep)));
  loop.buffer.resize(static_cast<std::size_t>(loop.state_message.getEncodedSize()));

  LcmBridge bridge(opt.link.lcm_url, opt.link.command_channel);
  stats.realtime = prepare_realtime(opt.realtime);

  const std::int64_t cycles = std::llround(opt.link.duration_s * opt.link.rate_hz);
  PeriodicClock clock(std::llround(1e9 / opt.link.rate_hz));
  for (std::int64_t cycle = 0; cycle < cycles; ++cycle) {
    stats.wake_jitter_ns.record(clock.wait_for_release());
    bridge.receive(&on_command, &loop, kMaxCommandsPerCycle);
    loop.state.inputs = loop.gate.inputs_for_cycle(monotonic_ns());
    const std::int64_t step_start = monotonic_ns();
    for (int k = 0; k < stats.steps_per_cycle; ++k) stats.step_failures += model::step(loop.state) != mbrt::StepStatus::ok;
    stats.step_ns.record(monotonic_ns() - step_start);
    if (cycle % opt.publish_every == 0) publish_state(loop, bridge, opt.link.state_channel, cycle);
    const std::int64_t end = monotonic_ns();
    stats.cycle_ns.record(end - clock.release_ns());
    clock.finish_cycle(end);
  }
  stats.cycles = cycles;
  stats.deadline_misses = clock.deadline_misses();
  stats.overruns = clock.overruns();
  stats.commands = loop.gate.counts();
  stats.state_finite = finite(loop.state);

  const std::string json = to_json(stats);
  if (!write_report(json, opt.link.report)) return 1;
  return stats.state_finite ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse(argc, argv);
  try {
    return run(opt);
  } catch (const std::exception& e) {  // start-up only: the loop throws nothing
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
