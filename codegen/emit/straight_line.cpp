#include "straight_line.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "emitter.hpp"

namespace mbrt::codegen {

namespace {
StraightLine* recording = nullptr;
}  // namespace

StraightLine::StraightLine() : previous_(recording) { recording = this; }
StraightLine::~StraightLine() { recording = previous_; }

StraightLine& StraightLine::current() {
  if (!recording) throw std::logic_error("an Expr operation outside a StraightLine");
  return *recording;
}

Expr StraightLine::input(const std::string& cpp) {
  Expr e;
  const auto [it, added] = inputs_.try_emplace(cpp, static_cast<int>(nodes_.size()));
  e.node_ = it->second;
  if (added) nodes_.push_back({'i', {}, {}, cpp});
  return e;
}

void StraightLine::output(const std::string& target, const Expr& e) { outputs_.emplace_back(target, e); }

// Operands arrive unsigned (constants may be negative); the callers move the
// signs to the result.
Expr StraightLine::record(char op, const Expr& a, const Expr& b) {
  const auto key = std::make_tuple(op, a.node_, a.negated_, a.c_, b.node_, b.negated_, b.c_);
  Expr e;
  if (const auto found = seen_.find(key); found != seen_.end()) {
    e.node_ = found->second;
    return e;
  }
  e.node_ = static_cast<int>(nodes_.size());
  nodes_.push_back({op, a, b, {}});
  seen_.emplace(key, e.node_);
  return e;
}

Expr operator-(const Expr& a) {
  Expr r = a;
  if (r.is_constant()) r.c_ = -r.c_;
  else r.negated_ = !r.negated_;
  return r;
}

Expr StraightLine::difference(const Expr& a, const Expr& b) {
  if (a.node_ == b.node_) return 0.0;
  return record('-', a, b);
}

Expr StraightLine::add(const Expr& a, const Expr& b) {
  if (a.is_constant() && b.is_constant()) return a.c_ + b.c_;
  if (a.is(0.0)) return b;
  if (b.is(0.0)) return a;
  if (a.is_constant()) return add(b, a);
  Expr ua = a;
  ua.negated_ = false;
  if (b.is_constant()) return a.negated_ ? -record('+', ua, -b) : record('+', ua, b);
  Expr ub = b;
  ub.negated_ = false;
  if (a.negated_ && b.negated_) return -add(ua, ub);
  if (a.negated_) return difference(ub, ua);
  if (b.negated_) return difference(ua, ub);
  if (a.node_ == b.node_) return multiply(2.0, ua);
  return a.node_ < b.node_ ? record('+', ua, ub) : record('+', ub, ua);
}

Expr StraightLine::multiply(const Expr& a, const Expr& b) {
  if (a.is_constant() && b.is_constant()) return a.c_ * b.c_;
  if (a.is(0.0) || b.is(0.0)) return 0.0;
  if (a.is_constant()) return multiply(b, a);
  Expr ua = a;
  ua.negated_ = false;
  if (b.is_constant()) {
    if (b.c_ == 1.0) return a;
    if (b.c_ == -1.0) return -a;
    const bool flip = a.negated_ != (b.c_ < 0.0);
    // (y c1) c2 is y (c1 c2): one product where there were two.
    const Node x = nodes_[static_cast<std::size_t>(ua.node_)];
    const bool scaled = x.op == '*' && x.b.is_constant();
    const double k = scaled ? x.b.c_ * std::abs(b.c_) : std::abs(b.c_);
    const Expr product = !scaled ? record('*', ua, k) : k == 1.0 ? x.a : record('*', x.a, k);
    return flip ? -product : product;
  }
  Expr ub = b;
  ub.negated_ = false;
  const Expr product = ua.node_ <= ub.node_ ? record('*', ua, ub) : record('*', ub, ua);
  return a.negated_ != b.negated_ ? -product : product;
}

Expr StraightLine::divide(const Expr& a, const Expr& b) {
  if (b.is_constant()) return multiply(a, 1.0 / b.c_);
  if (a.is(0.0)) return 0.0;
  Expr ub = b;
  ub.negated_ = false;
  Expr ua = a;
  bool flip = b.negated_;
  if (a.is_constant()) {
    flip = flip != (a.c_ < 0.0);
    ua = std::abs(a.c_);
  } else {
    flip = flip != a.negated_;
    ua.negated_ = false;
  }
  const Expr q = record('/', ua, ub);
  return flip ? -q : q;
}

Expr StraightLine::function(char op, const Expr& a) {
  if (a.is_constant()) return op == 's' ? std::sin(a.c_) : std::cos(a.c_);
  Expr ua = a;
  ua.negated_ = false;
  const Expr y = record(op, ua, 0.0);
  return op == 's' && a.negated_ ? -y : y;  // sin is odd, cos even
}

Expr operator+(const Expr& a, const Expr& b) {
  if (a.is_constant() && b.is_constant()) return a.constant() + b.constant();
  return StraightLine::current().add(a, b);
}
Expr operator-(const Expr& a, const Expr& b) { return a + (-b); }
Expr operator*(const Expr& a, const Expr& b) {
  if (a.is_constant() && b.is_constant()) return a.constant() * b.constant();
  return StraightLine::current().multiply(a, b);
}
Expr operator/(const Expr& a, const Expr& b) {
  if (a.is_constant() && b.is_constant()) return a.constant() / b.constant();
  return StraightLine::current().divide(a, b);
}
Expr sin(const Expr& a) {
  return a.is_constant() ? Expr(std::sin(a.constant())) : StraightLine::current().function('s', a);
}
Expr cos(const Expr& a) {
  return a.is_constant() ? Expr(std::cos(a.constant())) : StraightLine::current().function('c', a);
}

std::string StraightLine::operand(const Expr& e, const std::vector<std::string>& names) const {
  if (e.is_constant()) return e.c_ < 0.0 ? "(" + num(e.c_) + ")" : num(e.c_);
  return (e.negated_ ? "-" : "") + names[static_cast<std::size_t>(e.node_)];
}

// A node is live when an output needs it. A product used once by a sum is
// fused into it; each sum fuses at most one product: '+' its first, '-' its
// subtrahend first.
StraightLine::Schedule StraightLine::schedule() const {
  const std::size_t n = nodes_.size();
  Schedule s{std::vector<bool>(n, false), std::vector<bool>(n, false), std::vector<char>(n, 0)};
  std::vector<int> uses(n, 0);
  const auto mark = [&](const Expr& e) {
    if (!e.is_constant()) ++uses[static_cast<std::size_t>(e.node_)];
  };
  for (const auto& [target, e] : outputs_) {
    mark(e);
    if (!e.is_constant()) s.live[static_cast<std::size_t>(e.node_)] = true;
  }
  for (std::size_t k = n; k-- > 0;) {
    if (!s.live[k]) continue;
    for (const Expr* x : {&nodes_[k].a, &nodes_[k].b}) {
      if (x->is_constant()) continue;
      mark(*x);
      s.live[static_cast<std::size_t>(x->node_)] = true;
    }
  }
  const auto fusable = [&](const Expr& e) {
    return !e.is_constant() && nodes_[static_cast<std::size_t>(e.node_)].op == '*' &&
           uses[static_cast<std::size_t>(e.node_)] == 1;
  };
  for (std::size_t k = 0; k < n; ++k) {
    const Node& x = nodes_[k];
    if (!s.live[k] || (x.op != '+' && x.op != '-')) continue;
    const char first = x.op == '+' ? 'a' : 'b', second = x.op == '+' ? 'b' : 'a';
    for (const char side : {first, second}) {
      const Expr& e = side == 'a' ? x.a : x.b;
      if (s.fuses[k] || !fusable(e) || s.fused[static_cast<std::size_t>(e.node_)]) continue;
      s.fuses[k] = side;
      s.fused[static_cast<std::size_t>(e.node_)] = true;
    }
  }
  return s;
}

OperationCount StraightLine::count() const {
  const Schedule s = schedule();
  OperationCount c;
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    if (!s.live[k] || s.fused[k]) continue;
    switch (nodes_[k].op) {
      case '+':
      case '-': ++(s.fuses[k] ? c.fma : c.add); break;
      case '*': ++c.mul; break;
      case '/': ++c.div; break;
      case 's':
      case 'c': ++c.trig; break;
      default: break;  // inputs are read, not computed
    }
  }
  return c;
}

std::string OperationCount::comment() const {
  std::string s = "// " + thousands(flops()) + " flops: " + thousands(mul) + " mul, " + thousands(add) + " add, " +
                  thousands(fma) + " fma";
  if (div) s += ", " + thousands(div) + " div";
  if (trig) s += ", " + thousands(trig) + " sin/cos calls";
  return s;
}

// Prints the live nodes in order; inputs are read where they are used.
std::string StraightLine::code(const std::string& indent) const {
  const std::size_t n = nodes_.size();
  const Schedule s = schedule();
  const std::vector<bool>& live = s.live;
  const std::vector<bool>& fused = s.fused;
  const std::vector<char>& fuses = s.fuses;
  std::vector<std::string> names(n);
  std::ostringstream o;
  int next = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const Node& x = nodes_[k];
    if (!live[k] || fused[k]) continue;
    if (x.op == 'i') {
      names[k] = x.text;
      continue;
    }
    const std::string a = operand(x.a, names), b = operand(x.b, names);
    std::string value;
    const auto product = [&](const Expr& e, bool minus) {
      const Node& p = nodes_[static_cast<std::size_t>(e.node_)];
      return (minus ? "-" : "") + operand(p.a, names) + ", " + operand(p.b, names);
    };
    switch (x.op) {
      case '+':
        if (fuses[k] == 'a') value = "mbrt::mul_add(" + product(x.a, false) + ", " + b + ")";
        else if (fuses[k] == 'b') value = "mbrt::mul_add(" + product(x.b, false) + ", " + a + ")";
        else value = a + " + " + b;
        break;
      case '-':
        if (fuses[k] == 'b') value = "mbrt::mul_add(" + product(x.b, true) + ", " + a + ")";
        else if (fuses[k] == 'a') value = "mbrt::mul_add(" + product(x.a, false) + ", -" + b + ")";
        else value = a + " - " + b;
        break;
      case '*': value = a + " * " + b; break;
      case '/': value = a + " / " + b; break;
      case 's': value = "std::sin(" + a + ")"; break;
      case 'c': value = "std::cos(" + a + ")"; break;
    }
    names[k] = "t" + std::to_string(next++);
    o << indent << "const double " << names[k] << " = " << value << ";\n";
  }
  for (const auto& [target, e] : outputs_) o << indent << target << " = " << operand(e, names) << ";\n";
  return o.str();
}

}  // namespace mbrt::codegen
