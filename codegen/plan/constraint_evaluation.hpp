// The model's constraints evaluated at its initial state with dynamic-size
// matrices: for checks and projection at generation time, never on the loop
// path. Each body owns 6 columns [v; w_body]; particles' w columns are zero.
#pragma once

#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "analysis.hpp"

namespace mbrt::codegen {

struct StackedConstraints {
  Eigen::VectorXd phi;
  Eigen::VectorXd phi_dot;  // B u + phi_t
  Eigen::VectorXd phi_t;    // explicit time derivative (drivers)
  Eigen::MatrixXd B;        // constraint_rows x 6 * bodies
};

// At the model's body states and time t.
StackedConstraints evaluate_constraints(const Model& model, const std::vector<ConstraintBlock>& blocks, double t);

// Block-diagonal inverse mass matrix, 6 * bodies square (zero rotational
// blocks for particles); sparse, so products with it stay linear in the
// bodies for models of hundreds of them.
Eigen::SparseMatrix<double> inverse_mass_matrix(const Model& model);

}  // namespace mbrt::codegen
