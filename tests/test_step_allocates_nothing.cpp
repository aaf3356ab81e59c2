// step() makes no heap allocation (allocation_counter.hpp interposes
// malloc). The same holds for the HIL loop's per-cycle work around the
// step: outputs, packing and encoding the state message, decoding and
// unpacking a command, the command gate and the timing histogram.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include <mbrt/rt/command_gate.hpp>
#include <mbrt/rt/latency_histogram.hpp>

#include "a01_pendulum.hpp"
#include "actuated_lcm.hpp"
#include "allocation_counter.hpp"
#include "four_bar.hpp"
#include "heavy_top.hpp"

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
    m::step(s); /* warm up outside the counted region */                   \
    long bad = 0;                                                           \
    long seen = 0;                                                          \
    {                                                                       \
      AllocationCounter counter;                                            \
      for (long i = 0; i < (steps); ++i) bad += m::step(s) != mbrt::StepStatus::ok; \
      seen = counter.count();                                               \
    }                                                                       \
    CHECK(bad == 0);                                                        \
    CHECK(seen == 0);                                                       \
  } while (false)

TEST_CASE("step() allocates nothing over 1e5 steps") {
  CHECK_NO_ALLOCATION(a01_pendulum, 100000);
  CHECK_NO_ALLOCATION(heavy_top, 100000);
  CHECK_NO_ALLOCATION(four_bar, 100000);
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
