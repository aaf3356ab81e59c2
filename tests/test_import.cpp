// `mbrt import` checked against MuJoCo loading the same file: a URDF and an
// MJCF spatial arm (tests/models/import/) are imported, run with
// `mbrt sim --scheme rk4-tree --h 1e-4`, and compared with MuJoCo's RK4 at
// the same step: the initial and final energy (mj_energyPos + mj_energyVel)
// and every body's centre of mass over 0.5 s (docs/import.md).
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <mujoco/mujoco.h>

namespace fs = std::filesystem;

namespace {

constexpr double kStep = 1e-4;
constexpr int kEvery = 100;             // CSV rows every 100 steps
constexpr double kPositionTol = 1e-6;   // m, centre of mass
constexpr double kEnergyTol = 1e-9;     // J, relative to the energy's magnitude

struct Run {
  int exit_code;
  std::string out;
};

Run mbrt(const std::string& args) {
  const std::string cmd = "MBRT_CACHE_DIR='" + (fs::path(MBRT_TEST_WORK_DIR) / "cache").string() + "' '" + MBRT_EXE +
                          "' " + args;
  Run r{0, ""};
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), p)) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// A numeric field of sim's summary line (a flat JSON object).
double field(const std::string& json, const std::string& key) {
  const size_t at = json.find("\"" + key + "\": ");
  REQUIRE(at != std::string::npos);
  return std::stod(json.substr(at + key.size() + 4));
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

void check_against_mujoco(const std::string& source_name) {
  const fs::path work = fs::path(MBRT_TEST_WORK_DIR);
  fs::create_directories(work);
  const std::string source = std::string(MBRT_TEST_MODELS) + "/import/" + source_name;
  const fs::path yaml = work / (fs::path(source_name).stem().string() + ".yaml");
  const fs::path csv = work / (fs::path(source_name).stem().string() + ".csv");
  REQUIRE(mbrt("import '" + source + "' -o '" + yaml.string() + "'").exit_code == 0);
  const Run sim = mbrt("sim '" + yaml.string() + "' --scheme rk4-tree --h 1e-4 --t-end 0.5 --every " +
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

}  // namespace

TEST_CASE("a URDF arm imported runs as MuJoCo runs the same file") { check_against_mujoco("urdf_arm.urdf"); }

TEST_CASE("an MJCF arm imported runs as MuJoCo runs the same file") { check_against_mujoco("mjcf_arm.xml"); }
