// IR: dependency graph order, cycles, reachability and de-duplication; expression
// evaluation including domain errors, and external scripts through an `ExternalEvaluator`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <set>
#include <string>

#include "ir/ir.h"

namespace nomec::ir {
namespace {

NodeId add(Module& m, NodeKind kind, std::string name) { return m.add_node(kind, "", std::move(name), SourceRange{}); }

TEST(DepGraph, TopologicalOrderAndReachability) {
  Module m;
  NodeId p = add(m, NodeKind::Param, "b.p");
  NodeId v = add(m, NodeKind::Value, "pt.position");
  NodeId pt = add(m, NodeKind::Point, "pt");
  NodeId inst = add(m, NodeKind::Instance, "i");
  NodeId other = add(m, NodeKind::Instance, "j");
  m.deps.add_edge(p, v);
  m.deps.add_edge(v, pt);
  m.deps.add_edge(pt, inst);
  m.deps.add_edge(pt, inst);  // duplicate
  m.deps.add_edge(v, inst);
  m.deps.add_edge(pt, inst);  // non-adjacent duplicate, removed by finalize
  m.deps.finalize();
  EXPECT_EQ(m.deps.edge_count(), 4u);
  std::vector<NodeId> cycle;
  std::vector<NodeId> order = m.deps.topo_order(&cycle);
  EXPECT_TRUE(cycle.empty());
  auto pos = [&](NodeId n) { return std::find(order.begin(), order.end(), n) - order.begin(); };
  EXPECT_LT(pos(p), pos(v));
  EXPECT_LT(pos(v), pos(pt));
  EXPECT_LT(pos(pt), pos(inst));
  std::vector<NodeId> affected = m.deps.affected_by(p);
  EXPECT_EQ(affected, (std::vector<NodeId>{v, pt, inst}));
  EXPECT_TRUE(m.deps.affected_by(other).empty());
}

// After finalize every node's users are sorted and unique, whatever their number: the short
// lists (one or two users, sorted without a call to sort) and the long ones alike. Checked
// against a std::set of the same edges for lists of every length up to 6, in every order
// of insertion that a rotation and a reversal give, with duplicates.
TEST(DepGraph, UsersAreSortedAndUniqueForEveryListLength) {
  Module m;
  std::vector<NodeId> targets;
  for (int i = 0; i < 8; ++i) targets.push_back(add(m, NodeKind::Instance, "t" + std::to_string(i)));
  std::vector<std::pair<NodeId, std::set<int32_t>>> expected;
  for (int len = 1; len <= 6; ++len) {
    for (int rot = 0; rot < len; ++rot) {
      for (bool reverse : {false, true}) {
        NodeId from = add(m, NodeKind::Param, "p");
        std::vector<NodeId> to(targets.begin(), targets.begin() + len);
        std::rotate(to.begin(), to.begin() + rot, to.end());
        if (reverse) std::reverse(to.begin(), to.end());
        std::set<int32_t> want;
        for (NodeId t : to) {
          m.deps.add_edge(from, t);
          want.insert(t.index);
        }
        m.deps.add_edge(from, to.front());  // a duplicate, not adjacent when len > 1
        expected.push_back({from, want});
      }
    }
  }
  m.deps.finalize();
  for (const auto& [from, want] : expected) {
    std::vector<int32_t> got;
    for (NodeId u : m.deps.users(from)) got.push_back(u.index);
    EXPECT_EQ(got, std::vector<int32_t>(want.begin(), want.end())) << "users of node " << from.index;
  }
  for (NodeId t : targets) EXPECT_TRUE(m.deps.users(t).empty());
}

TEST(DepGraph, CyclesAreReported) {
  Module m;
  NodeId a = add(m, NodeKind::Group, "a");
  NodeId b = add(m, NodeKind::Group, "b");
  NodeId c = add(m, NodeKind::Instance, "c");
  m.deps.add_edge(a, b);
  m.deps.add_edge(b, a);
  m.deps.add_edge(c, a);
  std::vector<NodeId> cycle;
  m.deps.topo_order(&cycle);
  EXPECT_EQ(cycle, (std::vector<NodeId>{a, b}));
}

ExprId num(Module& m, double v) {
  Expr e;
  e.kind = ExprKind::Const;
  e.value = v;
  return m.add_expr(e);
}

ExprId bin(Module& m, char op, ExprId a, ExprId b) {
  Expr e;
  e.kind = ExprKind::Binary;
  e.op = op;
  e.operands[0] = a;
  e.operands[1] = b;
  return m.add_expr(e);
}

TEST(Evaluate, ArithmeticAndFunctions) {
  Module m;
  EXPECT_DOUBLE_EQ(evaluate(m, bin(m, '^', num(m, 2), bin(m, '^', num(m, 3), num(m, 2)))).value, 512);
  EXPECT_DOUBLE_EQ(evaluate(m, bin(m, 'i', num(m, 7), num(m, 2))).value, 3);
  const ExprId ones[] = {num(m, 1), num(m, 1)};
  EXPECT_NEAR(evaluate(m, m.add_call(Func::Atan2, ones, SourceRange{})).value, 0.7853981633974483, 1e-15);
  NodeId p = add(m, NodeKind::Param, "b.x");
  m.param(p).value = 4;
  Expr ref;
  ref.kind = ExprKind::Param;
  ref.param = p;
  EXPECT_DOUBLE_EQ(evaluate(m, bin(m, '*', m.add_expr(ref), num(m, 2))).value, 8);
}

// Generic walks (parameters read, whether a value depends on sliders, the caches' reads)
// see every kind's operands through `subexprs`: a unary's one, a binary's two, a call's
// arguments and an External's parameter references, which evaluation itself skips.
TEST(Module, SubexpressionsOfEachKind) {
  Module m;
  const ExprId two = num(m, 2), three = num(m, 3);
  Expr neg;
  neg.kind = ExprKind::Unary;
  neg.op = '-';
  neg.operands[0] = two;
  const ExprId minus_two = m.add_expr(neg);
  const ExprId sum = bin(m, '+', minus_two, three);
  const ExprId args[] = {sum, two, three};
  const ExprId call = m.add_call(Func::Max, args, SourceRange{});
  NodeId p = add(m, NodeKind::Param, "b.x");
  Expr ref;
  ref.kind = ExprKind::Param;
  ref.param = p;
  const ExprId reads[] = {m.add_expr(ref)};
  const ExprId script = m.add_external(0, 1, reads, SourceRange{});
  auto subs = [&](ExprId e) {
    std::span<const ExprId> s = m.subexprs(m.expr(e));
    return std::vector<ExprId>(s.begin(), s.end());
  };
  EXPECT_EQ(subs(minus_two), (std::vector<ExprId>{two}));
  EXPECT_EQ(subs(sum), (std::vector<ExprId>{minus_two, three}));
  EXPECT_EQ(subs(call), (std::vector<ExprId>{sum, two, three}));
  EXPECT_EQ(subs(script), (std::vector<ExprId>{reads[0]}));
  EXPECT_TRUE(subs(two).empty());
  EXPECT_TRUE(subs(reads[0]).empty());
  EXPECT_EQ(m.external_script(m.expr(script)).value, 1);
  EXPECT_DOUBLE_EQ(evaluate(m, call).value, 3);
  EXPECT_EQ(expr_text(m, call), "max(-2 + 3, 2, 3)");
}

// A node's children and operands are lists threaded through the module's `links`: each
// keeps the order it was built in however the lists of several nodes interleave.
TEST(Module, ChildrenAndOperandsKeepTheirOrder) {
  Module m;
  const NodeId mesh = add(m, NodeKind::Mesh, "m"), group = add(m, NodeKind::Group, "g");
  const NodeId p0 = add(m, NodeKind::Point, "m.p0"), inst = add(m, NodeKind::Instance, "g.i");
  const NodeId p1 = add(m, NodeKind::Point, "m.p1"), face = add(m, NodeKind::Face, "m.f");
  m.add_child(mesh, p0);
  m.add_child(group, inst);
  m.add_child(mesh, p1);
  m.add_child(mesh, face);
  auto children = [&](NodeId n) {
    std::vector<NodeId> out;
    for (NodeId k : m.children(m.node(n))) out.push_back(k);
    return out;
  };
  EXPECT_EQ(children(mesh), (std::vector<NodeId>{p0, p1, face}));
  EXPECT_EQ(children(group), (std::vector<NodeId>{inst}));
  EXPECT_TRUE(children(p0).empty());
  EXPECT_TRUE(m.children(m.node(face)).empty());
  const OperandId translate = m.add_operand(Operand{"translate", {}, {}, inst, {}});
  const OperandId position = m.add_operand(Operand{"position", {}, {}, p0, {}});
  const OperandId rotate = m.add_operand(Operand{"rotate", {}, {}, inst, {}});
  m.add_node_operand(inst, translate);
  m.add_node_operand(p0, position);
  m.add_node_operand(inst, rotate);
  std::vector<std::string_view> names;
  for (OperandId o : m.operands_of(m.node(inst))) names.push_back(m.operand(o).name);
  EXPECT_EQ(names, (std::vector<std::string_view>{"translate", "rotate"}));
  Module copy = m;  // copies keep the lists
  EXPECT_EQ(std::distance(copy.operands_of(copy.node(p0)).begin(), copy.operands_of(copy.node(p0)).end()), 1);
}

TEST(Evaluate, DomainErrorsNameTheValues) {
  Module m;
  EvalResult r = evaluate(m, bin(m, '/', num(m, 1), num(m, 0)));
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.problem, "division by zero: 1 / 0");
  const ExprId minus_four[] = {num(m, -4)};
  EvalResult s = evaluate(m, m.add_call(Func::Sqrt, minus_four, SourceRange{}));
  EXPECT_FALSE(s.ok);
  EXPECT_EQ(s.problem, "`sqrt(-4)`: square root of a negative number");
}

// `may_fail` says false only where `evaluate` cannot fail, and true only where some operand
// values make it fail: every function and operator over operands with awkward values
// (finite ones: no leaf of an expression is anything else), among them the largest and
// tiny ones, whose sums, products, quotients and exponentials overflow.
TEST(Evaluate, MayFailIsExactlyWhereEvaluationCanFail) {
  const double samples[] = {0, 1, -1, 2, -2, 0.5, 1e300, -1e300, 6.6, 1e-300, 1.7976931348623157e308, -1.7976931348623157e308};
  auto fails_somewhere = [&](auto make, size_t operands) {
    bool failed = false;
    for (double x : samples) {
      for (double y : samples) {
        Module m;
        const ExprId e = make(m, num(m, x), num(m, y));
        const bool fails = !evaluate(m, e).ok;
        EXPECT_FALSE(fails && !may_fail(m, m.expr(e))) << expr_text(m, e);
        failed = failed || fails;
        if (operands == 1) break;
      }
    }
    return failed;
  };
  for (char op : std::string("+-*/i%^")) {
    SCOPED_TRACE(std::string(1, op));
    const bool failed = fails_somewhere([&](Module& m, ExprId a, ExprId b) { return bin(m, op, a, b); }, 2);
    Module m;  // operands that are not constants
    const ExprId x = bin(m, '+', num(m, 1), num(m, 1));
    EXPECT_EQ(may_fail(m, m.expr(bin(m, op, x, x))), failed);
  }
  for (std::string_view name : func_names()) {
    SCOPED_TRACE(name);
    const Func f = *func_by_name(name);
    const size_t arity = func_arity(f) == 1 ? 1 : 2;
    auto call = [&](Module& m, ExprId a, ExprId b) {
      const ExprId args[] = {a, b};
      return m.add_call(f, std::span<const ExprId>(args, arity), SourceRange{});
    };
    const bool failed = fails_somewhere(call, arity);
    Module m;
    const ExprId x = bin(m, '+', num(m, 1), num(m, 1));
    EXPECT_EQ(may_fail(m, m.expr(call(m, x, x))), failed);
  }
  // A division by a constant of magnitude 1 or more, or a remainder by a non-zero constant,
  // cannot fail; by zero, by a smaller constant (it may overflow) or by a value, it may.
  // An operation on constants may fail exactly when it does.
  Module m;
  const ExprId x = bin(m, '+', num(m, 1), num(m, 1));
  EXPECT_FALSE(may_fail(m, m.expr(bin(m, '/', num(m, 1), num(m, 3)))));
  EXPECT_FALSE(may_fail(m, m.expr(bin(m, '/', x, num(m, -2)))));
  EXPECT_TRUE(may_fail(m, m.expr(bin(m, '/', x, num(m, 0.5)))));
  EXPECT_FALSE(may_fail(m, m.expr(bin(m, '%', x, num(m, 0.5)))));
  EXPECT_TRUE(may_fail(m, m.expr(bin(m, '/', num(m, 1), num(m, 0)))));
  EXPECT_TRUE(may_fail(m, m.expr(bin(m, '%', num(m, 1), bin(m, '-', num(m, 1), num(m, 1))))));
  EXPECT_FALSE(may_fail(m, m.expr(bin(m, '*', num(m, 1e200), num(m, 1e100)))));
  EXPECT_TRUE(may_fail(m, m.expr(bin(m, '*', num(m, 1e200), num(m, 1e200)))));
}

// `may_fail_now` (which decides whether the checker evaluates a value) says false only where
// evaluating the value now cannot fail: over random expressions of the operations that can
// only overflow, the bounded functions and operations on constants, with leaves from tiny to
// huge, every one it passes evaluates; and it passes most of those with moderate numbers.
TEST(Evaluate, MayFailNowIsSound) {
  std::mt19937 rng(45);
  const double magnitudes[] = {0, 1e-300, 0.5, 1, 3, 1e5, 1e40, 1e100, 1e154, 1e200, 1e300, 1.7e308};
  int passed = 0, moderate = 0, moderate_passed = 0;
  for (int round = 0; round < 20000; ++round) {
    Module m;
    const NodeId p = add(m, NodeKind::Param, "b.x");
    bool is_moderate = true;
    auto leaf = [&]() -> ExprId {
      double v = magnitudes[rng() % std::size(magnitudes)] * ((rng() & 1) != 0 ? -1 : 1);
      is_moderate = is_moderate && std::fabs(v) <= 1e5;
      if (rng() % 3 == 0) {
        m.param(p).value = v;
        Expr e;
        e.kind = ExprKind::Param;
        e.param = p;
        return m.add_expr(e);
      }
      return num(m, v);
    };
    std::function<ExprId(int)> tree = [&](int depth) -> ExprId {
      if (depth == 0 || rng() % 4 == 0) return leaf();
      switch (rng() % 9) {
        case 0: return bin(m, "+-*"[rng() % 3], tree(depth - 1), tree(depth - 1));
        case 1: return bin(m, "/i%"[rng() % 3], tree(depth - 1), num(m, (rng() & 1) != 0 ? 2.5 : -1));
        case 2: {
          const double power = static_cast<double>(rng() % 400);
          is_moderate = is_moderate && power <= 5;
          return bin(m, '^', num(m, 10), num(m, power));
        }
        case 3: {
          Expr neg;
          neg.kind = ExprKind::Unary;
          neg.op = '-';
          neg.operands[0] = tree(depth - 1);
          return m.add_expr(neg);
        }
        default: {
          static const Func one[] = {Func::Sin, Func::Cos, Func::Tan, Func::Tanh, Func::Atan, Func::Abs,
                                     Func::Floor, Func::Ceil, Func::Round, Func::Sign, Func::Double};
          static const Func two[] = {Func::Hypot, Func::Min, Func::Max, Func::Atan2};
          const bool binary_call = rng() % 3 == 0;
          const ExprId args[] = {tree(depth - 1), tree(depth - 1)};
          const Func f = binary_call ? two[rng() % std::size(two)] : one[rng() % std::size(one)];
          return m.add_call(f, std::span<const ExprId>(args, binary_call ? 2 : 1), SourceRange{});
        }
      }
    };
    const ExprId root = tree(4);
    const bool risky = may_fail_now(m, m.exprs);
    const EvalResult r = evaluate(m, root);
    if (!risky) {
      ++passed;
      ASSERT_TRUE(r.ok) << expr_text(m, root) << ": " << r.problem;
    }
    if (is_moderate) {
      ++moderate;
      moderate_passed += risky ? 0 : 1;
    }
  }
  EXPECT_GT(passed, 2000);
  EXPECT_GT(moderate_passed, moderate * 9 / 10);
  // By hand: the checker's usual values pass; large numbers, and operations on constants
  // with large results, do not.
  Module m;
  const NodeId p = add(m, NodeKind::Param, "b.r");
  m.param(p).value = 2;
  Expr r;
  r.kind = ExprKind::Param;
  r.param = p;
  const size_t first = m.exprs.size();
  const ExprId angle[] = {bin(m, '/', bin(m, '*', num(m, 2), num(m, 3.14159)), num(m, 8))};
  bin(m, '*', m.add_expr(r), m.add_call(Func::Cos, angle, SourceRange{}));
  auto since = [&](size_t from) { return std::span<const Expr>(m.exprs).subspan(from); };
  EXPECT_FALSE(may_fail_now(m, since(first)));
  m.param(p).value = 1e300;
  EXPECT_FALSE(may_fail_now(m, since(first)));  // times at most 1: cannot overflow
  const size_t second = m.exprs.size();
  bin(m, '*', m.add_expr(r), num(m, 1e10));
  EXPECT_TRUE(may_fail_now(m, since(second)));
  const size_t third = m.exprs.size();
  bin(m, '*', bin(m, '^', num(m, 10), num(m, 300)), num(m, 1e10));  // 10^300 has 3-digit operands
  EXPECT_TRUE(may_fail_now(m, since(third)));
  const size_t fourth = m.exprs.size();
  const ExprId radius[] = {m.add_expr(r)};
  m.add_call(Func::Sqrt, radius, SourceRange{});  // a domain of its own: always evaluated
  EXPECT_TRUE(may_fail_now(m, since(fourth)));
}

// No value is infinite or NaN: an operation whose result overflows fails at that operation,
// naming its operands, and so does a constant, slider value or script value that is not
// finite (the front end and the slider requests refuse those earlier; this is the last wall).
TEST(Evaluate, ResultsThatAreNotFiniteAreProblems) {
  Module m;
  const SourceRange where{FileId(0), 5, 12};
  auto with_range = [&](ExprId e) {
    m.exprs[static_cast<size_t>(e.index)].range = where;
    return e;
  };
  EvalResult product = evaluate(m, with_range(bin(m, '*', num(m, 1e200), num(m, 1e200))));
  EXPECT_FALSE(product.ok);
  EXPECT_EQ(product.problem, "1e+200 * 1e+200 is too large: numbers stop near 1.8e308");
  EXPECT_EQ(product.where, where);
  // Nested: the overflowing operation is named, not the whole expression.
  EvalResult nested = evaluate(m, bin(m, '-', num(m, 1), with_range(bin(m, '+', num(m, 1.5e308), num(m, 1.5e308)))));
  EXPECT_EQ(nested.problem, "1.5e+308 + 1.5e+308 is too large: numbers stop near 1.8e308");
  EXPECT_EQ(nested.where, where);
  EXPECT_EQ(evaluate(m, bin(m, '/', num(m, 1e300), num(m, 1e-300))).problem,
            "1e+300 / 1e-300 is too large: numbers stop near 1.8e308");
  EXPECT_EQ(evaluate(m, bin(m, '^', num(m, 10), num(m, 400))).problem, "10 ^ 400 is too large: numbers stop near 1.8e308");
  EXPECT_EQ(evaluate(m, bin(m, '^', num(m, 0), num(m, -1))).problem, "division by zero: 0 ^ -1");
  const ExprId thousand[] = {num(m, 1000)};
  EXPECT_EQ(evaluate(m, m.add_call(Func::Exp, thousand, SourceRange{})).problem,
            "`exp(1000)` is too large: numbers stop near 1.8e308");
  EXPECT_EQ(evaluate(m, m.add_call(Func::Cosh, thousand, SourceRange{})).problem,
            "`cosh(1000)` is too large: numbers stop near 1.8e308");
  // Leaves.
  EXPECT_EQ(evaluate(m, num(m, INFINITY)).problem, "inf is not a finite number");
  EXPECT_FALSE(evaluate(m, bin(m, '+', num(m, std::nan("")), num(m, 1))).ok);
  const NodeId p = add(m, NodeKind::Param, "b.x");
  m.param(p).value = -INFINITY;
  Expr ref;
  ref.kind = ExprKind::Param;
  ref.param = p;
  EXPECT_EQ(evaluate(m, m.add_expr(ref)).problem, "the slider's value (-inf) is not a finite number");
  // Finite results of large operands are kept.
  EXPECT_DOUBLE_EQ(evaluate(m, bin(m, '*', num(m, 1e200), num(m, 1e100))).value, 1e300);
}

// An evaluator of external scripts as the front end provides one: script 0 is twice its
// input, script 1 fails below 1.
class Twice final : public ExternalEvaluator {
 public:
  explicit Twice(NodeId p) : inputs_{p} {}
  std::span<const NodeId> inputs() const override { return inputs_; }
  ExternalResult evaluate(uint32_t script, std::span<const double> values) const override {
    if (script == 1 && values[0] < 1) return {0, false, "below 1"};
    return {values[0] * 2, true, {}};
  }
  std::string_view text(uint32_t script) const override { return script == 0 ? "expr {2*$x}" : "check"; }

 private:
  std::vector<NodeId> inputs_;
};

TEST(Evaluate, ExternalScriptsGetTheInputsCurrentValues) {
  Module m;
  NodeId p = add(m, NodeKind::Param, "b.x");
  m.param(p).value = 4;
  Expr dep;
  dep.kind = ExprKind::Param;
  dep.param = p;
  const ExprId reads[] = {m.add_expr(dep)};
  const SourceRange where{FileId(0), 3, 9};
  const ExprId twice = m.add_external(0, 8, reads, where);
  const ExprId checked = m.add_external(1, 4, reads, where);
  EvalResult none = evaluate(m, twice);  // no evaluator: an error, not a guess
  EXPECT_FALSE(none.ok);
  m.external = std::make_shared<Twice>(p);
  EXPECT_DOUBLE_EQ(evaluate(m, twice).value, 8);
  m.param(p).value = 0.5;
  EXPECT_DOUBLE_EQ(evaluate(m, twice).value, 1);
  EvalResult bad = evaluate(m, checked);
  EXPECT_FALSE(bad.ok);
  EXPECT_EQ(bad.problem, "below 1");
  EXPECT_EQ(bad.where.begin, 3u);
  EXPECT_EQ(bad.where.end, 9u);
  EXPECT_EQ(expr_text(m, twice), "tcl{expr {2*$x}}($b.x)");
}

}  // namespace
}  // namespace nomec::ir
