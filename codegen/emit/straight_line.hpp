// Straight-line code recorded from an algorithm that runs at generation time
// on symbolic values (docs/staggered-tree.md). Constants fold, zero terms and
// unit factors drop, signs ride along with the values, equal subexpressions
// are computed once, a product that feeds one sum becomes mbrt::mul_add, and
// only what an output needs is printed.
#pragma once

#include <map>
#include <string>
#include <tuple>
#include <vector>

namespace mbrt::codegen {

// A value of the generated code: a constant known now, or +/- a recorded node.
class Expr {
 public:
  Expr(double c = 0.0) : c_(c) {}  // implicit: constants mix with expressions
  bool is_constant() const { return node_ < 0; }
  bool is(double c) const { return is_constant() && c_ == c; }
  double constant() const { return c_; }

 private:
  friend class StraightLine;
  friend Expr operator-(const Expr& a);
  int node_ = -1;
  bool negated_ = false;
  double c_ = 0.0;
};

Expr operator+(const Expr& a, const Expr& b);
Expr operator-(const Expr& a, const Expr& b);
Expr operator*(const Expr& a, const Expr& b);
Expr operator/(const Expr& a, const Expr& b);
Expr operator-(const Expr& a);
inline Expr& operator+=(Expr& a, const Expr& b) { return a = a + b; }
inline Expr& operator-=(Expr& a, const Expr& b) { return a = a - b; }
Expr sin(const Expr& a);
Expr cos(const Expr& a);

// The operations the printed statements execute. A fused multiply-add counts
// as two flops, as floating-point operation counts usually do.
struct OperationCount {
  int mul = 0, add = 0, fma = 0, div = 0, trig = 0;
  int flops() const { return mul + add + div + 2 * fma; }
  std::string comment() const;  // "// 1,234 flops: 500 mul, ..."
};

// The body of one generated function. While it exists, operations on Exprs
// record into it; one is recorded at a time.
class StraightLine {
 public:
  StraightLine();
  ~StraightLine();
  StraightLine(const StraightLine&) = delete;
  StraightLine& operator=(const StraightLine&) = delete;

  // A value the function reads: a C++ expression of its arguments, one node
  // however often it is asked for.
  Expr input(const std::string& cpp);
  // Writes e to target (a C++ lvalue) at the end of the function.
  void output(const std::string& target, const Expr& e);
  // The statements, each line starting with indent.
  std::string code(const std::string& indent) const;
  // What those statements compute.
  OperationCount count() const;

  static StraightLine& current();
  Expr add(const Expr& a, const Expr& b);
  Expr multiply(const Expr& a, const Expr& b);
  Expr divide(const Expr& a, const Expr& b);
  Expr function(char op, const Expr& a);

 private:
  Expr record(char op, const Expr& a, const Expr& b);
  Expr difference(const Expr& a, const Expr& b);  // a - b of two unsigned nodes
  struct Node {
    char op;  // 'i' input, '+', '-', '*', '/', 's' sin, 'c' cos
    Expr a, b;
    std::string text;  // inputs
  };
  // Which nodes are printed, and which sum takes which product into a mul_add.
  struct Schedule {
    std::vector<bool> live, fused;
    std::vector<char> fuses;  // 'a' or 'b': the operand fused into this sum
  };
  Schedule schedule() const;
  std::string operand(const Expr& e, const std::vector<std::string>& names) const;
  std::vector<Node> nodes_;
  std::map<std::tuple<char, int, bool, double, int, bool, double>, int> seen_;
  std::map<std::string, int> inputs_;  // input nodes by their text
  std::vector<std::pair<std::string, Expr>> outputs_;
  StraightLine* previous_;
};

}  // namespace mbrt::codegen
