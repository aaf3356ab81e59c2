// The generated CAN layouts, classic (actuated) and CAN FD (actuated_fd, the
// same model generated with --can-fd): outputs and inputs survive their
// frames to within the signals' resolution (1e-6), NaN, Inf and values
// beyond the int32 range arrive as NaN, CAN FD frames have CAN FD lengths
// and carry the state in fewer frames, and what the HIL loop must count as
// malformed or ignore is reported so: a wrong length, a frame of the other
// kind, a remote frame, an unknown or extended ID.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <limits>

#include "actuated_can.hpp"
#include "actuated_fd_can.hpp"

namespace classic = mbrt::models::actuated;
namespace fd = mbrt::models::actuated_fd;
namespace can = mbrt::can;

TEST_CASE("a signal's bytes are the little-endian int32 of value / 1e-6") {
  classic::Outputs y{};
  y[0] = 1.234567;   // 1234567 = 0x0012D687
  y[1] = -0.000001;  // -1 = 0xFFFFFFFF
  classic::can::StateFrames f;
  classic::can::pack_state(y, {}, f);
  CHECK(f[1].can_id == 0x101);
  CHECK(f[1].len == 8);
  CHECK(f[1].flags == 0);
  const unsigned char expected[8] = {0x87, 0xD6, 0x12, 0x00, 0xFF, 0xFF, 0xFF, 0xFF};
  for (int i = 0; i < 8; ++i) CHECK(f[1].data[i] == expected[i]);

  // In CAN FD the same values follow the 8-byte header in the state frame.
  fd::can::StateFrames g;
  fd::can::pack_state(y, {}, g);
  CHECK(g[0].can_id == 0x100);
  CHECK(g[0].flags == CANFD_FDF);
  for (int i = 0; i < 8; ++i) CHECK(g[0].data[8 + i] == expected[i]);
}

TEST_CASE("CAN FD frames have CAN FD lengths and carry the state in fewer frames") {
  static_assert(classic::kOutputs == 17 && classic::kInputs == 3);
  CHECK(classic::can::kStateFrames == 1 + 9);  // header, then 2 values a frame
  CHECK(classic::can::kCommandFrames == 3);
  CHECK(fd::can::kStateFrames == 2);  // header and 14 values, then 3 values
  CHECK(fd::can::kCommandFrames == 1);
  fd::can::StateFrames state;
  fd::can::pack_state(fd::Outputs{}, {}, state);
  CHECK(state[0].len == 64);
  CHECK(state[1].len == 12);
  fd::can::CommandFrames command;
  fd::can::pack_command(1, 1, fd::Inputs{}, command);
  CHECK(command[0].len == 16);
  for (int bytes = 0; bytes <= 64; ++bytes) {
    const int len = can::Layout{true, 0, 0}.length(bytes);
    CHECK(can::is_fd_length(len));
    CHECK(len >= bytes);
    for (int shorter = bytes; shorter < len; ++shorter) CHECK(!can::is_fd_length(shorter));
  }
}

template <class Frames, class Outputs, class Pack, class Unpack>
void check_state_round_trip(const Outputs& y, Pack pack, Unpack unpack) {
  Frames frames;
  pack(y, {7, 65535, 12.34567}, frames);
  Outputs back{};
  can::StateHeader h;
  for (const canfd_frame& f : frames) REQUIRE(unpack(f, back, h) == can::FrameCheck::ok);
  for (std::size_t i = 0; i < y.size(); ++i) CHECK(std::abs(back[i] - y[i]) <= 0.5e-6 + 1e-12);
  CHECK(h.seq == 7);
  CHECK(h.command_seq == 65535);
  CHECK(h.t == doctest::Approx(12.34567).epsilon(1e-9));
}

TEST_CASE("outputs of a moving model survive the state frames") {
  classic::State s = classic::initial_state();
  for (int i = 0; i < 100; ++i) classic::step(s);
  classic::Outputs y;
  classic::outputs(s, y);
  check_state_round_trip<classic::can::StateFrames>(y, classic::can::pack_state, classic::can::unpack_state);
  check_state_round_trip<fd::can::StateFrames>(y, fd::can::pack_state, fd::can::unpack_state);
  classic::can::StateFrames frames;
  classic::can::pack_state(y, {}, frames);
  CHECK(frames.back().len == 4);  // 17 outputs: a lone last value
}

template <class Frames, class Pack, class Unpack>
void check_command_round_trip(Pack pack, Unpack unpack) {
  const double inf = std::numeric_limits<double>::infinity();
  using Inputs = std::array<double, 3>;
  for (const Inputs& u : {Inputs{1.5, -19.999999, 0.25}, Inputs{std::nan(""), inf, 3000.0}}) {
    Frames frames;
    pack(41, 40, u, frames);
    std::array<double, 3> back{};
    int inputs = 0;
    for (const canfd_frame& f : frames) {
      can::CommandPart p;
      REQUIRE(unpack(f, p) == can::FrameCheck::ok);
      CHECK(p.seq == 41);
      CHECK(p.state_seq == 40);
      for (int i = 0; i < p.count; ++i) back[static_cast<std::size_t>(p.first_input + i)] = p.values[static_cast<std::size_t>(i)];
      inputs += p.count;
    }
    CHECK(inputs == 3);
    for (std::size_t i = 0; i < 3; ++i) {
      if (std::isfinite(u[i]) && std::abs(u[i]) < 2147) CHECK(std::abs(back[i] - u[i]) <= 0.5e-6 + 1e-12);
      else CHECK(std::isnan(back[i]));
    }
  }
}

TEST_CASE("inputs survive the command frames; NaN, Inf and huge values arrive as NaN") {
  check_command_round_trip<classic::can::CommandFrames>(classic::can::pack_command, classic::can::unpack_command);
  check_command_round_trip<fd::can::CommandFrames>(fd::can::pack_command, fd::can::unpack_command);
}

TEST_CASE("a layout of many values spreads them over full frames, and they come back") {
  for (const bool is_fd : {false, true}) {
    const can::Layout l{is_fd, 40, 20};
    std::array<double, 40> y{}, y_back{};
    std::array<double, 20> u{}, u_back{};
    for (std::size_t i = 0; i < y.size(); ++i) y[i] = 0.001 * static_cast<double>(i) - 0.01;
    for (std::size_t i = 0; i < u.size(); ++i) u[i] = -0.5 * static_cast<double>(i);  // exact in the signals
    std::array<canfd_frame, 21> frames{};
    REQUIRE(l.state_frames() <= 21);
    can::pack_state(l, 0x100, y.data(), {}, frames.data());
    can::StateHeader h;
    for (int k = 0; k < l.state_frames(); ++k) {
      REQUIRE(can::unpack_state(l, 0x100, frames[static_cast<std::size_t>(k)], y_back.data(), h) == can::FrameCheck::ok);
    }
    for (std::size_t i = 0; i < y.size(); ++i) CHECK(std::abs(y_back[i] - y[i]) <= 0.5e-6 + 1e-12);
    REQUIRE(l.command_frames() <= 21);
    can::pack_command(l, 0x200, 1, 2, u.data(), frames.data());
    for (int k = 0; k < l.command_frames(); ++k) {
      can::CommandPart p;
      REQUIRE(can::unpack_command(l, 0x200, frames[static_cast<std::size_t>(k)], p) == can::FrameCheck::ok);
      for (int i = 0; i < p.count; ++i) u_back[static_cast<std::size_t>(p.first_input + i)] = p.values[static_cast<std::size_t>(i)];
    }
    CHECK(u_back == u);
    // 40 outputs: classic 1 + 20 frames; FD 14 in the header, then 16 and 10 (40 bytes -> 48).
    CHECK(l.state_frames() == (is_fd ? 3 : 21));
    CHECK(l.command_frames() == (is_fd ? 2 : 20));
    if (is_fd) CHECK(l.state_length(2) == 48);
  }
}

TEST_CASE("wrong length, the other kind of frame, remote frames, unknown and extended IDs are told apart") {
  classic::can::CommandFrames frames;
  classic::can::pack_command(1, 1, classic::Inputs{}, frames);
  can::CommandPart c;
  canfd_frame f = frames[0];
  f.len = 7;
  CHECK(classic::can::unpack_command(f, c) == can::FrameCheck::malformed);
  f = frames[0];
  f.flags = CANFD_FDF;  // a CAN FD frame where a classic one belongs
  CHECK(classic::can::unpack_command(f, c) == can::FrameCheck::malformed);
  f = frames[0];
  f.can_id |= CAN_RTR_FLAG;
  CHECK(classic::can::unpack_command(f, c) == can::FrameCheck::malformed);
  f = frames[0];
  f.can_id = classic::can::kCommandId + classic::kInputs;  // one past the last input
  CHECK(classic::can::unpack_command(f, c) == can::FrameCheck::unknown_id);
  f.can_id = classic::can::kCommandId | CAN_EFF_FLAG;
  CHECK(classic::can::unpack_command(f, c) == can::FrameCheck::unknown_id);
  f.can_id = classic::can::kStateId;  // a state frame is not a command
  CHECK(classic::can::unpack_command(f, c) == can::FrameCheck::unknown_id);

  classic::can::StateFrames state;
  classic::can::pack_state(classic::Outputs{}, {}, state);
  classic::Outputs y{};
  can::StateHeader h;
  state.back().len = 8;  // the lone last value has DLC 4
  CHECK(classic::can::unpack_state(state.back(), y, h) == can::FrameCheck::malformed);

  fd::can::CommandFrames fd_frames;
  fd::can::pack_command(1, 1, fd::Inputs{}, fd_frames);
  for (const int len : {12, 20, 64}) {  // CAN FD lengths, but not this frame's 16
    f = fd_frames[0];
    f.len = static_cast<std::uint8_t>(len);
    CHECK(fd::can::unpack_command(f, c) == can::FrameCheck::malformed);
  }
  f = fd_frames[0];
  f.flags = 0;  // a classic frame where a CAN FD one belongs
  CHECK(fd::can::unpack_command(f, c) == can::FrameCheck::malformed);
  f.can_id = fd::can::kCommandId + 1;  // the only command frame is kCommandId
  CHECK(fd::can::unpack_command(f, c) == can::FrameCheck::unknown_id);
}
