#include "op_count.hpp"

namespace mbrt::codegen {

std::string thousands(long n) {
  std::string digits = std::to_string(n);
  for (int at = static_cast<int>(digits.size()) - 3; at > 0; at -= 3) digits.insert(static_cast<size_t>(at), ",");
  return digits;
}

std::string OpCount::text() const {
  std::string s = thousands(total()) + " flops: " + thousands(mul) + " mul, " + thousands(add) + " add";
  if (div) s += ", " + thousands(div) + " div";
  if (sqrt) s += ", " + thousands(sqrt) + " sqrt";
  return s;
}

OpCount operator*(long times, const OpCount& c) {
  return {times * c.mul, times * c.add, times * c.div, times * c.sqrt};
}

namespace ops {

OpCount product(long m, long k, long n) { return {m * n * k, m * n * (k - 1), 0, 0}; }

OpCount sum(long m, long n) { return {0, m * n, 0, 0}; }

OpCount scale(long m, long n) { return {m * n, 0, 0, 0}; }

// Column j: its pivot takes j products, the n - 1 - j entries below it j
// products and a division each.
OpCount cholesky(long n) {
  OpCount c;
  for (long j = 0; j < n; ++j) {
    const long below = n - 1 - j;
    c.mul += j + below * j;
    c.add += j + below * j;
    c.div += below;
    c.sqrt += 1;
  }
  return c;
}

OpCount solve_right_lower_transposed(long r, long n) {
  const long products = r * n * (n - 1) / 2;
  return {products, products, r * n, 0};
}

OpCount triangular_solve(long n) {
  const long products = n * (n - 1) / 2;
  return {products, products, n, 0};
}

// Doolittle elimination: column k updates the (n - 1 - k)^2 trailing block
// and divides n - 1 - k multipliers; then each unit column costs a forward
// and a backward substitution.
OpCount lu_inverse(long n) {
  OpCount c;
  for (long k = 0; k < n; ++k) {
    const long rest = n - 1 - k;
    c.div += rest;
    c.mul += rest * rest;
    c.add += rest * rest;
  }
  const OpCount forward{n * (n - 1) / 2, n * (n - 1) / 2, 0, 0};
  c += n * forward;
  c += n * triangular_solve(n);
  return c;
}

}  // namespace ops

}  // namespace mbrt::codegen
