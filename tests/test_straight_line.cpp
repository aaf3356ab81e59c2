// The straight-line code recorder behind the generated recursions
// (codegen/emit/straight_line.hpp): what it folds, shares, fuses and drops.
#include <doctest/doctest.h>

#include <string>

#include "straight_line.hpp"

using mbrt::codegen::Expr;
using mbrt::codegen::StraightLine;

TEST_CASE("constants fold, and zero and unit factors leave nothing to compute") {
  StraightLine line;
  const Expr x = line.input("x");
  CHECK((Expr(2.0) * Expr(3.0) + Expr(1.0)).constant() == 7.0);
  CHECK((x * 0.0).is(0.0));
  CHECK((x - x).is(0.0));
  line.output("a", x * 1.0 + 0.0);
  line.output("b", -(x * -1.0));
  CHECK(line.code("") == "a = x;\nb = x;\n");
}

TEST_CASE("equal subexpressions are computed once, signs ride along") {
  StraightLine line;
  const Expr x = line.input("x"), y = line.input("y");
  line.output("a", x * y);
  line.output("b", y * x);
  line.output("c", -(x * y));
  line.output("d", (-x) * (-y));
  CHECK(line.code("") == "const double t0 = x * y;\na = t0;\nb = t0;\nc = -t0;\nd = t0;\n");
}

TEST_CASE("a product that feeds one sum is fused; what no output needs is not printed") {
  StraightLine line;
  const Expr x = line.input("x"), y = line.input("y"), z = line.input("z");
  const Expr unused = x * z * 3.0;
  (void)unused;
  line.output("a", x * y + z);
  line.output("b", z - y * z * 2.0);
  const std::string code = line.code("");
  CHECK(code == "const double t0 = mbrt::mul_add(x, y, z);\nconst double t1 = y * z;\n"
                "const double t2 = mbrt::mul_add(-t1, 2.0, z);\na = t0;\nb = t2;\n");
}

TEST_CASE("the operation count is what the printed statements execute") {
  StraightLine line;
  const Expr x = line.input("x"), y = line.input("y"), z = line.input("z");
  line.output("a", x * y + z);    // one fused multiply-add
  line.output("b", (x + y) / z);  // an add and a division
  line.output("c", x * z * 3.0);  // two products
  const mbrt::codegen::OperationCount n = line.count();
  CHECK(n.mul == 2);
  CHECK(n.add == 1);
  CHECK(n.fma == 1);
  CHECK(n.div == 1);
  CHECK(n.flops() == 6);
  CHECK(n.comment() == "// 6 flops: 2 mul, 1 add, 1 fma, 1 div");
  mbrt::codegen::OperationCount many;
  many.mul = 1234;
  CHECK(many.comment() == "// 1,234 flops: 1,234 mul, 0 add, 0 fma");
}
