// A modal body's mass matrix (include/mbrt/modal_body.hpp): the Gram matrix
// of the beam's points moved by its modes and by its shortening's shift,
// summed point by point; so the frame's reduced mass stays positive
// definite however far the beam bends, where a first moment with the
// shortening and an inertia without it lost definiteness at a few per cent
// of the length.
#include <doctest/doctest.h>

#include <random>

#include <Eigen/Eigenvalues>

#include "modal_body.hpp"
#include "modal_momenta.hpp"

namespace cg = mbrt::codegen;

namespace {

// Simo & Vu-Quoc's spin-up beam (1986) with a soft axial mode kept: four
// bending modes and the axial one (EA 2.8e4 N puts it at 24 rad/s).
const cg::BeamProperties kSpinUpBeam{10.0, 2.8e4, 1.4e4, 1.4e4, 1.4e4, 1.2, 1.0e-3, 20};
// A light boom with unequal bending stiffnesses and six bending modes.
const cg::BeamProperties kBoom{2.0, 4.0e6, 900.0, 1500.0, 2400.0, 3.0, 0.02, 20};

template <int N>
Eigen::MatrixXd library_mass_matrix(const mbrt::ModalBody<N>& b, const Eigen::Matrix<double, N, 1>& q) {
  const mbrt::ModalMass<N> mm = mbrt::modal_mass<N>(b, q);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(6 + N, 6 + N);
  M.topLeftCorner<3, 3>() = b.m * mbrt::Mat3::Identity();
  M.block<3, 3>(0, 3) = -mbrt::skew(mm.c);
  M.block<3, 3>(3, 0) = mbrt::skew(mm.c);
  M.block<3, 3>(3, 3) = mm.J;
  M.block<3, N>(0, 6) = mm.St_T.transpose();
  M.block<3, N>(3, 6) = mm.Sr_T.transpose();
  M.block<N, 3>(6, 0) = mm.St_T;
  M.block<N, 3>(6, 3) = mm.Sr_T;
  M.bottomRightCorner<N, N>() = mm.L * mm.L.transpose();
  return M;
}

template <int N>
double smallest_reduced_eigenvalue(const mbrt::ModalBody<N>& b, const Eigen::Matrix<double, N, 1>& q) {
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(mbrt::modal_reduced_mass<N>(b, q)).eigenvalues()[0];
}

// The tip's displacement per unit of q along d.
double tip_per_unit(const cg::ModalPlan& p, const Eigen::VectorXd& d) {
  return (cg::modal_node(p, static_cast<int>(p.node_names.size()) - 1).displacement * d).norm();
}

template <int N>
void check_gram_and_definite(const cg::BeamProperties& beam) {
  const cg::ModalPlan p = cg::plan_modal_body(beam, N, 0.0);
  const mbrt::ModalBody<N> body = cg::step_constants<N>(p);
  const modal_momenta::ModalBeamMass reference(beam, N);
  std::mt19937 random(11);
  std::normal_distribution<double> normal;
  double worst = 1e300;
  for (int k = 0; k < 60; ++k) {
    Eigen::Matrix<double, N, 1> d;
    for (int i = 0; i < N; ++i) d[i] = k < N ? (i == k ? 1.0 : 0.0) : normal(random);
    // Out to a tip displacement of 40 % of the length.
    for (double reach : {0.01, 0.05, 0.2, 0.4}) {
      const Eigen::Matrix<double, N, 1> q = reach * beam.length / tip_per_unit(p, Eigen::VectorXd(d)) * d;
      const Eigen::MatrixXd M = library_mass_matrix<N>(body, q), M_ref = reference.mass_matrix(Eigen::VectorXd(q));
      CHECK((M - M_ref).norm() < 1e-8 * M_ref.norm());
      worst = std::min(worst, smallest_reduced_eigenvalue<N>(body, q));
    }
  }
  MESSAGE("length " << beam.length << " m, " << N << " modes: the reduced mass's smallest eigenvalue out to 40 % of the length "
                    << worst << " (at rest " << smallest_reduced_eigenvalue<N>(body, Eigen::Matrix<double, N, 1>::Zero()) << ")");
  CHECK(worst > 0.0);
}

}  // namespace

TEST_CASE("a modal beam's mass matrix is its points' Gram matrix, positive definite however far it bends") {
  check_gram_and_definite<5>(kSpinUpBeam);
  check_gram_and_definite<6>(kBoom);
}

namespace {

// A free modal beam's state and its rates under the step's kernel
// (modal_loads, modal_inverse_mass, modal_rates), no gravity.
template <int N>
struct FreeBeam {
  using Modes = Eigen::Matrix<double, N, 1>;
  mbrt::Vec3 r, v, w;
  mbrt::EulerParameters e;
  Modes q, p;

  FreeBeam rate(const mbrt::ModalBody<N>& b) const {
    const mbrt::Mat3 R = mbrt::rotation_matrix(e);
    mbrt::Wrench load{mbrt::Vec3::Zero(), mbrt::Vec3::Zero()};
    const mbrt::ModalLoad<N> l = mbrt::modal_loads<N>(b, R, v, w, mbrt::Vec3::Zero(), q, p, Modes::Zero(), load);
    const mbrt::Vec6 a = mbrt::inverse_mass_times(mbrt::modal_inverse_mass<N>(b, e, q), load);
    FreeBeam d;
    d.r = v, d.v = a.head<3>(), d.w = a.tail<3>();
    d.e = 0.5 * mbrt::quaternion_product(e, mbrt::EulerParameters(0, w.x(), w.y(), w.z()));
    d.q = mbrt::modal_rates<N>(b, R, v, w, q, p);
    d.p = l.momentum_rate;
    return d;
  }
  FreeBeam plus(const FreeBeam& d, double h) const {
    FreeBeam x = *this;
    x.r += h * d.r, x.v += h * d.v, x.w += h * d.w, x.e += h * d.e, x.q += h * d.q, x.p += h * d.p;
    return x;
  }
  double energy(const mbrt::ModalBody<N>& b) const {
    mbrt::Wrench unused{mbrt::Vec3::Zero(), mbrt::Vec3::Zero()};
    const mbrt::Mat3 R = mbrt::rotation_matrix(e);
    return mbrt::modal_kinetic_energy<N>(b, R, v, w, q, p) +
           mbrt::modal_loads<N>(b, R, v, w, mbrt::Vec3::Zero(), q, p, Modes::Zero(), unused).potential;
  }
};

// The largest change of energy over 2 s of classical Runge-Kutta at step h.
template <int N>
double energy_drift(const mbrt::ModalBody<N>& b, FreeBeam<N> x, double h) {
  const double e0 = x.energy(b);
  double worst = 0;
  for (int i = 0; i < static_cast<int>(std::lround(2.0 / h)); ++i) {
    const FreeBeam<N> k1 = x.rate(b), k2 = x.plus(k1, h / 2).rate(b), k3 = x.plus(k2, h / 2).rate(b), k4 = x.plus(k3, h).rate(b);
    x = x.plus(k1, h / 6).plus(k2, h / 3).plus(k3, h / 3).plus(k4, h / 6);
    x.e.normalize();
    worst = std::max(worst, std::abs(x.energy(b) - e0));
  }
  return worst;
}

}  // namespace

TEST_CASE("a free modal beam bent and tumbling keeps its energy: the spin's stiffness is in its kinetic energy") {
  // tests/models/modal_free.yaml's beam, tumbling at (0.4, 1.5, 3) rad/s from
  // rest in its frame with its first modes bent to a tip deflection of 8 %.
  const cg::BeamProperties beam{2.0, 2.0e5, 400.0, 300.0, 500.0, 2.0, 0.01, 16};
  constexpr int N = 6;
  const cg::ModalPlan plan = cg::plan_modal_body(beam, N, 0.0);
  const mbrt::ModalBody<N> body = cg::step_constants<N>(plan);
  REQUIRE(body.axial_moment > 0.0);
  FreeBeam<N> x;
  x.r.setZero(), x.v = mbrt::Vec3(0.3, -0.2, 0.5), x.w = mbrt::Vec3(0.4, 1.5, 3.0), x.e = mbrt::EulerParameters(1, 0, 0, 0);
  x.q << 1.0, -0.5, 0.3, 0, 0, 0;
  x.q *= 0.16 / tip_per_unit(plan, Eigen::VectorXd(x.q));
  const mbrt::ModalMass<N> mm = mbrt::modal_mass<N>(body, x.q);
  x.p = mm.St_T * x.v + mm.Sr_T * x.w;  // qdot = 0
  const double e0 = x.energy(body), coarse = energy_drift<N>(body, x, 1e-4), fine = energy_drift<N>(body, x, 5e-5);
  MESSAGE("energy " << e0 << " J: largest change over 2 s " << coarse << " J at 0.1 ms, " << fine << " J at 0.05 ms");
  // Fourth order towards zero: the equations keep the energy.
  CHECK(coarse < 1e-4 * e0);
  CHECK(fine < coarse / 10);
}
