// Modal bodies (docs/flexible.md): the generation-time invariants against the
// beam's finite-element mass and closed forms; generated models at 1 kHz
// against closed forms (a cantilever's static deflection and first bending
// frequency), an independent model of Simo & Vu-Quoc's spin-up, and
// conservation laws summed directly over the beam's mass (a free tumbling
// body); the generator's refusals.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "allocation_counter.hpp"
#include "analysis.hpp"
#include "generator_error.hpp"
#include "beam_modes.hpp"
#include "modal_body.hpp"
#include "modal_cantilever.hpp"
#include "modal_free.hpp"
#include "modal_free_fine.hpp"
#include "modal_momenta.hpp"
#include "modal_pinned_tool.hpp"
#include "modal_pinned_tool_baumgarte.hpp"
#include "modal_spin_up.hpp"
#include "model.hpp"
#include "spin_up_reference.hpp"
#include "step_allocations.hpp"

namespace {

using mbrt::Mat3;
using mbrt::Vec3;
namespace cg = mbrt::codegen;

Mat3 rotation_of(const mbrt::EulerParameters& p) { return Eigen::Quaterniond(p[0], p[1], p[2], p[3]).toRotationMatrix(); }

struct SpinUp {
  using State = mbrt::models::modal_spin_up::State;
  using Workspace = mbrt::models::modal_spin_up::Workspace;
  static State initial_state() { return mbrt::models::modal_spin_up::initial_state(); }
  static mbrt::StepStatus step(State& s, Workspace& w) { return mbrt::models::modal_spin_up::step(s, w); }
};


}  // namespace

TEST_CASE("a modal body's invariants agree with its beam's finite-element mass") {
  const cg::BeamProperties beam{2.0, 4.0e6, 900.0, 1500.0, 2400.0, 3.0, 0.02, 20};
  const cg::ModalPlan p = cg::plan_modal_body(beam, 4, 0.0);
  const double m = 6.0;
  // Unit modal masses: the displacement field's own integral sum_a int Psi_a^T Psi_a.
  CHECK((p.E[0] + p.E[4] + p.E[8] - Eigen::MatrixXd::Identity(4, 4)).norm() < 1e-12);
  // The first cantilever mode moves 0.6131 of the beam's mass (its effective mass).
  CHECK(p.St_T.row(0).squaredNorm() / m == doctest::Approx(0.6131).epsilon(1e-3));
  // Coupling with the frame's turn about its centre: beam_modes' about the
  // root, less the turn's translation of the centre, (L/2) e_d x e_x.
  const cg::BeamModes modes = cg::beam_modes(beam, cg::BeamSupport::clamped_root, 6);
  for (int k = 0; k < 4; ++k) {
    // The kept modes are the lowest four (no torsion among them here).
    CHECK(std::abs(std::abs(p.St_T.row(k).dot(modes.alpha.col(k))) - modes.alpha.col(k).squaredNorm()) < 1e-9);
    const double sign = p.St_T.row(k).dot(modes.alpha.col(k)) > 0 ? 1.0 : -1.0;
    for (int d = 0; d < 3; ++d) {
      const Eigen::Vector3d shift = Eigen::Vector3d::Unit(d).cross(Eigen::Vector3d(1.0, 0, 0));
      CHECK(p.Sr_T(k, d) == doctest::Approx(sign * (modes.beta(d, k) - shift.dot(modes.alpha.col(k)))).scale(1.0).epsilon(1e-9));
    }
  }
  // The frame's reduced mass is the rigid mass less what the modes take.
  Eigen::Matrix<double, 6, 6> rigid = Eigen::Matrix<double, 6, 6>::Zero();
  rigid.diagonal() << m, m, m, 0.02 * 2.0, m * 4.0 / 12, m * 4.0 / 12;
  Eigen::MatrixXd S(6, 4);
  S << p.St_T.transpose(), p.Sr_T.transpose();
  CHECK((p.reduced_inverse * (rigid - S * S.transpose()) - Eigen::Matrix<double, 6, 6>::Identity()).norm() < 1e-10);
}

TEST_CASE("a modal body's static deflection converges to the closed form with the number of modes") {
  // Bending in x-y only among the lowest modes (EIy far above EIz); a uniform
  // load q along y: each mode's static coordinate f_i / omega_i^2, f_i = q St_i,y / rho_A.
  const double L = 2.0, EIz = 2400.0, rho_A = 3.0, load = 10.0;
  const cg::BeamProperties beam{L, 4.0e9, 9.0e5, 2.4e8, EIz, rho_A, 0.02, 20};
  const double closed_form = load * std::pow(L, 4) / (8 * EIz);
  std::vector<double> error;
  for (int modes = 1; modes <= 4; ++modes) {
    const cg::ModalPlan p = cg::plan_modal_body(beam, modes, 0.0);
    double tip = 0;
    const cg::ModalNode tip_node = cg::modal_node(p, beam.elements);
    for (int i = 0; i < modes; ++i) tip += tip_node.displacement(1, i) * load / rho_A * p.St_T(i, 1) / (p.omega[i] * p.omega[i]);
    error.push_back(std::abs(tip / closed_form - 1));
  }
  MESSAGE("tip deflection's relative error with 1 to 4 modes: " << error[0] << ", " << error[1] << ", " << error[2] << ", "
                                                                << error[3]);
  for (size_t k = 1; k < error.size(); ++k) CHECK(error[k] < error[k - 1]);
  CHECK(error[0] < 0.03);
  CHECK(error[3] < 1e-4);
}

TEST_CASE("a modal cantilever at 1 kHz sags by q L^4 / (8 EI) in both planes and swings at its first bending frequency") {
  namespace m = mbrt::models::modal_cantilever;
  const double L = 2.0, rho_A = 3.0, EIy = 1500.0, EIz = 2400.0;
  const double sag_y = -3.0 * rho_A * std::pow(L, 4) / (8 * EIz), sag_z = -4.0 * rho_A * std::pow(L, 4) / (8 * EIy);
  m::State s = m::initial_state();
  const double energy0 = m::energy(s).total();
  m::Outputs y{};
  double sum_y = 0, sum_z = 0, worst_energy = 0, previous = 0;
  std::vector<double> up_crossings;
  const int steps = 20000;  // 20 s
  for (int i = 0; i < steps; ++i) {
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    m::outputs(s, y);
    sum_y += y[m::output::tip + 1], sum_z += y[m::output::tip + 2];
    const double z = y[m::output::tip + 2] - sag_z;
    if (previous < 0 && z >= 0) up_crossings.push_back(s.t);
    previous = z;
    worst_energy = std::max(worst_energy, std::abs(m::energy(s).total() - energy0));
  }
  const double period = (up_crossings.back() - up_crossings.front()) / static_cast<double>(up_crossings.size() - 1);
  const double first = 1.8751040687 * 1.8751040687 * std::sqrt(EIy / (rho_A * std::pow(L, 4)));
  MESSAGE("4 modes at 1 ms: mean sag " << sum_y / steps << ", " << sum_z / steps << " m (closed form " << sag_y << ", "
                                       << sag_z << "), period " << period << " s (closed form " << 2 * M_PI / first
                                       << "), energy error " << worst_energy << " J");
  // Two modes a plane hold all but 0.5 % of the static deflection.
  CHECK(sum_y / steps == doctest::Approx(sag_y).epsilon(0.01).scale(0));
  CHECK(sum_z / steps == doctest::Approx(sag_z).epsilon(0.01).scale(0));
  CHECK(period == doctest::Approx(2 * M_PI / first).epsilon(1e-3).scale(0));
  CHECK(worst_energy < 1e-4 * 6.0 * 5.0 * std::abs(sag_z));
  // The tip's velocity output is the rate of its position output.
  m::State a = s;
  m::Outputs ya{}, yb{};
  m::outputs(a, ya);
  REQUIRE(m::step(a) == mbrt::StepStatus::ok);
  m::outputs(a, yb);
  m::Outputs v{};
  m::outputs(s, v);
  const Vec3 mid_rate = (Vec3(yb[0], yb[1], yb[2]) - Vec3(ya[0], ya[1], ya[2])) / m::kStep;
  CHECK((mid_rate - Vec3(v[m::output::tip_velocity], v[m::output::tip_velocity + 1], v[m::output::tip_velocity + 2])).norm() <
        0.05 * mid_rate.norm() + 1e-6);
}

TEST_CASE("the modal spin-up beam at 1 kHz follows the independent modal model with geometric stiffness") {
  const spin_up::SpinUpReference reference = spin_up::spin_up_reference(true);
  REQUIRE(!reference.diverged);
  namespace m = mbrt::models::modal_spin_up;
  m::State s = m::initial_state();
  m::Outputs y{};
  double worst = 0, largest = 0;
  for (int i = 1; i <= 20000; ++i) {  // 20 s at 1 ms
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    if (i % 10 != 0) continue;
    m::outputs(s, y);
    const double theta = spin_up::hub_angle(s.t)[0];
    const double transverse = -std::sin(theta) * y[0] + std::cos(theta) * y[1];
    const double reference_tip = reference.tip[static_cast<size_t>(i / 10 - 1)];
    worst = std::max(worst, std::abs(transverse - reference_tip));
    largest = std::max(largest, std::abs(reference_tip));
  }
  MESSAGE("6 modes at 1 ms: largest tip deflection " << largest << " m, worst difference from the modal model " << worst
                                                     << " m");
  CHECK(largest > 0.5);
  CHECK(worst < 0.02 * largest);
}

using modal_momenta::Conservation;

// A free modal body model's drift from conservation (modal_momenta.hpp).
template <class State, class Step, class EnergyOf>
Conservation free_body_errors(State s, Step step, EnergyOf energy, double h) {
  const modal_momenta::ModalBeamMass mass({2.0, 2.0e5, 400.0, 300.0, 500.0, 2.0, 0.01, 16}, 6);
  const auto momenta = [&](const State& x) { return mass.momenta(x.rigid[0], x.modal_q[0].head(6), x.modal_p[0].head(6)); };
  return modal_momenta::conservation_errors(s, step, energy, momenta, h);
}

TEST_CASE("a free modal body keeps its energy, momentum and angular momentum to second order in the step") {
  namespace m = mbrt::models::modal_free;
  namespace f = mbrt::models::modal_free_fine;
  const Conservation coarse = free_body_errors(
      m::initial_state(), [](m::State& s) { return m::step(s); }, [](const m::State& s) { return m::energy(s).total(); },
      m::kStep);
  const Conservation fine = free_body_errors(
      f::initial_state(), [](f::State& s) { return f::step(s); }, [](const f::State& s) { return f::energy(s).total(); },
      f::kStep);
  MESSAGE("10 s, relative errors at 1 ms: energy " << coarse.energy << ", momentum " << coarse.momentum
                                                   << ", angular momentum " << coarse.angular_momentum << "; at 0.25 ms: "
                                                   << fine.energy << ", " << fine.momentum << ", " << fine.angular_momentum
                                                   << "; largest modal coordinate " << coarse.largest_q);
  CHECK(coarse.largest_q > 1e-4);  // the tumbling does bend it
  CHECK(coarse.energy < 1e-4);
  CHECK(coarse.momentum < 1e-4);
  CHECK(coarse.angular_momentum < 2e-3);
  // A quarter of the step: a sixteenth of the error, where a term of the
  // model (rather than of the step) would leave it.
  CHECK(fine.momentum < coarse.momentum / 10);
  CHECK(fine.angular_momentum < coarse.angular_momentum / 10);
}

// A light tool pinned at its root and spun up by a constant torque tau for
// 1.1 s (to 73 rad/s, 0.073 rad a step at 1 ms): every step holds, the
// energy gained is the torque's work tau theta, the turn follows the rigid
// tool's tau t^2 / (2 J) and the tip stays within the modes' small
// deflections. Before the inertia coupling took the deformation (it lagged a
// step), baumgarte lost this model in 17 steps.
struct SpinUpRecord {
  double worst_work_error, angle, largest_tip_deflection;
};

template <class State, class Step, class EnergyOf, class TipOf>
SpinUpRecord pinned_spin_up(State s, Step step, EnergyOf energy, TipOf tip_and_angle) {
  const double tau = 1.0, e0 = energy(s);
  SpinUpRecord r{0, 0, 0};
  double last = 0;
  for (int i = 0; i < 1100; ++i) {
    REQUIRE(step(s) == mbrt::StepStatus::ok);
    const auto [deflection, angle] = tip_and_angle(s);
    r.angle += std::remainder(angle - last, 2 * M_PI);  // joint angles wrap
    last = angle;
    r.largest_tip_deflection = std::max(r.largest_tip_deflection, deflection);
    r.worst_work_error = std::max(r.worst_work_error, std::abs(energy(s) - e0 - tau * r.angle));
  }
  return r;
}

// The tip's distance from the frame's x axis and the pin's angle.
std::array<double, 2> tip_deflection_and_angle(const mbrt::RigidState& b, const double* tip, double angle) {
  const Vec3 local = rotation_of(b.p).transpose() * (Vec3(tip[0], tip[1], tip[2]) - b.r);
  return {std::hypot(local.y(), local.z()), angle};
}

TEST_CASE("a light modal tool pinned at its root spins up under a constant torque at 1 kHz in staggered-pcst and baumgarte") {
  namespace p = mbrt::models::modal_pinned_tool;
  namespace b = mbrt::models::modal_pinned_tool_baumgarte;
  const double J = 0.5 * 0.3 * 0.3 / 3 + 1.0e-4 * 0.3, t = 1.1, rigid_angle = 1.0 * t * t / (2 * J);
  const SpinUpRecord pcst = pinned_spin_up(
      p::initial_state(), [](p::State& s) { return p::step(s); }, [](const p::State& s) { return p::energy(s).total(); },
      [](const p::State& s) {
        p::Outputs y{};
        p::outputs(s, y);
        return tip_deflection_and_angle(s.rigid[0], &y[p::output::tip], y[p::output::pin_angle]);
      });
  const SpinUpRecord baumgarte = pinned_spin_up(
      b::initial_state(), [](b::State& s) { return b::step(s); }, [](const b::State& s) { return b::energy(s).total(); },
      [](const b::State& s) {
        b::Outputs y{};
        b::outputs(s, y);
        return tip_deflection_and_angle(s.rigid[0], &y[b::output::tip], y[b::output::pin_angle]);
      });
  for (const SpinUpRecord& r : {pcst, baumgarte}) {
    MESSAGE("1.1 s: turned " << r.angle << " rad (rigid tool " << rigid_angle << "), energy less work off by " << r.worst_work_error
                             << " J of " << rigid_angle << ", largest tip deflection " << r.largest_tip_deflection << " m");
    CHECK(r.angle == doctest::Approx(rigid_angle).epsilon(0.02));
    // The geometric stiffness's energy 0.5 q^T kg(w) q changes with the spin
    // at fixed q, which no potential does: about 1 % of the work here.
    CHECK(r.worst_work_error < 0.025 * rigid_angle);
    CHECK(r.largest_tip_deflection > 0.005);  // it does bend
    CHECK(r.largest_tip_deflection < 0.03);   // a tenth of its length
  }
}

TEST_CASE("the generator refuses what a modal body cannot do, naming the key") {
  const std::string beam =
      "bodies:\n  - name: boom\n    flexible: {length: 2.0, elements: 10, modes: 4, EA: 1.0e6, GJ: 500.0, EI: 800.0, "
      "rho_A: 2.0, rho_J: 0.01}\n";
  const std::string pin = "joints:\n  - {name: pin, type: revolute, body1: ground, body2: boom, point: [0, 0, 0], axis: [0, 0, 1]}\n";
  CHECK(generator_error("name: ok\n" + beam + pin) == "");
  const std::string off_root = generator_error("name: off\n" + beam +
                                               "joints:\n  - {name: pin, type: revolute, body1: ground, body2: boom, "
                                               "point: [1.0, 0, 0], axis: [0, 0, 1]}\n");
  CHECK(off_root.find("joints.pin") != std::string::npos);
  CHECK(off_root.find("away from its root") != std::string::npos);
  const std::string tree = generator_error("name: tree\n" + beam + pin + "solver: {scheme: rk4-tree}\n");
  CHECK(tree.find("flexible.modes") != std::string::npos);
  CHECK(tree.find("staggered-pcst, baumgarte or blajer") != std::string::npos);
  CHECK(generator_error("name: many\n" + std::string(beam).replace(beam.find("modes: 4"), 8, "modes: 7") + pin)
            .find("at most 6 modes") != std::string::npos);
  CHECK(generator_error("name: fine\n" + std::string(beam).replace(beam.find("elements: 10"), 12, "elements: 61") + pin)
            .find("at most 60 elements for a modal body") != std::string::npos);
  std::string one_element = std::string(beam).replace(beam.find("elements: 10"), 12, "elements: 1");
  CHECK(generator_error("name: few\n" + one_element.replace(one_element.find("modes: 4"), 8, "modes: 6") + pin)
            .find("use more elements") != std::string::npos);
  // A round beam bends alike in both planes: 3 modes would keep one of the
  // second pair, in a direction left to round-off.
  const std::string split = generator_error("name: split\n" + std::string(beam).replace(beam.find("modes: 4"), 8, "modes: 3") + pin);
  CHECK(split.find("3 modes kept, but modes 3 and 4 have the same frequency (17.53") != std::string::npos);
  CHECK(split.find("keep 2 or 4 modes") != std::string::npos);
  const std::string one = generator_error("name: one\n" + std::string(beam).replace(beam.find("modes: 4"), 8, "modes: 1") + pin);
  CHECK(one.find("1 modes kept, but modes 1 and 2 have the same frequency (2.79") != std::string::npos);
  CHECK(one.find("keep 2 modes, so that") != std::string::npos);
  // A short round beam: the axial mode (EA 1e5: 28 Hz) comes after the
  // second bending pair, so the third pair is modes 6 and 7 and 6 modes split it.
  std::string short_beam = std::string(beam).replace(beam.find("modes: 4"), 8, "modes: 6");
  short_beam.replace(short_beam.find("EA: 1.0e6"), 9, "EA: 1.0e5");
  const std::string six = generator_error("name: six\n" + short_beam + pin);
  CHECK(six.find("6 modes kept, but modes 6 and 7 have the same frequency") != std::string::npos);
  CHECK(six.find("keep 5 modes, so that") != std::string::npos);
  CHECK(generator_error("name: flat\n" + std::string(beam).replace(beam.find("EI: 800.0"), 9, "EI: [800.0, 801.0]") + pin) == "");
  CHECK(generator_error("name: node\n" + beam +
                        "joints:\n  - {name: pin, type: planar, body1: ground, body2: boom@root, point: [0, 0, 0], axis: [0, 0, 1]}\n") ==
        "");  // a planar joint takes the root node too
}

TEST_CASE("the step with a modal body allocates nothing") { CHECK(allocations_in<SpinUp>(20000) == 0); }
