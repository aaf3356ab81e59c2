#include "sim_runner.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "shell_quote.hpp"
#include "toolchain.hpp"

namespace fs = std::filesystem;

namespace mbrt::codegen {

namespace {

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// FNV-1a, 64 bit: a content key for the cache, not a security measure.
std::uint64_t fnv1a(const std::string& text, std::uint64_t h = 1469598103934665603ull) {
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

fs::path cache_root(const SimOptions& o) {
  if (!o.cache_dir.empty()) return o.cache_dir;
  if (const char* d = std::getenv("MBRT_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return fs::path(d) / "mbrt";
  if (const char* d = std::getenv("HOME"); d && *d) return fs::path(d) / ".cache" / "mbrt";
  return fs::temp_directory_path() / "mbrt-cache";
}

// Runtime headers and program sources: the installed layout next to this
// executable (<prefix>/bin/mbrt, <prefix>/include, <prefix>/share/mbrt) when
// present, else the source tree it was built from.
struct Sources {
  std::vector<fs::path> includes;
  fs::path sim_driver;
  fs::path rt;        // the rt/ library sources and hil_driver.cpp
  fs::path stub;      // hil_stub/pd_controller.cpp
  fs::path python;    // holds the Python package mbrt (python/mbrt)
};

Sources sources() {
  std::error_code ec;
  const fs::path prefix = fs::read_symlink("/proc/self/exe", ec).parent_path().parent_path();
  const fs::path share = prefix / "share" / "mbrt";
  if (!ec && fs::exists(share / "sim_driver.cpp") && fs::exists(prefix / "include" / "mbrt")) {
    return {{prefix / "include"}, share / "sim_driver.cpp", share / "rt", share / "hil_stub" / "pd_controller.cpp",
            share / "python"};
  }
  const fs::path root = toolchain::kSourceRoot;
  return {{root / "include", root / "rt" / "include"}, root / "codegen" / "sim" / "sim_driver.cpp", root / "rt",
          root / "hil_stub" / "pd_controller.cpp", root / "python"};
}

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ';');) out.push_back(item);
  return out;
}

// What a program is built from: the rt/ library's sources (compiled once
// into the cache and shared by every program of every model), the sources
// compiled with the generated model, and whether the program speaks LCM
// (then lcm-gen runs on the model's types first).
struct ProgramPlan {
  const char* executable;
  std::vector<fs::path> runtime;
  std::vector<fs::path> sources;
  bool lcm;
};

ProgramPlan plan(Program program) {
  const Sources src = sources();
  if (program == Program::sim) return {"sim", {}, {src.sim_driver}, false};
  std::vector<fs::path> runtime;
  for (const std::string& f : split(toolchain::kRtSources)) runtime.push_back(src.rt / f);
  return {program == Program::hil ? "hil" : "pd_controller", runtime,
          {program == Program::hil ? src.rt / "hil_driver.cpp" : src.stub}, true};
}

std::string compile_flags(const ProgramPlan& p) {
  std::string flags = toolchain::kFlags;
#if defined(__x86_64__)
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) flags += std::string(" ") + toolchain::kVectorFlags;
#endif
  // lcm_coretypes.h reads doubles through int64_t pointers: with strict
  // aliasing, optimized builds encode stale bytes.
  if (p.lcm) flags += " -fno-strict-aliasing";
  return flags;
}

// Compiler, flags and the runtime headers: what every object depends on
// besides its own source.
std::uint64_t toolchain_key(const ProgramPlan& p) {
  std::uint64_t h = fnv1a(std::string(toolchain::kCompiler) + compile_flags(p));
  for (const fs::path& dir : sources().includes) {
    for (const auto& e : fs::recursive_directory_iterator(dir / "mbrt")) {
      if (e.is_regular_file()) h = fnv1a(e.path().filename().string() + read_file(e.path()), h);
    }
  }
  return h;
}

std::string hex(std::uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

// Everything the executable depends on: generated code, program sources,
// runtime headers, the compile command and LCM's library.
std::string content_key(const GeneratedCode& code, const ProgramPlan& p) {
  std::uint64_t h = fnv1a(code.header, toolchain_key(p));
  h = fnv1a(code.source, h);
  for (const GeneratedFile& f : code.interface_files) h = fnv1a(f.name + f.text, h);
  for (const fs::path& f : p.runtime) h = fnv1a(f.string() + read_file(f), h);
  for (const fs::path& f : p.sources) h = fnv1a(f.string() + read_file(f), h);
  if (p.lcm) h = fnv1a(toolchain::kLcmLibrary, h);
  return hex(h);
}

std::string include_flags() {
  std::string flags;
  for (const fs::path& inc : sources().includes) flags += " -I" + shell_quote(inc.string());
  return flags + " -I" + shell_quote(toolchain::kEigenInclude);
}

void run_or_throw(const std::string& cmd, const std::string& what, const fs::path& log, bool verbose) {
  if (verbose) std::fprintf(stderr, "%s: %s\n", what.c_str(), cmd.c_str());
  if (std::system((cmd + " 2> " + shell_quote(log.string())).c_str()) != 0) {
    throw std::runtime_error(what + " failed; see " + log.string());
  }
}

// The rt/ library's objects, each compiled once per compiler, flags, source
// and runtime headers into <cache>/rt and linked into every program after:
// they take most of a HIL program's compile (command-line options and JSON
// reports: 30 s of CPU of about 40), and do not depend on the model.
std::vector<fs::path> runtime_objects(const ProgramPlan& p, const SimOptions& options) {
  const fs::path dir = cache_root(options) / "rt";
  const std::uint64_t base = toolchain_key(p);
  std::vector<fs::path> objects;
  for (const fs::path& f : p.runtime) {
    const fs::path object = dir / (f.stem().string() + "-" + hex(fnv1a(read_file(f), base)) + ".o");
    if (!fs::exists(object)) {
      fs::create_directories(dir);
      if (!options.verbose) std::fprintf(stderr, "compiling %s (cached in %s)\n", f.filename().c_str(), dir.c_str());
      // A private name, then rename: concurrent builds never link a half-written object.
      const std::string tmp = object.string() + ".tmp" + std::to_string(::getpid());
      run_or_throw(std::string(toolchain::kCompiler) + " " + compile_flags(p) + include_flags() + " -c " +
                       shell_quote(f.string()) + " -o " + shell_quote(tmp),
                   "compiling " + f.string(), tmp + ".log", options.verbose);
      fs::rename(tmp, object);
      fs::remove(tmp + ".log");
    }
    objects.push_back(object);
  }
  return objects;
}

}  // namespace

std::string build_program(Program program, const Generated& g, const SimOptions& options) {
  const ProgramPlan p = plan(program);
  if (p.lcm && (g.model.inputs.empty() || g.model.outputs.empty())) {
    throw ModelError({g.model.file, 0, 0}, "inputs",
                     "model '" + g.model.name + "' needs both inputs and outputs to run in a HIL loop");
  }
  const fs::path dir = cache_root(options) / (g.model.name + "-" + p.executable + "-" + content_key(g.code, p));
  const fs::path exe = dir / p.executable;
  if (fs::exists(exe)) return exe.string();
  // Build in a private temporary directory, then rename: concurrent runs
  // and interrupted builds never leave a half-written executable.
  const fs::path tmp = dir.string() + ".tmp" + std::to_string(::getpid());
  fs::create_directories(tmp);
  write_generated(g.code, tmp.string());
  const std::vector<fs::path> objects = runtime_objects(p, options);
  std::string cmd = std::string(toolchain::kCompiler) + " " + compile_flags(p) + " -I" + shell_quote(tmp.string());
  cmd += include_flags() + " -DMBRT_MODEL_NAMESPACE=mbrt::models::" + g.model.name;
  if (!g.model.tunable.empty()) cmd += " -DMBRT_MODEL_PARAMETERS";  // --set KEY=VALUE (docs/parameters.md)
  if (!g.model.outputs.empty()) cmd += " -DMBRT_MODEL_OUTPUTS";      // --outputs
  if (p.lcm) {
    run_or_throw(std::string(toolchain::kLcmGen) + " -x --cpp-hpath " + shell_quote(tmp.string()) + " " +
                     shell_quote((tmp / (g.model.name + ".lcm")).string()),
                 "lcm-gen", tmp / "lcm-gen.log", options.verbose);
    cmd += " -DMBRT_MODEL_LCM_HEADER='\"" + g.model.name + "_lcm.hpp\"' -DMBRT_MODEL_CAN_HEADER='\"" + g.model.name +
           "_can.hpp\"'";
  } else {
    cmd += " -DMBRT_MODEL_HEADER='\"" + g.code.header_name + "\"'";
  }
  cmd += " " + shell_quote((tmp / g.code.source_name).string());
  for (const fs::path& f : p.sources) cmd += " " + shell_quote(f.string());
  for (const fs::path& o : objects) cmd += " " + shell_quote(o.string());
  cmd += " -o " + shell_quote((tmp / p.executable).string());
  if (p.lcm) cmd += std::string(" ") + toolchain::kLcmLibrary;
  if (!options.verbose) std::fprintf(stderr, "compiling %s %s (cached in %s)\n", g.model.name.c_str(), p.executable, dir.string().c_str());
  run_or_throw(cmd, "compiling the generated model", tmp / "compile.log", options.verbose);
  std::error_code ec;
  fs::rename(tmp, dir, ec);
  if (ec) fs::remove_all(tmp);  // another run finished first; use its result
  return exe.string();
}

std::string python_package_dir() { return sources().python.string(); }

int run_program(Program program, const Generated& g, const SimOptions& options) {
  std::string cmd = shell_quote(build_program(program, g, options));
  for (const std::string& a : options.driver_args) cmd += " " + shell_quote(a);
  std::fflush(stdout);
  const int rc = std::system(cmd.c_str());
  if (rc == -1) throw std::runtime_error("cannot start " + cmd);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : 1;
}

}  // namespace mbrt::codegen
