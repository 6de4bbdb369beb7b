// Expression evaluation (see ir.h): the one evaluator of the project, for slider
// expressions at check time, for the backend's operands, and for the functions of function
// surfaces at every grid point. Iterative (an explicit stack), so no expression, however
// deep, recurses on the C++ stack; errors are values that point at the sub-expression.
// Every value it returns is finite: an operation whose result overflows (`1e200 * 1e200`,
// `exp(1000)`) or a leaf that is not a finite number (a script's `Inf`) is an error there,
// so no infinity or NaN reaches geometry or an output file.
#include <algorithm>
#include <cmath>
#include <cstring>
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

// How an operator is written.
std::string_view op_text(char op) {
  switch (op) {
    case '+': return "+";
    case '-': return "-";
    case '*': return "*";
    case '/': return "/";
    case 'i': return "//";
    case '%': return "%";
    case '^': return "^";
    default: return "?";
  }
}

// The problem of an operation on finite operands whose result is not finite: it overflowed
// (`1e200 * 1e200`, `exp(1000)`), or divided by zero in disguise (`0 ^ -1`).
EvalResult not_finite(std::string what, SourceRange where) {
  return fail(fmt::format("{} is too large: numbers stop near 1.8e308", what), where);
}

// The operands evaluation visits (an External's parameter references are not evaluated).
// Those of `-x` and `a * b` are read in place (most nodes are leaves or operators).
std::span<const ExprId> evaluated_operands(const Module& m, const Expr& e) {
  switch (e.kind) {
    case ExprKind::Unary: return {e.operands, 1};
    case ExprKind::Binary: return {e.operands, 2};
    case ExprKind::Call: return m.subexprs(e);
    default: return {};
  }
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
      if (a == 0 && b < 0) return fail(fmt::format("division by zero: {} ^ {}", a, b), e.range);
      return value_of(r);
    }
    default:
      return fail("unknown operator", e.range);
  }
}

// `binary`, refusing a result that is not finite.
EvalResult finite_binary(const Expr& e, double a, double b) {
  EvalResult r = binary(e, a, b);
  if (r.ok && !std::isfinite(r.value)) return not_finite(fmt::format("{} {} {}", a, op_text(e.op), b), e.range);
  return r;
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

// `call`, refusing a result that is not finite.
EvalResult finite_call(const Expr& e, std::span<const double> v) {
  EvalResult r = call(e, v);
  if (r.ok && !std::isfinite(r.value)) {
    return not_finite(fmt::format("`{}({})`", func_name(e.func), fmt::join(v, ", ")), e.range);
  }
  return r;
}

// A script the module's external evaluator computes, given every input parameter's value.
EvalResult external(const Module& m, const Expr& e) {
  if (!m.external) return fail("this value is a script, and nothing here can evaluate it", e.range);
  SmallVec<double, 16> values;
  for (NodeId p : m.external->inputs()) values.push_back(m.param(p).value);
  ExternalResult r =
      m.external->evaluate(m.external_script(e).script, std::span<const double>(values.data(), values.size()));
  if (!r.ok) return fail(std::move(r.problem), e.range);
  if (!std::isfinite(r.value)) return fail(fmt::format("the script's value, {}, is not a finite number", r.value), e.range);
  return value_of(r.value);
}

// The value of a leaf (an expression without operands).
EvalResult leaf_value(const Module& m, const Expr& e, std::span<const double> variables) {
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

// `leaf_value`, refusing one that is not finite (the front end, `-D` and the slider
// requests refuse such numbers before they become constants or slider values; this is the
// last wall).
EvalResult leaf(const Module& m, const Expr& e, std::span<const double> variables) {
  EvalResult r = leaf_value(m, e, variables);
  if (r.ok && !std::isfinite(r.value)) {
    // (`name` is read only for the kinds that have one: the members share a union.)
    const bool named = e.kind == ExprKind::Builtin || e.kind == ExprKind::Variable;
    const std::string what = e.kind == ExprKind::Param ? fmt::format("the slider's value ({})", r.value)
                             : named                   ? fmt::format("`{}` ({})", e.name, r.value)
                                                       : fmt::format("{}", r.value);
    return fail(fmt::format("{} is not a finite number", what), e.range);
  }
  return r;
}

// Whether every operand of `e` is a constant (then `may_fail` can evaluate it).
bool has_constant_operands(const Module& m, const Expr& e) {
  const std::span<const ExprId> kids = evaluated_operands(m, e);
  return std::all_of(kids.begin(), kids.end(), [&](ExprId k) { return m.expr(k).kind == ExprKind::Const; });
}

}  // namespace

namespace {

// How `evaluate` may fail at an expression itself, whatever the (finite) values of its
// operands (constant or not): never; only by overflowing, and then by no more than the magnitude of its
// operands allows (`a + b`, `a * b`, `hypot(a, b)`: 1 + |result| is at most the product of
// 1 + |operand|); or otherwise (outside its domain: a division by a value, `sqrt`, `log`;
// or by growing without bound: `exp`, `^`).
enum class Risk { None, Overflow, Domain };

// An expression's `Risk` from its kind alone (an operation on constants is judged as any
// other), and a bound in bits on the factor by which it can raise 1 + |value| over the
// product of its operands' (see may_fail_now): for a leaf, 1 + |its value| itself; for a
// function whose value is bounded (`sin` at most 1, `tan` of a double below 1.7e16) or may
// exceed its argument by 1 (`floor`, `//`), that bound or factor; 0 (a factor of 1) for the
// rest, whose 1 + |value| is at most the product of their operands'. Cheap: the checker
// asks it of every expression it lowers.
struct Assessment {
  Risk risk = Risk::None;
  int bits = 0;
};

// The bits of 1 + |v|, rounded up: 1 below 1, else the binary exponent + 2; more than any
// finite bound for infinity or NaN.
int bits_of(double v) {
  uint64_t u = 0;
  std::memcpy(&u, &v, sizeof u);
  const int exponent = static_cast<int>((u >> 52) & 0x7ff);
  if (exponent == 0x7ff) return 4096;
  return exponent < 1023 ? 1 : exponent - 1023 + 2;  // 1 + |v| < 2^(exponent + 2)
}

Assessment assess(const Module& m, const Expr& e) {
  switch (e.kind) {
    case ExprKind::Const:
      return {std::isfinite(e.value) ? Risk::None : Risk::Domain, bits_of(e.value)};
    case ExprKind::Param:
      return {Risk::None, bits_of(m.param(e.param).value)};
    case ExprKind::Builtin:
      return {Risk::None, bits_of(e.name == "time" ? m.time : m.frame)};
    case ExprKind::Unary:
      return {};
    case ExprKind::Binary:
      switch (e.op) {
        case '+': case '-': case '*':
          return {Risk::Overflow, 0};
        case '/': case 'i': case '%': {
          // By a constant: a remainder cannot fail unless it is 0, nor a quotient by 1 or
          // more in magnitude (`binary` fails on a zero divisor; a smaller one may overflow).
          const Expr& divisor = m.expr(e.rhs());
          if (divisor.kind != ExprKind::Const || !std::isfinite(divisor.value)) return {Risk::Domain, 0};
          const bool ok = e.op == '%' ? divisor.value != 0 : std::fabs(divisor.value) >= 1;
          return {ok ? Risk::None : Risk::Domain, e.op == 'i' ? 1 : 0};
        }
        default:  // `^`: no real value, or growth without bound
          return {Risk::Domain, 0};
      }
    case ExprKind::Call:
      switch (e.func) {
        case Func::Hypot:
          return {Risk::Overflow, 0};
        case Func::Asin: case Func::Acos: case Func::Sqrt: case Func::Log: case Func::Ln:
        case Func::Log10: case Func::Pow: case Func::Mod: case Func::Int: case Func::Wide:
        case Func::Fmod: case Func::Srand: case Func::Exp: case Func::Sinh: case Func::Cosh:
          return {Risk::Domain, 0};
        case Func::Sin: case Func::Cos: case Func::Tanh: case Func::Sign:
        case Func::Floor: case Func::Ceil: case Func::Round:
          return {Risk::None, 1};
        case Func::Atan: return {Risk::None, 2};   // 1 + π/2 < 4
        case Func::Atan2: return {Risk::None, 3};  // 1 + π < 8
        case Func::Tan: return {Risk::None, 55};   // |tan(x)| < 1.7e16 < 2^54 for every double x
        default:
          return {};  // abs, min, max, double: at most an operand's magnitude
      }
    case ExprKind::Variable:
    case ExprKind::External:
    case ExprKind::Error:
      return {Risk::Domain, 0};
  }
  return {Risk::Domain, 0};
}

}  // namespace

bool may_fail(const Module& m, const Expr& e) {
  if ((e.kind == ExprKind::Binary || e.kind == ExprKind::Call) && has_constant_operands(m, e)) {
    // An operation on constants fails exactly when evaluating it does.
    SmallVec<double, 4> v;
    for (ExprId k : evaluated_operands(m, e)) v.push_back(m.expr(k).value);
    if (std::any_of(v.begin(), v.end(), [](double x) { return !std::isfinite(x); })) return true;
    const std::span<const double> operands(v.data(), v.size());
    return !(e.kind == ExprKind::Binary ? finite_binary(e, operands[0], operands[1]) : finite_call(e, operands)).ok;
  }
  return assess(m, e).risk != Risk::None;
}

bool may_fail_now(const Module& m, std::span<const Expr> nodes) {
  // 1 + |value| of every node is at most the product, over the leaves and bounded functions
  // beneath it, of their factors (by induction: 1 + |a + b| and 1 + |a * b| are at most
  // (1 + |a|)(1 + |b|)); below 2^1023 the value is finite, rounding included.
  constexpr int kFiniteBits = 1023;
  bool may_overflow = false;
  int bits = 0;
  for (const Expr& e : nodes) {
    const Assessment a = assess(m, e);
    if (a.risk == Risk::Domain) return true;
    may_overflow = may_overflow || a.risk == Risk::Overflow;
    bits = std::min(bits + a.bits, 1 << 20);
  }
  return may_overflow && bits >= kFiniteBits;
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
    // A finite constant or slider value, the most common nodes, without more ado.
    if (e.kind == ExprKind::Const || e.kind == ExprKind::Param) {
      const double v = e.kind == ExprKind::Const ? e.value : m.param(e.param).value;
      if (std::isfinite(v)) {
        values.push_back(v);
        stack.pop_back();
        continue;
      }
    }
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
    if (e.kind == ExprKind::Unary) {
      value = e.op == '-' ? -values.back() : values.back();
      values.truncate(values.size() - 1);
    } else if (e.kind == ExprKind::Binary && (e.op == '+' || e.op == '-' || e.op == '*')) {
      const double a = values[values.size() - 2], b = values.back();
      value = e.op == '+' ? a + b : e.op == '-' ? a - b : a * b;
      if (!std::isfinite(value)) return not_finite(fmt::format("{} {} {}", a, e.op, b), e.range);
      values.truncate(values.size() - 2);
    } else {
      EvalResult r;
      if (n == 0) {
        r = leaf(m, e, variables);
      } else {
        std::span<const double> operands(values.end() - n, static_cast<size_t>(n));
        r = e.kind == ExprKind::Binary ? finite_binary(e, operands[0], operands[1]) : finite_call(e, operands);
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
