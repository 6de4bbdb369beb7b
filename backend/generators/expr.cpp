// Recursive-descent parser and tree evaluator for generator function texts (expr.h).
#include "backend/generators/expr.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <numbers>

namespace nomec::backend {
namespace {

using Fn = double (*)(double);
struct Function {
  std::string_view name;
  Fn fn;
};
const Function kFunctions[] = {
    {"sin", [](double x) { return std::sin(x); }},   {"cos", [](double x) { return std::cos(x); }},
    {"tan", [](double x) { return std::tan(x); }},   {"asin", [](double x) { return std::asin(x); }},
    {"acos", [](double x) { return std::acos(x); }}, {"atan", [](double x) { return std::atan(x); }},
    {"sqrt", [](double x) { return std::sqrt(x); }}, {"abs", [](double x) { return std::abs(x); }},
    {"exp", [](double x) { return std::exp(x); }},   {"log", [](double x) { return std::log(x); }},
    {"sinh", [](double x) { return std::sinh(x); }}, {"cosh", [](double x) { return std::cosh(x); }},
    {"tanh", [](double x) { return std::tanh(x); }},
};
constexpr int kMaxDepth = 200;
constexpr int kMaxHeight = 2000;

}  // namespace

class ExprParser {
 public:
  ExprParser(std::string_view text, const std::vector<std::string>& vars, Expression& out)
      : s_(text), vars_(vars), out_(out) {}

  bool run(std::string* error) {
    skip();
    if (pos_ >= s_.size()) {
      return err("empty expression", error);
    }
    int root = expr(0);
    if (root >= 0) {
      skip();
      if (pos_ < s_.size()) {
        root = -1;
        set_error("unexpected `" + std::string(1, s_[pos_]) + "`");
      }
    }
    if (root < 0) {
      if (error) *error = error_;
      return false;
    }
    out_.root_ = root;
    return true;
  }

 private:
  using Op = Expression::Node::Op;

  bool err(std::string m, std::string* error) {
    if (error) *error = std::move(m);
    return false;
  }
  void set_error(std::string m) {
    if (error_.empty()) error_ = std::move(m);
  }
  void skip() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  bool eat(char c) {
    skip();
    if (pos_ < s_.size() && s_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  int add(Expression::Node n) {
    // Evaluation recurses once per level of the tree: bound its height (a long chain
    // `u+u+…` is as deep as it is long).
    int height = 1;
    if (n.lhs >= 0) height = std::max(height, heights_[n.lhs] + 1);
    if (n.rhs >= 0) height = std::max(height, heights_[n.rhs] + 1);
    if (height > kMaxHeight) {
      set_error("expression too long or nested too deeply");
      return -1;
    }
    heights_.push_back(height);
    out_.nodes_.push_back(n);
    return static_cast<int>(out_.nodes_.size()) - 1;
  }
  int binary(Op op, int l, int r) {
    if (l < 0 || r < 0) return -1;
    Expression::Node n;
    n.op = op;
    n.lhs = l;
    n.rhs = r;
    return add(n);
  }

  int expr(int depth) {
    if (depth > kMaxDepth) {
      set_error("expression nested too deeply");
      return -1;
    }
    int l = term(depth);
    while (l >= 0) {
      if (eat('+')) {
        l = binary(Op::Add, l, term(depth));
      } else if (eat('-')) {
        l = binary(Op::Sub, l, term(depth));
      } else {
        break;
      }
    }
    return l;
  }
  int term(int depth) {
    int l = unary(depth);
    while (l >= 0) {
      if (eat('*')) {
        l = binary(Op::Mul, l, unary(depth));
      } else if (eat('/')) {
        l = binary(Op::Div, l, unary(depth));
      } else {
        break;
      }
    }
    return l;
  }
  int unary(int depth) {
    if (depth > kMaxDepth) {
      set_error("expression nested too deeply");
      return -1;
    }
    if (eat('-')) {
      int x = unary(depth + 1);
      if (x < 0) return -1;
      Expression::Node n;
      n.op = Op::Neg;
      n.lhs = x;
      return add(n);
    }
    if (eat('+')) {
      return unary(depth + 1);
    }
    int base = primary(depth);
    if (base >= 0 && eat('^')) {
      return binary(Op::Pow, base, unary(depth + 1));
    }
    return base;
  }
  int primary(int depth) {
    skip();
    if (pos_ >= s_.size()) {
      set_error("unexpected end of expression");
      return -1;
    }
    const char c = s_[pos_];
    if (c == '(') {
      ++pos_;
      int x = expr(depth + 1);
      if (x >= 0 && !eat(')')) {
        set_error("missing `)`");
        return -1;
      }
      return x;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      const size_t start = pos_;
      while (pos_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '.')) ++pos_;
      if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E')) {
        size_t p = pos_ + 1;
        if (p < s_.size() && (s_[p] == '+' || s_[p] == '-')) ++p;
        if (p < s_.size() && std::isdigit(static_cast<unsigned char>(s_[p]))) {
          pos_ = p;
          while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
        }
      }
      const std::string lit(s_.substr(start, pos_ - start));
      char* end = nullptr;
      const double v = std::strtod(lit.c_str(), &end);
      if (end != lit.c_str() + lit.size()) {
        set_error("bad number `" + lit + "`");
        return -1;
      }
      Expression::Node n;
      n.op = Op::Number;
      n.number = v;
      return add(n);
    }
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      const size_t start = pos_;
      while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) ++pos_;
      const std::string name(s_.substr(start, pos_ - start));
      skip();
      if (pos_ < s_.size() && s_[pos_] == '(') {
        for (int f = 0; f < static_cast<int>(std::size(kFunctions)); ++f) {
          if (kFunctions[f].name == name) {
            ++pos_;
            int x = expr(depth + 1);
            if (x < 0) return -1;
            if (!eat(')')) {
              set_error("missing `)` after the argument of `" + name + "`");
              return -1;
            }
            Expression::Node n;
            n.op = Op::Call;
            n.index = f;
            n.lhs = x;
            return add(n);
          }
        }
        set_error("unknown function `" + name + "`");
        return -1;
      }
      for (int i = 0; i < static_cast<int>(vars_.size()); ++i) {
        if (vars_[i] == name) {
          Expression::Node n;
          n.op = Op::Variable;
          n.index = i;
          return add(n);
        }
      }
      if (name == "pi" || name == "e") {
        Expression::Node n;
        n.op = Op::Number;
        n.number = name == "pi" ? std::numbers::pi : std::numbers::e;
        return add(n);
      }
      std::string known;
      for (const auto& v : vars_) known += (known.empty() ? "" : ", ") + v;
      set_error("unknown name `" + name + "` (variables: " + known + ", constants: pi, e)");
      return -1;
    }
    set_error("unexpected `" + std::string(1, c) + "`");
    return -1;
  }

  std::string_view s_;
  const std::vector<std::string>& vars_;
  Expression& out_;
  size_t pos_ = 0;
  std::string error_;
  std::vector<int> heights_;
};

std::optional<Expression> Expression::parse(std::string_view text,
                                            const std::vector<std::string>& variables,
                                            std::string* error) {
  Expression e;
  ExprParser p(text, variables, e);
  if (!p.run(error)) {
    return std::nullopt;
  }
  return e;
}

double Expression::evaluate(const std::vector<double>& values) const { return eval(root_, values); }

double Expression::eval(int node, const std::vector<double>& values) const {
  const Node& n = nodes_[node];
  switch (n.op) {
    case Node::Op::Number: return n.number;
    case Node::Op::Variable:
      return n.index < static_cast<int>(values.size()) ? values[n.index] : 0.0;
    case Node::Op::Add: return eval(n.lhs, values) + eval(n.rhs, values);
    case Node::Op::Sub: return eval(n.lhs, values) - eval(n.rhs, values);
    case Node::Op::Mul: return eval(n.lhs, values) * eval(n.rhs, values);
    case Node::Op::Div: return eval(n.lhs, values) / eval(n.rhs, values);
    case Node::Op::Pow: return std::pow(eval(n.lhs, values), eval(n.rhs, values));
    case Node::Op::Neg: return -eval(n.lhs, values);
    case Node::Op::Call: return kFunctions[n.index].fn(eval(n.lhs, values));
  }
  return 0.0;
}

}  // namespace nomec::backend
