// step() makes no heap allocation (allocation_counter.hpp interposes
// malloc). The same holds for the HIL loop's per-cycle work around the
// step: outputs, packing and encoding the state message, decoding and
// unpacking a command, the command gate and the timing histogram; over
// CAN, classic and CAN FD, packing the state frames, the UDP wire format both
// ways, the candump line and log, unpacking and assembling command frames.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include <mbrt/rt/can_command_assembler.hpp>
#include <mbrt/rt/can_udp_wire.hpp>
#include <mbrt/rt/candump_log.hpp>
#include <mbrt/rt/command_gate.hpp>
#include <mbrt/rt/latency_histogram.hpp>

#include "a01_pendulum.hpp"
#include "actuated_can.hpp"
#include "actuated_fd_can.hpp"
#include "actuated_lcm.hpp"
#include "actuated_rk4p.hpp"
#include "allocation_counter.hpp"
#include "arm_7_midpoint.hpp"
#include "arm_7_rk4.hpp"
#include "arm_7_rk8.hpp"
#include "arm_7_tree.hpp"
#include "four_bar.hpp"
#include "four_bar_general.hpp"
#include "four_bar_nps.hpp"
#include "four_bar_rk4p.hpp"
#include "four_bar_s4.hpp"
#include "heavy_top.hpp"
#include "two_masses_special.hpp"

TEST_CASE("the allocation counter sees heap allocations") {
  long seen = 0;
  {
    AllocationCounter counter;
    std::vector<double> v(1000, 1.0);
    seen = counter.count();
    CHECK(v.back() == 1.0);
  }
  CHECK(seen >= 1);
}

#define CHECK_NO_ALLOCATION(model, steps)                                   \
  do {                                                                      \
    namespace m = mbrt::models::model;                                      \
    m::State s = m::initial_state();                                        \
    static m::Workspace w; /* caller-owned, as a real-time loop keeps it */ \
    m::step(s, w); /* warm up outside the counted region */                \
    long bad = 0;                                                           \
    long seen = 0;                                                          \
    {                                                                       \
      AllocationCounter counter;                                            \
      for (long i = 0; i < (steps); ++i) bad += m::step(s, w) != mbrt::StepStatus::ok; \
      seen = counter.count();                                               \
    }                                                                       \
    CHECK(bad == 0);                                                        \
    CHECK(seen == 0);                                                       \
  } while (false)

TEST_CASE("step() allocates nothing over 1e5 steps") {
  CHECK_NO_ALLOCATION(a01_pendulum, 100000);
  CHECK_NO_ALLOCATION(heavy_top, 100000);
  CHECK_NO_ALLOCATION(four_bar, 100000);
  CHECK_NO_ALLOCATION(four_bar_nps, 100000);  // staggered-nps: a tree and cut rows
  CHECK_NO_ALLOCATION(four_bar_general, 100000);    // --no-specialize
  CHECK_NO_ALLOCATION(two_masses_special, 100000);  // gravity-free, an unloaded body
  CHECK_NO_ALLOCATION(arm_7_tree, 100000);          // staggered-tree
  CHECK_NO_ALLOCATION(arm_7_midpoint, 100000);      // midpoint-tree
  CHECK_NO_ALLOCATION(arm_7_rk4, 100000);           // rk4-tree
  CHECK_NO_ALLOCATION(arm_7_rk8, 100000);           // rk8-tree
  CHECK_NO_ALLOCATION(four_bar_rk4p, 100000);       // rk4-projected, redundant rows
  CHECK_NO_ALLOCATION(actuated_rk4p, 100000);       // rk4-projected with inputs
  CHECK_NO_ALLOCATION(four_bar_s4, 100000);         // staggered4, redundant rows
}

// A workspace is scratch memory: a step must give the same state whatever
// the workspace held before, so one workspace can serve any number of states.
// The same run twice, in the same State and Workspace objects (Eigen's
// vectorized loops depend on addresses): once as a loop runs it, once with
// every byte of the workspace 0xff (a NaN in every double) before each step.
#define CHECK_WORKSPACE_IS_SCRATCH(model)                                          \
  do {                                                                             \
    namespace m = mbrt::models::model;                                             \
    CHECK(m::kWorkspaceBytes == sizeof(m::Workspace));                            \
    static m::State s;                                                             \
    static m::Workspace w;                                                         \
    s = m::initial_state();                                                        \
    for (int i = 0; i < 200; ++i) REQUIRE(m::step(s, w) == mbrt::StepStatus::ok);  \
    const m::State plain = s;                                                      \
    s = m::initial_state();                                                        \
    for (int i = 0; i < 200; ++i) {                                                \
      std::memset(static_cast<void*>(&w), 0xff, sizeof w);                         \
      REQUIRE(m::step(s, w) == mbrt::StepStatus::ok);                              \
    }                                                                              \
    for (std::size_t i = 0; i < s.rigid.size(); ++i) {                             \
      CHECK(s.rigid[i].r == plain.rigid[i].r);                                     \
      CHECK(s.rigid[i].p == plain.rigid[i].p);                                     \
      CHECK(s.rigid[i].v == plain.rigid[i].v);                                     \
      CHECK(s.rigid[i].w == plain.rigid[i].w);                                     \
    }                                                                              \
    for (std::size_t i = 0; i < s.particle.size(); ++i) {                          \
      CHECK(s.particle[i].r == plain.particle[i].r);                               \
      CHECK(s.particle[i].v == plain.particle[i].v);                               \
    }                                                                              \
    CHECK(s.lambda == plain.lambda);                                               \
  } while (false)

TEST_CASE("the caller's workspace carries nothing from one step to the next") {
  CHECK_WORKSPACE_IS_SCRATCH(a01_pendulum);
  CHECK_WORKSPACE_IS_SCRATCH(arm_7_tree);
  CHECK_WORKSPACE_IS_SCRATCH(arm_7_midpoint);
  CHECK_WORKSPACE_IS_SCRATCH(arm_7_rk4);
  CHECK_WORKSPACE_IS_SCRATCH(four_bar_rk4p);
  CHECK_WORKSPACE_IS_SCRATCH(four_bar_s4);
  CHECK_WORKSPACE_IS_SCRATCH(heavy_top);
  CHECK_WORKSPACE_IS_SCRATCH(four_bar);
  CHECK_WORKSPACE_IS_SCRATCH(four_bar_nps);
  CHECK_WORKSPACE_IS_SCRATCH(four_bar_general);
  CHECK_WORKSPACE_IS_SCRATCH(two_masses_special);
}

TEST_CASE("the HIL cycle around the step allocates nothing") {
  namespace m = mbrt::models::actuated;
  m::State s = m::initial_state();
  mbrt::rt::CommandGate<m::kInputs> gate(m::kInputInfo, {50000000, 50000000});
  mbrt::rt::LatencyHistogram histogram;
  m::Outputs y{};
  m::StateMessage state_message{};
  m::CommandMessage command{}, received{};
  std::vector<unsigned char> state_bytes(static_cast<size_t>(state_message.getEncodedSize()));
  std::vector<unsigned char> command_bytes(static_cast<size_t>(command.getEncodedSize()));
  long applied = 0, seen = 0;
  {
    AllocationCounter counter;
    for (long cycle = 0; cycle < 10000; ++cycle) {
      // A controller's command arrives as bytes; the loop decodes and judges it.
      command.seq = cycle;
      command.tau_pivot = cycle % 2 ? 1.0 : std::nan("");  // every other one is refused
      command.encode(command_bytes.data(), 0, static_cast<int>(command_bytes.size()));
      const int size = static_cast<int>(command_bytes.size());
      if (received.decode(command_bytes.data(), 0, size) != size) gate.reject_malformed();
      m::Inputs u{};
      m::unpack_inputs(received, u);
      applied += gate.offer(received.seq, 0, u, cycle * 1000000) == mbrt::rt::CommandVerdict::applied;
      s.inputs = gate.inputs_for_cycle(cycle * 1000000);
      m::step(s);
      m::outputs(s, y);
      m::pack_outputs(y, state_message);
      state_message.encode(state_bytes.data(), 0, static_cast<int>(state_bytes.size()));
      histogram.record(cycle);
    }
    seen = counter.count();
  }
  CHECK(applied == 5000);
  CHECK(seen == 0);
}

// The CAN part of the cycle, with the frames and packing of one layout
// (classic or CAN FD) of the actuated model.
template <class StateFrames, class CommandFrames, class PackState, class PackCommand, class UnpackCommand>
void check_can_cycle(PackState pack_state, PackCommand pack_command, UnpackCommand unpack_command) {
  namespace m = mbrt::models::actuated;
  m::State s = m::initial_state();
  mbrt::rt::CommandGate<m::kInputs> gate(m::kInputInfo, {50000000, 50000000});
  mbrt::rt::CanCommandAssembler<m::kInputs> assembler;
  m::Outputs y{};
  StateFrames state_frames;
  CommandFrames command_frames;
  std::uint8_t datagram[mbrt::rt::kCanUdpMaxDatagram];
  char line[mbrt::rt::kCandumpLineSize];
  mbrt::rt::CandumpLog log("/dev/null", "udp0");
  long applied = 0, malformed = 0, seen = 0;
  {
    AllocationCounter counter;
    for (long cycle = 0; cycle < 10000; ++cycle) {
      // A controller's command frames cross the UDP wire; the loop decodes,
      // logs, unpacks and assembles them, and the gate judges the command.
      const m::Inputs u{cycle % 2 ? 1.0 : std::nan(""), 0.0, 0.0};  // every other one is refused
      pack_command(static_cast<std::uint16_t>(cycle), static_cast<std::uint16_t>(cycle), u, command_frames);
      for (const canfd_frame& sent : command_frames) {
        canfd_frame f;
        const std::size_t n = mbrt::rt::encode_can_udp(sent, 1.0, datagram);
        if (!mbrt::rt::decode_can_udp(datagram, n, f)) ++malformed;
        mbrt::rt::format_candump_line(f, 1.5, "udp0", line);
        log.write(f, 1.5);
        mbrt::can::CommandPart c;
        if (unpack_command(f, c) != mbrt::can::FrameCheck::ok) ++malformed;
        else if (assembler.add(c)) {
          applied += gate.offer(assembler.sequence(), 0, assembler.values(), cycle * 1000000) ==
                     mbrt::rt::CommandVerdict::applied;
        }
      }
      s.inputs = gate.inputs_for_cycle(cycle * 1000000);
      m::step(s);
      m::outputs(s, y);
      pack_state(y, {static_cast<std::uint16_t>(cycle), 0, s.t}, state_frames);
      for (const canfd_frame& f : state_frames) mbrt::rt::encode_can_udp(f, 1.0, datagram);
    }
    seen = counter.count();
  }
  CHECK(malformed == 0);
  CHECK(applied == 5000);
  CHECK(seen == 0);
}

TEST_CASE("the HIL cycle over CAN allocates nothing") {
  namespace c = mbrt::models::actuated::can;
  check_can_cycle<c::StateFrames, c::CommandFrames>(c::pack_state, c::pack_command, c::unpack_command);
}

TEST_CASE("the HIL cycle over CAN FD allocates nothing") {
  namespace c = mbrt::models::actuated_fd::can;
  check_can_cycle<c::StateFrames, c::CommandFrames>(c::pack_state, c::pack_command, c::unpack_command);
}
