#include "initial_conditions.hpp"

#include <mbrt/rotation.hpp>

#include "constraint_evaluation.hpp"

namespace mbrt::codegen {

namespace {

int block_of_row(const Analysis& a, Eigen::Index row) {
  for (size_t i = 0; i < a.constraints.size(); ++i) {
    const ConstraintBlock& b = a.constraints[i];
    if (row >= b.first_row && row < b.first_row + b.rows) return static_cast<int>(i);
  }
  return -1;
}

// du = -M^-1 B^T S^+ r: the M-orthogonal correction that removes residual r.
Eigen::VectorXd correction(const StackedConstraints& c, const Eigen::SparseMatrix<double>& m_inv, const Eigen::VectorXd& r) {
  const Eigen::MatrixXd S = c.B * m_inv * c.B.transpose();
  return -m_inv * c.B.transpose() * S.completeOrthogonalDecomposition().solve(r);
}

}  // namespace

InitialResidual initial_residual(const Model& model, const Analysis& analysis) {
  InitialResidual r;
  if (analysis.constraint_rows == 0) return r;
  const StackedConstraints c = evaluate_constraints(model, analysis.constraints, 0.0);
  Eigen::Index row;
  r.position = c.phi.cwiseAbs().maxCoeff(&row);
  r.position_block = block_of_row(analysis, row);
  r.velocity = c.phi_dot.cwiseAbs().maxCoeff(&row);
  r.velocity_block = block_of_row(analysis, row);
  return r;
}

void project_initial_state(Model& model, const Analysis& analysis) {
  if (analysis.constraint_rows == 0) return;
  const Eigen::SparseMatrix<double> m_inv = inverse_mass_matrix(model);
  const int max_iterations = 50;
  int iteration = 0;
  for (;; ++iteration) {
    const StackedConstraints c = evaluate_constraints(model, analysis.constraints, 0.0);
    if (c.phi.cwiseAbs().maxCoeff() < 1e-13) break;
    if (iteration == max_iterations) {
      throw ModelError({model.file, 0, 0}, "--project-initial",
                       "positions did not converge to the constraints (residual " +
                           std::to_string(c.phi.cwiseAbs().maxCoeff()) + "); the joints may not be assemblable");
    }
    const Eigen::VectorXd du = correction(c, m_inv, c.phi);
    for (size_t i = 0; i < model.bodies.size(); ++i) {
      Body& b = model.bodies[i];
      const int k = 6 * static_cast<int>(i);
      b.position += du.segment<3>(k);
      if (!b.particle) {
        b.orientation = mbrt::quaternion_product(b.orientation, mbrt::cayley_increment(du.segment<3>(k + 3)));
        b.orientation.normalize();
      }
    }
  }
  const StackedConstraints c = evaluate_constraints(model, analysis.constraints, 0.0);
  const Eigen::VectorXd du = correction(c, m_inv, c.phi_dot);
  for (size_t i = 0; i < model.bodies.size(); ++i) {
    Body& b = model.bodies[i];
    const int k = 6 * static_cast<int>(i);
    b.velocity += du.segment<3>(k);
    if (!b.particle) b.angular_velocity += du.segment<3>(k + 3);
  }
}

}  // namespace mbrt::codegen
