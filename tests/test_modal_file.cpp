// Modal bodies from data files (docs/flexible.md, "Modal data from a
// file"): a spring chain's modes computed from its stiffness have the
// closed-form frequencies; held at their clamped nodes and loaded (forces,
// a torque and a motor_torque input at nodes), the chain (by its stiffness
// and by its modes) and a two-element cantilever settle at the closed-form
// static displacements and slopes; a free truss keeps its
// energy (summed over the nodes with the file's stiffness), momentum and
// angular momentum; the generator's messages on bad files, and its warning
// where a structure without geometric stiffness could spin too fast.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "analysis.hpp"
#include "modal_body.hpp"
#include "modal_file_free.hpp"
#include "modal_file_free_fine.hpp"
#include "modal_file_loads.hpp"
#include "modal_file_loads_blajer.hpp"
#include "modal_momenta.hpp"
#include "model.hpp"
#include "stable_step.hpp"

namespace {

using mbrt::Vec3;
namespace cg = mbrt::codegen;

const std::string kModels = MBRT_TEST_MODELS;

std::string generator_error(const std::string& yaml, const std::string& file = kModels + "/inline.yaml") {
  try {
    cg::analyse(cg::parse_model(yaml, file));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// A file next to the inline models, removed after the test.
struct TemporaryFile {
  std::filesystem::path path;
  TemporaryFile(const std::string& name, const std::string& text)
      : path(std::filesystem::temp_directory_path() / ("mbrt_test_modal_file_" + name)) {
    std::ofstream(path) << text;
  }
  ~TemporaryFile() { std::filesystem::remove(path); }
};

}  // namespace

TEST_CASE("a spring chain's modes from its stiffness have the closed-form frequencies") {
  // Two masses m on springs k (root - a - b) per direction: omega^2 =
  // (k / m)(3 -+ sqrt 5) / 2, and b moves (1 +- sqrt 5) / 2 times as far as a.
  const cg::Model model = cg::load_model(kModels + "/modal_file_loads.yaml");
  std::vector<double> expected;
  for (const double k : {1000.0, 400.0, 250.0}) {
    for (const double sign : {-1.0, 1.0}) expected.push_back(std::sqrt(k / 0.5 * (3 + sign * std::sqrt(5.0)) / 2));
  }
  std::sort(expected.begin(), expected.end());
  for (const int body : {0, 1}) {  // by its stiffness, by its modes
    const cg::ModalPlan p = cg::plan_modal(model.modal[static_cast<size_t>(body)]);
    REQUIRE(p.modes == 6);
    for (int i = 0; i < 6; ++i) CHECK(p.omega[i] == doctest::Approx(expected[static_cast<size_t>(i)]).epsilon(1e-9));
    // The lowest mode is along z (k = 250): b moves the golden ratio times a.
    const cg::ModalNode a = cg::modal_node(p, 3), b = cg::modal_node(p, 4);
    CHECK(b.displacement(2, 0) / a.displacement(2, 0) == doctest::Approx((1 + std::sqrt(5.0)) / 2).epsilon(1e-9));
    CHECK(a.displacement.col(0).head<2>().norm() < 1e-12);
    // Unit modal mass: m (a^2 + b^2) = 1.
    CHECK(0.5 * (a.displacement.col(0).squaredNorm() + b.displacement.col(0).squaredNorm()) == doctest::Approx(1.0).epsilon(1e-9));
    CHECK(p.m == doctest::Approx(1.6));
  }
}

namespace {

// Outputs after 10 s, displacements from the nodes' places at rest; the
// input tip_motor commands 0.5 N m.
struct SettledLoads {
  Vec3 a, b, a_m, b_m, middle, tip, middle_t, tip_t;
  double tip_turn_y, tip_turn_z, middle_turn_z, tip_t_turn;
};

struct LoadOutputs {
  int a, b, a_m, b_m, middle, tip, middle_t, tip_t;
};

template <class State, class Step, class Outputs, class OutputsOf>
SettledLoads settle(State s, Step step, Outputs y, OutputsOf outputs, LoadOutputs at, int motor, double h) {
  s.inputs[static_cast<size_t>(motor)] = 0.5;
  const int steps = static_cast<int>(std::lround(10.0 / h));
  for (int i = 0; i < steps; ++i) REQUIRE(step(s) == mbrt::StepStatus::ok);
  outputs(s, y);
  const auto place = [&](int k) { return Vec3(y[static_cast<size_t>(k)], y[static_cast<size_t>(k + 1)], y[static_cast<size_t>(k + 2)]); };
  // body_pose: x, y, z, then Euler parameters e0..e3; a small turn is 2 e.
  const auto turn = [&](int k, int axis) { return 2 * y[static_cast<size_t>(k + 4 + axis)]; };
  return {place(at.a) - Vec3(1, 0, 0),      place(at.b) - Vec3(2, 0, 0),         place(at.a_m) - Vec3(1, 0, 1),
          place(at.b_m) - Vec3(2, 0, 1),    place(at.middle) - Vec3(0.5, 0, 2), place(at.tip) - Vec3(1, 0, 2),
          place(at.middle_t) - Vec3(0.5, 0, 3), place(at.tip_t) - Vec3(1, 0, 3), turn(at.tip, 1),
          turn(at.tip, 2),                  turn(at.middle, 2),                  turn(at.tip_t, 2)};
}

}  // namespace

TEST_CASE("modal bodies from data files, held and loaded, settle at the closed-form static displacements") {
  namespace l = mbrt::models::modal_file_loads;
  namespace b = mbrt::models::modal_file_loads_blajer;
  const SettledLoads pcst = settle(l::initial_state(), [](l::State& s) { return l::step(s); }, l::Outputs{},
                                   [](const l::State& s, l::Outputs& y) { l::outputs(s, y); },
                                   LoadOutputs{l::output::a, l::output::b, l::output::a_m, l::output::b_m, l::output::middle,
                                               l::output::tip, l::output::middle_t, l::output::tip_t},
                                   l::input::tip_motor, l::kStep);
  const SettledLoads blajer = settle(b::initial_state(), [](b::State& s) { return b::step(s); }, b::Outputs{},
                                     [](const b::State& s, b::Outputs& y) { b::outputs(s, y); },
                                     LoadOutputs{b::output::a, b::output::b, b::output::a_m, b::output::b_m, b::output::middle,
                                                 b::output::tip, b::output::middle_t, b::output::tip_t},
                                     b::input::tip_motor, b::kStep);
  // The chain: P = (3, 2, 1) N on b, springs k = (1000, 400, 250) N/m.
  const Vec3 a = Vec3(3.0 / 1000, 2.0 / 400, 1.0 / 250), b2 = 2 * a;
  // The cantilever: P = (10, 2, 3) N at the tip, L = 1 m, EA = 2e4 N, EI = 100
  // (x-y) and 150 (x-z) N m^2; its middle at x = L / 2.
  const double L = 1.0, EA = 2.0e4, EIz = 100.0, EIy = 150.0;
  const Vec3 tip(10 * L / EA, 2 * L * L * L / (3 * EIz), 3 * L * L * L / (3 * EIy));
  const Vec3 middle(10 * (L / 2) / EA, 5 * 2 * L * L * L / (48 * EIz), 5 * 3 * L * L * L / (48 * EIy));
  const double tip_turn_z = 2 * L * L / (2 * EIz), tip_turn_y = -3 * L * L / (2 * EIy);
  const double middle_turn_z = 2 * (L / 2) * (2 * L - L / 2) / (2 * EIz);  // P x (2L - x) / (2 EI)
  // The torque M = 1.5 N m about z at frame_t's tip.
  const double M = 1.5;
  const Vec3 tip_t(0, M * L * L / (2 * EIz), 0), middle_t(0, M * (L / 2) * (L / 2) / (2 * EIz), 0);
  for (const SettledLoads& r : {pcst, blajer}) {
    MESSAGE("10 s: chain b " << r.b.transpose() << " m (closed form " << b2.transpose() << "), given by modes "
                             << r.b_m.transpose() << "; cantilever tip " << r.tip.transpose() << " (" << tip.transpose()
                             << "), turned " << r.tip_turn_y << ", " << r.tip_turn_z << " rad (" << tip_turn_y << ", "
                             << tip_turn_z << "); under the torque: tip " << r.tip_t.transpose() << " ("
                             << tip_t.transpose() << "), turned " << r.tip_t_turn << " (" << M * L / EIz << ")");
    // All modes kept, at rest: exact to the solver's round-off, less the
    // small rotation's second order in the turn (2 e = theta (1 - theta^2 / 24)).
    CHECK((r.a - a).norm() < 1e-9);
    CHECK((r.b - b2).norm() < 1e-9);
    CHECK((r.a_m - a).norm() < 1e-9);
    CHECK((r.b_m - b2).norm() < 1e-9);
    CHECK((r.tip - tip).norm() < 1e-9);
    CHECK((r.middle - middle).norm() < 1e-9);
    CHECK(r.tip_turn_z == doctest::Approx(tip_turn_z).epsilon(1e-4));
    CHECK(r.tip_turn_y == doctest::Approx(tip_turn_y).epsilon(1e-4));
    CHECK(r.middle_turn_z == doctest::Approx(middle_turn_z).epsilon(1e-4));
    // A torque at a node whose rotations carry no mass reaches the modes
    // through the translations it moves, exactly; the node's own turn lacks
    // the rotations' local static part (docs/flexible.md): 0.0129 of 0.015 rad.
    CHECK((r.tip_t - tip_t).norm() < 1e-9);
    CHECK((r.middle_t - middle_t).norm() < 1e-9);
    CHECK(r.tip_t_turn > 0.8 * M * L / EIz);
    CHECK(r.tip_t_turn < M * L / EIz);
  }
}

namespace {

// The truss's energy, momentum and angular momentum summed over its nodes:
// kinetic energy of the displaced nodes plus the strain energy
// u^T K u / 2 of the file's stiffness K, independent of the step's invariants.
class TrussMass {
 public:
  explicit TrussMass(const cg::ModalSource& source) : s_(*source.structure), plan_(cg::plan_modal(source)) {}

  struct Totals {
    double energy;
    Vec3 momentum, angular_momentum;
  };

  Totals totals(const mbrt::RigidState& b, const Eigen::VectorXd& q, const Eigen::VectorXd& p) const {
    const mbrt::Mat3 R = Eigen::Quaterniond(b.p[0], b.p[1], b.p[2], b.p[3]).toRotationMatrix();
    // p = qdot + St^T R^T v + Sr(q)^T w, summed over the nodes.
    Eigen::MatrixXd St_T = Eigen::MatrixXd::Zero(plan_.modes, 3), Sr_T = St_T;
    for (size_t k = 0; k < s_.nodes.size(); ++k) {
      const Eigen::MatrixXd D = displacement(k);
      const Vec3 rho = place(k) + D * q;
      for (int j = 0; j < plan_.modes; ++j) {
        St_T.row(j) += s_.nodes[k].mass * D.col(j).transpose();
        Sr_T.row(j) += s_.nodes[k].mass * rho.cross(Vec3(D.col(j))).transpose();
      }
    }
    const Eigen::VectorXd qd = p - St_T * (R.transpose() * b.v) - Sr_T * b.w;
    Totals t{0, Vec3::Zero(), Vec3::Zero()};
    Eigen::VectorXd u(3 * static_cast<Eigen::Index>(s_.nodes.size()));
    for (size_t k = 0; k < s_.nodes.size(); ++k) {
      const Eigen::MatrixXd D = displacement(k);
      const Vec3 rho = place(k) + D * q, v = b.v + R * (b.w.cross(rho) + D * qd);
      const double m = s_.nodes[k].mass;
      t.energy += 0.5 * m * v.squaredNorm();
      t.momentum += m * v;
      t.angular_momentum += m * (b.r + R * rho).cross(v);
      u.segment<3>(3 * static_cast<Eigen::Index>(k)) = D * q;
    }
    t.energy += 0.5 * u.dot(s_.stiffness * u);
    return t;
  }

 private:
  Vec3 place(size_t k) const { return s_.nodes[k].position - s_.centre; }
  Eigen::MatrixXd displacement(size_t k) const { return plan_.shapes.block(6 * static_cast<Eigen::Index>(k), 0, 3, plan_.modes); }

  cg::ModalStructure s_;
  cg::ModalPlan plan_;
};

template <class State, class Step>
modal_momenta::Conservation truss_errors(State s, Step step, double h) {
  const TrussMass truss(cg::load_model(kModels + "/modal_file_free.yaml").modal[0]);
  const auto totals = [&](const State& x) { return truss.totals(x.rigid[0], x.modal_q[0].head(6), x.modal_p[0].head(6)); };
  return modal_momenta::conservation_errors(
      s, step, [&](const State& x) { return totals(x).energy; },
      [&](const State& x) {
        const TrussMass::Totals t = totals(x);
        return std::array<Vec3, 2>{t.momentum, t.angular_momentum};
      },
      h);
}

}  // namespace

TEST_CASE("a free truss from a data file keeps its energy, momentum and angular momentum to second order in the step") {
  namespace m = mbrt::models::modal_file_free;
  namespace f = mbrt::models::modal_file_free_fine;
  const modal_momenta::Conservation coarse = truss_errors(m::initial_state(), [](m::State& s) { return m::step(s); }, m::kStep);
  const modal_momenta::Conservation fine = truss_errors(f::initial_state(), [](f::State& s) { return f::step(s); }, f::kStep);
  MESSAGE("10 s, relative errors at 1 ms: energy " << coarse.energy << ", momentum " << coarse.momentum << ", angular momentum "
                                                   << coarse.angular_momentum << "; at 0.25 ms: " << fine.energy << ", "
                                                   << fine.momentum << ", " << fine.angular_momentum
                                                   << "; largest modal coordinate " << coarse.largest_q);
  CHECK(coarse.largest_q > 1e-3);  // the spin does stretch it
  CHECK(coarse.energy < 1e-4);
  CHECK(coarse.momentum < 1e-6);
  CHECK(coarse.angular_momentum < 1e-3);
  CHECK(fine.energy < coarse.energy / 8);
  CHECK(fine.angular_momentum < coarse.angular_momentum / 8);
}

TEST_CASE("the generator names the data file, its line and what is wrong") {
  const std::string body = "name: bad\nbodies:\n  - name: part\n    flexible: {file: ";
  const auto with_file = [&](const std::string& name, const std::string& text) {
    const TemporaryFile file(name, text);
    return generator_error(body + file.path.string() + ", modes: 2}\n");
  };
  const std::string nodes =
      "coordinates: 3\nnodes:\n  - {name: root, position: [0, 0, 0], mass: 1}\n  - {name: base, position: [0, 1, 0], mass: 1}\n"
      "  - {name: a, position: [1, 0, 0], mass: 1}\n  - {name: b, position: [2, 0, 0], mass: 1}\n";
  // A chain root - a - b of 100 N/m springs along x, y and z.
  std::string rows;
  for (int i = 0; i < 12; ++i) {
    std::array<double, 12> r{};
    const int node = i / 3, d = i % 3;
    const auto spring = [&](int n1, int n2) {
      if (node != n1 && node != n2) return;
      r[static_cast<size_t>(3 * n1 + d)] += node == n1 ? 100 : -100;
      r[static_cast<size_t>(3 * n2 + d)] += node == n1 ? -100 : 100;
    };
    spring(0, 2), spring(2, 3);
    rows += "  - [";
    for (size_t j = 0; j < 12; ++j) rows += (j ? ", " : "") + std::to_string(r[j]);
    rows += "]\n";
  }
  CHECK(with_file("good.yaml", nodes + "clamped: [root, base]\nstiffness:\n" + rows) == "");

  const std::string missing = generator_error(body + "no_such_file.yaml, modes: 2}\n");
  CHECK(missing.find("bodies[0].flexible.file") != std::string::npos);
  CHECK(missing.find("cannot open the modal data file") != std::string::npos);
  CHECK(missing.find("no_such_file.yaml") != std::string::npos);

  const std::string short_row = with_file("short.yaml", nodes + "clamped: [root]\nstiffness:\n" + rows.substr(0, rows.rfind(", ")) + "]\n");
  CHECK(short_row.find("mbrt_test_modal_file_short.yaml:") != std::string::npos);
  CHECK(short_row.find("stiffness[11]: expected a row of 12 numbers (3 per node), got a list of 11 items") != std::string::npos);

  std::string skewed = rows;
  skewed.replace(skewed.find("-100.000000"), 11, "-90.000000");
  CHECK(with_file("skew.yaml", nodes + "clamped: [root]\nstiffness:\n" + skewed).find("stiffness: not symmetric: row 6, column 0 is -100, row 0, column 6 is -90") !=
        std::string::npos);

  CHECK(with_file("clamp.yaml", nodes + "clamped: [tip]\nstiffness:\n" + rows).find("clamped[0]: unknown node 'tip'") !=
        std::string::npos);
  // Unclamped, the chain's springs (each along one direction) resist a rigid
  // turn, and base hangs on none: it has 6 zero frequencies, but not the rigid body's.
  CHECK(with_file("free.yaml", nodes + "stiffness:\n" + rows).find("must move freely as a rigid body, but a rigid turn about y strains it") !=
        std::string::npos);
  CHECK(with_file("both.yaml", nodes + "clamped: [root]\nstiffness:\n" + rows + "modes: []\n")
            .find("give either stiffness (its modes are computed) or modes (frequencies and shapes), not both") != std::string::npos);
  const std::string skew_modes =
      nodes + "clamped: [root, base]\nmodes:\n  - {frequency: 1.0, shape: [[0, 0, 0], [0, 0, 0], [1, 0, 0], [1, 0, 0]]}\n"
              "  - {frequency: 2.0, shape: [[0, 0, 0], [0, 0, 0], [1, 0, 0], [0, 0, 0]]}\n";
  CHECK(with_file("modes.yaml", skew_modes).find("modes 1 and 2 are not orthogonal in the nodes' mass") != std::string::npos);
  const std::string moving_clamp =
      nodes + "clamped: [root, base]\nmodes:\n  - {frequency: 1.0, shape: [[0, 0, 0], [0, 0, 1], [1, 0, 0], [1, 0, 0]]}\n"
              "  - {frequency: 2.0, shape: [[0, 0, 0], [0, 0, 0], [1, 0, 0], [-1, 0, 0]]}\n";
  CHECK(with_file("clamp_moves.yaml", moving_clamp).find("mode 1 moves clamped node 'base'") != std::string::npos);
  const std::string line = "coordinates: 3\nnodes:\n  - {name: a, position: [0, 0, 0], mass: 1}\n  - {name: b, position: [1, 0, 0], mass: 1}\n"
                           "clamped: [a]\nmodes:\n  - {frequency: 1.0, shape: [[0, 0, 0], [0, 1, 0]]}\n";
  CHECK(with_file("line.yaml", line).find("no inertia about some axis") != std::string::npos);

  // Nodes and attachments: a joint where the modes are clamped, forces at nodes by name or number.
  const TemporaryFile chain("chain.yaml", nodes + "clamped: [root, base]\nstiffness:\n" + rows);
  const std::string part = body + chain.path.string() + ", modes: 2}\n";
  CHECK(generator_error(part + "joints:\n  - {name: hold, type: fixed, body1: ground, body2: part, point: [0, 1, 0]}\n"
                               "forces:\n  - {type: force, body: part@b, vector: [1, 0, 0]}\n  - {type: force, body: part@2, vector: [1, 0, 0]}\n") == "");
  const std::string off = generator_error(part + "joints:\n  - {name: hold, type: fixed, body1: ground, body2: part, point: [1, 0, 0]}\n");
  CHECK(off.find("away from where its modes are clamped; put it at part@root (0.000000, 0.000000, 0.000000 at t = 0), part@base") !=
        std::string::npos);
  CHECK(generator_error(part + "forces:\n  - {type: force, body: part@c, vector: [1, 0, 0]}\n")
            .find("unknown node 'c' of modal body 'part' (its nodes in") != std::string::npos);
  CHECK(generator_error(part + "joints:\n  - {name: hold, type: fixed, body1: ground, body2: part@root, point: [0, 0, 0]}\n")
            .find("attaches at one of its clamped nodes' places") != std::string::npos);
}

TEST_CASE("the generator warns where a structure from a file could spin near its lowest frequency") {
  // The truss's lowest frequency is 70.7 rad/s: the warning starts at 0.3 of
  // it; the energy bound turns the spin about z to 30.3 rad/s about its middle axis.
  const auto warning = [](double spin) {
    const cg::Model m = cg::parse_model("name: spinning\nbodies:\n  - name: truss\n    flexible: {file: modal_data/octahedron.yaml, "
                                        "modes: 6}\n    angular_velocity: [0, 0, " + std::to_string(spin) + "]\n",
                                        kModels + "/inline.yaml");
    return cg::modal_spin_warning(m, cg::estimate_stable_step(m));
  };
  CHECK(warning(15.0) == "");
  const std::string fast = warning(30.0);
  CHECK(fast.find("modal body truss (from " + kModels + "/modal_data/octahedron.yaml) has no geometric stiffness") != std::string::npos);
  CHECK(fast.find("could turn at 30.3 rad/s, 0.429 of its lowest mode's 70.7 rad/s") != std::string::npos);
}
