// Checks the Butcher tableaus of runge_kutta_tableaus.hpp against Butcher's
// order conditions, independently of the rest of the library: a method has
// order p iff for every rooted tree t with |t| <= p the elementary weight
// Phi(t) = sum_i b_i Phi_i(t) equals 1 / gamma(t) (Hairer, Norsett & Wanner
// 1993, "Solving Ordinary Differential Equations I", section II.2, Theorem
// 2.13). The rooted trees are generated here; their counts per order are
// checked against the known sequence 1, 1, 2, 4, 9, 20, 48, 115.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "mbrt/schemes/runge_kutta_tableaus.hpp"

namespace {

using mbrt::schemes::ClassicalRungeKutta4;
using mbrt::schemes::DormandPrince8;

constexpr int kMaxTreeOrder = 8;

// A rooted tree: its number of nodes and, in non-decreasing order, the indices
// (into the list of trees it belongs to) of the subtrees hanging off its root.
// Each tree is a multiset of smaller trees, so this representation is unique.
struct RootedTree {
  int order;
  std::vector<std::size_t> subtrees;
};

// Appends to new_trees every tree of the given order whose root's subtrees are
// `chosen` plus a non-decreasing sequence of indices >= first_candidate into
// smaller_trees with orders summing to remaining_order.
void append_trees_with_subtrees(const std::vector<RootedTree>& smaller_trees, int order, int remaining_order,
                                std::size_t first_candidate, std::vector<std::size_t>& chosen,
                                std::vector<RootedTree>& new_trees) {
  if (remaining_order == 0) {
    new_trees.push_back({order, chosen});
    return;
  }
  for (std::size_t candidate = first_candidate; candidate < smaller_trees.size(); ++candidate) {
    if (smaller_trees[candidate].order > remaining_order) continue;
    chosen.push_back(candidate);
    append_trees_with_subtrees(smaller_trees, order, remaining_order - smaller_trees[candidate].order, candidate,
                               chosen, new_trees);
    chosen.pop_back();
  }
}

// All rooted trees with at most max_order nodes, by non-decreasing order.
std::vector<RootedTree> rooted_trees_up_to(int max_order) {
  std::vector<RootedTree> trees{{1, {}}};
  for (int order = 2; order <= max_order; ++order) {
    std::vector<RootedTree> new_trees;
    std::vector<std::size_t> chosen;
    append_trees_with_subtrees(trees, order, order - 1, 0, chosen, new_trees);
    trees.insert(trees.end(), new_trees.begin(), new_trees.end());
  }
  return trees;
}

struct Tableau {
  std::vector<std::vector<long double>> a;
  std::vector<long double> b;
};

template <class Method>
Tableau tableau_of() {
  Tableau tableau{std::vector<std::vector<long double>>(Method::kStages), std::vector<long double>(Method::kStages)};
  for (int i = 0; i < Method::kStages; ++i) {
    tableau.a[i].assign(Method::a[i], Method::a[i] + Method::kStages);
    tableau.b[i] = Method::b[i];
  }
  return tableau;
}

// For each tree, |Phi(t) gamma(t) - 1|: the relative error of its order condition.
std::vector<long double> order_condition_residuals(const Tableau& tableau, const std::vector<RootedTree>& trees) {
  const std::size_t stages = tableau.b.size();
  std::vector<std::vector<long double>> stage_weights(trees.size());  // Phi_i(t), i = 1..stages
  std::vector<long double> densities(trees.size());                   // gamma(t)
  std::vector<long double> residuals(trees.size());
  for (std::size_t t = 0; t < trees.size(); ++t) {
    std::vector<long double> weights(stages, 1.0L);
    long double density = trees[t].order;
    for (std::size_t subtree : trees[t].subtrees) {
      for (std::size_t i = 0; i < stages; ++i) {
        long double a_times_subtree_weights = 0.0L;
        for (std::size_t j = 0; j < stages; ++j) a_times_subtree_weights += tableau.a[i][j] * stage_weights[subtree][j];
        weights[i] *= a_times_subtree_weights;
      }
      density *= densities[subtree];
    }
    long double elementary_weight = 0.0L;
    for (std::size_t i = 0; i < stages; ++i) elementary_weight += tableau.b[i] * weights[i];
    residuals[t] = std::fabs(elementary_weight * density - 1.0L);
    stage_weights[t] = std::move(weights);
    densities[t] = density;
  }
  return residuals;
}

// The largest residual over the trees whose order lies in [min_order, max_order].
long double worst_residual(const Tableau& tableau, int min_order, int max_order) {
  const std::vector<RootedTree> trees = rooted_trees_up_to(max_order);
  const std::vector<long double> residuals = order_condition_residuals(tableau, trees);
  long double worst = 0.0L;
  for (std::size_t t = 0; t < trees.size(); ++t)
    if (trees[t].order >= min_order) worst = std::max(worst, residuals[t]);
  return worst;
}

}  // namespace

TEST_CASE("the generator yields 1, 1, 2, 4, 9, 20, 48, 115 rooted trees of orders 1 to 8") {
  const std::vector<RootedTree> trees = rooted_trees_up_to(kMaxTreeOrder);
  const int expected_counts[kMaxTreeOrder] = {1, 1, 2, 4, 9, 20, 48, 115};
  for (int order = 1; order <= kMaxTreeOrder; ++order)
    CHECK(std::count_if(trees.begin(), trees.end(), [&](const RootedTree& tree) { return tree.order == order; }) ==
          expected_counts[order - 1]);
  CHECK(trees.size() == 200);
}

TEST_CASE_TEMPLATE("each row of a sums to c", Method, ClassicalRungeKutta4, DormandPrince8) {
  // Relative to sum_j |a_ij|, which bounds the error of storing the a_ij as doubles.
  for (int i = 0; i < Method::kStages; ++i) {
    long double row_sum = 0.0L, row_magnitude = 0.0L;
    for (int j = 0; j < Method::kStages; ++j) row_sum += Method::a[i][j], row_magnitude += std::fabs(Method::a[i][j]);
    CHECK(std::fabs(row_sum - Method::c[i]) <= 1e-15L * std::max(row_magnitude, 1.0L));
  }
}

TEST_CASE("ClassicalRungeKutta4 has order exactly four") {
  const long double worst = worst_residual(tableau_of<ClassicalRungeKutta4>(), 1, ClassicalRungeKutta4::kOrder);
  MESSAGE("ClassicalRungeKutta4: worst residual up to order 4 = ", static_cast<double>(worst));
  CHECK(worst <= 1e-15L);
  CHECK(worst_residual(tableau_of<ClassicalRungeKutta4>(), 5, 5) > 1e-2L);
}

TEST_CASE("DormandPrince8 satisfies all 200 order conditions up to order eight") {
  const long double worst = worst_residual(tableau_of<DormandPrince8>(), 1, DormandPrince8::kOrder);
  MESSAGE("DormandPrince8: worst residual up to order 8 = ", static_cast<double>(worst));
  // The 30-digit coefficients meet every condition to about 1e-27; rounding
  // them to double leaves a worst residual of 3.5e-14 (order 8, gamma = 504).
  CHECK(worst <= 1e-13L);
}

TEST_CASE("perturbing one weight of DormandPrince8 by 1e-6 violates an order condition") {
  Tableau perturbed = tableau_of<DormandPrince8>();
  perturbed.b[5] += 1e-6L;
  const long double worst = worst_residual(perturbed, 1, DormandPrince8::kOrder);
  MESSAGE("perturbed DormandPrince8: worst residual up to order 8 = ", static_cast<double>(worst));
  CHECK(worst > 1e-9L);
}
