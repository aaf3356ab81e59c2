// The generated LCM messages: outputs and inputs survive packing, encoding,
// decoding and unpacking bit for bit, and what the HIL loop must count as
// malformed does not decode: another message type (fingerprint), a truncated
// message, trailing bytes.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "actuated_lcm.hpp"

namespace model = mbrt::models::actuated;

namespace {
template <class Message>
std::vector<unsigned char> encoded(const Message& m) {
  std::vector<unsigned char> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  REQUIRE(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())) == static_cast<int>(bytes.size()));
  return bytes;
}
}  // namespace

TEST_CASE("outputs of a moving model survive the state message") {
  model::State s = model::initial_state();
  for (int i = 0; i < 100; ++i) model::step(s);
  model::Outputs y, back;
  model::outputs(s, y);
  model::StateMessage m{}, received{};
  model::pack_outputs(y, m);
  const std::vector<unsigned char> bytes = encoded(m);
  REQUIRE(model::decode_exactly(bytes.data(), static_cast<int>(bytes.size()), received));
  model::unpack_outputs(received, back);
  CHECK(back == y);
  CHECK(received.wheel_pose[3] == y[model::output::wheel_pose + 3]);  // named fields, not positions
}

TEST_CASE("inputs survive the command message, NaN included") {
  const model::Inputs u{1.5, std::nan(""), -0.25};
  model::CommandMessage m{}, received{};
  model::pack_inputs(u, m);
  m.seq = 42;
  const std::vector<unsigned char> bytes = encoded(m);
  REQUIRE(model::decode_exactly(bytes.data(), static_cast<int>(bytes.size()), received));
  model::Inputs back{};
  model::unpack_inputs(received, back);
  CHECK(back[0] == 1.5);
  CHECK(std::isnan(back[1]));
  CHECK(back[2] == -0.25);
  CHECK(received.seq == 42);
}

TEST_CASE("another type, a truncated message or trailing bytes do not decode as a command") {
  model::CommandMessage command{};
  const std::vector<unsigned char> state = encoded(model::StateMessage{});
  CHECK(!model::decode_exactly(state.data(), static_cast<int>(state.size()), command));

  std::vector<unsigned char> bytes = encoded(model::CommandMessage{});
  CHECK(!model::decode_exactly(bytes.data(), static_cast<int>(bytes.size()) - 1, command));
  bytes.push_back(0);
  CHECK(!model::decode_exactly(bytes.data(), static_cast<int>(bytes.size()), command));
  bytes.pop_back();
  CHECK(model::decode_exactly(bytes.data(), static_cast<int>(bytes.size()), command));
}
