// Floating-point operations of a generated stage by the dense formulas of
// the block algebra it prints: what a reader of the generated code needs to
// see where a step's work goes. The compiled step's own count (`mbrt gen
// --report`, from the executed instructions) differs by what the compiler
// fuses, vectorizes and drops.
#pragma once

#include <string>

namespace mbrt::codegen {

struct OpCount {
  long mul = 0, add = 0, div = 0, sqrt = 0;  // add counts subtractions too

  long total() const { return mul + add + div + sqrt; }
  OpCount& operator+=(const OpCount& o) {
    mul += o.mul;
    add += o.add;
    div += o.div;
    sqrt += o.sqrt;
    return *this;
  }
  // "1,234 flops: 600 mul, 580 add, 40 div, 14 sqrt" (div and sqrt when there are any)
  std::string text() const;
};

// 1234567 -> "1,234,567"
std::string thousands(long n);

OpCount operator*(long times, const OpCount& c);

namespace ops {

// (m x k) (k x n)
OpCount product(long m, long k, long n);
// Adding or subtracting an m x n block.
OpCount sum(long m, long n);
// A scalar times an m x n block.
OpCount scale(long m, long n);
// mbrt::cholesky_in_place on n x n.
OpCount cholesky(long n);
// mbrt::solve_right_lower_transposed: X (r x n) := X L^-T.
OpCount solve_right_lower_transposed(long r, long n);
// mbrt::solve_lower or solve_lower_transposed on n rows.
OpCount triangular_solve(long n);
// Inverse of n x n by LU with partial pivoting (Eigen's partialPivLu().inverse()):
// the factorization, then n forward and backward substitutions.
OpCount lu_inverse(long n);

}  // namespace ops

}  // namespace mbrt::codegen
