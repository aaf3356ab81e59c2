// Joints that turn with a modal body's section (revolute, universal, fixed,
// prismatic, cylindrical, screw, planar) at its nodes (docs/flexible.md). Three clamped beams of six modes, settled
// under loads that the joints pass as forces and torques, against the same
// six modes written down independently: Euler-Bernoulli's cantilever modes
// in closed form (Ritz, with the joints' conditions on them), which also
// shows how far six modes stand from the beam's closed forms; a cantilever
// carrying a tool's mass and rotary inertia against its characteristic
// equation; equilibrium of the joints' reactions. A free beam carrying a
// tool and a flap by such joints keeps the bodies' energy, momentum and
// angular momentum, at second order in the step, allocating nothing. A
// joint spring and a joint_torque input on a revolute joint at a node, and
// its angle and rate as outputs, against the same closed forms; the same
// for a prismatic joint sliding along the turned section's oblique axis, and
// a driven cylindrical one. A screw and a planar joint at the nodes of an
// undamped beam keep its energy and their bodies on the sections' turned
// axis and plane. A four-bar welded to a modal coupler's node keeps its energy less the
// crank torque's work.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Dense>

#include "modal_joint_turns.hpp"
#include "modal_joint_turns_blajer.hpp"
#include "modal_joint_turns_fine.hpp"
#include "generator_error.hpp"
#include "modal_momenta.hpp"
#include "modal_node_spring.hpp"
#include "modal_node_spring_blajer.hpp"
#include "modal_node_screw.hpp"
#include "modal_node_screw_blajer.hpp"
#include "modal_node_screw_coarse.hpp"
#include "modal_node_sleeve.hpp"
#include "modal_node_sleeve_blajer.hpp"
#include "modal_node_slider.hpp"
#include "modal_node_slider_blajer.hpp"
#include "modal_node_turns.hpp"
#include "modal_node_turns_baumgarte.hpp"
#include "modal_node_turns_blajer.hpp"
#include "modal_static_loads.hpp"
#include "modal_static_loads_blajer.hpp"
#include "modal_weld_loop.hpp"
#include "modal_weld_loop_blajer.hpp"
#include "step_allocations.hpp"

namespace {

using mbrt::Vec3;

// A cantilever's first n bending modes in closed form (Euler-Bernoulli;
// e.g. Blevins 1979, Formulas for Natural Frequency and Mode Shape, table
// 8-1): cos(bL) cosh(bL) = -1, unit modal mass, their values and slopes at
// x by rho_A and length; what a modal body of n modes represents, to its
// elements' discretization error.
class CantileverModes {
 public:
  CantileverModes(int n, double EI, double rho_A, double L) : EI_(EI), rho_A_(rho_A), L_(L) {
    for (int k = 1; k <= n; ++k) {
      double lo = k == 1 ? 1.0 : (k - 0.5) * std::numbers::pi - 1.0, hi = k == 1 ? 2.5 : (k - 0.5) * std::numbers::pi + 1.0;
      const auto f = [](double b) { return std::cos(b) * std::cosh(b) + 1.0; };
      for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (std::signbit(f(lo)) == std::signbit(f(mid)) ? lo : hi) = mid;
      }
      beta_.push_back(0.5 * (lo + hi) / L);
    }
  }
  int size() const { return static_cast<int>(beta_.size()); }
  double omega_squared(int k) const { return EI_ * std::pow(beta_[static_cast<size_t>(k)], 4) / rho_A_; }
  // Value (d = 0) or slope (d = 1) of mode k at x; sqrt(rho_A L) of the
  // classic shape is its unit modal mass (its mean square is 1).
  double shape(int k, double x, int d = 0) const {
    const double b = beta_[static_cast<size_t>(k)], bL = b * L_, s = (std::cosh(bL) + std::cos(bL)) / (std::sinh(bL) + std::sin(bL));
    const double scale = 1.0 / std::sqrt(rho_A_ * L_);
    if (d == 0) return scale * (std::cosh(b * x) - std::cos(b * x) - s * (std::sinh(b * x) - std::sin(b * x)));
    return scale * b * (std::sinh(b * x) + std::sin(b * x) - s * (std::cosh(b * x) - std::cos(b * x)));
  }
  // Static response: the modal coordinates under a force F and a moment M at x.
  Eigen::VectorXd loaded(double x, double F, double M) const {
    Eigen::VectorXd q(size());
    for (int k = 0; k < size(); ++k) q[k] = (shape(k, x) * F + shape(k, x, 1) * M) / omega_squared(k);
    return q;
  }
  double at(const Eigen::VectorXd& q, double x, int d = 0) const {
    double y = 0;
    for (int k = 0; k < size(); ++k) y += q[k] * shape(k, x, d);
    return y;
  }
  // Held at the tip too (value and slope): the modes' combinations that
  // keep both, as columns, orthonormal.
  Eigen::MatrixXd clamped_tip() const {
    Eigen::MatrixXd C(2, size());
    for (int k = 0; k < size(); ++k) C(0, k) = shape(k, L_), C(1, k) = shape(k, L_, 1);
    Eigen::FullPivLU<Eigen::MatrixXd> lu(C);
    return Eigen::HouseholderQR<Eigen::MatrixXd>(lu.kernel()).householderQ() * Eigen::MatrixXd::Identity(size(), size() - 2);
  }
  Eigen::VectorXd stiffness() const {
    Eigen::VectorXd k(size());
    for (int i = 0; i < size(); ++i) k[i] = omega_squared(i);
    return k;
  }

 private:
  std::vector<double> beta_;
  double EI_, rho_A_, L_;
};

// The cantilever with a tip body of mass M and rotary inertia J: the lowest
// root of the 2 x 2 determinant of its tip conditions, EI w'' = J w^2 w' and
// EI w''' = -M w^2 w, on w = A (cos - cosh)(bx) + B (sin - sinh)(bx).
double tip_body_frequency(double EI, double rho_A, double L, double M, double J) {
  const auto det = [&](double w) {
    const double b = std::pow(rho_A * w * w / EI, 0.25), c = std::cos(b * L), s = std::sin(b * L), ch = std::cosh(b * L),
                 sh = std::sinh(b * L);
    const Eigen::Vector2d W(c - ch, s - sh), W1 = b * Eigen::Vector2d(-s - sh, c - ch), W2 = b * b * Eigen::Vector2d(-c - ch, -s - sh),
                          W3 = b * b * b * Eigen::Vector2d(s - sh, -c - ch);
    Eigen::Matrix2d m;
    m.row(0) = EI * W2 - J * w * w * W1;
    m.row(1) = -EI * W3 - M * w * w * W;
    return m.determinant();
  };
  double lo = 1e-3 * std::sqrt(EI / (rho_A * std::pow(L, 4))), step = lo;
  while (std::signbit(det(lo)) == std::signbit(det(lo + step))) lo += step;
  double hi = lo + step;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::signbit(det(lo)) == std::signbit(det(mid)) ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Settled: the mean over whole swings (up-crossings of the tail's mean) in
// the last 4 s, where light damping has not yet stilled the tool's swing.
double settled(const std::vector<double>& y, double h) {
  const size_t tail = y.size() - static_cast<size_t>(std::lround(4.0 / h));
  double mean = 0;
  for (size_t i = tail; i < y.size(); ++i) mean += y[i] / static_cast<double>(y.size() - tail);
  size_t first = 0, last = 0;
  for (size_t i = tail + 1; i < y.size(); ++i) {
    if (y[i - 1] < mean && y[i] >= mean) (first == 0 ? first : last) = i;
  }
  if (last <= first) return mean;
  double sum = 0;
  for (size_t i = first; i < last; ++i) sum += y[i];
  return sum / static_cast<double>(last - first);
}

// From the up-crossings of the settled value in the first `window` s,
// undamped: stiffness-proportional damping c K gives mode k the ratio
// c w_k / 2 (the joints add no stiffness, so their modes keep C = c K).
double undamped_frequency(const std::vector<double>& y, double settled_value, double h, double c, double window) {
  std::vector<double> crossings;
  for (size_t i = 1; i < y.size() && static_cast<double>(i) * h < window; ++i) {
    if (y[i - 1] < settled_value && y[i] >= settled_value) {
      crossings.push_back(h * (static_cast<double>(i) - 1 + (settled_value - y[i - 1]) / (y[i] - y[i - 1])));
    }
  }
  REQUIRE(crossings.size() >= 5);
  const double damped = 2 * std::numbers::pi * static_cast<double>(crossings.size() - 1) / (crossings.back() - crossings.front());
  const double z = c * damped / 2;
  return damped / std::sqrt(1 - z * z);
}

// The section's turn about z from a body_pose output's Euler parameters.
double turn_z(const double* pose) { return 2 * std::atan2(pose[6], pose[3]); }

struct Turns {
  double middle_a, tip_b, slope_b, tool_turn, tip_c, slope_c;
  double frequency_a, frequency_b;
  mbrt::JointReaction clamp_a, tip_a, mount, hold;
};

// One model file in three schemes: the same outputs and joints.
namespace turns = mbrt::models::modal_node_turns;

template <class State, class Outputs, class Reactions, class Step, class Out, class React>
Turns settle_turns(State s, double h, Step step, Out outputs, React reactions) {
  Outputs y{};
  std::vector<double> a, b, b_turn, t_turn, c, c_turn;
  const int steps = static_cast<int>(std::lround(15.0 / h));
  for (int i = 0; i < steps; ++i) {
    REQUIRE(step(s) == mbrt::StepStatus::ok);
    outputs(s, y);
    a.push_back(y[turns::output::middle_a + 1]);
    b.push_back(y[turns::output::tip_b + 1]), b_turn.push_back(turn_z(&y[turns::output::tip_b]));
    t_turn.push_back(turn_z(&y[turns::output::tool_pose]));
    c.push_back(y[turns::output::tip_c + 1]), c_turn.push_back(turn_z(&y[turns::output::tip_c]));
  }
  Reactions r;
  reactions(s, r);
  Turns out{settled(a, h), settled(b, h), settled(b_turn, h), settled(t_turn, h), settled(c, h), settled(c_turn, h), 0, 0,
            r[turns::constraint::clamp_a], r[turns::constraint::tip_a], r[turns::constraint::mount], r[turns::constraint::hold]};
  // boom_a swings at 40 Hz, damped by 13 % of critical; the tool at 3 Hz.
  out.frequency_a = undamped_frequency(a, out.middle_a, h, 0.001, 0.2);
  out.frequency_b = undamped_frequency(b, out.tip_b, h, 0.001, 3.0);
  return out;
}

#define SETTLE_TURNS(NS)                                                                                          \
  settle_turns<mbrt::models::NS::State, mbrt::models::NS::Outputs, mbrt::models::NS::Reactions>(                  \
      mbrt::models::NS::initial_state(), mbrt::models::NS::kStep, [](auto& s) { return mbrt::models::NS::step(s); }, \
      [](const auto& s, auto& y) { mbrt::models::NS::outputs(s, y); }, [](const auto& s, auto& r) { mbrt::models::NS::reactions(s, r); })

}  // namespace

TEST_CASE("beams held at nodes by fixed and revolute joints settle and swing as their six modes written in closed form") {
  const double EI = 100.0, rho_A = 1.0, L = 1.0, P = 2.0, tau = 1.0, F = 1.0, d = 0.5;
  const CantileverModes modes(6, EI, rho_A, L);
  // boom_a, clamped at both ends: the modes that keep the tip still, loaded at the middle.
  const Eigen::MatrixXd Z = modes.clamped_tip();
  const Eigen::MatrixXd K = Z.transpose() * modes.stiffness().asDiagonal() * Z;
  Eigen::VectorXd middle_load(modes.size());
  for (int k = 0; k < modes.size(); ++k) middle_load[k] = P * modes.shape(k, L / 2);
  const double middle_a = modes.at(Z * K.ldlt().solve(Z.transpose() * middle_load), L / 2);
  const double frequency_a = std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K).eigenvalues().minCoeff());
  // boom_b turned at its tip; boom_c pushed at its tip and turned by the arm's F d.
  const Eigen::VectorXd b = modes.loaded(L, 0, tau), c = modes.loaded(L, F, F * d);
  const double frequency_b = tip_body_frequency(EI, rho_A, L, 0.5, 0.02);
  const std::array<Turns, 3> runs = {SETTLE_TURNS(modal_node_turns), SETTLE_TURNS(modal_node_turns_baumgarte),
                                     SETTLE_TURNS(modal_node_turns_blajer)};
  for (const Turns& r : runs) {
    MESSAGE("clamped at both ends: middle " << r.middle_a << " m (six modes " << middle_a << ", Euler-Bernoulli " << P * L * L * L / (192 * EI)
                                            << "), first frequency " << r.frequency_a << " rad/s (" << frequency_a << ", "
                                            << 22.3733 * std::sqrt(EI / (rho_A * L * L * L * L)) << ")");
    MESSAGE("tool turned: tip " << r.tip_b << " m, turned " << r.slope_b << " rad, the tool " << r.tool_turn << " (six modes "
                                << modes.at(b, L) << ", " << modes.at(b, L, 1) << "; Euler-Bernoulli " << tau * L * L / (2 * EI) << ", "
                                << tau * L / EI << "), first frequency " << r.frequency_b << " rad/s (tip body's equation "
                                << frequency_b << ")");
    MESSAGE("arm held by a driver: tip " << r.tip_c << " m, turned " << r.slope_c << " rad (six modes " << modes.at(c, L) << ", "
                                         << modes.at(c, L, 1) << "; Euler-Bernoulli " << F * L * L * L / (3 * EI) + F * d * L * L / (2 * EI)
                                         << ", " << F * L * L / (2 * EI) + F * d * L / EI << "), driver torque "
                                         << r.hold.torque.transpose());
    // The same six modes: to the elements' discretization, 0.5 %.
    CHECK(r.middle_a == doctest::Approx(middle_a).epsilon(0.005).scale(0));
    CHECK(r.frequency_a == doctest::Approx(frequency_a).epsilon(0.005).scale(0));
    CHECK(r.tip_b == doctest::Approx(modes.at(b, L)).epsilon(0.005).scale(0));
    CHECK(r.slope_b == doctest::Approx(modes.at(b, L, 1)).epsilon(0.005).scale(0));
    CHECK(r.tip_c == doctest::Approx(modes.at(c, L)).epsilon(0.005).scale(0));
    CHECK(r.slope_c == doctest::Approx(modes.at(c, L, 1)).epsilon(0.005).scale(0));
    // The fixed joint turns the tool with the section.
    CHECK(r.tool_turn == doctest::Approx(r.slope_b).epsilon(1e-6).scale(0));
    // A tip body's mass and rotary inertia: the first mode is well inside six.
    CHECK(r.frequency_b == doctest::Approx(frequency_b).epsilon(0.003).scale(0));
    // Equilibrium: the clamps share P (boom_a is still); the mount holds the
    // tool against tau and the driver the arm against F d, to what is left
    // of the tool's and the arm's swing (1 %).
    CHECK(r.clamp_a.force.y() + r.tip_a.force.y() == doctest::Approx(-P).epsilon(1e-6).scale(0));
    CHECK(r.mount.torque.z() == doctest::Approx(-tau).epsilon(0.01).scale(0));
    CHECK(std::abs(r.hold.torque.z()) == doctest::Approx(F * d).epsilon(0.01).scale(0));
  }
}

namespace {

// A sprung, driven joint at the tip node (tests/models/modal_node_spring.yaml,
// a hinge carrying an arm; modal_node_slider.yaml, a slide carrying a
// slider), 15 s with the input held at `input`: settled tip, its turn and the
// joint's coordinate, and the largest gap between the joint's rate output and
// the central difference of its coordinate output.
struct SprungJoint {
  double tip, slope, coordinate, rate_gap, largest_rate;
};

struct SprungJointSignals {
  int input, tip, coordinate, rate;  // the model's input and output indices
};

template <class State, class Outputs, class Step, class Out>
SprungJoint settle_sprung_joint(State s, double h, double input, SprungJointSignals at, Step step, Out outputs) {
  s.inputs[static_cast<size_t>(at.input)] = input;
  Outputs y{};
  std::vector<double> tip, slope, coordinate, rate;
  const int steps = static_cast<int>(std::lround(15.0 / h));
  for (int i = 0; i < steps; ++i) {
    REQUIRE(step(s) == mbrt::StepStatus::ok);
    outputs(s, y);
    tip.push_back(y[static_cast<size_t>(at.tip + 1)]), slope.push_back(turn_z(&y[static_cast<size_t>(at.tip)]));
    coordinate.push_back(y[static_cast<size_t>(at.coordinate)]), rate.push_back(y[static_cast<size_t>(at.rate)]);
  }
  SprungJoint r{settled(tip, h), settled(slope, h), settled(coordinate, h), 0, 0};
  for (size_t i = 1; i + 1 < coordinate.size(); ++i) {
    r.rate_gap = std::max(r.rate_gap, std::abs(rate[i] - (coordinate[i + 1] - coordinate[i - 1]) / (2 * h)));
    r.largest_rate = std::max(r.largest_rate, std::abs(rate[i]));
  }
  return r;
}

#define SETTLE_SPRUNG_JOINT(NS, INPUT, SIGNALS)                                                                               \
  settle_sprung_joint<mbrt::models::NS::State, mbrt::models::NS::Outputs>(                                                    \
      mbrt::models::NS::initial_state(), mbrt::models::NS::kStep, INPUT, SIGNALS, [](auto& s) { return mbrt::models::NS::step(s); }, \
      [](const auto& s, auto& y) { mbrt::models::NS::outputs(s, y); })

namespace spring = mbrt::models::modal_node_spring;
namespace slider = mbrt::models::modal_node_slider;
const SprungJointSignals kHinge{spring::input::motor, spring::output::tip, spring::output::hinge_angle, spring::output::hinge_rate};
const SprungJointSignals kSlide{slider::input::motor, slider::output::tip, slider::output::slide_position, slider::output::slide_rate};

}  // namespace

TEST_CASE("a joint spring and a joint input on a revolute joint at a modal node pass their torques to the node's section") {
  const double EI = 100.0, rho_A = 1.0, L = 1.0, F = 1.0, d = 0.5, k = 50.0;
  const CantileverModes modes(6, EI, rho_A, L);
  const Eigen::VectorXd c = modes.loaded(L, F, F * d);
  for (const double torque : {0.0, 0.2}) {
    for (const SprungJoint& r :
         {SETTLE_SPRUNG_JOINT(modal_node_spring, torque, kHinge), SETTLE_SPRUNG_JOINT(modal_node_spring_blajer, torque, kHinge)}) {
      // The force stays along y while the arm turns by slope + angle.
      const double held = (F * d * std::cos(r.slope + r.coordinate) + torque) / k;
      MESSAGE("input " << torque << " N m: tip " << r.tip << " m, turned " << r.slope << " rad (six modes " << modes.at(c, L) << ", "
                       << modes.at(c, L, 1) << "), hinge " << r.coordinate << " rad ((F d + input) / k " << held
                       << "), rate output off its angle's differences by " << r.rate_gap << " of " << r.largest_rate << " rad/s");
      CHECK(r.tip == doctest::Approx(modes.at(c, L)).epsilon(0.005).scale(0));
      CHECK(r.slope == doctest::Approx(modes.at(c, L, 1)).epsilon(0.005).scale(0));
      CHECK(r.coordinate == doctest::Approx(held).epsilon(0.002).scale(0));
      CHECK(r.rate_gap < 1e-3 * r.largest_rate);
    }
  }
}

TEST_CASE("a joint spring and a joint input on a prismatic joint at a modal node slide along the node's turned section") {
  const double EI = 100.0, rho_A = 1.0, L = 1.0, F = 1.0, k = 50.0;
  const CantileverModes modes(6, EI, rho_A, L);
  for (const double push : {0.0, 0.2}) {
    for (const SprungJoint& r :
         {SETTLE_SPRUNG_JOINT(modal_node_slider, push, kSlide), SETTLE_SPRUNG_JOINT(modal_node_slider_blajer, push, kSlide)}) {
      // The slide's axis, at pi/4 to the beam, turns with the section; the
      // force keeps along y. The tip carries F and the moment of the slide's
      // offset along the turned axis.
      const double axis = std::numbers::pi / 4 + r.slope;
      const double held = (F * std::sin(axis) + push) / k;
      const Eigen::VectorXd c = modes.loaded(L, F, F * r.coordinate * std::cos(axis));
      MESSAGE("input " << push << " N: tip " << r.tip << " m, turned " << r.slope << " rad (six modes " << modes.at(c, L) << ", "
                       << modes.at(c, L, 1) << "; F L^3 / (3 EI) " << F * L * L * L / (3 * EI) << "), slide " << r.coordinate
                       << " m ((F sin(pi/4 + turn) + input) / k " << held << "), rate output off its differences by " << r.rate_gap << " of "
                       << r.largest_rate << " m/s");
      CHECK(r.tip == doctest::Approx(modes.at(c, L)).epsilon(0.002).scale(0));
      CHECK(r.slope == doctest::Approx(modes.at(c, L, 1)).epsilon(0.002).scale(0));
      CHECK(r.coordinate == doctest::Approx(held).epsilon(1e-4).scale(0));
      CHECK(r.rate_gap < 1e-3 * r.largest_rate);
    }
  }
}

namespace {

mbrt::Mat3 rotation_of(const double* pose) { return Eigen::Quaterniond(pose[3], pose[4], pose[5], pose[6]).toRotationMatrix(); }
Vec3 place_of(const double* pose) { return {pose[0], pose[1], pose[2]}; }

// tests/models/modal_node_sleeve.yaml for 15 s with the input at `push`:
// the settled tip, its turn and the driver's force on the sleeve along the
// turned axis; at the end, the sleeve's offset from the tip node and the
// angle of the axis, pi/4 + the tip's turn.
struct DrivenSleeve {
  double tip, slope, stroke_force;
  Vec3 offset;
  double axis;
};

template <class State, class Outputs, class Reactions, class Step, class Out, class React>
DrivenSleeve settle_sleeve(State s, double h, double push, Step step, Out outputs, React reactions) {
  namespace sleeve = mbrt::models::modal_node_sleeve;
  s.inputs[sleeve::input::push] = push;
  Outputs y{};
  Reactions r;
  std::vector<double> tip, slope, force;
  const int steps = static_cast<int>(std::lround(15.0 / h));
  for (int i = 0; i < steps; ++i) {
    REQUIRE(step(s) == mbrt::StepStatus::ok);
    outputs(s, y);
    reactions(s, r);
    const double turn = turn_z(&y[sleeve::output::tip]), axis = std::numbers::pi / 4 + turn;
    tip.push_back(y[sleeve::output::tip + 1]), slope.push_back(turn);
    force.push_back(r[sleeve::constraint::stroke].force.dot(Vec3(std::cos(axis), std::sin(axis), 0)));
  }
  const Vec3 offset = place_of(&y[sleeve::output::sleeve_pose]) - place_of(&y[sleeve::output::tip]);
  return {settled(tip, h), settled(slope, h), settled(force, h), offset, std::numbers::pi / 4 + slope.back()};
}

#define SETTLE_SLEEVE(NS, PUSH)                                                                                                  \
  settle_sleeve<mbrt::models::NS::State, mbrt::models::NS::Outputs, mbrt::models::NS::Reactions>(                               \
      mbrt::models::NS::initial_state(), mbrt::models::NS::kStep, PUSH, [](auto& s) { return mbrt::models::NS::step(s); },     \
      [](const auto& s, auto& y) { mbrt::models::NS::outputs(s, y); }, [](const auto& s, auto& r) { mbrt::models::NS::reactions(s, r); })

}  // namespace

TEST_CASE("a driver and a joint input on a cylindrical joint at a modal node slide the sleeve along the node's turned section") {
  const double EI = 100.0, rho_A = 1.0, L = 1.0, F = 1.0, d = 0.1;
  const CantileverModes modes(6, EI, rho_A, L);
  for (const double push : {0.0, 0.2}) {
    for (const DrivenSleeve& r : {SETTLE_SLEEVE(modal_node_sleeve, push), SETTLE_SLEEVE(modal_node_sleeve_blajer, push)}) {
      // The driver holds the sleeve d along the axis at pi/4 to the beam,
      // turned with the section; the tip carries F and the moment of that
      // offset, the driver F's share along the axis and the input.
      const double axis = std::numbers::pi / 4 + r.slope;
      const Eigen::VectorXd c = modes.loaded(L, F, F * d * std::cos(axis));
      MESSAGE("input " << push << " N: tip " << r.tip << " m, turned " << r.slope << " rad (six modes " << modes.at(c, L) << ", "
                       << modes.at(c, L, 1) << "), driver's force along the axis " << r.stroke_force
                       << " N (-(F sin(pi/4 + turn) + input) " << -(F * std::sin(axis) + push) << "); at the end the sleeve "
                       << r.offset.norm() << " m from the tip at " << std::atan2(r.offset.y(), r.offset.x()) << " rad (pi/4 + turn "
                       << r.axis << ")");
      CHECK(r.tip == doctest::Approx(modes.at(c, L)).epsilon(0.002).scale(0));
      CHECK(r.slope == doctest::Approx(modes.at(c, L, 1)).epsilon(0.002).scale(0));
      CHECK(r.stroke_force == doctest::Approx(-(F * std::sin(axis) + push)).epsilon(5e-4).scale(0));
      CHECK(r.offset.norm() == doctest::Approx(d).epsilon(1e-9).scale(0));
      CHECK(std::atan2(r.offset.y(), r.offset.x()) == doctest::Approx(r.axis).epsilon(1e-9).scale(0));
      CHECK(std::abs(r.offset.z()) < 1e-12);
    }
  }
}

namespace {

// tests/models/modal_node_screw.yaml for 3 s: the largest drift of the
// energy and the largest kinetic energy; the nut's largest distance from the
// tip section's turned axis, turn off it, and gap between its slide along it
// and the lead's share of its turn about it (the turn followed through
// whole turns), and its largest slide; the plate's largest distance from the
// middle section's turned plane, turn off its normal, and largest slide.
struct ScrewAndPlate {
  double energy_drift = 0, largest_kinetic = 0;
  double off_axis = 0, off_turn = 0, thread_gap = 0, slide = 0;
  double off_plane = 0, plate_tilt = 0, plate_slide = 0;
};

template <class State, class Outputs, class Step, class Out, class EnergyOf>
ScrewAndPlate screw_and_plate(State s, double h, Step step, Out outputs, EnergyOf energy) {
  namespace screw = mbrt::models::modal_node_screw;
  const double lead = 0.1, e0 = energy(s).total();
  ScrewAndPlate r;
  Outputs y{};
  double turn = 0;  // the nut's turn about the axis, followed through whole turns
  const int steps = static_cast<int>(std::lround(3.0 / h));
  for (int i = 0; i < steps; ++i) {
    REQUIRE(step(s) == mbrt::StepStatus::ok);
    const mbrt::Energy e = energy(s);
    r.energy_drift = std::max(r.energy_drift, std::abs(e.total() - e0));
    r.largest_kinetic = std::max(r.largest_kinetic, e.kinetic);
    outputs(s, y);
    const mbrt::Mat3 tip = rotation_of(&y[screw::output::tip]), middle = rotation_of(&y[screw::output::middle]);
    const Vec3 p = tip.transpose() * (place_of(&y[screw::output::nut_pose]) - place_of(&y[screw::output::tip]));
    const mbrt::Mat3 Q = tip.transpose() * rotation_of(&y[screw::output::nut_pose]);
    const double step_turn = std::atan2(Q(2, 1), Q(1, 1)) - std::remainder(turn, 2 * std::numbers::pi);
    turn += std::remainder(step_turn, 2 * std::numbers::pi);
    r.off_axis = std::max(r.off_axis, p.tail<2>().norm());
    r.off_turn = std::max({r.off_turn, std::abs(Q(1, 0)), std::abs(Q(2, 0)), std::abs(Q(0, 1)), std::abs(Q(0, 2))});
    r.thread_gap = std::max(r.thread_gap, std::abs(p.x() - lead / (2 * std::numbers::pi) * turn));
    r.slide = std::max(r.slide, std::abs(p.x()));
    const Vec3 u = middle.transpose() * (place_of(&y[screw::output::plate_pose]) - place_of(&y[screw::output::middle]));
    const mbrt::Mat3 P = middle.transpose() * rotation_of(&y[screw::output::plate_pose]);
    r.off_plane = std::max(r.off_plane, std::abs(u.y()));
    r.plate_tilt = std::max({r.plate_tilt, std::abs(P(0, 1)), std::abs(P(2, 1)), std::abs(P(1, 0)), std::abs(P(1, 2))});
    r.plate_slide = std::max(r.plate_slide, std::hypot(u.x(), u.z()));
  }
  return r;
}

#define SCREW_AND_PLATE(NS)                                                                                                 \
  screw_and_plate<mbrt::models::NS::State, mbrt::models::NS::Outputs>(                                                      \
      mbrt::models::NS::initial_state(), mbrt::models::NS::kStep, [](auto& s) { return mbrt::models::NS::step(s); },       \
      [](const auto& s, auto& y) { mbrt::models::NS::outputs(s, y); }, [](const auto& s) { return mbrt::models::NS::energy(s); })

}  // namespace

TEST_CASE("a screw and a planar joint at an undamped modal beam's nodes keep its energy and their bodies on the turned sections") {
  const ScrewAndPlate pcst = SCREW_AND_PLATE(modal_node_screw), blajer = SCREW_AND_PLATE(modal_node_screw_blajer);
  const ScrewAndPlate coarse = SCREW_AND_PLATE(modal_node_screw_coarse);
  for (const ScrewAndPlate& r : {pcst, blajer, coarse}) {
    MESSAGE("3 s: energy drift " << r.energy_drift << " J (largest kinetic " << r.largest_kinetic << " J); nut off the turned axis "
                                 << r.off_axis << " m, turned off it " << r.off_turn << ", slide less lead x turn " << r.thread_gap
                                 << " m of " << r.slide << " m; plate off the turned plane " << r.off_plane << " m, tilted "
                                 << r.plate_tilt << ", slid " << r.plate_slide << " m");
    // The joints do move their bodies: the sections turn, the nut screws out, the plate slides.
    CHECK(r.slide > 0.02);
    CHECK(r.plate_slide > 0.5);
    CHECK(r.off_axis < 1e-9);
    CHECK(r.off_turn < 1e-9);
    CHECK(r.thread_gap < 1e-9);
    CHECK(r.off_plane < 1e-9);
    CHECK(r.plate_tilt < 1e-9);
    CHECK(r.energy_drift < 2e-5 * r.largest_kinetic);
  }
  // Second order: half the step, a quarter of the drift (within a third).
  CHECK(pcst.energy_drift < coarse.energy_drift / 3);
}

namespace {

struct StaticLoads {
  double middle_a, frequency_a, tip_b, slope_b, frequency_b;
};

namespace loads = mbrt::models::modal_static_loads;

template <class State, class Outputs, class Step, class Out>
StaticLoads settle_static_loads(State s, double h, Step step, Out outputs) {
  Outputs y{};
  std::vector<double> a, b, b_turn;
  for (int i = 0; i < static_cast<int>(std::lround(15.0 / h)); ++i) {
    REQUIRE(step(s) == mbrt::StepStatus::ok);
    outputs(s, y);
    a.push_back(y[loads::output::middle_a + 1]), b.push_back(y[loads::output::tip_b + 1]);
    b_turn.push_back(turn_z(&y[loads::output::tip_b]));
  }
  StaticLoads out{settled(a, h), 0, settled(b, h), settled(b_turn, h), 0};
  out.frequency_a = undamped_frequency(a, out.middle_a, h, 0.001, 0.2);
  out.frequency_b = undamped_frequency(b, out.tip_b, h, 0.001, 3.0);
  return out;
}

#define SETTLE_STATIC_LOADS(NS)                                                                      \
  settle_static_loads<mbrt::models::NS::State, mbrt::models::NS::Outputs>(                           \
      mbrt::models::NS::initial_state(), mbrt::models::NS::kStep, [](auto& s) { return mbrt::models::NS::step(s); }, \
      [](const auto& s, auto& y) { mbrt::models::NS::outputs(s, y); })

}  // namespace

TEST_CASE("static shapes of the loads at a node joint give the clamped beam and the turned tip their closed forms") {
  const double EI = 100.0, rho_A = 1.0, L = 1.0, P = 2.0, tau = 1.0, unit = std::sqrt(EI / (rho_A * L * L * L * L));
  const double frequency_b = tip_body_frequency(EI, rho_A, L, 0.5, 0.02);
  for (const StaticLoads& r : {SETTLE_STATIC_LOADS(modal_static_loads), SETTLE_STATIC_LOADS(modal_static_loads_blajer)}) {
    MESSAGE("four modes and the tip's static shapes: clamped middle " << r.middle_a << " m (" << P * L * L * L / (192 * EI)
                                                                      << "), first frequency " << r.frequency_a << " rad/s ("
                                                                      << 22.3733 * unit << "); turned tip " << r.tip_b << " m ("
                                                                      << tau * L * L / (2 * EI) << "), turned by " << r.slope_b
                                                                      << " rad (" << tau * L / EI << "), first frequency "
                                                                      << r.frequency_b << " (" << frequency_b << ")");
    // Six modes alone: 0.77 of the middle, 16 % fast, 0.93 of the turn (above).
    CHECK(r.middle_a == doctest::Approx(P * L * L * L / (192 * EI)).epsilon(0.01).scale(0));
    CHECK(r.frequency_a == doctest::Approx(22.3733 * unit).epsilon(0.005).scale(0));
    CHECK(r.tip_b == doctest::Approx(tau * L * L / (2 * EI)).epsilon(0.003).scale(0));
    CHECK(r.slope_b == doctest::Approx(tau * L / EI).epsilon(0.003).scale(0));
    CHECK(r.frequency_b == doctest::Approx(frequency_b).epsilon(0.003).scale(0));
  }
}

namespace {

using modal_momenta::Conservation;

template <class State, class Step, class Energy>
Conservation joint_turns_errors(const State& start, double h, Step step, Energy energy) {
  const modal_momenta::ModalBeamMass rod({1.5, 2.0e5, 400.0, 150.0, 250.0, 2.0, 0.01, 12}, 4);
  // The rigid bodies' masses and inertias (tests/models/modal_joint_turns.yaml).
  const std::array<double, 2> mass = {0.4, 0.3};
  const std::array<Vec3, 2> inertia = {Vec3(0.002, 0.003, 0.004), Vec3(0.02, 0.02, 0.01)};
  const auto momenta = [&](const State& x) {
    std::array<Vec3, 2> m = rod.momenta(x.rigid[0], x.modal_q[0].head(4), x.modal_p[0].head(4));
    for (size_t i = 0; i < 2; ++i) {
      const mbrt::RigidState& b = x.rigid[i + 1];
      const mbrt::Mat3 R = Eigen::Quaterniond(b.p[0], b.p[1], b.p[2], b.p[3]).toRotationMatrix();
      m[0] += mass[i] * b.v;
      m[1] += mass[i] * b.r.cross(b.v) + R * inertia[i].cwiseProduct(b.w);
    }
    return m;
  };
  return modal_momenta::conservation_errors(start, step, energy, momenta, h);
}

#define JOINT_TURNS_ERRORS(NS)                                                                                          \
  joint_turns_errors(mbrt::models::NS::initial_state(), mbrt::models::NS::kStep, [](auto& s) { return mbrt::models::NS::step(s); }, \
                     [](const auto& s) { return mbrt::models::NS::energy(s).total(); })

}  // namespace

TEST_CASE("a free modal body carrying bodies by fixed and revolute joints at its nodes keeps energy, momentum and angular momentum") {
  const Conservation pcst = JOINT_TURNS_ERRORS(modal_joint_turns);
  const Conservation blajer = JOINT_TURNS_ERRORS(modal_joint_turns_blajer);
  const Conservation fine = JOINT_TURNS_ERRORS(modal_joint_turns_fine);
  modal_momenta::check_second_order(pcst, blajer, fine);
}

// The welded four-bar (tests/models/modal_weld_loop.yaml) for 20 s: the
// largest drift of its energy from the start plus the crank torque's work,
// and of its joints' velocity rows.
struct WeldLoopRun {
  double energy_drift, velocity_rows, start_energy;
};

template <class State, class Step, class Energy, class CrankAngle, class Violation>
WeldLoopRun weld_loop_run(State s, double h, Step step, Energy energy, CrankAngle crank_angle, Violation violation) {
  const double torque = 5.0, e0 = energy(s), angle0 = crank_angle(s);
  WeldLoopRun r{0, 0, e0};
  const int steps = static_cast<int>(std::lround(20.0 / h));
  for (int i = 0; i < steps; ++i) {
    REQUIRE(step(s) == mbrt::StepStatus::ok);
    r.energy_drift = std::max(r.energy_drift, std::abs(energy(s) - e0 - torque * (crank_angle(s) - angle0)));
    r.velocity_rows = std::max(r.velocity_rows, violation(s).velocity);
  }
  return r;
}

#define WELD_LOOP_RUN(NS)                                                                                              \
  weld_loop_run(                                                                                                       \
      mbrt::models::NS::initial_state(), mbrt::models::NS::kStep, [](auto& s) { return mbrt::models::NS::step(s); },   \
      [](const auto& s) { return mbrt::models::NS::energy(s).total(); },                                               \
      [](const auto& s) {                                                                                              \
        mbrt::models::NS::Outputs y{};                                                                                 \
        mbrt::models::NS::outputs(s, y);                                                                               \
        return y[mbrt::models::NS::output::crank_angle];                                                               \
      },                                                                                                               \
      [](const auto& s) { return mbrt::models::NS::constraint_violation(s); })

TEST_CASE("a four-bar welded to an undamped modal coupler's node keeps its energy less the torque's work at 0.25 ms") {
  const WeldLoopRun baumgarte = WELD_LOOP_RUN(modal_weld_loop);
  const WeldLoopRun blajer = WELD_LOOP_RUN(modal_weld_loop_blajer);
  for (const WeldLoopRun& r : {baumgarte, blajer}) {
    MESSAGE("20 s: energy less work drifts by " << r.energy_drift << " J of " << r.start_energy << ", velocity rows "
                                                << r.velocity_rows);
    CHECK(r.energy_drift < 1e-3 * r.start_energy);
  }
  CHECK(baumgarte.velocity_rows < 1e-4);
  CHECK(blajer.velocity_rows < 1e-6);
}

TEST_CASE("the step holding modal nodes by joints that turn allocates nothing") {
  struct Pcst {
    using State = mbrt::models::modal_joint_turns::State;
    using Workspace = mbrt::models::modal_joint_turns::Workspace;
    static State initial_state() { return mbrt::models::modal_joint_turns::initial_state(); }
    static mbrt::StepStatus step(State& s, Workspace& w) { return mbrt::models::modal_joint_turns::step(s, w); }
  };
  struct Blajer {
    using State = mbrt::models::modal_joint_turns_blajer::State;
    using Workspace = mbrt::models::modal_joint_turns_blajer::Workspace;
    static State initial_state() { return mbrt::models::modal_joint_turns_blajer::initial_state(); }
    static mbrt::StepStatus step(State& s, Workspace& w) { return mbrt::models::modal_joint_turns_blajer::step(s, w); }
  };
  CHECK(allocations_in<Pcst>(2000) == 0);
  CHECK(allocations_in<Blajer>(2000) == 0);
}

TEST_CASE("the generator turns joints with a modal node's section, and refuses what it cannot") {
  const std::string beam =
      "bodies:\n  - name: boom\n    flexible: {length: 2.0, elements: 10, modes: 4, EA: 1.0e6, GJ: 500.0, EI: 800.0, "
      "rho_A: 2.0, rho_J: 0.01}\n  - {name: arm, mass: 1.0, inertia: [0.01, 0.01, 0.01], position: [2.5, 0, 0]}\n";
  const std::string clamp = "  - {name: clamp, type: fixed, body1: ground, body2: boom, point: [0, 0, 0]}\n";
  const auto with = [&](const std::string& joint, const std::string& more = "") {
    return generator_error("name: turns\n" + beam + "joints:\n" + clamp + joint + more);
  };
  // The node's place is the joint's point unless one is given.
  const std::string hinge = "  - {name: hinge, type: revolute, body1: boom@tip, body2: arm, axis: [0, 0, 1]}\n";
  CHECK(with(hinge) == "");
  CHECK(with("  - {name: hinge, type: revolute, body1: boom@tip, body2: arm, point: [2, 0, 0], axis: [0, 0, 1]}\n") == "");
  CHECK(with("  - {name: cross, type: universal, body1: boom@7, body2: arm, axis1: [0, 0, 1], axis2: [0, 1, 0]}\n") == "");
  CHECK(with("  - {name: weld, type: fixed, body1: arm, body2: boom@tip}\n") == "");
  CHECK(with("  - {name: hinge, type: revolute, body1: boom@tip, body2: arm, point: [1.9, 0, 0], axis: [0, 0, 1]}\n")
            .find("node 10 of modal body 'boom', which is at (2.000000, 0.000000, 0.000000") != std::string::npos);
  // Drivers, joint springs, joint inputs and joint outputs take the joint
  // at the node; friction there is not modelled.
  CHECK(with(hinge, "drivers:\n  - {name: turn, type: joint_angle, joint: hinge, function: {polynomial: [0, 1]}}\n") == "");
  CHECK(with(hinge, "forces:\n  - {type: joint_spring, joint: hinge, stiffness: 10.0}\n") == "");
  CHECK(with(hinge, "outputs:\n  - {name: angle, type: joint_position, joint: hinge}\n") == "");
  CHECK(with(hinge, "inputs:\n  - {name: motor, type: joint_torque, joint: hinge, min: -1, max: 1, safe: 0}\n") == "");
  CHECK(with("  - {name: hinge, type: revolute, body1: boom@tip, body2: arm, axis: [0, 0, 1], friction: {torque: 0.1}}\n")
            .find("joint 'hinge' holds a modal body's node: friction there is not modelled") != std::string::npos);
  // A prismatic joint there takes a spring, an input, outputs and a driver,
  // not friction; cylindrical, screw and planar joints take a node, a
  // velocity_toward joint does not.
  const std::string slide = "  - {name: slide, type: prismatic, body1: boom@tip, body2: arm, axis: [0, 1, 0]}\n";
  CHECK(with(slide, "forces:\n  - {type: joint_spring, joint: slide, stiffness: 10.0}\n") == "");
  CHECK(with(slide, "inputs:\n  - {name: push, type: joint_force, joint: slide, min: -1, max: 1, safe: 0}\n") == "");
  CHECK(with(slide, "outputs:\n  - {name: at, type: joint_position, joint: slide}\n") == "");
  CHECK(with(slide, "drivers:\n  - {name: move, type: joint_distance, joint: slide, function: {polynomial: [0, 1]}}\n") == "");
  CHECK(with("  - {name: slide, type: prismatic, body1: boom@tip, body2: arm, axis: [0, 1, 0], friction: {force: 0.1}}\n")
            .find("joint 'slide' holds a modal body's node: friction there is not modelled") != std::string::npos);
  CHECK(with("  - {name: slide, type: cylindrical, body1: boom@tip, body2: arm, axis: [0, 1, 0]}\n") == "");
  CHECK(with("  - {name: thread, type: screw, body1: boom@tip, body2: arm, axis: [1, 0, 0], lead: 0.1}\n") == "");
  CHECK(with("  - {name: table, type: planar, body1: boom@tip, body2: arm, axis: [0, 1, 0]}\n") == "");
  CHECK(with("  - {name: aim, type: velocity_toward, body1: boom@tip, body2: arm, point1: [2, 0, 0], point2: [3, 0, 0], "
             "plane_normal: [0, 0, 1]}\n")
            .find("a velocity_toward joint attaches to modal body 'boom' at its root: name the body") != std::string::npos);
}

TEST_CASE("the generator takes a modal beam's static loads and says what is wrong with them") {
  const auto beam = [](const std::string& modes, const std::string& loads) {
    return generator_error("name: loads\nbodies:\n  - name: boom\n    flexible: {length: 2.0, elements: 10, modes: " + modes +
                           ", static_loads: " + loads + ", EA: 1.0e6, GJ: 500.0, EI: [800.0, 900.0], rho_A: 2.0, rho_J: 0.01}\n"
                           "joints:\n  - {name: clamp, type: fixed, body1: ground, body2: boom, point: [0, 0, 0]}\n");
  };
  CHECK(beam("4", "{tip: [y, rz]}") == "");
  CHECK(beam("2", "{tip: [y, z, ry, rz]}") == "");
  CHECK(beam("3", "{5: [x, y], tip: [y]}") == "");
  CHECK(beam("4", "{tip: [y, z, rz]}").find("4 modes and 3 static loads make 7 modes; a body keeps at most 6") != std::string::npos);
  CHECK(beam("4", "{tip: [rx]}").find("rx twists the beam, and its modes leave torsion out") != std::string::npos);
  CHECK(beam("4", "{root: [y]}").find("the root is clamped") != std::string::npos);
  CHECK(beam("4", "{tip: [y, y]}").find("'y' given twice for this node") != std::string::npos);
  CHECK(beam("4", "{11: [y]}").find("unknown node '11' of modal body 'boom'") != std::string::npos);
  CHECK(beam("4", "[tip]").find("expected a map of nodes to load directions, such as {tip: [y, rz]}") != std::string::npos);
  // One element bends in each plane in two ways, which four modes already hold.
  CHECK(generator_error("name: one\nbodies:\n  - name: boom\n    flexible: {length: 2.0, elements: 1, modes: 4, static_loads: "
                        "{tip: [y]}, EA: 1.0e6, GJ: 500.0, EI: [800.0, 900.0], rho_A: 2.0, rho_J: 0.01}\n")
            .find("bodies.boom.flexible.static_loads: static_loads: the load at node tip along y moves the body as the modes "
                  "kept and the loads before it already do; drop it") != std::string::npos);
  CHECK(generator_error("name: nodal\nbodies:\n  - name: boom\n    flexible: {length: 2.0, elements: 4, static_loads: {tip: [y]}, "
                        "EA: 1.0e6, GJ: 500.0, EI: [800.0, 900.0], rho_A: 2.0, rho_J: 0.01}\n")
            .find("static_loads shape a modal body's modes; give modes, or remove it for a nodal beam") != std::string::npos);
  CHECK(beam("4", "{tip: [w]}").find("bodies[0].flexible.static_loads.tip[0]: expected one of: x, y, z, rx, ry, rz, got 'w'") !=
        std::string::npos);
}
