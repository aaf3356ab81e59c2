// The operation counts the generator writes above its block-algebra stages
// (codegen/emit/op_count.hpp), against counts made by hand from the loops of
// mbrt/dense_cholesky.hpp and the textbook formulas.
#include <doctest/doctest.h>

#include "op_count.hpp"

using mbrt::codegen::OpCount;
namespace ops = mbrt::codegen::ops;

namespace {
bool same(const OpCount& a, const OpCount& b) {
  return a.mul == b.mul && a.add == b.add && a.div == b.div && a.sqrt == b.sqrt;
}
}  // namespace

TEST_CASE("products, sums and scalings of blocks") {
  CHECK(same(ops::product(2, 3, 4), {24, 16, 0, 0}));  // 8 entries, 3 products and 2 sums each
  CHECK(same(ops::product(5, 1, 5), {25, 0, 0, 0}));   // an outer product adds nothing
  CHECK(same(ops::sum(5, 6), {0, 30, 0, 0}));
  CHECK(same(ops::scale(6, 1), {6, 0, 0, 0}));
}

TEST_CASE("Cholesky counted from its loops") {
  CHECK(same(ops::cholesky(1), {0, 0, 0, 1}));
  // l00 = sqrt(a00); l10 = a10 / l00; l11 = sqrt(a11 - l10^2)
  CHECK(same(ops::cholesky(2), {1, 1, 1, 2}));
  // l20 and l10 (2 div), l11 (1 mul), l21 = (a21 - l20 l10) / l11, l22 (2 mul)
  CHECK(same(ops::cholesky(3), {4, 4, 3, 3}));
  // The products: n (n - 1) (n + 1) / 6 multiplications, as many additions.
  for (long n = 1; n <= 8; ++n) {
    CHECK(ops::cholesky(n).mul == n * (n - 1) * (n + 1) / 6);
    CHECK(ops::cholesky(n).div == n * (n - 1) / 2);
  }
}

TEST_CASE("triangular solves") {
  // y0 /= l00; y1 = (y1 - l10 y0) / l11; y2 = (y2 - l20 y0 - l21 y1) / l22
  CHECK(same(ops::triangular_solve(3), {3, 3, 3, 0}));
  // the same for each of the 4 rows of X
  CHECK(same(ops::solve_right_lower_transposed(4, 3), {12, 12, 12, 0}));
}

TEST_CASE("the inverse of a 2 x 2 block by LU") {
  // LU: l = a10 / a00, u11 = a11 - l a01. Per unit column: forward y1 = e1 - l y0,
  // backward x1 = y1 / u11, x0 = (y0 - a01 x1) / a00.
  CHECK(same(ops::lu_inverse(2), {5, 5, 5, 0}));
}

TEST_CASE("totals and the comment's text") {
  OpCount c = ops::cholesky(3);
  c += 2 * ops::product(10, 10, 10);
  CHECK(c.total() == 14 + 2 * (1000 + 900));
  CHECK(OpCount{1234, 0, 0, 0}.text() == "1,234 flops: 1,234 mul, 0 add");
  CHECK(OpCount{600, 580, 40, 14}.text() == "1,234 flops: 600 mul, 580 add, 40 div, 14 sqrt");
  CHECK(mbrt::codegen::thousands(1000000) == "1,000,000");
  CHECK(mbrt::codegen::thousands(999) == "999");
  CHECK(mbrt::codegen::thousands(100000) == "100,000");
}
