// Joints at a modal body's nodes (docs/flexible.md): the rows' split
// between the frame and the modal momenta against finite differences of the
// node's motion and its section's turn, for point joints (spherical,
// distance) and those with axes (revolute, universal, fixed); and, for point
// joints, a propped
// cantilever and a simply supported beam against their closed-form
// deflections, reactions and first frequencies in the three schemes that
// take modal bodies; a free beam holding two particles by such joints keeps
// the bodies' energy, momentum and angular momentum, in a step that
// allocates nothing; the generator's checks.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include <mbrt/joints.hpp>
#include <mbrt/modal_body.hpp>

#include "analysis.hpp"
#include "generator_error.hpp"
#include "modal_joint_pair.hpp"
#include "modal_joint_pair_blajer.hpp"
#include "modal_joint_pair_fine.hpp"
#include "modal_momenta.hpp"
#include "modal_propped.hpp"
#include "modal_propped_baumgarte.hpp"
#include "modal_propped_blajer.hpp"
#include "model.hpp"
#include "step_allocations.hpp"

namespace {

using mbrt::Mat3;
using mbrt::Vec3;
namespace cg = mbrt::codegen;
constexpr int N = 3;
using Modes = Eigen::Matrix<double, N, 1>;

// A frame and its modes along smooth functions of time; p follows from its
// definition, p = dT/dqdot, with T the kinetic energy of the modes' linear
// field shifted by sigma(q) = (q^T D_a q / (2 m))_a (include/mbrt/modal_body.hpp):
// formed here as the linear field's mass matrix in the shifted frame's
// velocities, carried back by the shift, M = G^T M_lin G.
struct Trajectory {
  mbrt::ModalBody<N> body;
  Vec3 r(double t) const { return {0.3 * t + 0.2 * t * t, std::sin(1.3 * t), 0.5 - 0.4 * t * t * t}; }
  Mat3 R(double t) const {
    return (Eigen::AngleAxisd(0.7 + 1.9 * t, Vec3(0.3, -0.5, 0.8).normalized()) *
            Eigen::AngleAxisd(std::sin(2.1 * t), Vec3(-0.6, 0.2, 0.4).normalized()))
        .toRotationMatrix();
  }
  Modes q(double t) const { return {0.05 * std::sin(3.0 * t), -0.02 + 0.03 * t * t, 0.04 * std::cos(1.7 * t)}; }
  // Velocities by central differences of positions (to 1e-10 at this step).
  Vec3 v(double t) const { return (r(t + kD) - r(t - kD)) / (2 * kD); }
  Vec3 w(double t) const {
    const Mat3 W = R(t).transpose() * (R(t + kD) - R(t - kD)) / (2 * kD);
    return {W(2, 1), W(0, 2), W(1, 0)};
  }
  Modes p(double t) const {
    const Modes x = q(t), qd = (q(t + kD) - q(t - kD)) / (2 * kD);
    // The linear field rho0 + Psi q: first moment St q, inertia about the
    // origin J + int (|u|^2 + 2 rho0 . u) I - rho0 u^T - u rho0^T - u u^T,
    // Sr^T's rows int (rho0 + u) x Psi_j.
    Mat3 X, W;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        X(a, b) = body.G[static_cast<size_t>(3 * a + b)].dot(x);
        W(a, b) = x.dot(body.E[static_cast<size_t>(3 * a + b)] * x);
      }
    const Mat3 J = body.J + (2 * X.trace() + W.trace()) * Mat3::Identity() - X - X.transpose() - W;
    Eigen::Matrix<double, N, 3> Sr_T = body.Sr_T;
    for (int j = 0; j < N; ++j) {
      Modes e = Modes::Zero();
      e(j) = 1;
      Vec3 moment;  // int u x Psi_j: component i is e_iab int u_a Psi_bj
      for (int i = 0; i < 3; ++i) {
        const int a = (i + 1) % 3, b = (i + 2) % 3;
        moment(i) = x.dot(body.E[static_cast<size_t>(3 * a + b)] * e) - x.dot(body.E[static_cast<size_t>(3 * b + a)] * e);
      }
      Sr_T.row(j) += moment.transpose();
    }
    Eigen::Matrix<double, 6 + N, 6 + N> M_lin = Eigen::Matrix<double, 6 + N, 6 + N>::Zero();
    M_lin.topLeftCorner<3, 3>() = body.m * Mat3::Identity();
    M_lin.block<3, 3>(0, 3) = -mbrt::skew(body.St_T.transpose() * x);
    M_lin.block<3, 3>(3, 0) = mbrt::skew(body.St_T.transpose() * x);
    M_lin.block<3, 3>(3, 3) = J;
    M_lin.block<3, N>(0, 6) = body.St_T.transpose();
    M_lin.block<3, N>(3, 6) = Sr_T.transpose();
    M_lin.block<N, 3>(6, 0) = body.St_T;
    M_lin.block<N, 3>(6, 3) = Sr_T;
    M_lin.bottomRightCorner<N, N>().setIdentity();
    // The shift: v_shifted = v + w x sigma + (d sigma / dq) qdot.
    Eigen::Matrix<double, 3, N> g;
    for (int a = 0; a < 3; ++a) g.row(a) = (body.kg[static_cast<size_t>(6 + a)] * x).transpose() / body.m;
    const Vec3 sigma = 0.5 * g * x;
    Eigen::Matrix<double, 6 + N, 6 + N> G = Eigen::Matrix<double, 6 + N, 6 + N>::Identity();
    G.block<3, 3>(0, 3) = -mbrt::skew(sigma);
    G.block<3, N>(0, 6) = g;
    const Eigen::Matrix<double, 6 + N, 6 + N> M = G.transpose() * M_lin * G;
    Eigen::Matrix<double, 6 + N, 1> y;
    y << R(t).transpose() * v(t), w(t), qd;
    return (M * y).tail<N>();
  }
  static constexpr double kD = 1e-5;
};

// The node's rows at t through the kernel and modal_node_rows, as the
// generated constraint_rows forms them, with the modal body on `side` (1 or 2)
// and a ground point on the other.
template <class Kernel, int K>
struct NodeRows {
  mbrt::ConstraintRows<K> rows;
  Eigen::Matrix<double, K, 6> jq, jp;
};

template <int K, class Kernel>
NodeRows<Kernel, K> node_rows(const Trajectory& x, const mbrt::ModalPoint<N>& c, double t, int side, Kernel kernel) {
  const mbrt::BodyPose pose{x.r(t), x.R(t)};
  const mbrt::BodyVelocity vel{x.v(t), x.w(t)};
  const Modes q = x.q(t), p = x.p(t);
  const mbrt::ModalPointMotion<N> node = mbrt::modal_point_motion<N>(x.body, c, pose, vel, q, p);
  const mbrt::BodyPose ground{Vec3::Zero(), Mat3::Identity()};
  const mbrt::BodyVelocity still{Vec3::Zero(), Vec3::Zero()};
  mbrt::JointFrame f{};
  f.length = 1.7;
  // Two triads, each the kernels' a, b, c: the axes of the joints that turn with the section.
  const Mat3 triad1 = Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Mat3 triad2 = Eigen::AngleAxisd(-1.1, Vec3(-2, 0.5, 1).normalized()).toRotationMatrix();
  f.a1 = triad1.col(0), f.b1 = triad1.col(1), f.c1 = triad1.col(2);
  f.a2 = triad2.col(0), f.b2 = triad2.col(1), f.c2 = triad2.col(2);
  const Vec3 anchor(0.4, -1.1, 0.9);
  (side == 1 ? f.s1 : f.s2) = node.point;
  (side == 1 ? f.s2 : f.s1) = anchor;
  f = mbrt::turned_joint_frame(f, side, node.turn.C);
  const mbrt::BodyVelocity carried = node.velocity;
  NodeRows<Kernel, K> out;
  out.rows = side == 1 ? kernel(f, {pose, carried}, {ground, still}) : kernel(f, {ground, still}, {pose, carried});
  out.jq = mbrt::modal_node_rows<N, K>(x.body, c, pose, vel, q, node, side == 1 ? out.rows.J1 : out.rows.J2, out.rows.quad, out.jp);
  return out;
}

template <int K, class Kernel>
void check_against_differences(const Trajectory& x, const mbrt::ModalPoint<N>& c, int side, Kernel kernel) {
  const double t = 0.37, d = 1e-4;
  const auto phi = [&](double s) { return node_rows<K>(x, c, s, side, kernel).rows.phi; };
  const NodeRows<Kernel, K> at = node_rows<K>(x, c, t, side, kernel);
  const Eigen::Matrix<double, K, 6>& J = side == 1 ? at.rows.J1 : at.rows.J2;
  Eigen::Matrix<double, 6, 1> u, u_dot;
  u << x.v(t), x.w(t);
  u_dot << (x.v(t + d) - x.v(t - d)) / (2 * d), (x.w(t + d) - x.w(t - d)) / (2 * d);
  Eigen::Matrix<double, 6, 1> p = Eigen::Matrix<double, 6, 1>::Zero(), p_dot = Eigen::Matrix<double, 6, 1>::Zero();
  p.head<N>() = x.p(t);
  p_dot.head<N>() = (x.p(t + d) - x.p(t - d)) / (2 * d);
  const Eigen::Matrix<double, K, 1> rate = J * u + at.jp * p;
  const Eigen::Matrix<double, K, 1> acceleration = J * u_dot + at.jp * p_dot + at.rows.quad;
  const Eigen::Matrix<double, K, 1> rate_fd = (phi(t + d) - phi(t - d)) / (2 * d);
  const Eigen::Matrix<double, K, 1> acceleration_fd = (phi(t + d) - 2 * phi(t) + phi(t - d)) / (d * d);
  MESSAGE("side " << side << ", " << K << " rows: rate off by " << (rate - rate_fd).norm() << " of " << rate_fd.norm()
                  << ", acceleration by " << (acceleration - acceleration_fd).norm() << " of " << acceleration_fd.norm()
                  << "; the rigid rows alone would be off by " << (J * u_dot + at.rows.quad - acceleration_fd).norm());
  CHECK((rate - rate_fd).norm() < 1e-7 * rate_fd.norm());
  CHECK((acceleration - acceleration_fd).norm() < 1e-5 * acceleration_fd.norm());
  CHECK(at.jq.template rightCols<6 - N>().isZero(0.0));
}

}  // namespace

TEST_CASE("a joint's rows at a modal body's node move as finite differences of the node's motion and its section's turn") {
  Trajectory x;
  std::srand(7);
  x.body.m = 2.5;
  x.body.J = Eigen::Vector3d(0.2, 0.9, 1.1).asDiagonal();
  x.body.St_T.setRandom();
  x.body.Sr_T.setRandom();
  for (auto& e : x.body.E) e.setRandom();
  for (int a = 6; a < 9; ++a) {  // the shortening's first moment: symmetric Hessians
    const Eigen::Matrix<double, N, N> h = Eigen::Matrix<double, N, N>::Random();
    x.body.kg[static_cast<size_t>(a)] = h + h.transpose();
  }
  x.body.kg_cases = 0b111000000u;
  mbrt::ModalPoint<N> c;
  c.point = Vec3(0.6, -0.2, 0.1);
  c.displacement.setRandom();
  c.rotation.setRandom();
  const auto spherical = [](const mbrt::JointFrame& f, const mbrt::BodyMotion& a, const mbrt::BodyMotion& b) {
    return mbrt::spherical(f, a, b);
  };
  const auto distance = [](const mbrt::JointFrame& f, const mbrt::BodyMotion& a, const mbrt::BodyMotion& b) {
    return mbrt::distance(f, a, b);
  };
  const auto revolute = [](const mbrt::JointFrame& f, const mbrt::BodyMotion& a, const mbrt::BodyMotion& b) {
    return mbrt::revolute(f, a, b);
  };
  const auto universal = [](const mbrt::JointFrame& f, const mbrt::BodyMotion& a, const mbrt::BodyMotion& b) {
    return mbrt::universal(f, a, b);
  };
  const auto fixed = [](const mbrt::JointFrame& f, const mbrt::BodyMotion& a, const mbrt::BodyMotion& b) {
    return mbrt::fixed(f, a, b);
  };
  for (int side : {1, 2}) {
    check_against_differences<3>(x, c, side, spherical);
    check_against_differences<1>(x, c, side, distance);
    check_against_differences<5>(x, c, side, revolute);
    check_against_differences<4>(x, c, side, universal);
    check_against_differences<6>(x, c, side, fixed);
  }
}

// A generated model's functions as one type, for the templates below.
#define MODEL_TYPE(NS)                                                                         \
  struct NS {                                                                                  \
    using State = mbrt::models::NS::State;                                                     \
    using Outputs = mbrt::models::NS::Outputs;                                                 \
    using Reactions = mbrt::models::NS::Reactions;                                             \
    using Workspace = mbrt::models::NS::Workspace;                                             \
    static constexpr double kStep = mbrt::models::NS::kStep;                                   \
    static State initial_state() { return mbrt::models::NS::initial_state(); }                 \
    static mbrt::StepStatus step(State& s) { return mbrt::models::NS::step(s); }               \
    static mbrt::StepStatus step(State& s, Workspace& w) { return mbrt::models::NS::step(s, w); } \
    static void outputs(const State& s, Outputs& y) { mbrt::models::NS::outputs(s, y); }       \
    static void reactions(const State& s, Reactions& r) { mbrt::models::NS::reactions(s, r); } \
    static double energy(const State& s) { return mbrt::models::NS::energy(s).total(); }       \
  };

namespace models {
MODEL_TYPE(modal_propped)
MODEL_TYPE(modal_propped_baumgarte)
MODEL_TYPE(modal_propped_blajer)
MODEL_TYPE(modal_joint_pair)
MODEL_TYPE(modal_joint_pair_blajer)
MODEL_TYPE(modal_joint_pair_fine)
}  // namespace models

namespace {

// One model file in three schemes: the same outputs and joints.
namespace propped = mbrt::models::modal_propped;

// After 15 s, damped to rest: the middle nodes' deflections along y, the
// reactions, and the first frequencies from the first second's up-crossings
// of the settled deflection, undamped: stiffness-proportional damping c K
// gives mode k the ratio c w_k / 2 (the joints add no stiffness, so their
// modes keep C = c K), and it swings at w_k sqrt(1 - (c w_k / 2)^2).
struct Propped {
  double middle_a, middle_b;
  mbrt::JointReaction clamp_a, prop_a, root_b, tip_b;
  double frequency_a, frequency_b;
};

double undamped_frequency(const std::vector<double>& y, double settled, double h) {
  std::vector<double> crossings;
  for (size_t i = 1; i < y.size(); ++i) {
    if (y[i - 1] < settled && y[i] >= settled) crossings.push_back(h * (static_cast<double>(i) - 1 + (settled - y[i - 1]) / (y[i] - y[i - 1])));
  }
  REQUIRE(crossings.size() >= 5);
  const double damped = 2 * std::numbers::pi * static_cast<double>(crossings.size() - 1) / (crossings.back() - crossings.front());
  const double z = 0.001 * damped / 2;  // to 1e-5: the ratio at the undamped frequency would differ by z^2
  return damped / std::sqrt(1 - z * z);
}

template <class M>
Propped settle_propped() {
  typename M::State s = M::initial_state();
  typename M::Outputs y{};
  std::vector<double> a, b;
  const int steps = static_cast<int>(std::lround(15.0 / M::kStep)), first_second = static_cast<int>(std::lround(1.0 / M::kStep));
  for (int i = 0; i < steps; ++i) {
    REQUIRE(M::step(s) == mbrt::StepStatus::ok);
    M::outputs(s, y);
    if (i < first_second) a.push_back(y[propped::output::middle_a + 1]), b.push_back(y[propped::output::middle_b + 1]);
  }
  typename M::Reactions r;
  M::reactions(s, r);
  Propped out{y[propped::output::middle_a + 1], y[propped::output::middle_b + 1],
              r[propped::constraint::clamp_a], r[propped::constraint::prop_a], r[propped::constraint::root_b],
              r[propped::constraint::tip_b], 0, 0};
  out.frequency_a = undamped_frequency(a, out.middle_a, M::kStep);
  out.frequency_b = undamped_frequency(b, out.middle_b, M::kStep);
  return out;
}

}  // namespace

TEST_CASE("a propped cantilever and a simply supported beam of modes settle, react and swing as Euler-Bernoulli's") {
  const double P = 2.0, L = 1.0, EI = 100.0, unit = std::sqrt(EI / (1.0 * L * L * L * L));
  const std::array<Propped, 3> runs = {settle_propped<models::modal_propped>(), settle_propped<models::modal_propped_baumgarte>(),
                                       settle_propped<models::modal_propped_blajer>()};
  for (const Propped& r : runs) {
    MESSAGE("propped: middle " << r.middle_a << " m (closed form " << 7 * P * L * L * L / (768 * EI) << "), prop "
                               << r.prop_a.force.transpose() << " N (" << -5 * P / 16 << " along y), clamp "
                               << r.clamp_a.force.transpose() << " N, " << r.clamp_a.torque.transpose() << " N m ("
                               << -11 * P / 16 << ", " << -3 * P * L / 16 << "), first frequency " << r.frequency_a
                               << " rad/s (" << 15.418 * unit << ")");
    MESSAGE("simply supported: middle " << r.middle_b << " m (" << P * L * L * L / (48 * EI) << "), pins "
                                        << r.root_b.force.transpose() << " and " << r.tip_b.force.transpose() << " N ("
                                        << -P / 2 << " and " << P / 2 << " along y), first frequency " << r.frequency_b
                                        << " (" << std::numbers::pi * std::numbers::pi * unit << ")");
    // Four cantilever modes as Ritz functions: within 1 % statically.
    CHECK(r.middle_a == doctest::Approx(7 * P * L * L * L / (768 * EI)).epsilon(0.01).scale(0));
    CHECK(r.prop_a.force.y() == doctest::Approx(-5 * P / 16).epsilon(0.02).scale(0));
    CHECK(r.clamp_a.force.y() == doctest::Approx(-11 * P / 16).epsilon(0.01).scale(0));
    CHECK(r.clamp_a.torque.z() == doctest::Approx(-3 * P * L / 16).epsilon(0.03).scale(0));
    CHECK(r.middle_b == doctest::Approx(P * L * L * L / (48 * EI)).epsilon(0.01).scale(0));
    // root_b acts on the beam; tip_b's body 1 is the beam, so it reports what the ground receives.
    CHECK(r.root_b.force.y() == doctest::Approx(-P / 2).epsilon(0.01).scale(0));
    CHECK(r.tip_b.force.y() == doctest::Approx(P / 2).epsilon(0.01).scale(0));
    // Along the propped beam the prop's and the clamp's rows repeat (its
    // modes do not stretch it): how they share a force along it is left to
    // the scheme, but the two cancel.
    CHECK(std::abs(r.prop_a.force.x() + r.clamp_a.force.x()) < 1e-6);
    CHECK(std::abs(r.root_b.force.x()) < 1e-6);
    CHECK(std::abs(r.tip_b.force.x()) < 1e-6);
    for (const mbrt::JointReaction& j : {r.prop_a, r.clamp_a, r.root_b, r.tip_b}) CHECK(std::abs(j.force.z()) < 1e-9);
    CHECK(r.frequency_a == doctest::Approx(15.418 * unit).epsilon(0.005).scale(0));
    CHECK(r.frequency_b == doctest::Approx(std::numbers::pi * std::numbers::pi * unit).epsilon(0.005).scale(0));
  }
}

namespace {

using modal_momenta::Conservation;

template <class M>
Conservation joint_pair_errors() {
  const modal_momenta::ModalBeamMass rod({1.5, 2.0e5, 400.0, 150.0, 250.0, 2.0, 0.01, 12}, 4);
  const auto momenta = [&](const typename M::State& x) {
    std::array<Vec3, 2> m = rod.momenta(x.rigid[0], x.modal_q[0].head(4), x.modal_p[0].head(4));
    for (const auto& [particle, mass] : {std::pair{x.particle[0], 0.4}, std::pair{x.particle[1], 0.3}}) {
      m[0] += mass * particle.v;
      m[1] += mass * particle.r.cross(particle.v);
    }
    return m;
  };
  return modal_momenta::conservation_errors(
      M::initial_state(), [](typename M::State& s) { return M::step(s); },
      [](const typename M::State& s) { return M::energy(s); }, momenta, M::kStep);
}

}  // namespace

TEST_CASE("a free modal body holding particles by joints at two nodes keeps the bodies' energy, momentum and angular momentum") {
  const Conservation pcst = joint_pair_errors<models::modal_joint_pair>();
  const Conservation blajer = joint_pair_errors<models::modal_joint_pair_blajer>();
  const Conservation fine = joint_pair_errors<models::modal_joint_pair_fine>();
  modal_momenta::check_second_order(pcst, blajer, fine);
}

TEST_CASE("the step holding modal nodes by joints allocates nothing") {
  CHECK(allocations_in<models::modal_joint_pair>(2000) == 0);
  CHECK(allocations_in<models::modal_joint_pair_blajer>(2000) == 0);
}


TEST_CASE("the generator holds a modal body's node by a point joint or a screw, and refuses what it cannot hold there") {
  const std::string beam =
      "bodies:\n  - name: boom\n    flexible: {length: 2.0, elements: 10, modes: 4, EA: 1.0e6, GJ: 500.0, EI: 800.0, "
      "rho_A: 2.0, rho_J: 0.01}\n";
  const std::string clamp = "  - {name: clamp, type: fixed, body1: ground, body2: boom, point: [0, 0, 0]}\n";
  // The node's place is the joint's point unless one is given, which must be
  // the node's. Propped, the beam's x row repeats the clamp's, and is taken.
  const std::string propped = "name: ok\n" + beam + "joints:\n" + clamp + "  - {name: prop, type: spherical, body1: ground, body2: boom@tip}\n";
  CHECK(generator_error(propped) == "");
  CHECK(cg::analyse(cg::parse_model(propped, "modal.yaml")).redundant_rows == 1);
  CHECK(generator_error("name: ok\n" + beam + "joints:\n" + clamp +
                        "  - {name: prop, type: spherical, body1: boom@7, body2: ground, point: [1.4, 0, 0]}\n") == "");
  CHECK(generator_error("name: ok\n" + beam + "joints:\n" + clamp +
                        "  - {name: link, type: distance, body1: boom@tip, body2: ground, point2: [2, 3, 0]}\n") == "");
  const std::string off = generator_error("name: off\n" + beam + "joints:\n" + clamp +
                                          "  - {name: prop, type: spherical, body1: ground, body2: boom@tip, point: [1.9, 0, 0]}\n");
  CHECK(off.find("joints.prop") != std::string::npos);
  CHECK(off.find("node 10 of modal body 'boom', which is at (2.000000, 0.000000, 0.000000") != std::string::npos);
  const std::string screw = generator_error("name: screw\n" + beam + "joints:\n" + clamp +
                                            "  - {name: thread, type: screw, body1: ground, body2: boom@tip, "
                                            "point: [2, 0, 0], axis: [0, 0, 1], lead: 0.01}\n");
  CHECK(screw == "");  // a screw joint takes the node too
  // Pinned at both ends along its axis, a beam of bending modes cannot bend
  // without stretching; propped (its frame clamped, unable to turn) it can.
  const std::string pinned = generator_error(
      "name: pinned\n" + beam +
      "joints:\n  - {name: root, type: spherical, body1: ground, body2: boom, point: [0, 0, 0]}\n"
      "  - {name: tip, type: spherical, body1: boom@tip, body2: ground}\n");
  CHECK(pinned.find("joints.tip: its rows repeat the other joints' at t = 0, and part at second order as the bodies move: "
                    "it holds modal body 'boom' at a node") != std::string::npos);
  const std::string pair = "  - name: other\n    flexible: {length: 2.0, elements: 10, modes: 4, EA: 1.0e6, GJ: 500.0, EI: 800.0, "
                           "rho_A: 2.0, rho_J: 0.01}\n    position: [4, 0, 0]\n    orientation: [0, 0, 0, 1]\n";
  const std::string other_clamp = "  - {name: other_clamp, type: fixed, body1: ground, body2: other, point: [4, 0, 0]}\n";
  CHECK(generator_error("name: meet\n" + beam + pair + "joints:\n" + clamp + other_clamp +
                        "  - {name: meet, type: spherical, body1: boom@tip, body2: other@tip}\n") == "");
  CHECK(generator_error("name: apart\n" + beam + pair + "joints:\n" + clamp + other_clamp +
                        "  - {name: meet, type: spherical, body1: boom@9, body2: other@tip}\n")
            .find("a spherical joint holds its two nodes together, but they start 0.2 m apart") != std::string::npos);
  CHECK(generator_error("name: roller\n" + beam +
                        "joints:\n  - {name: root, type: spherical, body1: ground, body2: boom, point: [0, 0, 0]}\n"
                        "  - {name: tip, type: distance, body1: boom@tip, body2: ground, point2: [2, -10, 0]}\n") == "");
}
