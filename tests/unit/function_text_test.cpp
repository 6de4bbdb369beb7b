// Function texts of the function surfaces (`funcX [ … ]`): parsed by the grammar's
// `functionText` rule, lowered into the IR with the file's other expressions and evaluated
// by the one IR evaluator at the generator's variables. Arithmetic and precedence, the
// built-in functions and constants, and the `--check` errors a sculptor sees for a broken
// function (each at its place in the text).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "frontend/check/check.h"

namespace nomec {
namespace {

struct Checked {
  SourceManager sources;
  DiagnosticEngine diags;
  CheckResult result;
};

// `genparametricsurf` with `funcX [text]`, checked as NOME3.
std::unique_ptr<Checked> check_function(const std::string& text) {
  auto c = std::make_unique<Checked>();
  const std::string file = "genparametricsurf g funcX [" + text +
                           "] funcY [v] funcZ [0] (0 1 0 1 1 1) endgenparametricsurf\n";
  c->result = check_source(c->sources, "f.nom", file, CheckOptions{}, c->diags);
  c->diags.sort_and_dedupe();
  return c;
}

// funcX at (u, v); fails the test when the text does not check cleanly.
double eval(const std::string& text, double u = 0, double v = 0) {
  auto c = check_function(text);
  EXPECT_EQ(c->diags.error_count(), 0) << text.substr(0, 60) << ": " << c->diags.diagnostics().front().message;
  const ir::Module& m = c->result.module;
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    const ir::NodeId id(static_cast<int32_t>(i));
    if (m.node(id).kind != ir::NodeKind::Generator || m.node(id).name != "g") continue;
    const ir::GenArgBinding* b = m.gen_arg(id, ir::arg_index(ir::gen_arg::Genparametricsurf::funcX));
    if (b == nullptr || m.operand(b->value).exprs.empty()) break;
    const double vars[] = {u, v};
    const ir::EvalResult r = ir::evaluate(m, m.refs(m.operand(b->value).exprs)[0], vars);
    EXPECT_TRUE(r.ok) << text << ": " << r.problem;
    return r.value;
  }
  ADD_FAILURE() << text << ": no funcX in the IR";
  return NAN;
}

// The one error `--check` gives for funcX = text: its message, and its column in the line.
struct Error {
  std::string message;
  uint32_t column = 0;
};
Error error(const std::string& text) {
  auto c = check_function(text);
  for (const Diagnostic& d : c->diags.diagnostics()) {
    if (d.severity != Severity::Error) continue;
    EXPECT_EQ(c->diags.error_count(), 1) << text.substr(0, 60);
    return Error{d.message, d.range.begin + 1};
  }
  ADD_FAILURE() << text.substr(0, 60) << ": no error";
  return {};
}
constexpr uint32_t kTextColumn = 28;  // where the function text starts in the line

TEST(FunctionText, ArithmeticAndPrecedence) {
  EXPECT_DOUBLE_EQ(eval("1 + 2 * 3"), 7);
  EXPECT_DOUBLE_EQ(eval("(1 + 2) * 3"), 9);
  EXPECT_DOUBLE_EQ(eval("2 ^ 3 ^ 2"), 512);  // right-associative
  EXPECT_DOUBLE_EQ(eval("-2 ^ 2"), -4);      // `^` binds tighter than unary minus
  EXPECT_DOUBLE_EQ(eval("2 ^ -1"), 0.5);
  EXPECT_DOUBLE_EQ(eval("8 / 4 / 2"), 1);
  EXPECT_DOUBLE_EQ(eval("10 - 4 - 3"), 3);
  EXPECT_DOUBLE_EQ(eval("- -u", 3), 3);
  EXPECT_DOUBLE_EQ(eval("u * v + 1", 2, 5), 11);
  EXPECT_DOUBLE_EQ(eval("u*v-1", 2, 5), 9);  // no spaces: one expression
  EXPECT_DOUBLE_EQ(eval("1.5e2"), 150);
  EXPECT_DOUBLE_EQ(eval(".5"), 0.5);
}

TEST(FunctionText, FunctionsAndConstants) {
  EXPECT_NEAR(eval("cos(pi)"), -1, 1e-15);
  EXPECT_NEAR(eval("log(exp(1))"), 1, 1e-15);
  EXPECT_NEAR(eval("sqrt(abs(-16)) + exp(0) + sinh(0) + cosh(0) + tanh(0)"), 6, 1e-15);
  EXPECT_NEAR(eval("asin(1) + acos(1) + atan(0) + tan(0) + sin(0)"), std::numbers::pi / 2, 1e-15);
  EXPECT_NEAR(eval("cos(u)*v", std::numbers::pi, 2), -2, 1e-15);
}

TEST(FunctionText, LongChainsEvaluateUpToTheOperationLimit) {
  std::string chain = "u";
  for (int i = 0; i < 900; ++i) chain += "+u";
  EXPECT_DOUBLE_EQ(eval(chain, 1), 901);
  // Past 1000 operations, one error (and the parse stays linear in the text's length).
  for (int i = 0; i < 20000; ++i) chain += "-u";
  const Error e = error(chain);
  EXPECT_EQ(e.message, "expression nests more than 1000 operations deep; split it into sliders or points");
  EXPECT_EQ(e.column, kTextColumn);
}

TEST(FunctionText, ErrorsAtTheirPlace) {
  Error e = error("w + 1");
  EXPECT_EQ(e.message, "unknown name `w` in the function; its variables are `u`, `v`; did you mean `u`?");
  EXPECT_EQ(e.column, kTextColumn);
  e = error("sinn(u)");
  EXPECT_EQ(e.message, "unknown function `sinn`; did you mean `sin`?");
  EXPECT_EQ(e.column, kTextColumn);
  e = error("(u + 1");
  EXPECT_EQ(e.message, "`(` is never closed: expected `)` before the `]` that ends the function");
  e = error("sin(u");
  EXPECT_EQ(e.message, "`(` is never closed: expected `)` before the `]` that ends the function");
  EXPECT_EQ(e.column, kTextColumn + 3);
  e = error("u +");
  EXPECT_EQ(e.message, "the function ends after `+`: the value after it is missing");
  EXPECT_EQ(e.column, kTextColumn + 2);
  e = error("u *");
  EXPECT_EQ(e.message, "the function ends after `*`: the value after it is missing");
  // `u v` is a product (exprtk's implicit multiplication); two numbers side by side are not.
  e = error("2 3");
  EXPECT_EQ(e.message, "unexpected `3` in the function; a function is one expression, e.g. `cos(u)*v`");
  EXPECT_EQ(e.column, kTextColumn + 2);
  e = error("u $ 2");
  EXPECT_EQ(e.message, "unexpected character `$`");
  e = error("   ");
  EXPECT_EQ(e.message, "the function is empty; write one expression of its variables, e.g. `cos(u)*v`");
}

TEST(FunctionText, DeepNestingIsOneErrorNotACrash) {
  Error e = error(std::string(1000, '(') + "u" + std::string(1000, ')'));
  EXPECT_EQ(e.message, "brackets, signs or `^` nest more than 200 levels deep here; nomec stops reading the function at this point");
  e = error(std::string(1000, '-') + "u");
  EXPECT_EQ(e.message, "brackets, signs or `^` nest more than 200 levels deep here; nomec stops reading the function at this point");
}

}  // namespace
}  // namespace nomec
