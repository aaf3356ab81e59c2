#include "sim_runner.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <sys/wait.h>
#include <unistd.h>

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

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

fs::path cache_root(const SimOptions& o) {
  if (!o.cache_dir.empty()) return o.cache_dir;
  if (const char* d = std::getenv("MBRT_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return fs::path(d) / "mbrt";
  if (const char* d = std::getenv("HOME"); d && *d) return fs::path(d) / ".cache" / "mbrt";
  return fs::temp_directory_path() / "mbrt-cache";
}

// Runtime headers and driver: the installed layout next to this executable
// (<prefix>/bin/mbrt, <prefix>/include, <prefix>/share/mbrt) when present,
// else the source tree it was built from.
struct Sources {
  fs::path include;
  fs::path driver;
};

Sources sources() {
  std::error_code ec;
  const fs::path prefix = fs::read_symlink("/proc/self/exe", ec).parent_path().parent_path();
  if (!ec && fs::exists(prefix / "share" / "mbrt" / "sim_driver.cpp") && fs::exists(prefix / "include" / "mbrt")) {
    return {prefix / "include", prefix / "share" / "mbrt" / "sim_driver.cpp"};
  }
  return {toolchain::kRuntimeInclude, toolchain::kDriverSource};
}

std::string compile_flags() {
  std::string flags = toolchain::kFlags;
#if defined(__x86_64__)
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) flags += std::string(" ") + toolchain::kVectorFlags;
#endif
  return flags;
}

// Everything the executable depends on: generated code, driver, runtime
// headers and the compile command.
std::string content_key(const GeneratedCode& code) {
  std::uint64_t h = fnv1a(code.header);
  h = fnv1a(code.source, h);
  h = fnv1a(read_file(sources().driver), h);
  h = fnv1a(std::string(toolchain::kCompiler) + compile_flags(), h);
  for (const auto& e : fs::directory_iterator(sources().include / "mbrt")) {
    h = fnv1a(e.path().filename().string() + read_file(e.path()), h);
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace

std::string build_simulator(const Generated& g, const SimOptions& options) {
  const fs::path dir = cache_root(options) / (g.model.name + "-" + content_key(g.code));
  const fs::path exe = dir / "sim";
  if (fs::exists(exe)) return exe.string();
  // Build in a private temporary directory, then rename: concurrent runs
  // and interrupted builds never leave a half-written executable.
  const fs::path tmp = dir.string() + ".tmp" + std::to_string(::getpid());
  fs::create_directories(tmp);
  write_generated(g.code, tmp.string());
  const Sources src = sources();
  const std::string cmd = std::string(toolchain::kCompiler) + " " + compile_flags() + " -I" +
                          quote(tmp.string()) + " -I" + quote(src.include.string()) + " -I" +
                          quote(toolchain::kEigenInclude) + " -DMBRT_MODEL_HEADER='\"" + g.code.header_name +
                          "\"' -DMBRT_MODEL_NAMESPACE=mbrt::models::" + g.model.name + " " +
                          quote((tmp / g.code.source_name).string()) + " " + quote(src.driver.string()) +
                          " -o " + quote((tmp / "sim").string()) + " 2> " + quote((tmp / "compile.log").string());
  if (options.verbose) std::fprintf(stderr, "compiling: %s\n", cmd.c_str());
  else std::fprintf(stderr, "compiling %s (cached in %s)\n", g.model.name.c_str(), dir.string().c_str());
  if (std::system(cmd.c_str()) != 0) {
    throw std::runtime_error("compiling the generated model failed; see " + (tmp / "compile.log").string());
  }
  std::error_code ec;
  fs::rename(tmp, dir, ec);
  if (ec) fs::remove_all(tmp);  // another run finished first; use its result
  return exe.string();
}

int run_simulation(const std::string& model_path, const SimOptions& options) {
  const Generated g = generate(model_path, options.generate);
  std::string cmd = quote(build_simulator(g, options));
  for (const std::string& a : options.driver_args) cmd += " " + quote(a);
  std::fflush(stdout);
  const int rc = std::system(cmd.c_str());
  if (rc == -1) throw std::runtime_error("cannot start the simulator");
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : 1;
}

}  // namespace mbrt::codegen
