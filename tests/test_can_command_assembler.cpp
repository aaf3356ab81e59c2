// Whole commands from CAN command frames: complete only when every input's
// frame of one sequence number has arrived, in any order (one input per
// frame in classic CAN, several in CAN FD); a repeated frame
// does not complete a command; a new sequence number starts over; a repeated
// whole command is assembled again (for the gate to call a duplicate); and
// 16-bit sequence numbers unwrap across 65535 -> 0.
#include <doctest/doctest.h>

#include <array>

#include <mbrt/rt/can_command_assembler.hpp>

using mbrt::can::CommandPart;
using mbrt::rt::CanCommandAssembler;
using mbrt::rt::unwrap16;

namespace {
// A classic CAN command frame's content: one input.
CommandPart one(int input, std::uint16_t seq, std::uint16_t state_seq, double value) {
  CommandPart p;
  p.first_input = input;
  p.count = 1;
  p.seq = seq;
  p.state_seq = state_seq;
  p.values[0] = value;
  return p;
}
}  // namespace

TEST_CASE("unwrap16 picks the counter nearest the last one") {
  CHECK(unwrap16(0, 0) == 0);
  CHECK(unwrap16(10, 12) == 12);
  CHECK(unwrap16(10, 8) == 8);
  CHECK(unwrap16(65535, 0) == 65536);
  CHECK(unwrap16(65536 + 5, 65534) == 65534);
  CHECK(unwrap16(3 * 65536 + 100, 99) == 3 * 65536 + 99);
}

TEST_CASE("a command is whole when each input's frame of one sequence number arrived") {
  CanCommandAssembler<3> a;
  CHECK(!a.add(one(2, 7, 5, 2.0)));
  CHECK(!a.add(one(0, 7, 5, 0.5)));
  CHECK(!a.add(one(0, 7, 5, 9.0)));  // repeated frame: neither completes nor overwrites
  CHECK(a.add(one(1, 7, 5, 1.0)));
  CHECK(a.sequence() == 7);
  CHECK(a.state_seq() == 5);
  CHECK(a.values() == std::array<double, 3>{0.5, 1.0, 2.0});
  // The same command again is assembled again.
  CHECK(!a.add(one(0, 7, 5, 0.5)));
  CHECK(!a.add(one(1, 7, 5, 1.0)));
  CHECK(a.add(one(2, 7, 5, 2.0)));
  CHECK(a.sequence() == 7);
}

TEST_CASE("a frame of another sequence number drops the unfinished command") {
  CanCommandAssembler<2> a;
  CHECK(!a.add(one(0, 1, 0, 1.0)));
  CHECK(!a.add(one(0, 2, 1, 2.0)));  // command 1 never completes
  CHECK(!a.add(one(1, 1, 0, 1.0)));  // a late frame of command 1 starts it over
  CHECK(!a.add(one(1, 2, 1, 2.0)));
  CHECK(a.add(one(0, 2, 1, 2.0)));
  CHECK(a.sequence() == 2);
}

TEST_CASE("sequence numbers unwrap across 65535 -> 0") {
  CanCommandAssembler<1> a;
  for (long seq = 0; seq < 70000; seq += 1000) {
    REQUIRE(a.add(one(0, static_cast<std::uint16_t>(seq), 0, 0.0)));
    CHECK(a.sequence() == seq);
  }
}

TEST_CASE("a CAN FD frame carries several inputs; the command is whole when all its frames arrived") {
  CanCommandAssembler<17> a;  // 15 inputs in the first frame, 2 in the second
  CommandPart first;
  first.count = 15;
  first.seq = 3;
  first.state_seq = 2;
  for (int i = 0; i < 15; ++i) first.values[static_cast<std::size_t>(i)] = i;
  CommandPart second = first;
  second.first_input = 15;
  second.count = 2;
  second.values = {15.0, 16.0};
  CHECK(!a.add(second));
  CHECK(!a.add(second));  // repeated: does not count twice
  CHECK(a.add(first));
  for (int i = 0; i < 17; ++i) CHECK(a.values()[static_cast<std::size_t>(i)] == i);
}
