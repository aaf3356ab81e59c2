// `mbrt gen --report`: the counting of floating-point operations, checked on
// a program with a known count, and the report of a model, specialized and
// general: its fields, and that the specializations make the step do less.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "flop_count.hpp"
#include "shell_command.hpp"

namespace fs = std::filesystem;
using mbrt::codegen::flops_of_instruction;

namespace {

// The report `mbrt ARGS -o DIR` prints, parsed strictly (invalid JSON fails the test).
nlohmann::json run(const std::string& args) {
  const fs::path dir = fs::path(MBRT_TEST_WORK_DIR);
  fs::create_directories(dir);
  const std::string cmd = std::string("MBRT_CACHE_DIR='" MBRT_TEST_PROGRAM_CACHE "' '") + MBRT_EXE + "' " + args +
                          " -o '" + (dir / "gen").string() + "' 2>/dev/null";
  const CommandRun r = run_shell(cmd);
  REQUIRE(r.exit_code == 0);
  return nlohmann::json::parse(r.out);
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
  const nlohmann::json special = run("gen '" + model + "' --report");
  const nlohmann::json general = run("gen '" + model + "' --report --no-specialize");
  for (const std::string key : {"source_bytes", "executable_bytes", "flops_per_step", "instructions_per_step"}) {
    CHECK_MESSAGE(special.at(key).get<double>() > 0.0, key);
  }
  CHECK(special.at("bodies") == 1);
  CHECK(special.at("flops_per_body").get<double>() == special.at("flops_per_step").get<double>());
  // The step's work shrinks; the source need not (it lists what was left out).
  for (const std::string key : {"flops_per_step", "instructions_per_step"}) {
    CHECK_MESSAGE(special.at(key).get<double>() < general.at(key).get<double>(), key);
  }
  const auto names = [](const nlohmann::json& list) {
    std::vector<std::string> out;
    for (const nlohmann::json& k : list) out.push_back(k.at("specialization"));
    return out;
  };
  const auto has = [](const std::vector<std::string>& v, const std::string& x) { return std::find(v.begin(), v.end(), x) != v.end(); };
  CHECK(special.at("turned_off").empty());
  const std::vector<std::string> all_off = general.at("turned_off");
  REQUIRE(all_off.size() >= 3);
  CHECK(std::vector<std::string>(all_off.begin(), all_off.begin() + 3) ==
        std::vector<std::string>{"principal_axes", "isotropic", "single_stage"});
  CHECK(has(names(special.at("skipped")), "single_stage"));
  CHECK_FALSE(has(names(general.at("skipped")), "single_stage"));
  CHECK(special.contains("predicted_ns_per_step"));
  // One specialization turned off: the step does more than specialized, less than general.
  const nlohmann::json one = run("gen '" + model + "' --report --no-specialize=single_stage");
  CHECK(one.at("turned_off") == nlohmann::json::array({"single_stage"}));
  CHECK(one.at("flops_per_step").get<double>() > special.at("flops_per_step").get<double>());
  CHECK(one.at("flops_per_step").get<double>() < general.at("flops_per_step").get<double>());
  CHECK(special.at("calibration").is_string());
  CHECK(special.at("stable_step").at("stable_step").is_number());
  CHECK(special.at("parallel").at("parts") == 1);
  CHECK(special.at("parallel").at("interface_solve") == "none");
}

TEST_CASE("the report gives the parallel step's parts and interface, and why a small model stays serial") {
  const std::string four_bar = std::string(MBRT_TEST_MODELS) + "/four_bar.yaml";
  const nlohmann::json small = run("gen '" + four_bar + "' --report --parallel-parts 2");
  CHECK(small.at("parallel").at("parts") == 1);
  CHECK(small.at("parallel").at("requested") == 2);
  CHECK(small.at("parallel").at("serial_reason").get<std::string>().find("parallel_min_rows") != std::string::npos);
  const nlohmann::json split =
      run("gen '" + four_bar + "' --report --parallel-parts 2 --parallel-min-rows 0 --parallel-interface pcg --pcg-iterations 3");
  const nlohmann::json& p = split.at("parallel");
  CHECK(p.at("parts") == 2);
  CHECK(p.at("interface_blocks").get<int>() >= 1);
  CHECK(p.at("serial_reason") == "");
  CHECK(p.at("interface_solve") == "pcg, 3 iterations, block preconditioner");
  int rows = p.at("interface_rows").get<int>();
  for (const auto& r : p.at("part_rows")) rows += r.get<int>();
  CHECK(rows == 20);  // four revolute joints of 5 rows: every block in a part or the interface
}

TEST_CASE("the report names the planar specialization where it applies and says why where it does not") {
  const auto find = [](const nlohmann::json& list, const std::string& name) {
    for (const nlohmann::json& k : list)
      if (k.at("specialization") == name) return k;
    return nlohmann::json();
  };
  const nlohmann::json pendulum = run("gen '" + std::string(MBRT_TEST_MODELS) + "/a01_pendulum.yaml' --report");
  CHECK(find(pendulum.at("skipped"), "planar").contains("removed"));
  CHECK(pendulum.at("not_applied").empty());
  const nlohmann::json off = run("gen '" + std::string(MBRT_TEST_MODELS) + "/a01_pendulum.yaml' --report --no-specialize=planar");
  CHECK(off.at("turned_off") == nlohmann::json::array({"planar"}));
  CHECK(find(off.at("skipped"), "planar").is_null());
  const nlohmann::json top = run("gen '" + std::string(MBRT_TEST_MODELS) + "/heavy_top.yaml' --report");
  // One reason per plane tried: x-y, x-z, y-z.
  CHECK(find(top.at("not_applied"), "planar").at("reason") ==
        "gravity is not in the x-y plane; body top turns about an axis other than y; body top moves out of the y-z plane");
}
