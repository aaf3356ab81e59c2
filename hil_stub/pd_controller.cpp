// A simulated controller in its own process: a PD joint controller that
// reads the model's state over LCM or a CAN bus and answers with commands at
// its own period, with a configurable compute delay, jitter and injected
// faults. Compiled by `mbrt stub` with the model's generated LCM types and
// CAN layout, with
//   -DMBRT_MODEL_LCM_HEADER="<name>_lcm.hpp" -DMBRT_MODEL_CAN_HEADER="<name>_can.hpp"
//   -DMBRT_MODEL_NAMESPACE=mbrt::models::<name>
//
// Every joint_torque or joint_force input whose joint has joint_position and
// joint_velocity outputs is driven to follow q_ref(t) = A sin(2 pi f t), t
// the simulation time of the latest state (the reference does not restart
// with the controller):
//   u = clamp(kp (q_ref - q) + kd (q_ref' - q'), min, max),
// with one kp and kd for all joints or one per controlled joint, in input order.
// Other inputs get their safe value. The report gives the tracking error
// over the states received after the first --settle seconds of control.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include <mbrt/rt/can_bus.hpp>
#include <mbrt/rt/lcm_bridge.hpp>
#include <mbrt/rt/periodic_clock.hpp>
#include <mbrt/rt/program_options.hpp>

#include MBRT_MODEL_CAN_HEADER
#include MBRT_MODEL_LCM_HEADER

namespace model = MBRT_MODEL_NAMESPACE;
using namespace mbrt::rt;

namespace {

constexpr double kPi = 3.14159265358979323846;

StubOptions parse(int argc, char** argv) {
  StubOptions o;
  o.link.state_channel = model::kStateChannel;
  o.link.command_channel = model::kCommandChannel;
  CLI::App app("stub: a PD controller with fault injection for a model running in `mbrt hil`", "pd_controller");
  add_stub_options(app, o);
  parse_or_exit(app, argc, argv);
  if (const std::string why = check_link_options(o.link); !why.empty()) fail(app, why);
  return o;
}

// An input driven by the PD law, with the outputs of its joint.
struct JointLoop {
  int input;
  int position;  // index in Outputs
  int velocity;
};

int output_of(const char* source, const char* type) {
  for (const mbrt::OutputInfo& o : model::kOutputInfo) {
    if (std::strcmp(o.source, source) == 0 && std::strcmp(o.type, type) == 0) return o.first;
  }
  return -1;
}

std::vector<JointLoop> joint_loops() {
  std::vector<JointLoop> loops;
  for (int i = 0; i < model::kInputs; ++i) {
    const mbrt::InputInfo& in = model::kInputInfo[static_cast<std::size_t>(i)];
    if (std::strcmp(in.type, "motor_torque") == 0) continue;
    const int q = output_of(in.target, "joint_position"), qd = output_of(in.target, "joint_velocity");
    if (q < 0 || qd < 0) {
      std::fprintf(stderr, "note: input %s gets its safe value: joint %s has no joint_position and joint_velocity outputs\n",
                   in.name, in.target);
      continue;
    }
    loops.push_back({i, q, qd});
  }
  return loops;
}

struct FaultCounts {
  long dropped = 0, duplicated = 0, reordered = 0, garbage = 0, nan = 0, out_of_range = 0;
};

struct Controller {
  StubOptions opt;
  std::vector<JointLoop> loops = joint_loops();
  // The latest state: its outputs and time, and what a command answering it quotes.
  model::Outputs y{};
  double t = 0.0;
  std::int64_t state_utime = 0;     // LCM
  std::uint16_t state_seq = 0;      // CAN
  bool have_state = false;
  double first_state_t = 0.0;
  long states_received = 0;
  long commands_sent = 0;
  double error_sum_sq = 0.0, error_max = 0.0;
  long error_samples = 0;
  FaultCounts faults;
  std::mt19937_64 random;
  std::vector<unsigned char> held;  // a command kept back to be sent after the next one (encoded)

  explicit Controller(const StubOptions& o) : opt(o), random(o.seed) {
    for (const std::vector<double>* g : {&opt.kp, &opt.kd}) {
      if (g->size() != 1 && g->size() != loops.size()) {
        throw std::runtime_error("--kp and --kd take one gain or one per controlled joint (" + std::to_string(loops.size()) + ")");
      }
    }
  }

  static double gain(const std::vector<double>& g, std::size_t joint) { return g.size() == 1 ? g[0] : g[joint]; }

  double q_ref(double t) const { return opt.amplitude * std::sin(2.0 * kPi * opt.frequency * t); }
  double qd_ref(double t) const { return 2.0 * kPi * opt.frequency * opt.amplitude * std::cos(2.0 * kPi * opt.frequency * t); }
  bool chance(double p) { return p > 0.0 && std::uniform_real_distribution<double>(0.0, 1.0)(random) < p; }

  void track(const model::Outputs& y, double t) {
    if (t - first_state_t < opt.settle_s) return;
    for (const JointLoop& j : loops) {
      const double e = q_ref(t) - y[static_cast<std::size_t>(j.position)];
      error_sum_sq += e * e;
      error_max = std::max(error_max, std::abs(e));
      ++error_samples;
    }
  }

  void on_state(double state_t) {
    t = state_t;
    if (!have_state) first_state_t = t;
    have_state = true;
    ++states_received;
    track(y, t);
  }

  model::Inputs command() const {
    model::Inputs u;
    for (int i = 0; i < model::kInputs; ++i) u[static_cast<std::size_t>(i)] = model::kInputInfo[static_cast<std::size_t>(i)].safe;
    for (std::size_t k = 0; k < loops.size(); ++k) {
      const JointLoop& j = loops[k];
      const mbrt::InputInfo& in = model::kInputInfo[static_cast<std::size_t>(j.input)];
      const double pd = gain(opt.kp, k) * (q_ref(t) - y[static_cast<std::size_t>(j.position)]) +
                        gain(opt.kd, k) * (qd_ref(t) - y[static_cast<std::size_t>(j.velocity)]);
      u[static_cast<std::size_t>(j.input)] = std::clamp(pd, in.min, in.max);
    }
    return u;
  }
};

// The controller's link: LCM messages or CAN frames. A command travels as
// one unit of bytes (a message, or its frames back to back), so the faults
// act on whole commands alike.
class Link {
 public:
  virtual ~Link() = default;
  // Takes the states waiting (up to wait_ms for the first) into c.
  virtual void receive(Controller& c, int wait_ms) = 0;
  virtual std::vector<unsigned char> encode(const model::Inputs& u, long seq, const Controller& c) = 0;
  // Something that looks like a command but must be refused as malformed, once.
  virtual std::vector<unsigned char> garbage(std::vector<unsigned char> command, std::mt19937_64& random) = 0;
  virtual void send(const std::vector<unsigned char>& command) = 0;
};

class LcmLink final : public Link {
 public:
  explicit LcmLink(const LinkOptions& o) : bridge_(o.lcm_url, o.state_channel), channel_(o.command_channel) {}

  void receive(Controller& c, int wait_ms) override { bridge_.receive(&on_state, &c, 64, wait_ms); }

  std::vector<unsigned char> encode(const model::Inputs& u, long seq, const Controller& c) override {
    model::CommandMessage m{};
    model::pack_inputs(u, m);
    m.seq = seq;
    m.state_utime = c.state_utime;
    m.utime = realtime_us();
    std::vector<unsigned char> bytes(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    return bytes;
  }

  // Random bytes of random length.
  std::vector<unsigned char> garbage(std::vector<unsigned char> bytes, std::mt19937_64& random) override {
    std::uniform_int_distribution<int> byte(0, 255);
    for (unsigned char& b : bytes) b = static_cast<unsigned char>(byte(random));
    bytes.resize(static_cast<std::size_t>(std::uniform_int_distribution<int>(1, static_cast<int>(bytes.size()))(random)));
    return bytes;
  }

  void send(const std::vector<unsigned char>& bytes) override {
    bridge_.publish(channel_.c_str(), bytes.data(), static_cast<int>(bytes.size()));
  }

 private:
  static void on_state(const void* data, int size, void* context) {
    Controller& c = *static_cast<Controller*>(context);
    model::StateMessage m{};
    if (!model::decode_exactly(data, size, m)) return;
    model::unpack_outputs(m, c.y);
    c.state_utime = m.utime;
    c.on_state(m.t);
  }

  LcmBridge bridge_;
  std::string channel_;
};

class CanLink final : public Link {
 public:
  explicit CanLink(const LinkOptions& o) : bus_(open_can_bus(o.can_bus, model::can::kLayout.fd)) {}

  // Like LCM's: waits up to wait_ms for the first frames, takes those
  // waiting, returns. A state is whole when all its output frames follow
  // its header frame.
  void receive(Controller& c, int wait_ms) override {
    const std::int64_t until = monotonic_ns() + wait_ms * 1000000ll;
    canfd_frame frames[64];
    int n = 0;
    while ((n = bus_->receive(frames, 64)) == 0 && monotonic_ns() < until) {
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    for (int k = 0; k < n; ++k) take(c, frames[k]);
  }

  std::vector<unsigned char> encode(const model::Inputs& u, long seq, const Controller& c) override {
    model::can::CommandFrames frames;
    model::can::pack_command(static_cast<std::uint16_t>(seq), c.state_seq, u, frames);
    std::vector<unsigned char> bytes(sizeof frames);
    std::memcpy(bytes.data(), frames.data(), sizeof frames);
    return bytes;
  }

  // The first frame alone, cut short (a wrong length; for CAN FD, one that may
  // be no CAN FD length at all).
  std::vector<unsigned char> garbage(std::vector<unsigned char> bytes, std::mt19937_64& random) override {
    canfd_frame f;
    std::memcpy(&f, bytes.data(), sizeof f);
    f.len = static_cast<std::uint8_t>(std::uniform_int_distribution<int>(0, f.len - 1)(random));
    bytes.resize(sizeof f);
    std::memcpy(bytes.data(), &f, sizeof f);
    return bytes;
  }

  void send(const std::vector<unsigned char>& bytes) override {
    for (std::size_t at = 0; at + sizeof(canfd_frame) <= bytes.size(); at += sizeof(canfd_frame)) {
      canfd_frame f;
      std::memcpy(&f, bytes.data() + at, sizeof f);
      bus_->send(f);
    }
  }

 private:
  void take(Controller& c, const canfd_frame& f) {
    mbrt::can::StateHeader h;
    if (model::can::unpack_state(f, pending_, h) != mbrt::can::FrameCheck::ok) return;
    const int index = static_cast<int>((f.can_id & CAN_SFF_MASK) - model::can::kStateId);
    if (index == 0) {
      header_ = h;
      have_ = 1;
    } else if (have_ == index) {
      ++have_;  // frames arrive in order on one bus
    } else {
      have_ = 0;  // a frame was lost: wait for the next header
    }
    if (have_ != model::can::kStateFrames) return;
    have_ = 0;
    c.y = pending_;
    c.state_seq = header_.seq;
    c.on_state(header_.t);
  }

  std::unique_ptr<CanBus> bus_;
  model::Outputs pending_{};
  mbrt::can::StateHeader header_;
  int have_ = 0;  // frames of the current state received, header first
};

// Builds the next command and sends it, or the fault that replaces it.
void send_command(Controller& c, Link& link, long seq) {
  model::Inputs u = c.command();
  if (c.chance(c.opt.faults.nan)) {
    u[0] = std::nan("");
    ++c.faults.nan;
  } else if (c.chance(c.opt.faults.out_of_range)) {
    u[0] = model::kInputInfo[0].max + 1.0 + std::abs(model::kInputInfo[0].max);
    ++c.faults.out_of_range;
  }
  if (c.opt.delay_us > 0.0 || c.opt.jitter_us > 0.0) {  // compute time of the control law
    const double us = c.opt.delay_us + std::uniform_real_distribution<double>(0.0, c.opt.jitter_us)(c.random);
    std::this_thread::sleep_for(std::chrono::microseconds(std::llround(us)));
  }
  std::vector<unsigned char> bytes = link.encode(u, seq, c);
  if (c.chance(c.opt.faults.garbage)) {
    bytes = link.garbage(std::move(bytes), c.random);
    ++c.faults.garbage;
  }
  if (c.chance(c.opt.faults.drop)) {
    ++c.faults.dropped;
    return;
  }
  if (c.held.empty() && c.chance(c.opt.faults.reorder)) {
    c.held = bytes;
    ++c.faults.reordered;
    return;
  }
  link.send(bytes);
  ++c.commands_sent;
  if (!c.held.empty()) {
    link.send(c.held);
    c.held.clear();
    ++c.commands_sent;
  }
  if (c.chance(c.opt.faults.duplicate)) {
    link.send(bytes);
    ++c.faults.duplicated;
  }
}

std::string report(const Controller& c) {
  const double rms = c.error_samples ? std::sqrt(c.error_sum_sq / static_cast<double>(c.error_samples)) : NAN;
  const nlohmann::ordered_json j = {
      {"states_received", c.states_received},
      {"commands_sent", c.commands_sent},
      {"joints_controlled", c.loops.size()},
      {"tracking_rms", rms},  // null without samples: JSON has no NaN
      {"tracking_max", c.error_max},
      {"tracking_samples", c.error_samples},
      {"faults",
       {{"dropped", c.faults.dropped},
        {"duplicated", c.faults.duplicated},
        {"reordered", c.faults.reordered},
        {"garbage", c.faults.garbage},
        {"nan", c.faults.nan},
        {"out_of_range", c.faults.out_of_range}}}};
  return j.dump() + "\n";
}

int run(const StubOptions& opt) {
  Controller c(opt);
  std::unique_ptr<Link> link;
  if (opt.link.can_bus.empty()) link = std::make_unique<LcmLink>(opt.link);
  else link = std::make_unique<CanLink>(opt.link);
  const std::int64_t period_ns = std::llround(1e9 / opt.link.rate_hz);
  const std::int64_t start = monotonic_ns();
  const std::int64_t end = start + std::llround(opt.link.duration_s * 1e9);
  std::int64_t next = start + period_ns;
  long seq = 0;
  while (monotonic_ns() < end) {
    // Take states until the next tick, then answer the latest one.
    for (std::int64_t now = monotonic_ns(); now < next; now = monotonic_ns()) {
      link->receive(c, static_cast<int>(std::max<std::int64_t>(1, (next - now) / 1000000)));
    }
    next += period_ns;
    if (opt.crash_after_s >= 0.0 && monotonic_ns() - start > std::llround(opt.crash_after_s * 1e9)) {
      std::fprintf(stderr, "pd_controller: crashing as asked (--crash-after %g)\n", opt.crash_after_s);
      std::_Exit(3);  // no clean-up, no report: like a real crash
    }
    if (c.have_state) send_command(c, *link, seq++);
  }
  const std::string json = report(c);
  if (!write_report(json, opt.link.report)) return 1;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const StubOptions opt = parse(argc, argv);
  try {
    return run(opt);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
