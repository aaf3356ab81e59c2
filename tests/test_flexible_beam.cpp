// Flexible bodies as nodal beams (docs/flexible.md): the element against
// finite differences of its energy; generated models against closed forms
// (a cantilever's static deflection under its weight and its first bending
// frequency, the stretch of a spinning beam), conservation laws (a free
// tumbling beam) and an independent model of Simo & Vu-Quoc's spin-up (the
// beam's modes with their geometric stiffness, codegen/plan/beam_modes).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Geometry>
#include <mbrt/beam_element.hpp>

#include "beam_modes.hpp"
#include "flexible_cantilever.hpp"
#include "flexible_free.hpp"
#include "flexible_spin_up.hpp"
#include "spin_up_reference.hpp"

namespace {

using mbrt::Mat3;
using mbrt::Vec3;

Mat3 rotation(const Vec3& axis, double angle) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

}  // namespace

TEST_CASE("a beam element's end forces and torques are minus its energy's gradient, and balance") {
  const mbrt::BeamElement e{Vec3(0.05, -0.02, 0.01), Vec3(-0.03, 0.04, 0.02), rotation(Vec3(1, 2, 3), 0.7),
                            rotation(Vec3(-2, 1, 1), 0.4), 0.5, 3e4, 1e4, 8e3, 150, 200, 320, 0.0};
  // Body poses giving the element stretch, shear, bending and torsion at once.
  mbrt::BodyPose p1{Vec3(0.1, 0.2, -0.1), rotation(Vec3(0.3, -1, 0.5), 0.9)};
  mbrt::BodyPose p2{Vec3(0.0, 0.0, 0.0), Mat3::Identity()};
  p2.R = p1.R * e.Q1 * rotation(Vec3(0.4, 0.7, -0.2), 0.25) * e.Q2.transpose();
  p2.r = p1.r + p1.R * e.s1 + p1.R * e.Q1 * Vec3(0.52, 0.03, -0.02) - p2.R * e.s2;
  const mbrt::BodyVelocity still{Vec3::Zero(), Vec3::Zero()};
  const auto load = [&](const mbrt::BodyPose& a, const mbrt::BodyPose& b) {
    return mbrt::beam_element(e, mbrt::BodyMotion{a, still}, mbrt::BodyMotion{b, still});
  };
  const mbrt::BeamElementLoad at = load(p1, p2);
  REQUIRE(at.energy > 1.0);
  // Generalized forces on [r; body-axis rotation] of each body.
  const Vec3 f1 = -at.f2, f2 = at.f2;
  const Vec3 m1 = at.tau1 + e.s1.cross(p1.R.transpose() * f1), m2 = at.tau2 + e.s2.cross(p2.R.transpose() * f2);
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    const Vec3 d = h * Vec3::Unit(k);
    mbrt::BodyPose a = p1, b = p1;
    a.r += d, b.r -= d;
    CHECK(-(load(a, p2).energy - load(b, p2).energy) / (2 * h) == doctest::Approx(f1[k]).epsilon(1e-6).scale(1.0));
    a = p1, b = p1;
    a.R = p1.R * rotation(Vec3::Unit(k), h), b.R = p1.R * rotation(Vec3::Unit(k), -h);
    CHECK(-(load(a, p2).energy - load(b, p2).energy) / (2 * h) == doctest::Approx(m1[k]).epsilon(1e-6).scale(1.0));
    a = p2, b = p2;
    a.r += d, b.r -= d;
    CHECK(-(load(p1, a).energy - load(p1, b).energy) / (2 * h) == doctest::Approx(f2[k]).epsilon(1e-6).scale(1.0));
    a = p2, b = p2;
    a.R = p2.R * rotation(Vec3::Unit(k), h), b.R = p2.R * rotation(Vec3::Unit(k), -h);
    CHECK(-(load(p1, a).energy - load(p1, b).energy) / (2 * h) == doctest::Approx(m2[k]).epsilon(1e-6).scale(1.0));
  }
  // No net moment about the origin: internal forces.
  const Vec3 x1 = p1.r + p1.R * e.s1, x2 = p2.r + p2.R * e.s2;
  const Vec3 moment = x1.cross(f1) + x2.cross(f2) + p1.R * at.tau1 + p2.R * at.tau2;
  CHECK(moment.norm() < 1e-9 * at.f2.norm());
}

// Damping dissipates: its extra forces and torques take power
// -damping (EA l0 e'^2 + k'^T diag(GJ, EIy, EIz) k' / l0) from the ends'
// motion (to first order in the rotation strains, small here).
TEST_CASE("a beam element's damping takes the power of its stretch and rotation rates") {
  mbrt::BeamElement e{Vec3::Zero(), Vec3::Zero(), Mat3::Identity(), Mat3::Identity(), 0.4, 2e4, 5e3, 5e3, 80, 100, 150, 0.0};
  const mbrt::BodyPose p1{Vec3::Zero(), Mat3::Identity()};
  const mbrt::BodyPose p2{Vec3(0.401, 0.002, -0.001), rotation(Vec3(1, -2, 3), 0.004)};
  const mbrt::BodyVelocity v1{Vec3(0.1, -0.2, 0.3), Vec3(0.5, 0.2, -0.4)}, v2{Vec3(-0.3, 0.1, 0.2), Vec3(-0.2, 0.6, 0.3)};
  const auto power = [&](double damping) {
    e.damping = damping;
    const mbrt::BeamElementLoad l = mbrt::beam_element(e, mbrt::BodyMotion{p1, v1}, mbrt::BodyMotion{p2, v2});
    return -l.f2.dot(v1.v) + l.tau1.dot(v1.w) + l.f2.dot(v2.v) + l.tau2.dot(v2.w);  // the ends are the centres
  };
  const double beta = 1e-3;
  const Vec3 d = p2.r - p1.r;
  const double stretch_rate = d.normalized().dot(v2.v - v1.v) / e.l0;
  const Vec3 k_rate = p2.R * v2.w - v1.w;
  const double expected = -beta * (e.EA * e.l0 * stretch_rate * stretch_rate +
                                   k_rate.dot(Vec3(e.GJ, e.EIy, e.EIz).cwiseProduct(k_rate)) / e.l0);
  CHECK(power(beta) - power(0.0) == doctest::Approx(expected).epsilon(0.01));
  CHECK(power(beta) - power(0.0) < 0.0);
}

TEST_CASE("a cantilever sags by q L^4 / (8 EI) in both planes on average and swings at its first bending frequency") {
  namespace m = mbrt::models::flexible_cantilever;
  // L = 2 m, rho A = 3 kg/m, EI = 1500 (about y) and 2400 N m^2 (about z), gravity (0, -3, -4) m/s^2.
  const double L = 2.0, rho_A = 3.0, EIy = 1500.0, EIz = 2400.0;
  const double sag_y = -3.0 * rho_A * std::pow(L, 4) / (8 * EIz), sag_z = -4.0 * rho_A * std::pow(L, 4) / (8 * EIy);
  m::State s = m::initial_state();
  const double energy0 = m::energy(s).total();
  const int tip = m::kBodyInfo[m::body::boom_n10].slot;
  double sum_y = 0, sum_z = 0, worst_energy = 0;
  std::vector<double> up_crossings;
  double previous = 0;
  const int steps = 200000;  // 20 s
  for (int i = 0; i < steps; ++i) {
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    const Vec3 r = s.rigid[static_cast<size_t>(tip)].r;
    sum_y += r.y(), sum_z += r.z();
    const double z = r.z() - sag_z;
    if (previous < 0 && z >= 0) up_crossings.push_back(s.t);
    previous = z;
    worst_energy = std::max(worst_energy, std::abs(m::energy(s).total() - energy0));
  }
  const double period = (up_crossings.back() - up_crossings.front()) / static_cast<double>(up_crossings.size() - 1);
  const double first = 1.8751040687 * 1.8751040687 * std::sqrt(EIy / (rho_A * std::pow(L, 4)));
  MESSAGE("10 elements: mean sag " << sum_y / steps << ", " << sum_z / steps << " m (closed form " << sag_y << ", "
                                   << sag_z << "), period " << period << " s (closed form " << 2 * M_PI / first
                                   << "), energy error " << worst_energy << " J");
  CHECK(sum_y / steps == doctest::Approx(sag_y).epsilon(0.01).scale(0));
  CHECK(sum_z / steps == doctest::Approx(sag_z).epsilon(0.01).scale(0));
  CHECK(period == doctest::Approx(2 * M_PI / first).epsilon(0.015).scale(0));  // lumped masses: 0.7 % long with 10 elements
  CHECK(worst_energy < 1e-5 * 6.0 * 5.0 * std::abs(sag_z));  // of the weight's work, m g sag
}

TEST_CASE("a free flexible beam keeps its energy, momentum and angular momentum while it tumbles") {
  namespace m = mbrt::models::flexible_free;
  // The documented lumping: each node carries its slice of the beam (half an
  // element at the ends) with the slice's inertia.
  const double l = 2.0 / 8, rho_A = 2.0, rho_J = 0.01;
  std::array<double, 9> mass{};
  std::array<Vec3, 9> inertia{};
  for (int k = 0; k <= 8; ++k) {
    const double slice = (k == 0 || k == 8) ? l / 2 : l;
    mass[k] = rho_A * slice;
    const double bending = rho_J / 2 * slice + mass[k] * slice * slice / 12;
    inertia[k] = Vec3(rho_J * slice, bending, bending);
  }
  const auto momenta = [&](const m::State& s) {
    Vec3 p = Vec3::Zero(), h = Vec3::Zero();
    for (int k = 0; k <= 8; ++k) {
      const mbrt::RigidState& b = s.rigid[static_cast<size_t>(k)];
      const Mat3 R = Eigen::Quaterniond(b.p[0], b.p[1], b.p[2], b.p[3]).toRotationMatrix();
      p += mass[k] * b.v;
      h += b.r.cross(mass[k] * b.v) + R * inertia[k].cwiseProduct(b.w);
    }
    return std::array<Vec3, 2>{p, h};
  };
  m::State s = m::initial_state();
  const auto [p0, h0] = momenta(s);
  const double e0 = m::energy(s).total();
  double worst_energy = 0, worst_p = 0, worst_h = 0, most_elastic = 0;
  for (int i = 0; i < 10000; ++i) {  // 2 s
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    const mbrt::Energy e = m::energy(s);
    const auto [p, h] = momenta(s);
    worst_energy = std::max(worst_energy, std::abs(e.total() - e0));
    worst_p = std::max(worst_p, (p - p0).norm());
    worst_h = std::max(worst_h, (h - h0).norm());
    most_elastic = std::max(most_elastic, e.potential);
  }
  MESSAGE("2 s: energy " << e0 << " J, error " << worst_energy << " J, most elastic energy " << most_elastic
                         << " J; momentum error " << worst_p << ", angular momentum error " << worst_h);
  CHECK(most_elastic > 1e-3);  // the tumbling does deform it
  CHECK(worst_energy < 1e-5 * e0);
  CHECK(worst_p < 1e-12 * p0.norm() + 1e-12);
  CHECK(worst_h < 1e-11 * h0.norm());
}

TEST_CASE("the spin-up beam follows an independent modal model with geometric stiffness, and stretches as it spins") {
  const spin_up::SpinUpReference reference = spin_up::spin_up_reference(true);
  REQUIRE(!reference.diverged);
  // Without its geometric stiffness the linear model softens and diverges
  // (Kane, Ryan & Banerjee 1987): the stiffening is what the test checks.
  CHECK(spin_up::spin_up_reference(false).diverged);
  namespace m = mbrt::models::flexible_spin_up;
  m::State s = m::initial_state();
  const int tip = m::kBodyInfo[m::body::beam_n10].slot;
  double worst = 0, largest = 0, stretch = 0;
  int samples = 0;
  for (int i = 1; i <= 250000; ++i) {  // 20 s at 80 us
    REQUIRE(m::step(s) == mbrt::StepStatus::ok);
    if (i % 125 != 0) continue;
    const double theta = spin_up::hub_angle(s.t)[0];
    const Vec3 r = s.rigid[static_cast<size_t>(tip)].r;
    const double transverse = -std::sin(theta) * r.x() + std::cos(theta) * r.y();
    const double reference_tip = reference.tip[static_cast<size_t>(i / 125 - 1)];
    worst = std::max(worst, std::abs(transverse - reference_tip));
    largest = std::max(largest, std::abs(reference_tip));
    if (s.t > 17.0) {
      stretch += std::cos(theta) * r.x() + std::sin(theta) * r.y() - 10.0;
      ++samples;
    }
  }
  stretch /= samples;
  // A beam spinning at constant rate: u(L) = rho Omega^2 L^3 / (3 E).
  const double spun = 1.2 * 36.0 * 1000.0 / (3 * 2.8e7);
  MESSAGE("ten elements: largest tip deflection " << largest << " m, worst difference from the modal model " << worst
                                                  << " m; stretch at 6 rad/s " << stretch << " m (closed form " << spun
                                                  << ")");
  CHECK(largest > 0.5);  // Simo & Vu-Quoc's figure: about 0.55 m at 7 s
  CHECK(worst < 0.02 * largest);
  CHECK(stretch == doctest::Approx(spun).epsilon(0.03).scale(0));
}
