// A tiny, safe arithmetic expression evaluator for the function-surface generators
// (`genparametricsurf funcX [ cos(u)*v ] …`): numbers, named variables, `pi`, `e`,
// + - * / ^ (right-associative), unary minus, parentheses and the functions sin cos tan
// asin acos atan sqrt abs exp log sinh cosh tanh. No other names, no side effects, bounded
// nesting; errors are values.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nomec::backend {

class Expression {
 public:
  /// Parses `text` with the given variable names (e.g. {"u", "v"}). On failure returns
  /// nullopt and sets `error` (lowercase, no trailing period), e.g. "unknown name `w`".
  static std::optional<Expression> parse(std::string_view text,
                                         const std::vector<std::string>& variables,
                                         std::string* error);
  /// Evaluates with `values[i]` bound to variable i. May return NaN or infinity.
  double evaluate(const std::vector<double>& values) const;

  struct Node {
    enum class Op { Number, Variable, Add, Sub, Mul, Div, Pow, Neg, Call } op = Op::Number;
    double number = 0.0;
    int index = 0;  // variable index or function index
    int lhs = -1;
    int rhs = -1;
  };

 private:
  double eval(int node, const std::vector<double>& values) const;
  std::vector<Node> nodes_;
  int root_ = -1;
  friend class ExprParser;
};

}  // namespace nomec::backend
