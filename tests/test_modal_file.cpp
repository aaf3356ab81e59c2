// Modal bodies from data files (docs/flexible.md, "Modal data from a
// file"): a spring chain's modes computed from its stiffness have the
// closed-form frequencies; held at their clamped nodes and loaded (forces,
// a torque and a motor_torque input at nodes), the chain (by its stiffness
// and by its modes) and a two-element cantilever settle at the closed-form
// static displacements and slopes; free structures (of nodes with mass, and
// with inertia that turns) keep their energy (summed over the nodes with the
// file's stiffness), momentum and angular momentum; a spinning cantilever
// with the file's geometric stiffness swings out of its plane of rotation at
// the published frequencies; the generator's messages on bad files, and its
// warning where a structure without geometric stiffness could spin too fast.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "analysis.hpp"
#include "generator_error.hpp"
#include "modal_body.hpp"
#include "modal_file_free.hpp"
#include "modal_file_free_fine.hpp"
#include "modal_file_loads.hpp"
#include "modal_file_loads_blajer.hpp"
#include "modal_momenta.hpp"
#include "modal_spinning_file.hpp"
#include "model.hpp"
#include "stable_step.hpp"

namespace {

using mbrt::Vec3;
namespace cg = mbrt::codegen;

const std::string kModels = MBRT_TEST_MODELS;
const std::string kInline = kModels + "/inline.yaml";  // data files resolve from the test models

// A data file in the temporary directory, removed after the test.
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
  double tip_turn_y, tip_turn_z, middle_turn_z, tip_t_turn, middle_t_turn;
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
          turn(at.tip, 2),                  turn(at.middle, 2),                  turn(at.tip_t, 2),
          turn(at.middle_t, 2)};
}

}  // namespace

TEST_CASE("a static shape of a file's structure gives the torque at its massless rotation its closed form") {
  // frame_s (tests/models/modal_file_loads.yaml): two modes and the static
  // shape of a torque about z at the tip, under M = 1.5 N m there; L = 1 m,
  // EI = 100 N m^2 (x-y). Euler-Bernoulli: turned by M x / EI, at M x^2 / (2 EI).
  namespace l = mbrt::models::modal_file_loads;
  l::State s = l::initial_state();
  for (int i = 0; i < static_cast<int>(std::lround(10.0 / l::kStep)); ++i) REQUIRE(l::step(s) == mbrt::StepStatus::ok);
  l::Outputs y{};
  l::outputs(s, y);
  const double M = 1.5, L = 1.0, EI = 100.0;
  const double tip = y[l::output::tip_s + 1], tip_turn = 2 * y[l::output::tip_s + 6], middle_turn = 2 * y[l::output::middle_s + 6];
  MESSAGE("tip " << tip << " m (" << M * L * L / (2 * EI) << "), turned " << tip_turn << " rad (" << M * L / EI << "), middle turned "
                 << middle_turn << " (" << M * L / (2 * EI) << ")");
  CHECK(tip == doctest::Approx(M * L * L / (2 * EI)).epsilon(1e-6).scale(0));
  // A small turn's Euler parameters: 2 e = theta (1 - theta^2 / 24).
  CHECK(tip_turn == doctest::Approx(M * L / EI).epsilon(1e-4).scale(0));
  CHECK(middle_turn == doctest::Approx(M * L / (2 * EI)).epsilon(1e-4).scale(0));
}

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
    CHECK(r.tip_turn_z == doctest::Approx(tip_turn_z).epsilon(1e-4).scale(0));
    CHECK(r.tip_turn_y == doctest::Approx(tip_turn_y).epsilon(1e-4).scale(0));
    CHECK(r.middle_turn_z == doctest::Approx(middle_turn_z).epsilon(1e-4).scale(0));
    // A torque on rotations that carry no mass (condensed) reaches the modes
    // through the translations it moves, exactly; the rotations then lack
    // their own static part K_bb^-1 M (Guyan's condensation: docs/flexible.md).
    // Here K_bb = (EI / l) [8 2; 2 4] over the middle's and the tip's turns
    // about z (l = L / 2): the tip turns M L / EI - 8 M l / (28 EI) = 0.012857
    // rad, not 0.015; the middle M L / (2 EI) + 2 M l / (28 EI).
    const double l = L / 2;
    CHECK((r.tip_t - tip_t).norm() < 1e-9);
    CHECK((r.middle_t - middle_t).norm() < 1e-9);
    CHECK(r.tip_t_turn == doctest::Approx(M * L / EIz - 8 * M * l / (28 * EIz)).epsilon(1e-4).scale(0));
    CHECK(r.middle_t_turn == doctest::Approx(M * L / (2 * EIz) + 2 * M * l / (28 * EIz)).epsilon(1e-4).scale(0));
  }
}

namespace {

// A structure's energy, momentum and angular momentum summed over its nodes:
// each node's mass at its displaced place, and its inertia turned by its
// small rotation theta (I + [theta]x I - I [theta]x, first order) at the
// angular velocity w + Theta qdot; plus the strain energy u^T K u / 2 of the
// file's stiffness K. Independent of the step's invariants.
class StructureMass {
 public:
  explicit StructureMass(const cg::ModalSource& source) : s_(*source.structure), plan_(cg::plan_modal(source)) {}

  struct Totals {
    double energy;
    Vec3 momentum, angular_momentum;
  };

  Totals totals(const mbrt::RigidState& b, const Eigen::VectorXd& q, const Eigen::VectorXd& p) const {
    const mbrt::Mat3 R = Eigen::Quaterniond(b.p[0], b.p[1], b.p[2], b.p[3]).toRotationMatrix();
    // p = qdot + St^T R^T v + Sr(q)^T w, summed over the nodes.
    Eigen::MatrixXd St_T = Eigen::MatrixXd::Zero(plan_.modes, 3), Sr_T = St_T;
    for (size_t k = 0; k < s_.nodes.size(); ++k) {
      const Eigen::MatrixXd D = rows(k, 0), T = rows(k, 3);
      const Vec3 rho = place(k) + D * q;
      const mbrt::Mat3 I = turned_inertia(k, T * q);
      for (int j = 0; j < plan_.modes; ++j) {
        St_T.row(j) += s_.nodes[k].mass * D.col(j).transpose();
        Sr_T.row(j) += (s_.nodes[k].mass * rho.cross(Vec3(D.col(j))) + I * T.col(j)).transpose();
      }
    }
    const Eigen::VectorXd qd = p - St_T * (R.transpose() * b.v) - Sr_T * b.w;
    const int c = s_.coordinates;
    Totals t{0, Vec3::Zero(), Vec3::Zero()};
    Eigen::VectorXd u(c * static_cast<Eigen::Index>(s_.nodes.size()));
    for (size_t k = 0; k < s_.nodes.size(); ++k) {
      const Eigen::MatrixXd D = rows(k, 0), T = rows(k, 3);
      const Vec3 rho = place(k) + D * q, v = b.v + R * (b.w.cross(rho) + D * qd), w = b.w + T * qd;
      const mbrt::Mat3 I = turned_inertia(k, T * q);
      const double m = s_.nodes[k].mass;
      t.energy += 0.5 * m * v.squaredNorm() + 0.5 * w.dot(I * w);
      t.momentum += m * v;
      t.angular_momentum += m * (b.r + R * rho).cross(v) + R * (I * w);
      u.segment(c * static_cast<Eigen::Index>(k), c) = plan_.shapes.middleRows(6 * static_cast<Eigen::Index>(k), c) * q;
    }
    t.energy += 0.5 * u.dot(s_.stiffness * u);
    return t;
  }

 private:
  Vec3 place(size_t k) const { return s_.nodes[k].position - s_.centre; }
  // The node's displacement (first = 0) or small rotation (first = 3) per mode.
  Eigen::MatrixXd rows(size_t k, int first) const {
    return plan_.shapes.block(6 * static_cast<Eigen::Index>(k) + first, 0, 3, plan_.modes);
  }
  mbrt::Mat3 turned_inertia(size_t k, const Vec3& theta) const {
    const mbrt::Mat3& I = s_.nodes[k].inertia;
    return I + mbrt::skew(theta) * I - I * mbrt::skew(theta);
  }

  cg::ModalStructure s_;
  cg::ModalPlan plan_;
};

// Body `body`'s drift from conservation in the free model.
template <class State, class Step>
modal_momenta::Conservation free_errors(State s, Step step, int body, int rigid, int modal, double h) {
  const StructureMass structure(cg::load_model(kModels + "/modal_file_free.yaml").modal[static_cast<size_t>(body)]);
  const auto totals = [&](const State& x) {
    return structure.totals(x.rigid[static_cast<size_t>(rigid)], x.modal_q[static_cast<size_t>(modal)].head(6),
                            x.modal_p[static_cast<size_t>(modal)].head(6));
  };
  return modal_momenta::conservation_errors(
      s, step, [&](const State& x) { return totals(x).energy; },
      [&](const State& x) {
        const StructureMass::Totals t = totals(x);
        return std::array<Vec3, 2>{t.momentum, t.angular_momentum};
      },
      h);
}

}  // namespace

TEST_CASE("free structures from data files keep their energy, momentum and angular momentum to second order in the step") {
  namespace m = mbrt::models::modal_file_free;
  namespace f = mbrt::models::modal_file_free_fine;
  const auto step = [](m::State& s) { return m::step(s); };
  const auto fine_step = [](f::State& s) { return f::step(s); };
  // The truss: nodes of mass alone.
  const modal_momenta::Conservation coarse = free_errors(m::initial_state(), step, 0, m::rigid::truss, m::modal::truss, m::kStep);
  const modal_momenta::Conservation fine = free_errors(f::initial_state(), fine_step, 0, f::rigid::truss, f::modal::truss, f::kStep);
  // The tumbler: nodes whose inertia turns with the modes.
  const modal_momenta::Conservation turning =
      free_errors(m::initial_state(), step, 1, m::rigid::tumbler, m::modal::tumbler, m::kStep);
  const modal_momenta::Conservation turning_fine =
      free_errors(f::initial_state(), fine_step, 1, f::rigid::tumbler, f::modal::tumbler, f::kStep);
  for (const auto& [name, c, cf] : {std::tuple{std::string("truss"), coarse, fine}, std::tuple{std::string("tumbler"), turning, turning_fine}}) {
    MESSAGE(name << ", 10 s, relative errors at 1 ms: energy " << c.energy << ", momentum " << c.momentum << ", angular momentum "
                 << c.angular_momentum << "; at 0.25 ms: " << cf.energy << ", " << cf.momentum << ", " << cf.angular_momentum);
    CHECK(c.momentum < 1e-6);
  }
  CHECK(coarse.energy < 1e-4);
  CHECK(coarse.angular_momentum < 1e-3);
  CHECK(fine.energy < coarse.energy / 8);
  CHECK(fine.angular_momentum < coarse.angular_momentum / 8);
  // The tumbler's reference turns the nodes' inertia to first order in
  // their small rotations: about 1e-6 apart from the step's second-order
  // model at any step. Leaving that turn out of the reference shows 1.6e-4
  // in energy and 3.7e-5 in angular momentum: the checks see terms of the
  // first order in the nodes' turns.
  CHECK(turning.energy < 1e-5);
  CHECK(turning.angular_momentum < 1e-5);
  CHECK(turning_fine.energy < 1e-5);
  CHECK(turning_fine.angular_momentum < 1e-5);
  MESSAGE("the truss's largest modal coordinate " << coarse.largest_q);
  CHECK(coarse.largest_q > 1e-3);  // the spin does stretch it
}

// The first out-of-plane frequency of a uniform cantilever spinning about an
// axis through its root, omega / sqrt(EI / (rho_A L^4)), at spin rates
// Omega / sqrt(EI / (rho_A L^4)) = 0 to 5: Wright, Smith, Thresher & Wang
// 1982, "Vibration modes of centrifugally stiffened beams", J. Applied
// Mechanics 49(1), table 1 (Southwell's coefficient about 1.19 at low spin).
constexpr std::array<double, 6> kSpinningFlapFrequency = {3.5160, 3.6816, 4.1373, 4.7973, 5.5850, 6.4495};

TEST_CASE("a cantilever from a data file with its geometric stiffness stiffens with spin at the published rate") {
  // modal_data/spinning_beam.yaml: 12 elements, EI 10 N m^2, rho_A 1 kg/m,
  // L 1 m; its spin cases are about the root, its frame at the middle.
  const double unit = std::sqrt(10.0);
  const cg::Model m = cg::parse_model("name: spinning\nbodies:\n  - name: beam\n    flexible: {file: modal_data/spinning_beam.yaml, modes: 4}\n",
                                      kModels + "/inline.yaml");
  const cg::ModalPlan p = cg::plan_modal(m.modal[0]);
  REQUIRE(m.modal[0].structure->spin_stiffens());
  const double centre = m.modal[0].structure->centre.x();
  CHECK(centre == doctest::Approx(0.5));
  for (size_t k = 0; k < kSpinningFlapFrequency.size(); ++k) {
    // Spun at Omega about z through the root, the frame (at the middle)
    // accelerates by -Omega^2 centre along x.
    const double spin = static_cast<double>(k) * unit;
    const Eigen::MatrixXd K = Eigen::MatrixXd(p.omega.cwiseAbs2().asDiagonal()) + spin * spin * p.kg[cg::kSpinZZ] -
                              spin * spin * centre * p.kg[cg::kAccelerationX];
    const double lowest = std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K).eigenvalues()[0]) / unit;
    MESSAGE("spin " << k << ": " << lowest << " (published " << kSpinningFlapFrequency[k] << ")");
    CHECK(lowest == doctest::Approx(kSpinningFlapFrequency[k]).epsilon(0.005));
  }
  // Beside it, the same beam spun about y: the yy case alike.
  CHECK((p.kg[cg::kSpinYY] - p.kg[cg::kSpinZZ]).norm() < 1e-9 * p.kg[cg::kSpinZZ].norm());
}

TEST_CASE("a file's spin cases, moved to the frame, give the stiffness of a spin about the file's origin with the frame's acceleration") {
  // Three point masses in a triangle off every axis (the first clamped),
  // springs between them, and nine arbitrary symmetric load cases. Spun at
  // w about the file's origin, the frame (the nodes' centre c) accelerates
  // by w x (w x c): the step's sum over the cases at that spin and
  // acceleration is the file's spin cases at w, projected on the modes.
  cg::ModalStructure s;
  s.file = "triangle";
  s.coordinates = 3;
  s.nodes = {{"a", {0.3, -0.2, 0.5}, 1.0, {}}, {"b", {1.1, 0.4, 0.2}, 2.0, {}}, {"c", {0.6, 0.9, -0.4}, 1.5, {}}};
  s.clamped = {0};
  for (const cg::ModalNodeData& d : s.nodes) s.centre += d.mass * d.position / 4.5;
  const auto spring = [](const Eigen::Vector3d& x1, const Eigen::Vector3d& x2, double k) {
    const Eigen::Vector3d e = (x2 - x1).normalized();
    return Eigen::Matrix3d(k * e * e.transpose());
  };
  s.stiffness = Eigen::MatrixXd::Zero(9, 9);
  const std::array<std::array<int, 2>, 3> ties = {{{0, 1}, {1, 2}, {0, 2}}};
  for (const auto& [i, j] : ties) {
    const Eigen::Matrix3d k = spring(s.nodes[static_cast<size_t>(i)].position, s.nodes[static_cast<size_t>(j)].position, 1000.0);
    s.stiffness.block<3, 3>(3 * i, 3 * i) += k, s.stiffness.block<3, 3>(3 * j, 3 * j) += k;
    s.stiffness.block<3, 3>(3 * i, 3 * j) -= k, s.stiffness.block<3, 3>(3 * j, 3 * i) -= k;
  }
  // Out of the plane the triangle needs a hold: a soft spring to ground at b and c.
  s.stiffness.diagonal().tail<6>().array() += 50.0;
  std::srand(11);
  for (Eigen::MatrixXd& g : s.geometric_stiffness) {
    const Eigen::MatrixXd r = Eigen::MatrixXd::Random(9, 9);
    g = r + r.transpose();
  }
  const cg::ModalPlan p = cg::plan_modal_structure(s, 6, 0.0);
  Eigen::MatrixXd shapes(9, 6);  // over the file's 3 coordinates a node
  for (int k = 0; k < 3; ++k) shapes.middleRows(3 * k, 3) = p.shapes.middleRows(6 * k, 3);
  for (const Eigen::Vector3d& w : {Eigen::Vector3d(0.3, -1.2, 2.0), Eigen::Vector3d(-2.5, 0.7, 0.4)}) {
    const std::array<double, 6> products = {w.x() * w.x(), w.y() * w.y(), w.z() * w.z(), w.x() * w.y(), w.x() * w.z(), w.y() * w.z()};
    const Eigen::Vector3d a = w.cross(w.cross(s.centre));
    Eigen::MatrixXd step = Eigen::MatrixXd::Zero(6, 6), about_origin = step;
    for (size_t k = 0; k < 6; ++k) {
      step += products[k] * p.kg[k];
      about_origin += products[k] * shapes.transpose() * s.geometric_stiffness[k] * shapes;
    }
    for (size_t i = 0; i < 3; ++i) step += a[static_cast<Eigen::Index>(i)] * p.kg[cg::kAccelerationX + i];
    CHECK((step - about_origin).norm() < 1e-10 * about_origin.norm());
  }
  // Without spin cases nothing is moved: acceleration cases alone give no spin terms.
  for (size_t k = 0; k < 6; ++k) s.geometric_stiffness[k].resize(0, 0);
  const cg::ModalPlan accelerating = cg::plan_modal_structure(s, 6, 0.0);
  for (size_t k = 0; k < 6; ++k) CHECK(accelerating.kg[k].isZero(0.0));
  CHECK(!accelerating.kg[cg::kAccelerationX].isZero(0.0));
}

TEST_CASE("spinning cantilevers from a data file swing out of their plane of rotation at the published frequency at 1 kHz") {
  // tests/models/modal_spinning_file.yaml: hubs driven at 3 sqrt(EI / (rho_A L^4))
  // about z and about y; a tip force normal to each plane of rotation.
  namespace m = mbrt::models::modal_spinning_file;
  const double unit = std::sqrt(10.0);
  m::State s = m::initial_state();
  m::Outputs y{};
  std::array<std::vector<double>, 2> swing;
  for (int i = 0; i < 6000; ++i) {  // 6 s, about 14 periods
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    m::outputs(s, y);
    swing[0].push_back(y[m::output::tip_z + 2]);
    swing[1].push_back(y[m::output::tip_y + 1]);
  }
  for (const std::vector<double>& x : swing) {
    double mean = 0;
    for (const double v : x) mean += v / static_cast<double>(x.size());
    std::vector<double> up;
    for (size_t i = 1; i < x.size(); ++i) {
      if (x[i - 1] < mean && x[i] >= mean) up.push_back(static_cast<double>(i) * m::kStep);
    }
    REQUIRE(up.size() > 10);
    const double period = (up.back() - up.front()) / static_cast<double>(up.size() - 1);
    const double frequency = 2 * M_PI / period / unit;
    MESSAGE("out of plane: " << frequency << " sqrt(EI / (rho_A L^4)) (published " << kSpinningFlapFrequency[3] << ", not spinning "
                             << kSpinningFlapFrequency[0] << "), tip between " << *std::min_element(x.begin(), x.end()) << " and "
                             << *std::max_element(x.begin(), x.end()) << " m");
    CHECK(frequency == doctest::Approx(kSpinningFlapFrequency[3]).epsilon(0.005));
  }
}

TEST_CASE("the generator names the data file, its line and what is wrong") {
  const std::string body = "name: bad\nbodies:\n  - name: part\n    flexible: {file: ";
  const auto with_file = [&](const std::string& name, const std::string& text) {
    const TemporaryFile file(name, text);
    return generator_error(body + file.path.string() + ", modes: 2}\n", kInline);
  };
  const std::string nodes =
      "coordinates: 3\nnodes:\n  - {name: root, position: [0, 0, 0], mass: 1}\n  - {name: base, position: [0, 1, 0], mass: 1}\n"
      "  - {name: a, position: [1, 0, 0], mass: 1}\n  - {name: b, position: [2, 0, 0], mass: 1}\n";
  // A chain root - a - b of springs along x, y and z: k[d] N/m along axis d.
  const auto chain_rows = [](const std::array<double, 3>& k) {
    std::string rows;
    for (int i = 0; i < 12; ++i) {
      std::array<double, 12> r{};
      const int node = i / 3, d = i % 3;
      const auto spring = [&](int n1, int n2) {
        if (node != n1 && node != n2) return;
        r[static_cast<size_t>(3 * n1 + d)] += node == n1 ? k[static_cast<size_t>(d)] : -k[static_cast<size_t>(d)];
        r[static_cast<size_t>(3 * n2 + d)] += node == n1 ? -k[static_cast<size_t>(d)] : k[static_cast<size_t>(d)];
      };
      spring(0, 2), spring(2, 3);
      rows += "  - [";
      for (size_t j = 0; j < 12; ++j) rows += (j ? ", " : "") + std::to_string(r[j]);
      rows += "]\n";
    }
    return rows;
  };
  const std::string rows = chain_rows({100, 200, 300});
  CHECK(with_file("good.yaml", nodes + "clamped: [root, base]\nstiffness:\n" + rows) == "");
  // Alike along x, y and z, its modes come in threes of one frequency
  // (0.618 sqrt(k / m) = 6.18 rad/s first): 2 modes would split the first three.
  const std::string split = with_file("split.yaml", nodes + "clamped: [root, base]\nstiffness:\n" + chain_rows({100, 100, 100}));
  CHECK(split.find("2 modes kept, but modes 1 to 3 have the same frequency (0.98") != std::string::npos);
  CHECK(split.find("keep 3 modes, so that") != std::string::npos);
  const std::string given_pair =
      nodes + "clamped: [root, base]\nmodes:\n  - {frequency: 1.0, shape: [[0, 0, 0], [0, 0, 0], [1, 0, 0], [1, 0, 0]]}\n"
              "  - {frequency: 2.0, shape: [[0, 0, 0], [0, 0, 0], [0, 1, 0], [0, 1, 0]]}\n"
              "  - {frequency: 2.0, shape: [[0, 0, 0], [0, 0, 0], [0, 0, 1], [0, 0, 1]]}\n";
  CHECK(with_file("given_pair.yaml", given_pair).find("2 modes kept, but modes 2 and 3 have the same frequency (2.0") !=
        std::string::npos);

  const std::string missing = generator_error(body + "no_such_file.yaml, modes: 2}\n", kInline);
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

  CHECK(with_file("geometric.yaml", nodes + "clamped: [root, base]\nstiffness:\n" + rows + "geometric_stiffness:\n  spin_zz:\n" + rows) == "");
  CHECK(with_file("geometric_case.yaml", nodes + "clamped: [root]\nstiffness:\n" + rows + "geometric_stiffness:\n  spin_z:\n" + rows)
            .find("geometric_stiffness.spin_z: unknown key 'spin_z' (expected one of: spin_xx, spin_yy, spin_zz") != std::string::npos);
  const std::string skewed_case = with_file("geometric_skew.yaml", nodes + "clamped: [root]\nstiffness:\n" + rows +
                                                                       "geometric_stiffness:\n  acceleration_x:\n" + skewed);
  CHECK(skewed_case.find("mbrt_test_modal_file_geometric_skew.yaml:") != std::string::npos);
  CHECK(skewed_case.find("geometric_stiffness.acceleration_x: not symmetric: row 6, column 0 is -100, row 0, column 6 is -90") !=
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
                               "forces:\n  - {type: force, body: part@b, vector: [1, 0, 0]}\n  - {type: force, body: part@2, vector: [1, 0, 0]}\n", kInline) == "");
  const std::string off = generator_error(part + "joints:\n  - {name: hold, type: fixed, body1: ground, body2: part, point: [1, 0, 0]}\n", kInline);
  CHECK(off.find("away from where its modes are clamped; put it at part@root (0.000000, 0.000000, 0.000000 at t = 0), part@base") !=
        std::string::npos);
  CHECK(generator_error(part + "forces:\n  - {type: force, body: part@c, vector: [1, 0, 0]}\n", kInline)
            .find("unknown node 'c' of modal body 'part' (its nodes in") != std::string::npos);
  CHECK(generator_error(part + "joints:\n  - {name: hold, type: fixed, body1: ground, body2: part@root, point: [0, 0, 0]}\n", kInline)
            .find("node 'root' of modal body 'part' has no rotations (coordinates: 3 in ") != std::string::npos);
  CHECK(generator_error(part + "joints:\n  - {name: hold, type: planar, body1: ground, body2: part@root, point: [0, 0, 0], "
                               "axis: [1, 0, 0]}\n", kInline)
            .find("node 'root' of modal body 'part' has no rotations (coordinates: 3 in ") != std::string::npos);
  CHECK(generator_error(part + "forces:\n  - {type: torque, body1: ground, body2: part@b, axis: [0, 0, 1], value: 1}\n", kInline)
            .find("node 'b' of modal body 'part' has no rotations (coordinates: 3 in ") != std::string::npos);
  // Static loads at a structure's nodes: by name, along its own coordinates.
  const auto loaded = [&](const std::string& loads) {
    return generator_error(body + chain.path.string() + ", modes: 2, static_loads: " + loads + "}\n", kInline);
  };
  CHECK(loaded("{b: [x, y]}") == "");
  CHECK(loaded("{b: [rz]}").find("static_loads.b[0]: expected one of: x, y, z, got 'rz'") != std::string::npos);
  CHECK(loaded("{root: [x]}").find("node 'root' is clamped: a load there does not deform the structure") != std::string::npos);
  CHECK(loaded("{c: [x]}").find("unknown node 'c' of modal body 'part'") != std::string::npos);
  CHECK(generator_error(body + kModels + "/modal_data/chain_modes.yaml, modes: 2, static_loads: {b: [x]}}\n", kInline)
            .find("static_loads need the structure's stiffness and clamped nodes; ") != std::string::npos);
  // A free structure's given modes must carry no rigid-body motion: here the
  // first moves every node alike.
  const std::string free_modes =
      nodes + "modes:\n  - {frequency: 0.001, shape: [[1, 0, 0], [1, 0, 0], [1, 0, 0], [1, 0, 0]]}\n"
              "  - {frequency: 2.0, shape: [[0, 0, 0], [0, 0, 0], [1, 0, 0], [-1, 0, 0]]}\n";
  CHECK(with_file("free_modes.yaml", free_modes).find("mode 1 of the free structure carries a rigid-body move along x") !=
        std::string::npos);
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
  // A file with the geometric stiffness of spin stiffens: no warning, at
  // nine times its lowest frequency.
  const cg::Model stiffened = cg::parse_model("name: spinning\nbodies:\n  - name: beam\n    flexible: {file: modal_data/spinning_beam.yaml, "
                                              "modes: 4}\n    angular_velocity: [0, 0, 100]\n",
                                              kModels + "/inline.yaml");
  CHECK(cg::modal_spin_warning(stiffened, cg::estimate_stable_step(stiffened)) == "");
  // The same beam without it is warned of.
  std::ifstream in(kModels + "/modal_data/spinning_beam.yaml");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const TemporaryFile plain("plain_beam.yaml", text.substr(0, text.find("geometric_stiffness:")));
  const cg::Model soft = cg::parse_model("name: spinning\nbodies:\n  - name: beam\n    flexible: {file: " + plain.path.string() +
                                         ", modes: 4}\n    angular_velocity: [0, 0, 100]\n",
                                         kModels + "/inline.yaml");
  CHECK(cg::modal_spin_warning(soft, cg::estimate_stable_step(soft)).find("has no geometric stiffness of spin") != std::string::npos);
}
