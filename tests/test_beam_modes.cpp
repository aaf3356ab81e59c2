// The beam's finite elements and modes (codegen/plan/beam_modes) against
// closed forms and published values: cantilever and free-free frequencies,
// axial and torsional ones, static deflections, the stretch of a spinning
// beam, the first mode's effective mass, and the frequencies of a rotating
// cantilever (geometric stiffening).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>

#include "beam_modes.hpp"

namespace {

using mbrt::codegen::BeamProperties;
using mbrt::codegen::BeamSupport;
using mbrt::codegen::kNodeCoordinates;

// Roots of cos(x) cosh(x) = -1 (cantilever) and = +1 (free-free), e.g.
// Blevins 1979, Formulas for Natural Frequency and Mode Shape, table 8-1.
constexpr std::array<double, 4> kCantileverRoots{1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349};
constexpr std::array<double, 3> kFreeFreeRoots{4.7300407449, 7.8532046241, 10.9956078380};

// The computed frequency nearest to `expected`.
double nearest(const Eigen::VectorXd& omega, double expected) {
  double best = omega[0];
  for (double w : omega) {
    if (std::abs(w - expected) < std::abs(best - expected)) best = w;
  }
  return best;
}

BeamProperties beam(int elements) {
  BeamProperties b;
  b.length = 2.0;
  b.EA = 4.0e6;
  b.GJ = 900.0;
  b.EIy = 1500.0;
  b.EIz = 2400.0;
  b.rho_A = 3.0;
  b.rho_J = 0.02;
  b.elements = elements;
  return b;
}

double bending(const BeamProperties& b, double root, double EI) {
  return root * root * std::sqrt(EI / (b.rho_A * std::pow(b.length, 4)));
}

}  // namespace

TEST_CASE("a cantilever's bending frequencies in both planes match the roots of cos cosh = -1") {
  const BeamProperties b = beam(40);
  const auto modes = mbrt::codegen::beam_modes(b, BeamSupport::clamped_root, 12);
  for (double EI : {b.EIy, b.EIz}) {
    for (size_t n = 0; n < kCantileverRoots.size(); ++n) {
      const double expected = bending(b, kCantileverRoots[n], EI);
      INFO("EI ", EI, ", mode ", n + 1, ": expected ", expected);
      // Cubic elements: errors of order (element length)^4, growing with the mode.
      constexpr std::array<double, 4> tolerance{1e-8, 3e-7, 2e-6, 8e-6};
      CHECK(nearest(modes.omega, expected) == doctest::Approx(expected).epsilon(tolerance[n]));
    }
  }
  // Unit modal mass.
  const auto full = mbrt::codegen::assemble_beam(b);
  const Eigen::MatrixXd mass = modes.shapes.transpose() * full.M * modes.shapes;
  CHECK((mass - Eigen::MatrixXd::Identity(12, 12)).norm() < 1e-10);
}

TEST_CASE("the bending frequencies converge at fourth order in the element length") {
  const double expected = bending(beam(1), kCantileverRoots[1], beam(1).EIy);
  const auto error = [&](int elements) {
    return std::abs(nearest(mbrt::codegen::beam_modes(beam(elements), BeamSupport::clamped_root, 8).omega, expected) /
                        expected - 1);
  };
  CHECK(error(10) / error(20) == doctest::Approx(16.0).epsilon(0.05));
}

TEST_CASE("a free beam's elastic frequencies match cos cosh = 1, and its modes do not move its mass centre") {
  const BeamProperties b = beam(40);
  const auto modes = mbrt::codegen::beam_modes(b, BeamSupport::free, 10);
  for (size_t n = 0; n < kFreeFreeRoots.size(); ++n) {
    const double expected = bending(b, kFreeFreeRoots[n], b.EIy);
    CHECK(nearest(modes.omega, expected) == doctest::Approx(expected).epsilon(n == 0 ? 3e-7 : 8e-6));
  }
  CHECK(modes.omega[0] == doctest::Approx(bending(b, kFreeFreeRoots[0], b.EIy)).epsilon(3e-7));
  // Elastic modes are mass-orthogonal to the rigid motions: no momentum.
  CHECK(modes.alpha.cwiseAbs().maxCoeff() < 1e-9);
  CHECK(modes.beta.cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("axial and torsional frequencies converge to (2n - 1) pi / 2 c / L at second order") {
  const double c_axial = std::sqrt(4.0e6 / 3.0), c_torsion = std::sqrt(900.0 / 0.02);
  double previous_error = 0.0;
  for (int elements : {20, 40}) {
    const BeamProperties b = beam(elements);
    // The lowest 40 modes reach the first axial one (4.4 times the fourth bending).
    const auto modes = mbrt::codegen::beam_modes(b, BeamSupport::clamped_root, 40);
    const double axial = M_PI / 2 * c_axial / b.length, torsion = M_PI / 2 * c_torsion / b.length;
    const double error = std::abs(nearest(modes.omega, axial) / axial - 1);
    CHECK(error < 3e-4);
    CHECK(nearest(modes.omega, torsion) == doctest::Approx(torsion).epsilon(3e-4));
    CHECK(nearest(modes.omega, 3 * torsion) == doctest::Approx(3 * torsion).epsilon(3e-3));
    if (previous_error > 0) CHECK(previous_error / error == doctest::Approx(4.0).epsilon(0.01));
    previous_error = error;
  }
}

TEST_CASE("a tip load deflects the cantilever by P L^3 / (3 EI) and turns its tip by P L^2 / (2 EI)") {
  const BeamProperties b = beam(3);  // cubic elements are exact at the nodes
  const int tip = kNodeCoordinates * b.elements;
  Eigen::VectorXd load = Eigen::VectorXd::Zero(kNodeCoordinates * (b.elements + 1));
  load[tip + 1] = 50.0;   // along y: bends about z
  load[tip + 2] = -30.0;  // along z: bends about y
  load[tip + 0] = 1.0e4;  // axial
  load[tip + 3] = 7.0;    // torque about x
  const Eigen::VectorXd u = mbrt::codegen::clamped_static_displacement(b, load);
  const double L = b.length;
  CHECK(u[tip + 1] == doctest::Approx(50.0 * L * L * L / (3 * b.EIz)).epsilon(1e-12).scale(0));
  CHECK(u[tip + 5] == doctest::Approx(50.0 * L * L / (2 * b.EIz)).epsilon(1e-12).scale(0));
  CHECK(u[tip + 2] == doctest::Approx(-30.0 * L * L * L / (3 * b.EIy)).epsilon(1e-12).scale(0));
  CHECK(u[tip + 4] == doctest::Approx(30.0 * L * L / (2 * b.EIy)).epsilon(1e-12).scale(0));  // w' = -ry
  CHECK(u[tip + 0] == doctest::Approx(1.0e4 * L / b.EA).epsilon(1e-12).scale(0));
  CHECK(u[tip + 3] == doctest::Approx(7.0 * L / b.GJ).epsilon(1e-12).scale(0));
}

TEST_CASE("a beam spinning about its root stretches by rho Omega^2 L^3 / (3 E)") {
  const BeamProperties b = beam(8);  // linear axial elements with consistent loads are exact at the nodes
  const double spin = 30.0, l = b.length / b.elements;
  Eigen::VectorXd load = Eigen::VectorXd::Zero(kNodeCoordinates * (b.elements + 1));
  for (int k = 0; k < b.elements; ++k) {  // f(x) = rho_A spin^2 x on the linear shapes
    const double xi = k * l, xj = xi + l, f = b.rho_A * spin * spin;
    load[kNodeCoordinates * k] += f * l * (2 * xi + xj) / 6;
    load[kNodeCoordinates * (k + 1)] += f * l * (xi + 2 * xj) / 6;
  }
  const Eigen::VectorXd u = mbrt::codegen::clamped_static_displacement(b, load);
  CHECK(u[kNodeCoordinates * b.elements] ==
        doctest::Approx(b.rho_A * spin * spin * std::pow(b.length, 3) / (3 * b.EA)).epsilon(1e-12).scale(0));
}

TEST_CASE("the first cantilever mode carries 61.3 % of the mass as effective mass") {
  // Effective modal masses of a uniform cantilever: 0.6131, 0.1883, 0.0647 of m
  // (e.g. Irvine 2010, Effective Modal Mass & Modal Participation Factors).
  const BeamProperties b = beam(40);
  const auto modes = mbrt::codegen::beam_modes(b, BeamSupport::clamped_root, 12);
  const double m = b.rho_A * b.length;
  std::vector<double> along_z;
  for (int k = 0; k < 12; ++k) {
    const double share = modes.alpha(2, k) * modes.alpha(2, k) / m;
    if (share > 0.01) along_z.push_back(share);
  }
  REQUIRE(along_z.size() >= 3);
  CHECK(along_z[0] == doctest::Approx(0.6131).epsilon(2e-4));
  CHECK(along_z[1] == doctest::Approx(0.1883).epsilon(5e-4).scale(0));
  CHECK(along_z[2] == doctest::Approx(0.0647).epsilon(2e-3).scale(0));
}

// Wright, Smith, Thresher & Wang (1982), "Vibration modes of centrifugally
// stiffened beams", J. Appl. Mech. 49, table 1 (no hub radius): the first two
// flapwise frequencies, sqrt(rho A L^4 / EI) omega, at the spin rates
// sqrt(rho A L^4 / EI) Omega = 0, 2, 6. A model without geometric stiffness
// keeps the first at 3.5160.
TEST_CASE("a rotating cantilever stiffens in flap as Wright et al. tabulate") {
  BeamProperties b;
  b.length = 1.0;
  b.rho_A = 1.0;
  b.EIy = 1.0;        // flap: deflection along z, the spin axis
  b.EIz = 400.0;      // chordwise modes far above
  b.EA = 1.0e8;
  b.GJ = 1.0;
  b.rho_J = 1e-4;
  b.elements = 30;
  const std::array<double, 3> spin{0.0, 2.0, 6.0};
  const std::array<double, 3> first{3.5160, 4.1373, 7.3604}, second{22.0345, 22.6149, 26.8091};
  const auto full = mbrt::codegen::assemble_beam(b);
  const int n = static_cast<int>(full.K.rows()) - kNodeCoordinates;  // the clamped root removed
  const auto modes = mbrt::codegen::beam_modes(b, BeamSupport::clamped_root, 4);
  for (size_t i = 0; i < spin.size(); ++i) {
    INFO("spin rate ", spin[i]);
    const double s2 = spin[i] * spin[i];
    const Eigen::MatrixXd K = (full.K + s2 * full.KG).bottomRightCorner(n, n);
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> fe(K, full.M.bottomRightCorner(n, n));
    CHECK(std::sqrt(fe.eigenvalues()[0]) == doctest::Approx(first[i]).epsilon(2e-5));
    CHECK(std::sqrt(fe.eigenvalues()[1]) == doctest::Approx(second[i]).epsilon(2e-5));
    // Four modes of the resting beam with their geometric stiffness: within 0.1 %.
    Eigen::MatrixXd modal = s2 * modes.KG;
    modal.diagonal() += modes.omega.cwiseAbs2();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> reduced(modal);
    CHECK(std::sqrt(reduced.eigenvalues()[0]) == doctest::Approx(first[i]).epsilon(1e-3));
    CHECK(std::sqrt(reduced.eigenvalues()[1]) == doctest::Approx(second[i]).epsilon(1e-3));
  }
}

TEST_CASE("bad beam data is refused naming the property") {
  BeamProperties b = beam(4);
  b.EIy = 0.0;
  CHECK_THROWS_WITH_AS(mbrt::codegen::assemble_beam(b), doctest::Contains("beam EIy: expected a finite number > 0"),
                       std::invalid_argument);
  b = beam(0);
  CHECK_THROWS_WITH_AS(mbrt::codegen::assemble_beam(b), doctest::Contains("beam elements: expected at least 1"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(mbrt::codegen::beam_modes(beam(1), BeamSupport::free, 7),
                       doctest::Contains("7 kept, but 1 elements give 6 elastic modes"), std::invalid_argument);
}
