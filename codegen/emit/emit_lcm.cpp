#include "emit_lcm.hpp"

#include <sstream>

namespace mbrt::codegen {

namespace {

std::string package_of(const Model& m) { return m.name + "_lcm"; }

std::string signal_comment(const Model& m, const Output& out) {
  const std::string source = out.joint >= 0 ? m.joints[static_cast<size_t>(out.joint)].name : m.body_name(out.body);
  return std::string(type_row(out.type).name) + " of " + source;
}

std::string lcm_types(const Model& m) {
  std::ostringstream o;
  o << "// mbrt generated LCM types of model '" << m.name << "' from " << m.file_name() << ".\n"
    << "// Generated code: regenerate, do not edit.\n"
    << "package " << package_of(m) << ";\n\n"
    << "// The model's outputs, published by the HIL loop on " << state_channel(m) << ".\n"
    << "struct state_t\n{\n"
    << "    int64_t utime;        // wall clock when published, microseconds\n"
    << "    int64_t seq;          // cycle number\n"
    << "    int64_t command_seq;  // sequence number of the command in use; -1 on the safe values\n"
    << "    double t;             // simulation time, s\n";
  for (const Output& out : m.outputs) {
    const int n = type_row(out.type).values;
    o << "    double " << out.name << (n > 1 ? "[" + std::to_string(n) + "]" : "") << ";  // " << signal_comment(m, out)
      << "\n";
  }
  o << "}\n\n"
    << "// Commands for the model's inputs, read by the HIL loop on " << command_channel(m) << ".\n"
    << "struct command_t\n{\n"
    << "    int64_t utime;        // wall clock when sent, microseconds\n"
    << "    int64_t seq;          // increasing; restarts are accepted after the stale timeout\n"
    << "    int64_t state_utime;  // utime of the state message this command answers; its age counts from there\n";
  for (const Input& in : m.inputs) {
    o << "    double " << in.name << ";  // " << type_row(in.type).name << ", range [" << in.min << ", " << in.max
      << "], safe " << in.safe << "\n";
  }
  o << "}\n";
  return o.str();
}

std::string packing(const Model& m) {
  const std::string pkg = package_of(m);
  std::ostringstream o;
  o << "// mbrt generated: model '" << m.name << "' Outputs and Inputs to and from its LCM messages.\n"
    << "// Generated code: regenerate, do not edit.\n#pragma once\n\n#include <algorithm>\n\n"
    << "#include \"" << m.name << ".hpp\"\n#include \"" << pkg << "/command_t.hpp\"\n#include \"" << pkg
    << "/state_t.hpp\"\n\nnamespace mbrt::models::" << m.name << " {\n\n"
    << "using StateMessage = " << pkg << "::state_t;\nusing CommandMessage = " << pkg << "::command_t;\n"
    << "inline constexpr const char* kStateChannel = \"" << state_channel(m) << "\";\n"
    << "inline constexpr const char* kCommandChannel = \"" << command_channel(m) << "\";\n\n";
  const auto copy = [&](const std::string& signature, bool to_message, bool outputs) {
    o << "inline void " << signature << " noexcept {\n";
    if (outputs) {
      for (const Output& out : m.outputs) {
        const std::string field = "m." + out.name, value = "y[output::" + out.name + "]";
        const int n = type_row(out.type).values;
        if (n == 1) {
          o << "  " << (to_message ? field + " = " + value : value + " = " + field) << ";\n";
        } else if (to_message) {
          o << "  std::copy_n(y.data() + output::" << out.name << ", " << n << ", " << field << ");\n";
        } else {
          o << "  std::copy_n(" << field << ", " << n << ", y.data() + output::" << out.name << ");\n";
        }
      }
    } else {
      for (const Input& in : m.inputs) {
        const std::string field = "m." + in.name, value = "u[input::" + in.name + "]";
        o << "  " << (to_message ? field + " = " + value : value + " = " + field) << ";\n";
      }
    }
    o << "}\n\n";
  };
  o << "// Decodes a whole message: false for another type (fingerprint), a\n"
    << "// truncated message or trailing bytes.\n"
    << "template <class Message>\n"
    << "inline bool decode_exactly(const void* data, int size, Message& m) noexcept {\n"
    << "  return m.decode(data, 0, size) == size;\n}\n\n";
  copy("pack_outputs(const Outputs& y, StateMessage& m)", true, true);
  copy("unpack_outputs(const StateMessage& m, Outputs& y)", false, true);
  copy("pack_inputs(const Inputs& u, CommandMessage& m)", true, false);
  copy("unpack_inputs(const CommandMessage& m, Inputs& u)", false, false);
  o << "}  // namespace mbrt::models::" << m.name << "\n";
  return o.str();
}

}  // namespace

std::string state_channel(const Model& model) { return model.name + "_STATE"; }
std::string command_channel(const Model& model) { return model.name + "_COMMAND"; }

std::vector<GeneratedFile> emit_lcm(const Model& model) {
  return {{model.name + ".lcm", lcm_types(model)}, {model.name + "_lcm.hpp", packing(model)}};
}

}  // namespace mbrt::codegen
