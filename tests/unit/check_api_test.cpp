// The checker through its API: the list-sign rule, dialect detection, parameter overrides,
// dependency edges from sliders to instances, 2016 `_`-joined vertex names, and byte
// offsets in files with non-ASCII text.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "frontend/check/check.h"

namespace nomec {
namespace {

struct Checked {
  SourceManager sources;
  DiagnosticEngine diags;
  CheckResult result;
};

std::unique_ptr<Checked> check(const std::string& path, const std::string& text,
                               CheckOptions options = {}) {
  auto c = std::make_unique<Checked>();
  c->result = check_source(c->sources, path, text, options, c->diags);
  c->diags.sort_and_dedupe();
  return c;
}

bool has(const Checked& c, DiagKind kind) {
  return std::any_of(c.diags.diagnostics().begin(), c.diags.diagnostics().end(),
                     [&](const Diagnostic& d) { return d.kind == kind; });
}

// The value of expression `i` of operand `field` of node `node`.
double field_value(const Checked& c, std::string_view node, std::string_view field, size_t i) {
  const ir::Module& m = c.result.module;
  for (const ir::Node& n : m.nodes) {
    if (n.name != node) continue;
    for (ir::OperandId o : m.operands_of(n)) {
      if (m.operand(o).name != field) continue;
      const std::span<const ir::ExprId> exprs = m.refs(m.operand(o).exprs);
      if (i < exprs.size()) return ir::evaluate(m, exprs[i]).value;
      ADD_FAILURE() << "operand " << field << " on " << node << " has " << exprs.size() << " expressions";
      return 0;
    }
  }
  ADD_FAILURE() << "no operand " << field << " on " << node;
  return 0;
}

TEST(Check, SignRuleSplitsSpaceSeparatedLists) {
  auto c = check("a.nom",
                 "bank b set w 2 0 4 1 endbank\n"
                 "point p (0 -0.5*$b.w 0) endpoint\n"
                 "point q (1 - 1 0 2) endpoint\n"   // binary minus: 3 elements
                 "point r ({expr 3 -1} 0 0) endpoint\n");
  EXPECT_EQ(c->diags.error_count(), 0);
  EXPECT_DOUBLE_EQ(field_value(*c, "p", "position", 1), -1.0);
  EXPECT_DOUBLE_EQ(field_value(*c, "q", "position", 0), 0.0);
  EXPECT_DOUBLE_EQ(field_value(*c, "r", "position", 0), 2.0);  // binary inside braces
  auto bad = check("a.nom", "point p (0 -1 0 1) endpoint\n");
  ASSERT_TRUE(has(*bad, DiagKind::ListArity));
  EXPECT_NE(bad->diags.diagnostics()[0].message.find("`0` | `-1` | `0` | `1`"), std::string::npos);
}

TEST(Check, PowerBindsTighterThanUnaryMinus) {
  auto c = check("a.nome", "point p ({expr -2^2} {expr 2^3^2} 0) endpoint\n");
  EXPECT_DOUBLE_EQ(field_value(*c, "p", "position", 0), -4.0);
  EXPECT_DOUBLE_EQ(field_value(*c, "p", "position", 1), 512.0);
  auto nome3 = check("a.nom", "point p ({expr -2^2} 0 0) endpoint\n");
  EXPECT_TRUE(has(*nome3, DiagKind::UnaryMinusPower));
}

TEST(Check, DialectDecidesFunnelArgumentOrder) {
  std::string text = "funnel f (8 0.5 0.2 1) endfunnel\n";
  auto nome = check("f.nome", text);
  EXPECT_EQ(nome->result.dialect, Dialect::Nome);
  EXPECT_DOUBLE_EQ(field_value(*nome, "f", "n", 0), 8);
  // All generations saved `.nom`: only the 2016 order makes these numbers a funnel.
  auto by_content = check("f.nom", text);
  EXPECT_EQ(by_content->result.dialect, Dialect::Nome);
  EXPECT_DOUBLE_EQ(field_value(*by_content, "f", "n", 0), 8);
  auto nome3 = check("f.nom", "bank b list (x) set x 1 0 2 1 endbank\nfunnel f (0.5 0.2 1 8) endfunnel\n");
  EXPECT_EQ(nome3->result.dialect, Dialect::Nome3);
  EXPECT_DOUBLE_EQ(field_value(*nome3, "f", "n", 0), 8);
  EXPECT_DOUBLE_EQ(field_value(*nome3, "f", "radius", 0), 0.5);
  EXPECT_FALSE(has(*nome3, DiagKind::ArgumentOrder));
  // The same funnel in the 2016 order, in a NOME3 file: read in that order, with a warning.
  auto swapped = check("f.nom", "bank b list (x) set x 1 0 2 1 endbank\n" + text);
  EXPECT_EQ(swapped->result.dialect, Dialect::Nome3);
  EXPECT_TRUE(has(*swapped, DiagKind::ArgumentOrder));
  EXPECT_DOUBLE_EQ(field_value(*swapped, "f", "n", 0), 8);
}

// The ArgumentOrder fix-it rewrites the list in the dialect's order, keeping each value's
// text: NOME3's `circle (20 1)` read as NOME2's `(n ro)` becomes `(1 20)`, `(radius segs)`.
TEST(Check, ArgumentOrderFixItReordersTheList) {
  auto c = check("c.nom", "torus t (5 1 360 0 360 12 6) endtorus\ncircle c (20 {expr 0.5*2}) endcircle\n");
  const Diagnostic* order = nullptr;
  for (const Diagnostic& d : c->diags.diagnostics()) {
    if (d.kind == DiagKind::ArgumentOrder) order = &d;
  }
  ASSERT_NE(order, nullptr);
  ASSERT_EQ(order->fixits.size(), 1u);
  EXPECT_EQ(order->fixits[0].replacement, "({expr 0.5*2} 20)");
  EXPECT_DOUBLE_EQ(field_value(*c, "c", "n", 0), 20);
  EXPECT_DOUBLE_EQ(field_value(*c, "c", "ro", 0), 1);
}

// NOME2's `bsplineK`: the digits of the keyword are the order; the end keyword carries them.
TEST(Check, DigitKeywordSetsTheOrder) {
  auto c = check("b.nom", "point a (0 0 0) endpoint\npoint b (1 1 0) endpoint\npoint d (2 0 0) endpoint\n"
                          "bspline3 s slices 4 (a b d) endbspline3\n");
  EXPECT_EQ(c->result.dialect, Dialect::Nome2);
  EXPECT_EQ(c->diags.error_count(), 0);
  EXPECT_DOUBLE_EQ(field_value(*c, "s", "order", 0), 3);
  EXPECT_EQ(ast::block_of_keyword("bspline12"), ast::BlockKind::Generator);
  EXPECT_EQ(ast::block_of_end_keyword("endbspline3"), ast::BlockKind::Generator);
  EXPECT_FALSE(ast::block_of_keyword("bspline123").has_value());
  EXPECT_FALSE(ast::block_of_keyword("bsplinex").has_value());
  auto bad = check("b.nom", "point a (0 0 0) endpoint\nbspline3 s (a a a) endbspline5\n");
  EXPECT_TRUE(has(*bad, DiagKind::MismatchedEndKeyword));
}

TEST(Check, OverridesAndTheirRange) {
  std::string text = "bank fp set n 8 3 10 1 endbank\nfunnel f ({expr $fp_n} 1 0 1) endfunnel\n";
  CheckOptions opt;
  opt.overrides = {{"fp.n", 5}};
  auto c = check("f.nome", text, opt);
  EXPECT_EQ(c->diags.error_count(), 0);
  EXPECT_DOUBLE_EQ(field_value(*c, "f", "n", 0), 5);
  opt.overrides = {{"fp.n", 50}};
  EXPECT_TRUE(has(*check("f.nome", text, opt), DiagKind::OverrideOutOfRange));
  opt.allow_out_of_range = true;
  auto allowed = check("f.nome", text, opt);
  EXPECT_DOUBLE_EQ(field_value(*allowed, "f", "n", 0), 50);
  opt.overrides = {{"fp.nn", 5}};
  EXPECT_TRUE(has(*check("f.nome", text, opt), DiagKind::OverrideUnknown));
}

// An override that is not finite is refused even where out-of-range values are allowed
// (NaN is in no range, so it passed the range test); the slider keeps its value.
TEST(Check, OverridesThatAreNotFiniteAreRefused) {
  std::string text = "bank fp set n 8 3 10 1 endbank\nfunnel f ({expr $fp_n} 1 0 1) endfunnel\n";
  for (bool allowed : {false, true}) {
    for (double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
      CheckOptions opt;
      opt.allow_out_of_range = allowed;
      opt.overrides = {{"fp.n", bad}};
      auto c = check("f.nome", text, opt);
      ASSERT_EQ(c->diags.error_count(), 1);
      EXPECT_EQ(c->diags.diagnostics()[0].kind, DiagKind::OverrideOutOfRange);
      EXPECT_NE(c->diags.diagnostics()[0].message.find("is not a finite number; `fp.n` keeps 8"), std::string::npos)
          << c->diags.diagnostics()[0].message;
      EXPECT_DOUBLE_EQ(field_value(*c, "f", "n", 0), 8);
    }
  }
}

TEST(Check, SliderReachesTheInstancesItControls) {
  auto c = check("f.nome",
                 "bank fp set z 1 0 2 0.1 set n 8 3 10 1 endbank\n"
                 "funnel f ({expr $fp_n} 1 0 1) endfunnel\n"
                 "group g instance a f translate (0 0 {expr $fp_z}) endinstance\n"
                 "instance b f endinstance endgroup\n"
                 "instance top g endinstance\n");
  ASSERT_EQ(c->diags.error_count(), 0);
  const ir::Module& m = c->result.module;
  auto id_of = [&](std::string_view name) {
    for (size_t i = 0; i < m.nodes.size(); ++i) {
      if (m.nodes[i].name == name) return ir::NodeId{static_cast<int32_t>(i)};
    }
    return ir::NodeId::None();
  };
  auto names = [&](ir::NodeId from) {
    std::vector<std::string> out;
    for (ir::NodeId n : m.deps.affected_by(from)) {
      if (m.node(n).kind == ir::NodeKind::Instance) out.push_back(m.node(n).name);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  // `fp.z` moves only instance `a` (and everything containing it); `fp.n` reaches both
  // instances of the funnel.
  EXPECT_EQ(names(id_of("fp.z")), (std::vector<std::string>{"g.a", "top"}));
  EXPECT_EQ(names(id_of("fp.n")), (std::vector<std::string>{"g.a", "g.b", "top"}));
}

TEST(Check, UnderscoreJoinedVertexNames) {
  std::string scene =
      "funnel fun (8 1 0 1) endfunnel\n"
      "group cube instance fun3 fun endinstance instance fun5 fun endinstance endgroup\n"
      "instance cf cube endinstance\n";
  auto ok = check("s.nome", scene + "mesh m face f (cf_fun3_hc3 fun5_hc2 cf.fun3.hc4) endface endmesh\n");
  EXPECT_EQ(ok->diags.error_count(), 0);
  auto bad = check("s.nome", scene + "mesh m face f (cf_fun3_hc3 fun5_hc9 cf.fun3.hc4) endface endmesh\n");
  ASSERT_TRUE(has(*bad, DiagKind::UnknownVertex));
}

TEST(Check, RangesAreByteOffsetsInUtf8Text) {
  // The comment holds multi-byte characters before the error.
  std::string text = "# Möbius — band\npoint p (1 2) endpoint\n";
  auto c = check("u.nome", text);
  ASSERT_TRUE(has(*c, DiagKind::ListArity));
  const Diagnostic& d = c->diags.diagnostics()[0];
  EXPECT_EQ(text.substr(d.range.begin, d.range.end - d.range.begin), "(1 2)");
}

TEST(Check, InvalidUtf8AndNulBytesDoNotStopTheChecker) {
  std::string text = std::string("point p (1 2 3) endpoint\n\xff\xfe") + '\0' + "\npoint q (1 2 3) endpoint\n";
  auto c = check("bad.nome", text);
  EXPECT_TRUE(has(*c, DiagKind::UnexpectedCharacter));
  EXPECT_EQ(c->result.module.nodes.size(), 2u);
}

// `CheckOptions::parsed` is called once per check, after the parse and before the check:
// the parse's syntax errors are reported by then, the checker's unknown names not yet (the
// language server starts filling its parse cache there). A flat mesh file calls it too.
TEST(Check, ParsedIsCalledOnceBetweenTheParseAndTheCheck) {
  SourceManager sources;
  DiagnosticEngine diags;
  CheckOptions options;
  int calls = 0;
  std::vector<DiagKind> seen;
  options.parsed = [&] {
    ++calls;
    for (const Diagnostic& d : diags.diagnostics()) seen.push_back(d.kind);
  };
  check_source(sources, "a.nom", "point p (0 0 0) endpoint\ninstance i nowhere endinstance\npoint q (1 2 3 endpoint\n",
               options, diags);
  EXPECT_EQ(calls, 1);
  EXPECT_NE(std::find(seen.begin(), seen.end(), DiagKind::SyntaxError), seen.end());
  EXPECT_EQ(std::find(seen.begin(), seen.end(), DiagKind::UnknownName), seen.end());
  EXPECT_NE(std::find_if(diags.diagnostics().begin(), diags.diagnostics().end(),
                         [](const Diagnostic& d) { return d.kind == DiagKind::UnknownName; }),
            diags.diagnostics().end());

  calls = 0;
  DiagnosticEngine flat_diags;
  check_source(sources, "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", options, flat_diags);
  EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace nomec
