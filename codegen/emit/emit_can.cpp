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
  if (out.type == OutputType::contact_force) return "N";
  if (out.type == OutputType::contact_stuck) return "";
  if (out.joint < 0) {
    if (out.type == OutputType::body_pose) return k < 3 ? "m" : "";
    return k < 3 ? "m/s" : "rad/s";
  }
  const bool revolute = m.joints[static_cast<size_t>(out.joint)].type == JointType::revolute;
  if (out.type == OutputType::joint_stuck) return "";
  if (out.type == OutputType::joint_friction) return revolute ? "N m" : "N";
  if (out.type == OutputType::joint_position) return revolute ? "rad" : "m";
  return revolute ? "rad/s" : "m/s";
}

// One name per output value: the signal's name, suffixed _0.._n-1 when it has several.
std::vector<ValueName> output_values(const Model& m) {
  std::vector<ValueName> v;
  for (const Output& out : m.outputs) {
    const int n = type_row(out.type).values;
    for (int k = 0; k < n; ++k) v.push_back({n == 1 ? out.name : out.name + "_" + std::to_string(k), output_unit(m, out, k)});
  }
  return v;
}

const char* input_unit(const Input& in) { return in.type == InputType::joint_force ? "N" : "N m"; }

void check_fits(const Model& m, const mbrt::can::Layout& l) {
  if (l.state_frames() > kMaxFrames || l.command_frames() > kMaxFrames) {
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

// The attribute DBC tools read a frame's kind from (Vector CANdb++,
// cantools: a format ending in CAN_FD), defined as they define it:
// enumeration value 14 is StandardCAN_FD. BusType marks the bus as CAN FD.
constexpr const char* kFrameFormatDefinition =
    "BA_DEF_ BO_ \"VFrameFormat\" ENUM \"StandardCAN\",\"ExtendedCAN\",\"reserved\",\"J1939PG\",\"reserved\",\"reserved\","
    "\"reserved\",\"reserved\",\"reserved\",\"reserved\",\"reserved\",\"reserved\",\"reserved\",\"reserved\","
    "\"StandardCAN_FD\",\"ExtendedCAN_FD\";\n"
    "BA_DEF_ \"BusType\" STRING ;\n"
    "BA_DEF_DEF_ \"VFrameFormat\" \"StandardCAN\";\n"
    "BA_DEF_DEF_ \"BusType\" \"CAN\";\n"
    "BA_ \"BusType\" \"CAN FD\";\n";
constexpr int kStandardCanFd = 14;

std::string dbc(const Model& m, bool fd) {
  const std::vector<ValueName> values = output_values(m);
  const mbrt::can::Layout l{fd, static_cast<int>(values.size()), static_cast<int>(m.inputs.size())};
  check_fits(m, l);
  const double lo = -mbrt::can::kMaxValue, hi = mbrt::can::kMaxValue;
  std::ostringstream o;
  o << "VERSION \"\"\n\nNS_ :\n" << (fd ? "\tBA_DEF_\n\tBA_DEF_DEF_\n\tBA_\n" : "") << "\tVAL_\n\nBS_:\n\nBU_: mbrt controller\n\n";
  std::vector<unsigned> ids;
  for (int k = 0; k < l.state_frames(); ++k) {
    ids.push_back(kStateId + static_cast<unsigned>(k));
    o << "BO_ " << ids.back() << " " << m.name << (k == 0 ? "_state" : "_outputs_" + std::to_string(k - 1)) << ": "
      << int{l.state_length(k)} << " mbrt\n";
    if (k == 0) {
      o << signal("seq", 0, 16, false, "1", 0, 65535, "", "controller")
        << signal("command_seq", 16, 16, false, "1", 0, 65535, "", "controller")
        << signal("t", 32, 32, false, kTimeFactor, 0, 42949.67295, "s", "controller");
    }
    for (int i = 0; i < l.output_count(k); ++i) {
      const ValueName& v = values[static_cast<size_t>(l.first_output(k) + i)];
      o << signal(v.name, 8 * l.output_byte(k, i), 32, true, kValueFactor, lo, hi, v.unit, "controller");
    }
    o << "\n";
  }
  for (int k = 0; k < l.command_frames(); ++k) {
    ids.push_back(kCommandId + static_cast<unsigned>(k));
    // A frame of one input is named after it.
    const std::string name = l.input_count(k) == 1 ? m.inputs[static_cast<size_t>(l.first_input(k))].name : std::to_string(k);
    o << "BO_ " << ids.back() << " " << m.name << "_command_" << name << ": " << int{l.command_length(k)} << " controller\n"
      << signal("seq", 0, 16, false, "1", 0, 65535, "", "mbrt") << signal("state_seq", 16, 16, false, "1", 0, 65535, "", "mbrt");
    for (int i = 0; i < l.input_count(k); ++i) {
      const Input& in = m.inputs[static_cast<size_t>(l.first_input(k) + i)];
      o << signal(in.name, 8 * l.input_byte(i), 32, true, kValueFactor, in.min, in.max, input_unit(in), "mbrt");
    }
    o << "\n";
  }
  if (fd) {
    o << kFrameFormatDefinition;
    for (unsigned id : ids) o << "BA_ \"VFrameFormat\" BO_ " << id << " " << kStandardCanFd << ";\n";
  }
  // Raw INT32_MIN: no value (NaN, Inf or beyond the range).
  for (int k = 0; k < l.state_frames(); ++k) {
    for (int i = 0; i < l.output_count(k); ++i) {
      const ValueName& v = values[static_cast<size_t>(l.first_output(k) + i)];
      o << "VAL_ " << kStateId + k << " " << v.name << " -2147483648 \"invalid\" ;\n";
    }
  }
  for (int k = 0; k < l.command_frames(); ++k) {
    for (int i = 0; i < l.input_count(k); ++i) {
      const Input& in = m.inputs[static_cast<size_t>(l.first_input(k) + i)];
      o << "VAL_ " << kCommandId + k << " " << in.name << " -2147483648 \"invalid\" ;\n";
    }
  }
  return o.str();
}

std::string packing(const Model& m, bool fd) {
  std::ostringstream o;
  o << "// mbrt generated: model '" << m.name << "' Outputs and Inputs in " << (fd ? "CAN FD" : "classic CAN") << " frames, as "
    << m.name << ".dbc\n// describes (layout in mbrt/can_frames.hpp). Generated code: regenerate, do not edit.\n#pragma once\n\n"
    << "#include <array>\n\n#include <mbrt/can_frames.hpp>\n\n#include \"" << m.name << ".hpp\"\n\n"
    << "namespace mbrt::models::" << m.name << "::can {\n\n"
    << "inline constexpr canid_t kStateId = 0x" << std::hex << kStateId << ";    // then the output frames\n"
    << "inline constexpr canid_t kCommandId = 0x" << kCommandId << std::dec << ";  // then the further command frames\n"
    << "inline constexpr mbrt::can::Layout kLayout{" << (fd ? "true" : "false") << ", kOutputs, kInputs};\n"
    << "inline constexpr int kStateFrames = kLayout.state_frames();\n"
    << "inline constexpr int kCommandFrames = kLayout.command_frames();\n"
    << "using StateFrames = std::array<canfd_frame, kStateFrames>;\n"
    << "using CommandFrames = std::array<canfd_frame, kCommandFrames>;\n\n"
    << "inline void pack_state(const Outputs& y, const mbrt::can::StateHeader& h, StateFrames& f) noexcept {\n"
    << "  mbrt::can::pack_state(kLayout, kStateId, y.data(), h, f.data());\n}\n"
    << "inline mbrt::can::FrameCheck unpack_state(const canfd_frame& f, Outputs& y, mbrt::can::StateHeader& h) noexcept {\n"
    << "  return mbrt::can::unpack_state(kLayout, kStateId, f, y.data(), h);\n}\n"
    << "inline void pack_command(std::uint16_t seq, std::uint16_t state_seq, const Inputs& u, CommandFrames& f) noexcept {\n"
    << "  mbrt::can::pack_command(kLayout, kCommandId, seq, state_seq, u.data(), f.data());\n}\n"
    << "inline mbrt::can::FrameCheck unpack_command(const canfd_frame& f, mbrt::can::CommandPart& p) noexcept {\n"
    << "  return mbrt::can::unpack_command(kLayout, kCommandId, f, p);\n}\n\n"
    << "}  // namespace mbrt::models::" << m.name << "::can\n";
  return o.str();
}

}  // namespace

std::vector<GeneratedFile> emit_can(const Model& model, bool fd) {
  return {{model.name + ".dbc", dbc(model, fd)}, {model.name + "_can.hpp", packing(model, fd)}};
}

}  // namespace mbrt::codegen
