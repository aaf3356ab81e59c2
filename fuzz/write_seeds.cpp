// Writes the seed corpora of the message-decoder fuzzers, made by the
// encoders from valid messages (and a few each decoder must refuse), in the
// records each fuzzer reads:
//   write_seeds DIR  ->  DIR/<fuzzer>/seed-<k>
#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include <mbrt/rt/can_udp_wire.hpp>

#include "actuated_can.hpp"
#include "actuated_lcm.hpp"
#include "take_any_lcm_commands.hpp"

namespace model = mbrt::models::actuated;
using Bytes = std::vector<std::uint8_t>;

namespace {

template <class T>
void append(Bytes& out, const T& v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  out.insert(out.end(), p, p + sizeof v);
}

void write_corpus(const std::filesystem::path& dir, const std::vector<Bytes>& seeds) {
  std::filesystem::create_directories(dir);
  for (std::size_t k = 0; k < seeds.size(); ++k) {
    std::ofstream(dir / ("seed-" + std::to_string(k)), std::ios::binary)
        .write(reinterpret_cast<const char*>(seeds[k].data()), static_cast<std::streamsize>(seeds[k].size()));
  }
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Commands as the PD controller sends them, then ones the gate must refuse.
const std::array<model::Inputs, 4> kCommands{{{1.0, -3.0, 0.5}, {5.0, 20.0, -1.0}, {kNaN, 0.0, 0.0}, {0.0, 25.0, 0.0}}};

// The frames of the model's states and commands.
std::vector<canfd_frame> frames() {
  std::vector<canfd_frame> all;
  model::Outputs y{};
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = 0.1 * static_cast<double>(i) - 0.3;
  model::can::StateFrames state;
  model::can::pack_state(y, {7, 3, 0.007}, state);
  all.insert(all.end(), state.begin(), state.end());
  for (std::size_t k = 0; k < kCommands.size(); ++k) {
    model::can::CommandFrames command;
    model::can::pack_command(static_cast<std::uint16_t>(k), 7, kCommands[k], command);
    all.insert(all.end(), command.begin(), command.end());
  }
  return all;
}

// One datagram per frame, plus an extended and a remote frame.
std::vector<Bytes> can_udp_seeds() {
  std::vector<canfd_frame> all = frames();
  const mbrt::can::Layout fd{true, model::kOutputs, model::kInputs};
  all.push_back(mbrt::can::empty_frame(model::can::kLayout, 0x1234567 | CAN_EFF_FLAG, 3));
  all.push_back(mbrt::can::empty_frame(model::can::kLayout, model::can::kCommandId | CAN_RTR_FLAG, 0));
  all.push_back(mbrt::can::empty_frame(fd, model::can::kCommandId, 16));
  std::vector<Bytes> seeds;
  for (const canfd_frame& f : all) {
    std::uint8_t wire[mbrt::rt::kCanUdpMaxDatagram];
    seeds.emplace_back(wire, wire + mbrt::rt::encode_can_udp(f, 1.7e9, wire));
  }
  return seeds;
}

// All frames in one run, 1 ms apart, commands 2 ms old.
std::vector<Bytes> can_command_seeds() {
  Bytes run;
  for (const canfd_frame& f : frames()) {
    append<std::uint8_t>(run, 1);
    append<std::uint8_t>(run, 2);
    append(run, f);
  }
  return {run};
}

// The commands in one run, 1 ms apart, each answering a state 2 ms old,
// then a state message (another type) and a truncated command.
std::vector<Bytes> lcm_command_seeds() {
  Bytes run;
  const auto add = [&](const auto& message, int size) {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(message.getEncodedSize()));
    message.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    append<std::uint8_t>(run, 1);
    append(run, static_cast<std::uint8_t>(size));
    run.insert(run.end(), bytes.begin(), bytes.begin() + size);
  };
  model::CommandMessage m{};
  for (std::size_t k = 0; k < kCommands.size(); ++k) {
    model::pack_inputs(kCommands[k], m);
    m.seq = static_cast<std::int64_t>(k);
    m.utime = mbrt::fuzz::kLcmStartUs + 1000 * static_cast<std::int64_t>(k + 1);
    m.state_utime = m.utime - 2000;
    add(m, m.getEncodedSize());
  }
  add(model::StateMessage{}, model::StateMessage{}.getEncodedSize());
  add(m, m.getEncodedSize() - 1);
  return {run};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: write_seeds DIR\n");
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  write_corpus(dir / "can_udp_wire_fuzzer", can_udp_seeds());
  write_corpus(dir / "can_command_fuzzer", can_command_seeds());
  write_corpus(dir / "lcm_command_fuzzer", lcm_command_seeds());
  return 0;
}
