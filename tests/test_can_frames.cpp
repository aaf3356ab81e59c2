// The generated CAN layout: outputs and inputs survive their frames to
// within the signals' resolution (1e-6), NaN, Inf and values beyond the
// int32 range arrive as NaN, and what the HIL loop must count as malformed
// or ignore is reported so: a wrong length, a remote frame, an unknown or
// extended ID.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "actuated_can.hpp"

namespace model = mbrt::models::actuated;
namespace can = mbrt::can;

TEST_CASE("a signal's bytes are the little-endian int32 of value / 1e-6") {
  model::Outputs y{};
  y[0] = 1.234567;   // 1234567 = 0x0012D687
  y[1] = -0.000001;  // -1 = 0xFFFFFFFF
  model::can::StateFrames f;
  model::can::pack_state(y, {}, f);
  CHECK(f[1].can_id == 0x101);
  CHECK(f[1].len == 8);
  const unsigned char expected[8] = {0x87, 0xD6, 0x12, 0x00, 0xFF, 0xFF, 0xFF, 0xFF};
  for (int i = 0; i < 8; ++i) CHECK(f[1].data[i] == expected[i]);
}

TEST_CASE("outputs of a moving model survive the state frames") {
  model::State s = model::initial_state();
  for (int i = 0; i < 100; ++i) model::step(s);
  model::Outputs y, back{};
  model::outputs(s, y);
  model::can::StateFrames frames;
  model::can::pack_state(y, {7, 65535, 12.34567}, frames);
  can::StateHeader h;
  for (const can_frame& f : frames) REQUIRE(model::can::unpack_state(f, back, h) == can::FrameCheck::ok);
  for (int i = 0; i < model::kOutputs; ++i) CHECK(std::abs(back[i] - y[i]) <= 0.5e-6 + 1e-12);
  CHECK(h.seq == 7);
  CHECK(h.command_seq == 65535);
  CHECK(h.t == doctest::Approx(12.34567).epsilon(1e-9));
  CHECK(frames.back().len == (model::kOutputs % 2 ? 4 : 8));
}

TEST_CASE("inputs survive the command frames; NaN, Inf and huge values arrive as NaN") {
  const double inf = std::numeric_limits<double>::infinity();
  for (const model::Inputs& u : {model::Inputs{1.5, -19.999999, 0.25}, model::Inputs{std::nan(""), inf, 3000.0}}) {
    model::can::CommandFrames frames;
    model::can::pack_command(41, 40, u, frames);
    for (int i = 0; i < model::kInputs; ++i) {
      can::CommandSignal c;
      REQUIRE(model::can::unpack_command(frames[i], c) == can::FrameCheck::ok);
      CHECK(c.input == i);
      CHECK(c.seq == 41);
      CHECK(c.state_seq == 40);
      if (std::isfinite(u[i]) && std::abs(u[i]) < 2147) CHECK(std::abs(c.value - u[i]) <= 0.5e-6 + 1e-12);
      else CHECK(std::isnan(c.value));
    }
  }
}

TEST_CASE("wrong length, remote frames, unknown and extended IDs are told apart") {
  model::can::CommandFrames frames;
  model::can::pack_command(1, 1, model::Inputs{}, frames);
  can::CommandSignal c;
  can_frame f = frames[0];
  f.len = 7;
  CHECK(model::can::unpack_command(f, c) == can::FrameCheck::malformed);
  f = frames[0];
  f.can_id |= CAN_RTR_FLAG;
  CHECK(model::can::unpack_command(f, c) == can::FrameCheck::malformed);
  f = frames[0];
  f.can_id = model::can::kCommandId + model::kInputs;  // one past the last input
  CHECK(model::can::unpack_command(f, c) == can::FrameCheck::unknown_id);
  f.can_id = model::can::kCommandId | CAN_EFF_FLAG;
  CHECK(model::can::unpack_command(f, c) == can::FrameCheck::unknown_id);
  f.can_id = model::can::kStateId;  // a state frame is not a command
  CHECK(model::can::unpack_command(f, c) == can::FrameCheck::unknown_id);

  model::can::StateFrames state;
  model::can::pack_state(model::Outputs{}, {}, state);
  model::Outputs y{};
  can::StateHeader h;
  state.back().len = 8;  // the lone last value has DLC 4
  CHECK(model::can::unpack_state(state.back(), y, h) == can::FrameCheck::malformed);
}
