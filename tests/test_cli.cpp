// The mbrt command line as a user runs it: generate, compile, simulate,
// CSV and JSON outputs, the compile cache, and its errors.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "shell_command.hpp"

namespace fs = std::filesystem;

namespace {

struct Run {
  int exit_code;
  std::string out;
  std::string err;
};

// Runs `mbrt ARGS` with the tests' compile cache.
Run mbrt(const std::string& args) {
  const fs::path dir = fs::path(MBRT_TEST_WORK_DIR);
  fs::create_directories(dir);
  const std::string err_file = (dir / "stderr.txt").string();
  const std::string cmd = std::string("MBRT_CACHE_DIR='" MBRT_TEST_PROGRAM_CACHE "' '") + MBRT_EXE + "' " + args + " 2>'" +
                          err_file + "'";
  const CommandRun c = run_shell(cmd);
  Run r{c.exit_code, c.out, ""};
  std::ifstream e(err_file);
  std::stringstream s;
  s << e.rdbuf();
  r.err = s.str();
  return r;
}

std::string model(const std::string& name) { return std::string("'") + MBRT_TEST_MODELS + "/" + name + "'"; }

std::string last_line(const std::string& text) {
  std::string t = text;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  const size_t nl = t.rfind('\n');
  return nl == std::string::npos ? t : t.substr(nl + 1);
}

std::vector<std::string> lines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// The summary JSON on the last line of `mbrt sim`'s output, parsed strictly.
nlohmann::json summary(const Run& r) { return nlohmann::json::parse(last_line(r.out)); }

}  // namespace

TEST_CASE("mbrt sim writes the CSV trajectory and ends with a JSON summary") {
  const fs::path csv = fs::path(MBRT_TEST_WORK_DIR) / "a01.csv";
  const Run r = mbrt("sim " + model("a01_pendulum.yaml") + " --t-end 1 --every 100 --velocities --out '" +
                     csv.string() + "'");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const nlohmann::json json = summary(r);
  for (const char* key : {"model", "scheme", "h", "steps", "wall_s", "ns_per_step", "max_ns_per_step", "max_position_violation",
                          "max_velocity_violation", "max_acceleration_violation", "max_quat_norm_error",
                          "energy_initial", "energy_final", "status"}) {
    CHECK_MESSAGE(json.contains(key), key);
  }
  CHECK(json.at("model") == "a01_pendulum");
  CHECK(json.at("status") == "ok");
  CHECK(json.at("steps") == 2000);  // t_end / h with h = 5e-4 from the model file
  CHECK(json.at("h") == 5e-4);
  const std::vector<std::string> rows = lines(csv);
  REQUIRE(rows.size() == 1 + 21);  // header, t = 0 and every 100 steps
  CHECK(rows[0] == "t,bob.x,bob.y,bob.z,bob.vx,bob.vy,bob.vz");
  CHECK(rows[1].rfind("0,-1,0,0,0,0,0", 0) == 0);
}

TEST_CASE("mbrt sim --outputs adds the model's outputs, a modal body's tip among them, and is refused without any") {
  const fs::path csv = fs::path(MBRT_TEST_WORK_DIR) / "modal_cantilever.csv";
  const Run r = mbrt("sim " + model("modal_cantilever.yaml") + " --t-end 0.5 --every 100 --outputs --out '" + csv.string() + "'");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::vector<std::string> rows = lines(csv);
  REQUIRE(rows.size() == 1 + 6);
  CHECK(rows[0] ==
        "t,boom.x,boom.y,boom.z,boom.e0,boom.e1,boom.e2,boom.e3,tip.0,tip.1,tip.2,tip.3,tip.4,tip.5,tip.6,"
        "tip_velocity.0,tip_velocity.1,tip_velocity.2,tip_velocity.3,tip_velocity.4,tip_velocity.5");
  // The 2 m beam's tip starts at x = 2, level, at rest.
  CHECK(rows[1].rfind("0,1,0,0,1,0,0,0,2,0,0,1,0,0,0,0,0,0,0,0,0", 0) == 0);
  const Run none = mbrt("sim " + model("a01_pendulum.yaml") + " --outputs");
  CHECK(none.exit_code == 2);
  CHECK(none.err.find("--outputs: model a01_pendulum has no outputs") != std::string::npos);
}

TEST_CASE("mbrt sim --reactions adds each friction joint's torque and stick state") {
  // The pendulum with 0.2 N m of friction sticks for good within 8 s (docs/friction.md).
  const fs::path csv = fs::path(MBRT_TEST_WORK_DIR) / "friction.csv";
  const Run r = mbrt("sim " + model("friction_pendulum.yaml") + " --t-end 8 --every 1000 --reactions --out '" +
                     csv.string() + "'");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::vector<std::string> rows = lines(csv);
  REQUIRE(rows.size() == 1 + 9);
  const std::string tail = ",pin.fx,pin.fy,pin.fz,pin.tx,pin.ty,pin.tz,pin.friction,pin.stuck";
  CHECK(rows[0].size() > tail.size());
  CHECK(rows[0].substr(rows[0].size() - tail.size()) == tail);
  std::vector<double> last;
  std::stringstream row(rows.back());
  for (std::string cell; std::getline(row, cell, ',');) last.push_back(std::stod(cell));
  REQUIRE(last.size() >= 2);
  CHECK(last.back() == 1.0);                         // stuck
  CHECK(std::abs(last[last.size() - 2]) <= 0.2);     // within the limit
  CHECK(std::abs(last[last.size() - 2]) > 0.0);      // holding gravity's moment
}

TEST_CASE("mbrt sim names Euler parameters and body-axis angular velocities of rigid bodies; --h overrides") {
  const fs::path csv = fs::path(MBRT_TEST_WORK_DIR) / "top.csv";
  const Run r =
      mbrt("sim " + model("heavy_top.yaml") + " --h 2e-4 --t-end 0.01 --velocities --out '" + csv.string() + "'");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(summary(r).at("h") == 2e-4);
  CHECK(summary(r).at("steps") == 50);
  CHECK(lines(csv)[0] == "t,top.x,top.y,top.z,top.e0,top.e1,top.e2,top.e3,top.vx,top.vy,top.vz,top.wx,top.wy,top.wz");
}

TEST_CASE("a second mbrt sim of the same model reuses the compiled step") {
  const Run first = mbrt("sim " + model("free_body.yaml") + " --t-end 0.01");
  REQUIRE(first.exit_code == 0);
  const Run second = mbrt("sim " + model("free_body.yaml") + " --t-end 0.02");
  REQUIRE(second.exit_code == 0);
  CHECK(second.err.find("compiling") == std::string::npos);
  CHECK(summary(second).at("steps") == 20);
}

TEST_CASE("mbrt gen writes the model's header and source") {
  const fs::path dir = fs::path(MBRT_TEST_WORK_DIR) / "gen";
  const Run r = mbrt("gen " + model("four_bar.yaml") + " -o '" + dir.string() + "'");
  REQUIRE(r.exit_code == 0);
  CHECK(fs::exists(dir / "four_bar.hpp"));
  CHECK(fs::exists(dir / "four_bar.cpp"));
  CHECK(fs::exists(dir / "four_bar_c.h"));  // the C interface, for every model
  CHECK(fs::exists(dir / "four_bar_c.cpp"));
}

TEST_CASE("a bad model file is reported with file, line and key, and nothing is generated") {
  const fs::path dir = fs::path(MBRT_TEST_WORK_DIR) / "bad";
  const Run r = mbrt("gen " + model("bad/unknown_body.yaml") + " -o '" + dir.string() + "'");
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("unknown_body.yaml:10:") != std::string::npos);
  CHECK(r.err.find("joints[0].body2") != std::string::npos);
  CHECK(r.err.find("crnk") != std::string::npos);
  CHECK(!fs::exists(dir / "unknown_body.cpp"));
}

TEST_CASE("inconsistent initial velocities name the worst joint; --project-initial repairs them") {
  const Run bad = mbrt("sim " + model("bad/inconsistent_velocity.yaml") + " --t-end 0.01");
  CHECK(bad.exit_code == 1);
  CHECK(bad.err.find("joint 'rod'") != std::string::npos);
  CHECK(bad.err.find("--project-initial") != std::string::npos);
  CHECK(bad.err.find("0.3") != std::string::npos);  // the residual: velocity along the bar

  const Run fixed = mbrt("sim " + model("bad/inconsistent_velocity.yaml") + " --t-end 0.01 --project-initial");
  INFO(fixed.err);
  REQUIRE(fixed.exit_code == 0);
  CHECK(summary(fixed).at("max_velocity_violation") < 1e-9);
}

TEST_CASE("a run that blows up exits with 3 and still ends with valid JSON") {
  const Run r = mbrt("sim " + model("unstable_spring.yaml") + " --t-end 1");
  CHECK(r.exit_code == 3);
  const nlohmann::json json = summary(r);  // JSON has no NaN or Inf: a parser would refuse them
  CHECK(json.at("status") == "non_finite");
  for (const auto& [key, value] : json.items()) CHECK_MESSAGE((value.is_number() || value.is_string() || value.is_null()), key);
}

TEST_CASE("staggered-nps refuses a model with more cut-joint rows than it solves, before anything runs") {
  const Run r = mbrt("gen " + model("benchmarks/a02_n_four_bar_40.yaml") + " -o gen_refused --scheme staggered-nps");
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("solver.scheme: staggered-nps closes loops with a dense system of cut-joint rows, at most 30; "
                   "this model has 200 (use staggered-pcst)") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists("gen_refused"));
}

TEST_CASE("bad command lines get a usage message and exit code 2") {
  CHECK(mbrt("").exit_code == 2);
  CHECK(mbrt("fly " + model("a01_pendulum.yaml")).exit_code == 2);
  const Run r = mbrt("sim " + model("a01_pendulum.yaml") + " --h fast");
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("--h: expected a number") != std::string::npos);
  CHECK(mbrt("sim " + model("a01_pendulum.yaml") + " --warp 9").exit_code == 2);
  CHECK(mbrt("sim '/nonexistent/model.yaml'").err.find("/nonexistent/model.yaml") != std::string::npos);
}

// Nothing is generated or compiled before the run options are checked: the
// errors name the option, and stderr has no "compiling" line.
TEST_CASE("sim's options are checked before the model is generated or compiled, with exit code 2") {
  const struct { std::string options, message; } bad[] = {
      {"--t-end -5", "--t-end: expected a finite time >= 0 s, got '-5'"},
      {"--t-end inf", "--t-end: expected a finite time >= 0 s, got 'inf'"},
      {"--t-end nan", "--t-end: expected a finite time >= 0 s, got 'nan'"},
      {"--every 0", "--every: expected an integer >= 1 (steps), got '0'"},
      {"--every 2.5", "--every: expected an integer, got '2.5'"},
      {"--out /nonexistent_dir/x.csv", "--out: no directory /nonexistent_dir for '/nonexistent_dir/x.csv'"},
      {"--scheme nosuch", "--scheme: expected one of: staggered-pcst, staggered-nps, ali3p, blajer, baumgarte, "
                          "staggered-tree, midpoint-tree, rk4-tree, rk4-projected, staggered4, rk8-tree, got 'nosuch'"},
      {"--h -1", "--h: expected a finite step > 0 s"},
      {"--h inf", "--h: expected a finite step > 0 s"},
      {"--euler-updates 0", "--euler-updates: expected an integer >= 1"},
      {"--name 9lives", "--name: expected a name matching [a-z][a-z0-9_]*, got '9lives'"},
      {"--ali3p-projection newton", "--ali3p-projection: expected bayo or cuadrado, got 'newton'"},
      {"--ali3p-integrator euler", "--ali3p-integrator: expected trapezoidal or generalized_alpha, got 'euler'"}};
  for (const auto& b : bad) {
    const Run r = mbrt("sim " + model("a01_pendulum.yaml") + " " + b.options);
    INFO(b.options << ": " << r.err);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find(b.message) != std::string::npos);
    CHECK(r.err.find("compiling") == std::string::npos);
  }
}

// The driver gets --t-end as written: a time below the 6 decimals of
// std::to_string still runs its steps.
TEST_CASE("sim takes --t-end at full precision") {
  const Run r = mbrt("sim " + model("a01_pendulum.yaml") + " --h 1e-7 --t-end 3e-7");
  REQUIRE(r.exit_code == 0);
  CHECK(summary(r).at("steps") == 3);  // "0.000000" would run none
}

TEST_CASE("mbrt gen writes the LCM types, the DBC and packing of a model with inputs and outputs") {
  const fs::path dir = fs::path(MBRT_TEST_WORK_DIR) / "gen_lcm";
  const Run r = mbrt("gen " + model("actuated.yaml") + " -o '" + dir.string() + "'");
  REQUIRE(r.exit_code == 0);
  CHECK(fs::exists(dir / "actuated.lcm"));
  CHECK(fs::exists(dir / "actuated_lcm.hpp"));
  CHECK(fs::exists(dir / "actuated.dbc"));
  CHECK(fs::exists(dir / "actuated_can.hpp"));
  REQUIRE(mbrt("gen " + model("four_bar.yaml") + " -o '" + dir.string() + "'").exit_code == 0);
  CHECK(fs::exists(dir / "four_bar.hpp"));
  CHECK(!fs::exists(dir / "four_bar.lcm"));  // no inputs: no LCM types
  CHECK(!fs::exists(dir / "four_bar.dbc"));
}

TEST_CASE("mbrt gen refuses input limits the CAN layout cannot carry") {
  const fs::path dir = fs::path(MBRT_TEST_WORK_DIR) / "gen_can_limits";
  fs::create_directories(dir);
  std::ifstream in(fs::path(MBRT_TEST_MODELS) / "actuated.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const std::string limit = "min: -20, max: 20";
  REQUIRE(yaml.find(limit) != std::string::npos);
  yaml.replace(yaml.find(limit), limit.size(), "min: -3000, max: 3000");
  std::ofstream(dir / "actuated.yaml") << yaml;
  const Run r = mbrt("gen '" + (dir / "actuated.yaml").string() + "' -o '" + dir.string() + "'");
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("do not fit the CAN layout") != std::string::npos);
}

TEST_CASE("mbrt hil refuses a model without inputs and outputs before compiling anything") {
  const Run r = mbrt("hil " + model("four_bar.yaml") + " --lcm 'udpm://239.255.76.67:7667?ttl=0'");
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("needs both inputs and outputs") != std::string::npos);
  CHECK(r.err.find("compiling") == std::string::npos);
}

TEST_CASE("sim's and hil's --set keys are the model's tunable ones, checked before compiling") {
  const std::string lcm = " --lcm 'udpm://239.255.76.67:7667?ttl=0' --duration 0";
  const struct { std::string command, message; } bad[] = {
      {"sim " + model("tunable_pendulum.yaml") + " --set bob.colour=1",
       "--set: 'bob.colour' is not a tunable parameter of tunable_pendulum; the tunable ones are gravity.x"},
      {"sim " + model("tunable_pendulum.yaml") + " --set bob.mass=heavy",
       "--set: expected KEY=VALUE with a finite number, got 'bob.mass=heavy'"},
      {"hil " + model("actuated.yaml") + lcm + " --set gravity.z=-1",
       "--set: 'gravity.z' is not a tunable parameter of actuated (it marks none"},
      {"hil " + model("actuated.yaml") + lcm + " --set =1", "--set: expected KEY=VALUE, got '=1'"}};
  for (const auto& b : bad) {
    const Run r = mbrt(b.command);
    INFO(b.command << ": " << r.err);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find(b.message) != std::string::npos);
    CHECK(r.err.find("compiling") == std::string::npos);
  }
}

TEST_CASE("mbrt hil refuses an IPv6 LCM group, saying that LCM's udpm provider is IPv4-only") {
  for (const std::string url : {"udpm://[ff15::1]:7667?ttl=0", "udpm://ff15::1:7667"}) {
    const Run r = mbrt("hil " + model("actuated.yaml") + " --lcm '" + url + "' --duration 0");
    INFO(r.err);
    CHECK(r.exit_code == 1);
    CHECK(r.err.find("cannot open LCM at '" + url + "': LCM's udpm provider is IPv4-only") != std::string::npos);
  }
}

TEST_CASE("sim --set drives a tunable driver with the coefficient set, and refuses one that leaves the initial rate") {
  // theta(t) = c1 t + 0.5 t^2 with c1 = 2 and the rotor's initial rate 2: at t = 1, theta = 2.5 rad.
  const fs::path csv = fs::path(MBRT_TEST_WORK_DIR) / "driven.csv";
  const Run r = mbrt("sim " + model("tunable_driven_pair.yaml") + " --t-end 1 --every 1000 --out '" + csv.string() +
                     "' --set spin.function.c1=2 --set rotor.angular_velocity.z=2");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::vector<std::string> rows = lines(csv);
  REQUIRE(rows.size() == 3);  // header, t = 0 and t = 1
  REQUIRE(rows[0].rfind("t,rotor.x,rotor.y,rotor.z,rotor.e0,rotor.e1,rotor.e2,rotor.e3,", 0) == 0);
  std::vector<double> v;
  std::stringstream row(rows[2]);
  for (std::string x; std::getline(row, x, ',');) v.push_back(std::stod(x));
  REQUIRE(v.size() > 7);
  CHECK(v[0] == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(std::abs(v[4] - std::cos(1.25)) < 1e-9);  // Euler parameters of 2.5 rad about z
  CHECK(std::abs(v[7] - std::sin(1.25)) < 1e-9);

  const Run off = mbrt("sim " + model("tunable_driven_pair.yaml") + " --t-end 0.01 --set spin.function.c1=2");
  CHECK(off.exit_code == 2);
  CHECK(off.err.find("violates the joints") != std::string::npos);
  CHECK(off.err.find("velocity 1,") != std::string::npos);  // the rotor's rate 1 against f'(0) = 2
}
