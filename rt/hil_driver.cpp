// Main program of `mbrt hil`: runs one generated model in a fixed-period
// loop and exchanges states and commands over LCM or a CAN bus. Compiled by
// `mbrt hil` together with the model and its LCM types and CAN layout, with
//   -DMBRT_MODEL_LCM_HEADER="<name>_lcm.hpp" -DMBRT_MODEL_CAN_HEADER="<name>_can.hpp"
//   -DMBRT_MODEL_NAMESPACE=mbrt::models::<name>
//
// Each cycle: wait for the release, take the waiting commands (validated by
// the command gate), step the model, publish its outputs. The cycle
// allocates nothing after start-up (test_step_allocates_nothing,
// test_lcm_allocates_nothing); the report is written after the loop.
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <mbrt/schemes/state_checks.hpp>
#include <mbrt/rt/can_bus.hpp>
#include <mbrt/rt/can_command_assembler.hpp>
#include <mbrt/rt/candump_log.hpp>
#include <mbrt/rt/command_gate.hpp>
#include <mbrt/rt/hil_report.hpp>
#include <mbrt/rt/lcm_bridge.hpp>
#include <mbrt/rt/periodic_clock.hpp>
#include <mbrt/rt/program_options.hpp>
#include <mbrt/rt/realtime_setup.hpp>
#include <mbrt/parameter_settings.hpp>

#include MBRT_MODEL_CAN_HEADER
#include MBRT_MODEL_LCM_HEADER

namespace model = MBRT_MODEL_NAMESPACE;
using namespace mbrt::rt;

namespace {

// Commands taken per cycle at most: a flood cannot stretch a cycle unboundedly.
constexpr int kMaxCommandsPerCycle = 32;
// Over CAN a command takes kCommandFrames frames, and the bus carries our
// own state frames back too (multicast loop).
constexpr int kMaxFramesPerCycle = 2 * kMaxCommandsPerCycle * (model::can::kCommandFrames + model::can::kStateFrames);
// Publication times of the last states, by seq: a CAN command's age counts
// from the state it answers.
constexpr std::size_t kPublishedStates = 1024;

HilOptions parse(int argc, char** argv) {
  HilOptions o;
  o.link.state_channel = model::kStateChannel;
  o.link.command_channel = model::kCommandChannel;
  CLI::App app("hil: the model's step in a fixed-period real-time loop, exchanging states and commands over LCM or CAN",
               "hil");
  add_hil_options(app, o);
  parse_or_exit(app, argc, argv);
  if (const std::string why = check_hil_options(o, model::kStep); !why.empty()) fail(app, why);
  return o;
}

std::int64_t seconds_to_ns(double s) { return std::llround(s * 1e9); }

// The loop's first state, with the --set parameters (docs/parameters.md);
// "" or why it cannot start.
std::string start_state(const std::vector<std::string>& set, model::State& s) {
#ifdef MBRT_MODEL_PARAMETERS
  return mbrt::start_with_settings(model::kParameterInfo, model::kDefaultParameters, set, model::initial_state,
                                   model::constraint_violation, s);
#else
  s = model::initial_state();
  return set.empty() ? "" : "the model has no tunable keys (docs/parameters.md)";
#endif
}

// The loop's data, all allocated before the first cycle.
struct Loop {
  model::State state = model::initial_state();
  model::Workspace workspace;  // what step() works on, kWorkspaceBytes
  model::Outputs outputs{};
  model::StateMessage state_message{};
  model::CommandMessage command_message{};
  CommandGate<model::kInputs> gate;
  HilRunStats stats;
  std::vector<unsigned char> buffer;
  // CAN only:
  model::can::StateFrames state_frames{};
  std::array<canfd_frame, kMaxFramesPerCycle> received{};
  CanCommandAssembler<model::kInputs> assembler;
  std::array<std::int64_t, kPublishedStates> published_ns{};
  std::array<std::int64_t, kPublishedStates> published_seq{};
  long undecodable = 0;

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
  const std::int64_t age_ns = lcm_command_age_ns(realtime_us(), m.utime, m.state_utime);
  const CommandVerdict v = loop.gate.offer(m.seq, age_ns, values, monotonic_ns());
  // Answering a state, its age is the round trip from that state's publication.
  if (v == CommandVerdict::applied && m.state_utime > 0) loop.stats.command_rtt_ns.record(age_ns);
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

double realtime_s() {
  timespec now;
  clock_gettime(CLOCK_REALTIME, &now);
  return static_cast<double>(now.tv_sec) + now.tv_nsec * 1e-9;
}

// The CAN link: the bus, and the log of what crossed it, if asked for.
struct CanLink {
  std::unique_ptr<CanBus> bus;
  std::unique_ptr<CandumpLog> log;

  explicit CanLink(const LinkOptions& o) : bus(open_can_bus(o.can_bus, model::can::kLayout.fd)) {
    const std::string udp = "udp://";
    if (!o.can_log.empty()) log = std::make_unique<CandumpLog>(o.can_log, o.can_bus.rfind(udp, 0) == 0 ? "udp0" : o.can_bus);
  }
  void logged(const canfd_frame& f) noexcept {
    if (log) log->write(f, realtime_s());
  }
};

// A whole CAN command: its age counts from the publication of the state it
// answers (unknown if that was more than kPublishedStates states ago: late).
void offer_can_command(Loop& loop, std::int64_t cycle) {
  const CanCommandAssembler<model::kInputs>& a = loop.assembler;
  const std::int64_t answered = unwrap16(cycle, a.state_seq());
  const std::size_t slot = static_cast<std::size_t>(answered) % kPublishedStates;
  const std::int64_t now = monotonic_ns();
  const bool known = answered >= 0 && loop.published_seq[slot] == answered;
  const std::int64_t age_ns = known ? now - loop.published_ns[slot] : std::numeric_limits<std::int64_t>::max();
  const CommandVerdict v = loop.gate.offer(a.sequence(), age_ns, a.values(), now);
  if (v == CommandVerdict::applied && known) loop.stats.command_rtt_ns.record(age_ns);
}

void receive_can_commands(Loop& loop, CanLink& link, std::int64_t cycle) {
  const int n = link.bus->receive(loop.received.data(), static_cast<int>(loop.received.size()));
  for (; loop.undecodable < link.bus->undecodable(); ++loop.undecodable) loop.gate.reject_malformed();
  for (int k = 0; k < n; ++k) {
    const canfd_frame& f = loop.received[static_cast<std::size_t>(k)];
    mbrt::can::CommandPart part;
    const mbrt::can::FrameCheck c = model::can::unpack_command(f, part);
    if (c == mbrt::can::FrameCheck::unknown_id) continue;  // other traffic on the bus, our own states included
    link.logged(f);
    if (c == mbrt::can::FrameCheck::malformed) loop.gate.reject_malformed();
    else if (loop.assembler.add(part)) offer_can_command(loop, cycle);
  }
}

void send_can_state(Loop& loop, CanLink& link, std::int64_t cycle) {
  model::outputs(loop.state, loop.outputs);
  const std::uint16_t applied = static_cast<std::uint16_t>(loop.gate.last_sequence());
  model::can::pack_state(loop.outputs, {static_cast<std::uint16_t>(cycle), applied, loop.state.t}, loop.state_frames);
  const std::size_t slot = static_cast<std::size_t>(cycle) % kPublishedStates;
  loop.published_seq[slot] = cycle;
  loop.published_ns[slot] = monotonic_ns();
  for (const canfd_frame& f : loop.state_frames) {
    link.bus->send(f);
    link.logged(f);
  }
}

int run(const HilOptions& opt) {
  // On the heap: a large model's workspace would not fit a small thread stack.
  const auto loop_memory = std::make_unique<Loop>(GateTimes{seconds_to_ns(opt.command_timeout_s), seconds_to_ns(opt.max_command_age_s)});
  Loop& loop = *loop_memory;
  if (const std::string why = start_state(opt.set, loop.state); !why.empty()) {
    std::fprintf(stderr, "hil: --set: %s\n", why.c_str());
    return 2;
  }
  HilRunStats& stats = loop.stats;
  stats.model = model::kName;
  const bool can = !opt.link.can_bus.empty();
  stats.transport = can ? "can " + opt.link.can_bus : "lcm " + opt.link.lcm_url;
  stats.rate_hz = opt.link.rate_hz;
  stats.steps_per_cycle = static_cast<int>(std::lround(1.0 / (opt.link.rate_hz * model::kStep)));
  loop.buffer.resize(static_cast<std::size_t>(loop.state_message.getEncodedSize()));

  std::unique_ptr<LcmBridge> bridge;
  std::unique_ptr<CanLink> can_link;
  if (can) can_link = std::make_unique<CanLink>(opt.link);
  else bridge = std::make_unique<LcmBridge>(opt.link.lcm_url, opt.link.command_channel);
  loop.published_seq.fill(-1);
  stats.workspace_bytes = model::kWorkspaceBytes;
  stats.realtime = prepare_realtime(opt.realtime, &loop.workspace, model::kWorkspaceBytes);
  model::start_workers();  // the parallel step's threads, before the loop (docs/parallel.md); none for a serial one

  const std::int64_t cycles = std::llround(opt.link.duration_s * opt.link.rate_hz);
  PeriodicClock clock(std::llround(1e9 / opt.link.rate_hz));
  for (std::int64_t cycle = 0; cycle < cycles; ++cycle) {
    stats.wake_jitter_ns.record(clock.wait_for_release());
    if (can) receive_can_commands(loop, *can_link, cycle);
    else bridge->receive(&on_command, &loop, kMaxCommandsPerCycle);
    loop.state.inputs = loop.gate.inputs_for_cycle(monotonic_ns());
    const std::int64_t step_start = monotonic_ns();
    for (int k = 0; k < stats.steps_per_cycle; ++k) stats.step_failures += model::step(loop.state, loop.workspace) != mbrt::StepStatus::ok;
    stats.step_ns.record(monotonic_ns() - step_start);
    if (cycle % opt.publish_every == 0) {
      if (can) send_can_state(loop, *can_link, cycle);
      else publish_state(loop, *bridge, opt.link.state_channel, cycle);
    }
    const std::int64_t end = monotonic_ns();
    stats.cycle_ns.record(end - clock.release_ns());
    clock.finish_cycle(end);
  }
  stats.cycles = cycles;
  stats.deadline_misses = clock.deadline_misses();
  stats.overruns = clock.overruns();
  stats.commands = loop.gate.counts();
  model::refresh_bodies(loop.state);  // where the step leaves them to be formed on demand
  stats.state_finite = mbrt::schemes::finite(loop.state);

  const std::string json = to_json(stats);
  if (!write_report(json, opt.link.report)) return 1;
  return stats.state_finite ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  const HilOptions opt = parse(argc, argv);
  try {
    return run(opt);
  } catch (const std::exception& e) {  // start-up only: the loop throws nothing
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
