#include "flop_count.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <regex>
#include <sstream>
#include <stdexcept>

#include <sys/wait.h>
#include <unistd.h>

#include "shell_quote.hpp"

namespace fs = std::filesystem;

namespace mbrt::codegen {

namespace {

bool starts_with(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// Executed instructions per (object file, address).
using Executed = std::map<std::string, std::map<unsigned long, double>>;

// Reads a callgrind profile written with --dump-instr=yes --dump-line=no
// --compress-pos=no --compress-strings=no: cost lines are "0xADDRESS COUNT";
// the line after "calls=" is a call's inclusive cost and is left out.
Executed read_profile(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read callgrind output " + file.string());
  Executed executed;
  std::string object, line;
  bool call_cost = false;
  while (std::getline(in, line)) {
    if (starts_with(line, "ob=")) object = line.substr(3);
    else if (starts_with(line, "calls=")) call_cost = true;
    else if (starts_with(line, "0x")) {
      if (!call_cost) {
        std::istringstream cost(line);
        std::string address;
        double count = 0.0;
        cost >> address >> count;
        executed[object][std::stoul(address, nullptr, 16)] += count;
      }
      call_cost = false;
    }
  }
  return executed;
}

Executed profile(const std::string& executable, double h, int steps, const fs::path& dir) {
  char t_end[64];
  std::snprintf(t_end, sizeof t_end, "%.17g", steps * h);
  const fs::path out = dir / ("callgrind." + std::to_string(steps));
  const std::string cmd = "valgrind --tool=callgrind --dump-instr=yes --dump-line=no --compress-pos=no "
                          "--compress-strings=no --callgrind-out-file=" + shell_quote(out.string()) + " " +
                          shell_quote(executable) + " --t-end " + t_end + " --every 1000000000 --serial > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  if (status != 0) {
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code == 127) throw std::runtime_error("valgrind not found: the report counts instructions with it (install valgrind)");
    throw std::runtime_error("the counting run under valgrind failed (exit " + std::to_string(code) + ", " + t_end +
                             " s of the model; does it diverge at its step? try mbrt sim MODEL --t-end " + t_end +
                             "): " + cmd);
  }
  return read_profile(out);
}

// Floating-point operations per instruction address of one object file.
std::map<unsigned long, int> flops_by_address(const std::string& object) {
  const std::string cmd = "objdump -d --no-show-raw-insn " + shell_quote(object) + " 2>/dev/null";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  if (!pipe) throw std::runtime_error("cannot run objdump");
  static const std::regex instruction(R"(^\s*([0-9a-f]+):\s+(\S+)\s*(\S*))");
  std::map<unsigned long, int> flops;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe.get())) {
    std::cmatch m;
    if (!std::regex_search(buffer, m, instruction)) continue;
    if (const int f = flops_of_instruction(m[2].str(), m[3].str()); f > 0) flops[std::stoul(m[1].str(), nullptr, 16)] = f;
  }
  return flops;
}

}  // namespace

int flops_of_instruction(const std::string& mnemonic, const std::string& operands) {
  std::string op = starts_with(mnemonic, "v") ? mnemonic.substr(1) : mnemonic;
  const bool fused = starts_with(op, "fmadd") || starts_with(op, "fmsub") || starts_with(op, "fnmadd") ||
                     starts_with(op, "fnmsub");
  if (fused) {
    op = op.substr(op.size() - 2);  // fmadd231sd -> sd
  } else {
    static const char* const kArithmetic[] = {"add", "sub", "mul", "div", "sqrt", "hadd", "hsub"};
    bool arithmetic = false;
    for (const char* a : kArithmetic) {
      const std::string name = a;
      if (op == name + "sd" || op == name + "pd") arithmetic = true;
    }
    if (!arithmetic) return 0;
    op = op.substr(op.size() - 2);
  }
  const int lanes = op == "sd" ? 1 : operands.find("%ymm") != std::string::npos ? 4 : 2;
  return fused ? 2 * lanes : lanes;
}

StepCount count_step(const std::string& executable, double h, int steps) {
  const fs::path dir = fs::temp_directory_path() / ("mbrt-count-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Executed one, two;
  try {
    one = profile(executable, h, steps, dir);
    two = profile(executable, h, 2 * steps, dir);
  } catch (...) {
    fs::remove_all(dir);
    throw;
  }
  fs::remove_all(dir);
  StepCount c;
  for (const auto& [object, counts] : two) {
    const bool on_disk = fs::exists(object);
    const std::map<unsigned long, int> flops = on_disk ? flops_by_address(object) : std::map<unsigned long, int>{};
    const auto& before = one[object];
    for (const auto& [address, count] : counts) {
      const auto b = before.find(address);
      const double extra = count - (b == before.end() ? 0.0 : b->second);
      c.instructions += extra;
      if (const auto f = flops.find(address); f != flops.end()) c.flops += extra * f->second;
    }
  }
  c.flops /= steps;
  c.instructions /= steps;
  return c;
}

}  // namespace mbrt::codegen
