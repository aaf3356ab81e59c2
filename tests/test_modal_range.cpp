// The deflection range in which a modal body's frame mass stays positive
// definite (codegen/plan/modal_range.hpp), and the generator's warning.
#include <doctest/doctest.h>

#include <string>

#include <Eigen/Eigenvalues>

#include "modal_range.hpp"
#include "model.hpp"
#include "stable_step.hpp"

namespace cg = mbrt::codegen;

namespace {

// Simo & Vu-Quoc's spin-up beam (1986) with a soft axial mode kept: four
// bending modes and the axial one (EA 2.8e4 N puts it at 24 rad/s).
const cg::BeamProperties kSpinUpBeam{10.0, 2.8e4, 1.4e4, 1.4e4, 1.4e4, 1.2, 1.0e-3, 20};

double smallest_eigenvalue(const mbrt::ModalBody<5>& body, const Eigen::VectorXd& q) {
  const Eigen::Matrix<double, 5, 1> fixed = q;
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(mbrt::modal_reduced_mass<5>(body, fixed)).eigenvalues()[0];
}

}  // namespace

TEST_CASE("the reduced mass loses definiteness where the range says, and only through the shortening") {
  cg::ModalPlan p = cg::plan_modal_body(kSpinUpBeam, 5, 0.0);
  const cg::ModalRange r = cg::modal_definite_range(p);
  REQUIRE(r.bounded);
  const mbrt::ModalBody<5> body = cg::step_constants<5>(p);
  // Definite at rest and just inside the deflection found, not just past it.
  CHECK(smallest_eigenvalue(body, Eigen::VectorXd::Zero(5)) > 0.0);
  CHECK(smallest_eigenvalue(body, 0.99 * r.deflection) > 0.0);
  CHECK(smallest_eigenvalue(body, 1.01 * r.deflection) < 0.0);
  CHECK(r.strain_energy == doctest::Approx(0.5 * r.deflection.dot(p.omega.cwiseAbs2().cwiseProduct(r.deflection))).epsilon(1e-9));
  CHECK(r.node == "tip");
  CHECK(r.span == doctest::Approx(10.0));
  // The first bending mode bends it there: a few per cent of the length, no more.
  CHECK(r.node_displacement > 0.005 * r.span);
  CHECK(r.node_displacement < 0.05 * r.span);
  // Without the shortening in the first moment (the acceleration cases), the
  // reduced mass stays definite out to half the span.
  for (size_t k = cg::kAccelerationX; k < cg::kAccelerationX + 3; ++k) p.kg[k].setZero();
  CHECK_FALSE(cg::modal_definite_range(p).bounded);
}

TEST_CASE("the generator warns where the scene can bend a modal body past its range") {
  const auto scene = [](const std::string& gravity, const std::string& more) {
    return cg::parse_model("name: boom\n" + gravity +
                               "bodies:\n  - name: boom\n    flexible: {length: 2.0, elements: 20, modes: 4, EA: 4.0e6, GJ: 900.0, "
                               "EI: [1500.0, 2400.0], rho_A: 3.0, rho_J: 0.02}\n"
                               "joints:\n  - {name: pin, type: revolute, body1: ground, body2: boom, point: [-1, 0, 0], axis: [0, 0, 1]}\n" +
                               more,
                           "boom.yaml");
  };
  const auto warning = [](const cg::Model& m) {
    std::vector<cg::ModalPlan> plans;
    for (const cg::ModalSource& s : m.modal) {
      plans.push_back(cg::plan_modal(s));
      plans.back().body = s.body;
    }
    return cg::modal_range_warning(m, cg::estimate_stable_step(m, plans), plans);
  };
  // At rest without gravity or loads it holds no energy to bend with.
  CHECK(warning(scene("", "")).empty());
  // Swinging down from level under gravity it can release tens of joules.
  const std::string falling = warning(scene("gravity: [0, -9.81, 0]\n", ""));
  CHECK(falling.find("modal body boom") != std::string::npos);
  CHECK(falling.find("stops being positive definite") != std::string::npos);
  CHECK(falling.find("the scene can release") != std::string::npos);
  // A driver can put in any energy.
  const std::string driven = warning(scene("", "drivers:\n  - {name: turn, type: joint_angle, joint: pin, function: {polynomial: [0, 1]}}\n"));
  CHECK(driven.find("drivers, inputs or forces") != std::string::npos);
}
