// Expression evaluation (see ir.h): the one evaluator of the project, for slider
// expressions at check time, for the backend's operands, and for the functions of function
// surfaces at every grid point. Iterative (an explicit stack), so no expression, however
// deep, recurses on the C++ stack; errors are values that point at the sub-expression.
#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "ir/ir.h"

namespace nomec::ir {

namespace {

EvalResult value_of(double v) {
  EvalResult r;
  r.value = v;
  return r;
}

EvalResult fail(std::string problem, SourceRange where) {
  EvalResult r;
  r.ok = false;
  r.problem = std::move(problem);
  r.where = where;
  return r;
}

// The operands evaluation visits (an External's parameter references are not evaluated).
std::span<const ExprId> evaluated_operands(const Module& m, const Expr& e) {
  return e.kind == ExprKind::External ? std::span<const ExprId>() : m.subexprs(e);
}

EvalResult binary(const Expr& e, double a, double b) {
  switch (e.op) {
    case '+': return value_of(a + b);
    case '-': return value_of(a - b);
    case '*': return value_of(a * b);
    case '/':
      if (b == 0) return fail(fmt::format("division by zero: {} / 0", a), e.range);
      return value_of(a / b);
    case 'i':
      if (b == 0) return fail(fmt::format("division by zero: {} // 0", a), e.range);
      return value_of(std::floor(a / b));
    case '%':
      if (b == 0) return fail(fmt::format("remainder by zero: {} % 0", a), e.range);
      return value_of(std::fmod(a, b));
    case '^': {
      double r = std::pow(a, b);
      if (std::isnan(r)) return fail(fmt::format("{} ^ {} has no real value", a, b), e.range);
      return value_of(r);
    }
    default:
      return fail("unknown operator", e.range);
  }
}

// Tcl 8.6's `srand(seed)`: seeds its Park–Miller generator (seed = 16807·seed mod 2³¹−1,
// Schrage's method) with the whole number `seed`, and returns the first `rand()` of it.
double tcl_srand(double seed) {
  constexpr int64_t kIa = 16807, kIm = 2147483647, kIq = 127773, kIr = 2836;
  int64_t s = static_cast<int64_t>(std::fmod(seed, 9.2e18)) & 0x7fffffff;
  if (s == 0 || s == 0x7fffffff) s ^= 123459876;
  const int64_t tmp = s / kIq;
  s = kIa * (s - tmp * kIq) - kIr * tmp;
  if (s < 0) s += kIm;
  return static_cast<double>(s) * (1.0 / static_cast<double>(kIm));
}

EvalResult call(const Expr& e, std::span<const double> v) {
  auto need = [&](bool ok, const char* what) -> std::optional<EvalResult> {
    if (!ok) return fail(fmt::format("`{}({})`: {}", func_name(e.func), fmt::join(v, ", "), what), e.range);
    return std::nullopt;
  };
  const double x = v.empty() ? 0 : v[0];
  switch (e.func) {
    case Func::Sin: return value_of(std::sin(x));
    case Func::Cos: return value_of(std::cos(x));
    case Func::Tan: return value_of(std::tan(x));
    case Func::Asin:
      if (auto f = need(x >= -1 && x <= 1, "argument outside [-1, 1]")) return *f;
      return value_of(std::asin(x));
    case Func::Acos:
      if (auto f = need(x >= -1 && x <= 1, "argument outside [-1, 1]")) return *f;
      return value_of(std::acos(x));
    case Func::Atan: return value_of(std::atan(x));
    case Func::Atan2: return value_of(std::atan2(v[0], v[1]));
    case Func::Sinh: return value_of(std::sinh(x));
    case Func::Cosh: return value_of(std::cosh(x));
    case Func::Tanh: return value_of(std::tanh(x));
    case Func::Sqrt:
      if (auto f = need(x >= 0, "square root of a negative number")) return *f;
      return value_of(std::sqrt(x));
    case Func::Abs: return value_of(std::fabs(x));
    case Func::Exp: return value_of(std::exp(x));
    case Func::Log:
    case Func::Ln:
      if (auto f = need(x > 0, "logarithm of a number that is not positive")) return *f;
      return value_of(std::log(x));
    case Func::Log10:
      if (auto f = need(x > 0, "logarithm of a number that is not positive")) return *f;
      return value_of(std::log10(x));
    case Func::Pow: {
      double r = std::pow(v[0], v[1]);
      if (auto f = need(!std::isnan(r), "no real value")) return *f;
      return value_of(r);
    }
    case Func::Min: return value_of(*std::min_element(v.begin(), v.end()));
    case Func::Max: return value_of(*std::max_element(v.begin(), v.end()));
    case Func::Floor: return value_of(std::floor(x));
    case Func::Ceil: return value_of(std::ceil(x));
    case Func::Round: return value_of(std::round(x));
    case Func::Sign: return value_of(static_cast<double>((x > 0) - (x < 0)));
    case Func::Mod:
      if (auto f = need(v[1] != 0, "remainder by zero")) return *f;
      return value_of(std::fmod(v[0], v[1]));
    case Func::Double: return value_of(x);
    case Func::Int:
    case Func::Wide:
      // Tcl truncates toward zero; a value beyond 64 bits has no integer (Tcl: "integer
      // value too large to represent").
      if (auto f = need(std::isfinite(x) && std::fabs(x) < 9.2e18, "no integer value")) return *f;
      return value_of(std::trunc(x));
    case Func::Fmod:
      if (auto f = need(v[1] != 0, "remainder by zero")) return *f;
      return value_of(std::fmod(v[0], v[1]));
    case Func::Hypot: return value_of(std::hypot(v[0], v[1]));
    case Func::Srand:
      if (auto f = need(std::isfinite(x) && x == std::trunc(x), "the seed must be a whole number")) return *f;
      return value_of(tcl_srand(x));
  }
  return fail("unknown function", e.range);
}

// A script the module's external evaluator computes, given every input parameter's value.
EvalResult external(const Module& m, const Expr& e) {
  if (!m.external) return fail("this value is a script, and nothing here can evaluate it", e.range);
  SmallVec<double, 16> values;
  for (NodeId p : m.external->inputs()) values.push_back(m.param(p).value);
  ExternalResult r =
      m.external->evaluate(m.external_script(e).script, std::span<const double>(values.data(), values.size()));
  if (!r.ok) return fail(std::move(r.problem), e.range);
  return value_of(r.value);
}

// The value of a leaf (an expression without operands).
EvalResult leaf(const Module& m, const Expr& e, std::span<const double> variables) {
  switch (e.kind) {
    case ExprKind::Const: return value_of(e.value);
    case ExprKind::Param: return value_of(m.param(e.param).value);
    case ExprKind::Builtin: return value_of(e.name == "time" ? m.time : m.frame);
    case ExprKind::External: return external(m, e);
    case ExprKind::Variable:
      if (e.variable < variables.size()) return value_of(variables[e.variable]);
      return fail(fmt::format("`{}` has no value here", e.name), e.range);
    default: return fail("", e.range);
  }
}

}  // namespace

bool may_fail(const Module& m, const Expr& e) {
  switch (e.kind) {
    case ExprKind::Const:
    case ExprKind::Param:
    case ExprKind::Builtin:
    case ExprKind::Unary:
      return false;
    case ExprKind::Binary:
      if (e.op == '+' || e.op == '-' || e.op == '*') return false;
      if (e.op == '/' || e.op == 'i' || e.op == '%') {  // `binary`: fails on a zero divisor only
        const Expr& divisor = m.expr(e.rhs());
        return divisor.kind != ExprKind::Const || divisor.value == 0;
      }
      return true;
    case ExprKind::Call:
      switch (e.func) {  // the functions `call` may fail for
        case Func::Asin: case Func::Acos: case Func::Sqrt: case Func::Log: case Func::Ln:
        case Func::Log10: case Func::Pow: case Func::Mod: case Func::Int: case Func::Wide:
        case Func::Fmod: case Func::Srand:
          return true;
        default:
          return false;
      }
    case ExprKind::Variable:
    case ExprKind::External:
    case ExprKind::Error:
      return true;
  }
  return true;
}

EvalResult evaluate(const Module& m, ExprId root, std::span<const double> variables) {
  if (!root.is_valid()) return fail("", SourceRange{});
  // Post-order walk: a frame is an expression and how many of its operands are evaluated;
  // the operands' values wait on `values` until their expression is computed.
  struct Frame {
    ExprId id;
    int done;
  };
  SmallVec<Frame, 16> stack;
  SmallVec<double, 16> values;
  stack.push_back({root, 0});
  while (!stack.empty()) {
    Frame& top = stack.back();
    const Expr& e = m.expr(top.id);
    const std::span<const ExprId> kids = evaluated_operands(m, e);
    const int n = static_cast<int>(kids.size());
    if (e.kind == ExprKind::Error) return fail("", e.range);
    if (top.done < n) {
      const ExprId c = kids[static_cast<size_t>(top.done++)];
      stack.push_back({c, 0});
      continue;
    }
    // The kinds that cannot fail are computed in place; the others go through the helpers,
    // whose results carry a problem (a string) when they fail.
    double value;
    if (n == 0 && e.kind == ExprKind::Const) {
      value = e.value;
    } else if (n == 0 && e.kind == ExprKind::Param) {
      value = m.param(e.param).value;
    } else if (e.kind == ExprKind::Unary) {
      value = e.op == '-' ? -values.back() : values.back();
      values.truncate(values.size() - 1);
    } else if (e.kind == ExprKind::Binary && (e.op == '+' || e.op == '-' || e.op == '*')) {
      const double a = values[values.size() - 2], b = values.back();
      value = e.op == '+' ? a + b : e.op == '-' ? a - b : a * b;
      values.truncate(values.size() - 2);
    } else {
      EvalResult r;
      if (n == 0) {
        r = leaf(m, e, variables);
      } else {
        std::span<const double> operands(values.end() - n, static_cast<size_t>(n));
        r = e.kind == ExprKind::Binary ? binary(e, operands[0], operands[1]) : call(e, operands);
        values.truncate(values.size() - static_cast<uint32_t>(n));
      }
      if (!r.ok) return r;
      value = r.value;
    }
    values.push_back(value);
    stack.pop_back();
  }
  return value_of(values.back());
}

}  // namespace nomec::ir
