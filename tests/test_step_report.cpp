// `mbrt gen --report`: the counting of floating-point operations, checked on
// a program with a known count, and the report of a model, specialized and
// general: its fields, and that the specializations make the step do less.
#include <doctest/doctest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include "flop_count.hpp"

namespace fs = std::filesystem;
using mbrt::codegen::flops_of_instruction;

namespace {

std::string run(const std::string& args) {
  const fs::path dir = fs::path(MBRT_TEST_WORK_DIR);
  fs::create_directories(dir);
  const std::string cmd = "MBRT_CACHE_DIR='" + (dir / "cache").string() + "' '" + MBRT_EXE + "' " + args +
                          " -o '" + (dir / "gen").string() + "' 2>/dev/null";
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), p)) out.append(buf.data(), n);
  REQUIRE(pclose(p) == 0);
  return out;
}

// The number after "key": in a one-level JSON object.
double number(const std::string& json, const std::string& key) {
  const size_t at = json.find("\"" + key + "\": ");
  REQUIRE_MESSAGE(at != std::string::npos, key);
  return std::stod(json.substr(at + key.size() + 4));
}

}  // namespace

TEST_CASE("arithmetic instructions on doubles count their lanes, fused multiply-adds twice") {
  CHECK(flops_of_instruction("addsd", "%xmm1,%xmm0") == 1);
  CHECK(flops_of_instruction("vsqrtsd", "%xmm1,%xmm1,%xmm0") == 1);
  CHECK(flops_of_instruction("vdivsd", "%xmm1,%xmm2,%xmm0") == 1);
  CHECK(flops_of_instruction("mulpd", "%xmm1,%xmm0") == 2);
  CHECK(flops_of_instruction("vsubpd", "%ymm1,%ymm2,%ymm0") == 4);
  CHECK(flops_of_instruction("vfmadd231sd", "%xmm1,%xmm2,%xmm0") == 2);
  CHECK(flops_of_instruction("vfnmadd213pd", "%xmm1,%xmm2,%xmm0") == 4);
  CHECK(flops_of_instruction("vfmadd231pd", "%ymm1,%ymm2,%ymm0") == 8);
  for (const char* other : {"vxorpd", "andpd", "vmaxsd", "vucomisd", "vcvtsi2sd", "vmovsd", "vunpcklpd", "addq", "vaddps"}) {
    CHECK_MESSAGE(flops_of_instruction(other, "%xmm1,%xmm0") == 0, other);
  }
}

TEST_CASE("a program with 7 operations per step counts 7") {
  const mbrt::codegen::StepCount c = mbrt::codegen::count_step(MBRT_FLOP_PROBE, 1e-3, 50);
  CHECK(c.flops == doctest::Approx(7.0).epsilon(1e-12));
  CHECK(c.instructions > 7.0);
}

TEST_CASE("the report lists what was left out and counts less for the specialized step") {
  const std::string model = std::string(MBRT_TEST_MODELS) + "/a01_pendulum.yaml";
  const std::string special = run("gen '" + model + "' --report");
  const std::string general = run("gen '" + model + "' --report --no-specialize");
  for (const std::string key : {"source_bytes", "executable_bytes", "flops_per_step", "instructions_per_step"}) {
    CHECK_MESSAGE(number(special, key) > 0.0, key);
  }
  // The step's work shrinks; the source need not (it lists what was left out).
  for (const std::string key : {"flops_per_step", "instructions_per_step"}) {
    CHECK_MESSAGE(number(special, key) < number(general, key), key);
  }
  CHECK(special.find("\"turned_off\": []") != std::string::npos);
  CHECK(general.find("\"turned_off\": [\"principal_axes\", \"isotropic\", \"single_stage\"") != std::string::npos);
  CHECK(special.find("\"specialization\": \"single_stage\"") != std::string::npos);
  CHECK(general.find("\"specialization\": \"single_stage\"") == std::string::npos);
  CHECK(special.find("\"predicted_ns_per_step\": ") != std::string::npos);
  // One specialization turned off: the step does more than specialized, less than general.
  const std::string one = run("gen '" + model + "' --report --no-specialize=single_stage");
  CHECK(one.find("\"turned_off\": [\"single_stage\"]") != std::string::npos);
  CHECK(number(one, "flops_per_step") > number(special, "flops_per_step"));
  CHECK(number(one, "flops_per_step") < number(general, "flops_per_step"));
  CHECK(special.find("\"calibration\": ") != std::string::npos);
}

TEST_CASE("the report names the planar specialization where it applies and says why where it does not") {
  const std::string pendulum = run("gen '" + std::string(MBRT_TEST_MODELS) + "/a01_pendulum.yaml' --report");
  CHECK(pendulum.find("\"specialization\": \"planar\", \"removed\"") != std::string::npos);
  CHECK(pendulum.find("\"not_applied\": []") != std::string::npos);
  const std::string off = run("gen '" + std::string(MBRT_TEST_MODELS) + "/a01_pendulum.yaml' --report --no-specialize=planar");
  CHECK(off.find("\"turned_off\": [\"planar\"]") != std::string::npos);
  CHECK(off.find("\"specialization\": \"planar\"") == std::string::npos);
  const std::string top = run("gen '" + std::string(MBRT_TEST_MODELS) + "/heavy_top.yaml' --report");
  // One reason per plane tried: x-y, x-z, y-z.
  CHECK(top.find("{\"specialization\": \"planar\", \"reason\": \"gravity is not in the x-y plane; body top turns "
                 "about an axis other than y; body top moves out of the y-z plane\"}") != std::string::npos);
}
