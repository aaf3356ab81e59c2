// `mbrt import` checked against MuJoCo loading the same file: a URDF and an
// MJCF spatial arm and an MJCF ball joint and free body (tests/models/import/)
// are imported, run with `mbrt sim --scheme rk4-tree --h 1e-4` (rk4-projected
// for the ball joint), and compared with MuJoCo's RK4 at
// the same step: the initial and final energy (mj_energyPos + mj_energyVel)
// and every body's centre of mass over 0.5 s (docs/import.md).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "shell_command.hpp"

#include <Eigen/Core>
#include <mujoco/mujoco.h>

namespace fs = std::filesystem;

namespace {

constexpr double kStep = 1e-4;
constexpr int kEvery = 100;             // CSV rows every 100 steps
constexpr double kPositionTol = 1e-6;   // m, centre of mass
constexpr double kEnergyTol = 1e-9;     // J, relative to the energy's magnitude

using Run = CommandRun;

Run mbrt(const std::string& args) {
  return run_shell(std::string("MBRT_CACHE_DIR='" MBRT_TEST_PROGRAM_CACHE "' '") + MBRT_EXE + "' " +
                   args);
}

// A numeric field of sim's summary, the JSON object on its last line (parsed strictly).
double field(const std::string& out, const std::string& key) {
  std::string text = out;
  while (!text.empty() && text.back() == '\n') text.pop_back();
  return nlohmann::json::parse(text.substr(text.rfind('\n') + 1)).at(key).get<double>();
}

// The CSV sim writes: column name -> values per row.
std::map<std::string, std::vector<double>> read_csv(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string n; std::getline(header, n, ',');) names.push_back(n);
  std::map<std::string, std::vector<double>> columns;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string cell;
    for (size_t i = 0; std::getline(row, cell, ','); ++i) columns[names.at(i)].push_back(std::stod(cell));
  }
  return columns;
}

using ModelPtr = std::unique_ptr<mjModel, decltype(&mj_deleteModel)>;
using DataPtr = std::unique_ptr<mjData, decltype(&mj_deleteData)>;

// MuJoCo's side: the source loaded by MuJoCo, RK4 at kStep, no contacts.
struct MuJoCo {
  ModelPtr m{nullptr, &mj_deleteModel};
  DataPtr d{nullptr, &mj_deleteData};

  explicit MuJoCo(const std::string& source) {
    std::array<char, 1000> error{};
    m.reset(mj_loadXML(source.c_str(), nullptr, error.data(), static_cast<int>(error.size())));
    REQUIRE_MESSAGE(m, error.data());
    m->opt.integrator = mjINT_RK4;
    m->opt.timestep = kStep;
    m->opt.disableflags |= mjDSBL_CONTACT;
    m->opt.enableflags |= mjENBL_ENERGY;
    d.reset(mj_makeData(m.get()));
    mj_forward(m.get(), d.get());
  }

  // mbrt's energy: MuJoCo's less the gravity energy of bodies fixed to the
  // world (mbrt's ground), which mj_energyPos counts.
  double energy() const {
    mj_energyPos(m.get(), d.get());
    mj_energyVel(m.get(), d.get());
    double e = d->energy[0] + d->energy[1];
    for (int i = 1; i < m->nbody; ++i) {
      if (m->body_weldid[i] == 0) e += m->body_mass[i] * Eigen::Map<const Eigen::Vector3d>(m->opt.gravity).dot(com(i));
    }
    return e;
  }

  Eigen::Vector3d com(int body) const { return Eigen::Map<const Eigen::Vector3d>(d->xipos + 3 * body); }

  // The centre of mass of every group of bodies welded together (one mbrt
  // body, named after the group's first body), by name.
  std::map<std::string, Eigen::Vector3d> moving_coms() const {
    std::map<int, std::pair<double, Eigen::Vector3d>> groups;
    for (int i = 1; i < m->nbody; ++i) {
      if (m->body_weldid[i] == 0) continue;
      auto& [mass, moment] = groups.try_emplace(m->body_weldid[i], 0.0, Eigen::Vector3d::Zero()).first->second;
      mass += m->body_mass[i];
      moment += m->body_mass[i] * com(i);
    }
    std::map<std::string, Eigen::Vector3d> out;
    for (const auto& [root, g] : groups) out[mj_id2name(m.get(), mjOBJ_BODY, root)] = g.second / g.first;
    return out;
  }
};

void check_against_mujoco(const std::string& source_name, const std::string& scheme) {
  const fs::path work = fs::path(MBRT_TEST_WORK_DIR);
  fs::create_directories(work);
  const std::string source = std::string(MBRT_TEST_MODELS) + "/import/" + source_name;
  const fs::path yaml = work / (fs::path(source_name).stem().string() + ".yaml");
  const fs::path csv = work / (fs::path(source_name).stem().string() + ".csv");
  REQUIRE(mbrt("import '" + source + "' -o '" + yaml.string() + "'").exit_code == 0);
  const Run sim = mbrt("sim '" + yaml.string() + "' --scheme " + scheme + " --h 1e-4 --t-end 0.5 --every " +
                       std::to_string(kEvery) + " --out '" + csv.string() + "'");
  REQUIRE(sim.exit_code == 0);

  MuJoCo mj(source);
  const double e0 = mj.energy();
  CHECK(std::abs(field(sim.out, "energy_initial") - e0) <= kEnergyTol * std::max(1.0, std::abs(e0)));

  const auto rows = read_csv(csv);
  const std::vector<double>& t = rows.at("t");
  double worst = 0.0;
  std::string worst_at;
  for (size_t k = 0; k < t.size(); ++k) {
    while (mj.d->time < t[k] - 0.5 * kStep) {
      mj_step(mj.m.get(), mj.d.get());
      if (mj.d->nefc != 0) FAIL("a MuJoCo constraint (a joint limit) became active at t = " << mj.d->time);
    }
    for (const auto& [name, com] : mj.moving_coms()) {
      const Eigen::Vector3d r(rows.at(name + ".x").at(k), rows.at(name + ".y").at(k), rows.at(name + ".z").at(k));
      if ((r - com).norm() > worst) {
        worst = (r - com).norm();
        worst_at = name + " at t = " + std::to_string(t[k]);
      }
    }
  }
  CHECK(t.back() == doctest::Approx(0.5));
  MESSAGE(std::setprecision(12) << source_name << ": energy " << e0 << " J (MuJoCo) vs " << field(sim.out, "energy_initial")
                      << " J (mbrt) at t = 0, " << mj.energy() << " vs " << field(sim.out, "energy_final")
                      << " J at 0.5 s; largest COM difference " << worst << " m (" << worst_at << ")");
  CHECK(worst <= kPositionTol);
  const double e1 = mj.energy();  // damping has taken some: both must agree on how much
  CHECK(std::abs(field(sim.out, "energy_final") - e1) <= 1e3 * kEnergyTol * std::max(1.0, std::abs(e1)));
}

// Writes `text` to the work directory as `name`; returns its path.
std::string write(const std::string& name, const std::string& text) {
  const fs::path file = fs::path(MBRT_TEST_WORK_DIR) / name;
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
  return file.string();
}

// `mbrt import SOURCE -o OUT`, stdout and stderr together.
Run import(const std::string& source, const std::string& out = "imported.yaml") {
  return mbrt("import '" + source + "' -o '" + (fs::path(MBRT_TEST_WORK_DIR) / out).string() + "' 2>&1");
}

constexpr const char* kRodLink = R"(<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>)";

std::string urdf_two_pins(const std::string& second_joint_extra) {
  return std::string(R"(<robot name="pins"><link name="base"/><link name="a">)") + kRodLink +
         R"(</link><link name="b">)" + kRodLink + R"(</link>
      <joint name="pin_a" type="continuous"><parent link="base"/><child link="a"/><axis xyz="0 1 0"/></joint>
      <joint name="pin_b" type="continuous"><parent link="a"/><child link="b"/><origin xyz="0 0 -1"/><axis xyz="0 1 0"/>)" +
         second_joint_extra + "</joint></robot>";
}

constexpr const char* kMjcfFourBar = R"(<mujoco model="four_bar"><worldbody>
  <body name="crank"><joint name="pin_a" type="hinge" axis="0 1 0"/><inertial pos="0 0 -0.5" mass="1" diaginertia="0.1 0.1 0.01"/>
    <body name="coupler" pos="0 0 -1"><joint name="pin_b" type="hinge" axis="0 1 0"/><inertial pos="0.5 0 0" mass="1" diaginertia="0.01 0.1 0.1"/>
      <body name="rocker" pos="1 0 0"><joint name="pin_c" type="hinge" axis="0 1 0"/><inertial pos="0 0 0.5" mass="1" diaginertia="0.1 0.1 0.01"/>
  </body></body></body></worldbody>
  <equality>%s</equality>%s</mujoco>)";

std::string mjcf_four_bar(const std::string& equality, const std::string& extra = "") {
  std::string text = kMjcfFourBar;
  text.replace(text.find("%s"), 2, equality);
  text.replace(text.find("%s"), 2, extra);
  return text;
}

}  // namespace

TEST_CASE("import refuses what mbrt cannot model, naming it, with exit 1") {
  const Run mimic = import(write("mimic.urdf", urdf_two_pins(R"(<mimic joint="pin_a" multiplier="2"/>)")));
  CHECK(mimic.exit_code == 1);
  CHECK(mimic.out.find("joint 'pin_b' mimics joint 'pin_a'") != std::string::npos);

  const Run broken = import(write("broken.urdf", "<robot name=\"x\"><link name=\"a\"></robot>"));
  CHECK(broken.exit_code == 1);
  CHECK(broken.out.find("broken.urdf: not a URDF file") != std::string::npos);

  const Run bad_xml = import(write("bad.xml", "<mujoco>\n<worldbody>\n<body name=\"b\" nosuch=\"1\"/>\n</worldbody>\n</mujoco>"));
  CHECK(bad_xml.exit_code == 1);
  CHECK(bad_xml.out.find("bad.xml") != std::string::npos);
  CHECK(bad_xml.out.find("line 3") != std::string::npos);

  const Run coupling = import(write("coupling.xml", mjcf_four_bar(R"(<joint name="gear" joint1="pin_a" joint2="pin_c"/>)")));
  CHECK(coupling.exit_code == 1);
  CHECK(coupling.out.find("equality 'gear': only connect and weld") != std::string::npos);

  const Run weld = import(write("weld.xml", mjcf_four_bar(R"(<weld name="glue" body1="crank" body2="rocker" relpose="0 0 0 1 0 0 0"/>)")));
  CHECK(weld.exit_code == 1);
  CHECK(weld.out.find("equality 'glue' is not satisfied at qpos0") != std::string::npos);
}

TEST_CASE("import names what it leaves out in warnings") {
  const Run r = import(write("warned.xml", mjcf_four_bar(R"(<connect name="pin_d" body1="rocker" body2="world" anchor="0 0 1"/>)",
                                                        R"(<actuator><motor name="drive" joint="pin_a"/></actuator>)")));
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("warning: ") != std::string::npos);
  CHECK(r.out.find("1 actuators ('drive') are not imported") != std::string::npos);
  const Run u = import(write("friction.urdf", urdf_two_pins(R"(<dynamics damping="0.1" friction="0.3"/>)")));
  CHECK(u.exit_code == 0);
  CHECK(u.out.find("joint 'pin_b': friction 0.3 is not supported") != std::string::npos);
}

TEST_CASE("a closed loop from a connect equality imports as a spherical joint and runs") {
  const std::string source = write("four_bar.xml",
      mjcf_four_bar(R"(<connect name="pin_d" body1="rocker" body2="world" anchor="0 0 1"/>)"));
  REQUIRE(import(source, "four_bar.yaml").exit_code == 0);
  std::ifstream in(fs::path(MBRT_TEST_WORK_DIR) / "four_bar.yaml");
  const std::string yaml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(yaml.find("{name: pin_d, type: spherical, body1: rocker, body2: ground, point: [1, 0, 0]}") != std::string::npos);
  CHECK(mbrt("sim '" + (fs::path(MBRT_TEST_WORK_DIR) / "four_bar.yaml").string() + "' --t-end 0.1").exit_code == 0);
}

TEST_CASE("import's command line errors exit 2") {
  CHECK(mbrt("import 2>&1").exit_code == 2);
  CHECK(mbrt("import arm.urdf 2>&1").exit_code == 2);
  CHECK(mbrt("import arm.stl -o arm.yaml 2>&1").exit_code == 2);
  CHECK(mbrt("import arm.urdf -o arm.yaml --nosuch 2>&1").exit_code == 2);
}

TEST_CASE("a URDF arm imported runs as MuJoCo runs the same file") { check_against_mujoco("urdf_arm.urdf", "rk4-tree"); }

TEST_CASE("an MJCF arm imported runs as MuJoCo runs the same file") { check_against_mujoco("mjcf_arm.xml", "rk4-tree"); }

// A ball joint and a free body: absolute coordinates, fourth order.
TEST_CASE("an MJCF ball joint and free body imported run as MuJoCo runs them") {
  check_against_mujoco("mjcf_ball.xml", "rk4-projected");
}
