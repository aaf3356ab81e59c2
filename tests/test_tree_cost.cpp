// The floating-point operations of the tree step's kernels per body, as the
// generator counts them in the comment above each kernel (docs/staggered-tree.md,
// "Measured"): random spatial revolute chains whose axes meet at general angles
// (tools/make_spatial.py random), the 7-link arm, the humanoid and a planar
// chain. The bounds sit just above today's counts, so a change to the emitter,
// the frames or the recorder that makes the step do more fails here. The whole
// step adds, per revolute joint, the half angle's sin_cos (34 flops) and the
// step's own loops (about 20).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

void run(const std::string& cmd) {
  INFO(cmd);
  REQUIRE(std::system(cmd.c_str()) == 0);
}

// The flops in the comment just above `static void NAME(` in src.
double kernel_flops(const std::string& src, const std::string& name) {
  const size_t at = src.find("static void " + name + "(");
  REQUIRE_MESSAGE(at != std::string::npos, name);
  const size_t comment = src.rfind("\n// ", at);
  std::smatch m;
  const std::string text = src.substr(comment, at - comment);
  REQUIRE_MESSAGE(std::regex_search(text, m, std::regex("// ([0-9,]+) flops")), name);
  std::string digits = m[1].str();
  digits.erase(std::remove(digits.begin(), digits.end(), ','), digits.end());
  return std::stod(digits);
}

struct PerBody {
  double recursion;  // joint_accelerations
  double states;     // body_states, which solver.body_states: on_demand leaves out of the step
  double both() const { return recursion + states; }
};

// The kernels' flops per body of the staggered-tree step of the model that
// `make` (a shell command) writes.
PerBody kernel_flops_per_body(const std::string& make, const std::string& name, int bodies) {
  const fs::path dir = fs::path(MBRT_TEST_WORK_DIR) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path model = dir / "model.yaml";
  run(make + " > '" + model.string() + "'");
  run("'" + std::string(MBRT_EXE) + "' gen '" + model.string() + "' --scheme staggered-tree --name " + name +
      " -o '" + dir.string() + "' 2>/dev/null");
  std::ifstream in(dir / (name + ".cpp"));
  REQUIRE(in);
  std::stringstream src;
  src << in.rdbuf();
  return {kernel_flops(src.str(), "joint_accelerations") / bodies, kernel_flops(src.str(), "body_states") / bodies};
}

std::string tool(const std::string& script) { return "python3 '" + std::string(MBRT_SOURCE_DIR) + "/tools/" + script + "'"; }

}  // namespace

TEST_CASE("random general-angle chains: the kernels stay within 580 flops per body") {
  // Every seed of one length gives the same count (no constant of a random
  // model is 0 or 1); the count grows slowly with the length.
  const std::array<std::array<int, 2>, 4> cases = {{{8, 4}, {12, 1}, {20, 3}, {32, 7}}};
  for (const auto& [links, seed] : cases) {
    const std::string name = "random_" + std::to_string(links) + "_" + std::to_string(seed);
    const PerBody per_body = kernel_flops_per_body(
        tool("make_spatial.py") + " random " + std::to_string(links) + " --seed " + std::to_string(seed), name, links);
    MESSAGE(name << ": " << per_body.both() << " flops per body, " << per_body.recursion << " of them the recursion");
    CHECK(per_body.both() <= 580.0);
    // With the bodies' states on demand the step is the recursion and about
    // 55 more, within the 500 a body of the goal (docs/staggered-tree.md).
    CHECK(per_body.recursion <= 420.0);
  }
}

TEST_CASE("arms, the humanoid and planar chains stay cheaper") {
  const std::string stress = std::string(MBRT_TEST_MODELS) + "/stress/";
  const double arm = kernel_flops_per_body("cat '" + stress + "arm_7.yaml'", "arm_7", 7).both();
  const double humanoid = kernel_flops_per_body("cat '" + stress + "humanoid_30.yaml'", "humanoid_30", 30).both();
  const double planar = kernel_flops_per_body(tool("make_chain.py") + " 16", "planar_16", 16).both();
  MESSAGE("arm_7 " << arm << ", humanoid_30 " << humanoid << ", planar 16 " << planar << " flops per body");
  CHECK(arm <= 260.0);
  CHECK(humanoid <= 250.0);
  CHECK(planar <= 105.0);
}
