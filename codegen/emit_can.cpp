#include "emit_can.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

#include <mbrt/can_frames.hpp>

#include "model.hpp"

namespace mbrt::codegen {

namespace {

// Standard 11-bit IDs: states and outputs from 0x100, commands from 0x200.
constexpr unsigned kStateId = 0x100;
constexpr unsigned kCommandId = 0x200;
constexpr int kMaxFrames = 0x100;

struct ValueName {
  std::string name, unit;
};

std::string output_unit(const Model& m, const Output& out, int k) {
  if (out.joint < 0) {
    if (out.type == OutputType::body_pose) return k < 3 ? "m" : "";
    return k < 3 ? "m/s" : "rad/s";
  }
  const bool revolute = m.joints[static_cast<size_t>(out.joint)].type == JointType::revolute;
  if (out.type == OutputType::joint_position) return revolute ? "rad" : "m";
  return revolute ? "rad/s" : "m/s";
}

// One name per output value: the signal's name, suffixed _0.._n-1 when it has several.
std::vector<ValueName> output_values(const Model& m) {
  std::vector<ValueName> v;
  for (const Output& out : m.outputs) {
    const int n = output_count(out.type);
    for (int k = 0; k < n; ++k) v.push_back({n == 1 ? out.name : out.name + "_" + std::to_string(k), output_unit(m, out, k)});
  }
  return v;
}

const char* input_unit(const Input& in) { return in.type == InputType::joint_force ? "N" : "N m"; }

void check_fits(const Model& m, int output_frames) {
  if (1 + output_frames > kMaxFrames || static_cast<int>(m.inputs.size()) > kMaxFrames) {
    throw ModelError({m.file, 0, 0}, "outputs", "too many outputs or inputs for the CAN layout (256 frames each)");
  }
  for (const Input& in : m.inputs) {
    if (std::abs(in.min) > mbrt::can::kMaxValue || std::abs(in.max) > mbrt::can::kMaxValue) {
      throw ModelError(in.where, "inputs",
                       "input '" + in.name + "': limits beyond +-2147.483647 do not fit the CAN layout's int32 signals");
    }
  }
}

// Factors as decimals: DBC readers parse them exactly as the C++ constants.
constexpr const char* kValueFactor = "0.000001";
constexpr const char* kTimeFactor = "0.00001";

std::string signal(const std::string& name, int start, int bits, bool is_signed, const char* factor, double min,
                   double max, const std::string& unit, const char* receiver) {
  std::ostringstream o;
  o << std::setprecision(10) << " SG_ " << name << " : " << start << "|" << bits << "@1" << (is_signed ? "-" : "+") << " (" << factor << ",0) ["
    << min << "|" << max << "] \"" << unit << "\" " << receiver << "\n";
  return o.str();
}

std::string dbc(const Model& m) {
  const std::vector<ValueName> values = output_values(m);
  const int output_frames = static_cast<int>((values.size() + 1) / 2);
  check_fits(m, output_frames);
  const double lo = -mbrt::can::kMaxValue, hi = mbrt::can::kMaxValue;
  std::ostringstream o;
  o << "VERSION \"\"\n\nNS_ :\n\tVAL_\n\nBS_:\n\nBU_: mbrt controller\n\n";
  o << "BO_ " << kStateId << " " << m.name << "_state: 8 mbrt\n"
    << signal("seq", 0, 16, false, "1", 0, 65535, "", "controller")
    << signal("command_seq", 16, 16, false, "1", 0, 65535, "", "controller")
    << signal("t", 32, 32, false, kTimeFactor, 0, 42949.67295, "s", "controller") << "\n";
  for (int k = 0; k < output_frames; ++k) {
    const size_t first = 2 * static_cast<size_t>(k);
    const bool pair = first + 1 < values.size();
    o << "BO_ " << kStateId + 1 + k << " " << m.name << "_outputs_" << k << ": " << (pair ? 8 : 4) << " mbrt\n";
    for (size_t i = first; i < first + (pair ? 2 : 1); ++i) {
      o << signal(values[i].name, 32 * static_cast<int>(i - first), 32, true, kValueFactor, lo, hi,
                  values[i].unit, "controller");
    }
    o << "\n";
  }
  for (size_t i = 0; i < m.inputs.size(); ++i) {
    const Input& in = m.inputs[i];
    o << "BO_ " << kCommandId + i << " " << m.name << "_command_" << in.name << ": 8 controller\n"
      << signal("seq", 0, 16, false, "1", 0, 65535, "", "mbrt") << signal("state_seq", 16, 16, false, "1", 0, 65535, "", "mbrt")
      << signal(in.name, 32, 32, true, kValueFactor, in.min, in.max, input_unit(in), "mbrt") << "\n";
  }
  // Raw INT32_MIN: no value (NaN, Inf or beyond the range).
  for (int k = 0; k < output_frames; ++k) {
    for (size_t i = 2 * static_cast<size_t>(k); i < values.size() && i < 2 * static_cast<size_t>(k) + 2; ++i) {
      o << "VAL_ " << kStateId + 1 + k << " " << values[i].name << " -2147483648 \"invalid\" ;\n";
    }
  }
  for (size_t i = 0; i < m.inputs.size(); ++i) {
    o << "VAL_ " << kCommandId + i << " " << m.inputs[i].name << " -2147483648 \"invalid\" ;\n";
  }
  return o.str();
}

std::string packing(const Model& m) {
  std::ostringstream o;
  o << "// mbrt generated: model '" << m.name << "' Outputs and Inputs in CAN frames, as " << m.name << ".dbc\n"
    << "// describes (layout in mbrt/can_frames.hpp). Generated code: regenerate, do not edit.\n#pragma once\n\n"
    << "#include <array>\n\n#include <mbrt/can_frames.hpp>\n\n#include \"" << m.name << ".hpp\"\n\n"
    << "namespace mbrt::models::" << m.name << "::can {\n\n"
    << "inline constexpr canid_t kStateId = 0x" << std::hex << kStateId << ";    // then the output frames\n"
    << "inline constexpr canid_t kCommandId = 0x" << kCommandId << std::dec << ";  // + input index\n"
    << "inline constexpr int kStateFrames = 1 + mbrt::can::output_frames<kOutputs>;\n"
    << "using StateFrames = std::array<can_frame, kStateFrames>;\n"
    << "using CommandFrames = std::array<can_frame, kInputs>;\n\n"
    << "inline void pack_state(const Outputs& y, const mbrt::can::StateHeader& h, StateFrames& f) noexcept {\n"
    << "  mbrt::can::pack_state(kStateId, y, h, f);\n}\n"
    << "inline mbrt::can::FrameCheck unpack_state(const can_frame& f, Outputs& y, mbrt::can::StateHeader& h) noexcept {\n"
    << "  return mbrt::can::unpack_state(kStateId, f, y, h);\n}\n"
    << "inline void pack_command(std::uint16_t seq, std::uint16_t state_seq, const Inputs& u, CommandFrames& f) noexcept {\n"
    << "  mbrt::can::pack_command(kCommandId, seq, state_seq, u, f);\n}\n"
    << "inline mbrt::can::FrameCheck unpack_command(const can_frame& f, mbrt::can::CommandSignal& s) noexcept {\n"
    << "  return mbrt::can::unpack_command<kInputs>(kCommandId, f, s);\n}\n\n"
    << "}  // namespace mbrt::models::" << m.name << "::can\n";
  return o.str();
}

}  // namespace

std::vector<GeneratedFile> emit_can(const Model& model) {
  return {{model.name + ".dbc", dbc(model)}, {model.name + "_can.hpp", packing(model)}};
}

}  // namespace mbrt::codegen
