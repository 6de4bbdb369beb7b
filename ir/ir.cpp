// IR implementation: function table, dependency graph algorithms, evaluation, dumps.
#include "ir/ir.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <map>

namespace nomec::ir {

namespace {
struct FuncInfo {
  Func func;
  std::string_view name;
  int arity;
};
constexpr FuncInfo kFuncs[] = {
    {Func::Sin, "sin", 1},     {Func::Cos, "cos", 1},     {Func::Tan, "tan", 1},
    {Func::Asin, "asin", 1},   {Func::Acos, "acos", 1},   {Func::Atan, "atan", 1},
    {Func::Atan2, "atan2", 2}, {Func::Sinh, "sinh", 1},   {Func::Cosh, "cosh", 1},
    {Func::Tanh, "tanh", 1},   {Func::Sqrt, "sqrt", 1},   {Func::Abs, "abs", 1},
    {Func::Exp, "exp", 1},     {Func::Log, "log", 1},     {Func::Ln, "ln", 1},
    {Func::Log10, "log10", 1}, {Func::Pow, "pow", 2},     {Func::Min, "min", -1},
    {Func::Max, "max", -1},    {Func::Floor, "floor", 1}, {Func::Ceil, "ceil", 1},
    {Func::Round, "round", 1}, {Func::Sign, "sign", 1},   {Func::Mod, "mod", 2},
};
}  // namespace

std::string_view func_name(Func f) { return kFuncs[static_cast<int>(f)].name; }
int func_arity(Func f) { return kFuncs[static_cast<int>(f)].arity; }
std::optional<Func> func_by_name(std::string_view name) {
  for (const FuncInfo& info : kFuncs) {
    if (info.name == name) {
      return info.func;
    }
  }
  return std::nullopt;
}

std::string_view node_kind_name(NodeKind kind) {
  switch (kind) {
#define NOMEC_IR_NODE(Kind, Name) \
  case NodeKind::Kind:            \
    return Name;
#include "ir/node_kinds.def"
  }
  return "?";
}

void DepGraph::add_edge(NodeId from, NodeId to) {
  if (!from.is_valid() || !to.is_valid() || from == to) {
    return;
  }
  resize(static_cast<size_t>(std::max(from.index, to.index)) + 1);
  // Duplicates are removed in `finalize`; skipping the common repeat here keeps lists short.
  if (last_to_[from.index] == to.index) {
    return;
  }
  last_to_[from.index] = to.index;
  edges_.emplace_back(from.index, to.index);
  stale_ = true;
}

void DepGraph::finalize() {
  sorted_ = true;
  stale_ = true;
  compact();
}

void DepGraph::compact() const {
  if (!stale_) {
    return;
  }
  const size_t n = last_to_.size();
  begin_.assign(n + 1, 0);
  for (const auto& [from, to] : edges_) {
    ++begin_[static_cast<size_t>(from) + 1];
  }
  for (size_t i = 0; i < n; ++i) {
    begin_[i + 1] += begin_[i];
  }
  items_.assign(edges_.size(), NodeId{});
  std::vector<uint32_t> fill(begin_.begin(), begin_.end() - 1);
  for (const auto& [from, to] : edges_) {  // stable: each list keeps insertion order
    items_[fill[from]++] = NodeId{to};
  }
  if (sorted_) {
    // Sort and deduplicate each list, then close the gaps left by removed duplicates.
    uint32_t out = 0;
    for (size_t i = 0; i < n; ++i) {
      auto first = items_.begin() + begin_[i];
      auto last = items_.begin() + begin_[i + 1];
      std::sort(first, last, [](NodeId a, NodeId b) { return a.index < b.index; });
      last = std::unique(first, last);
      begin_[i] = out;
      out = static_cast<uint32_t>(std::move(first, last, items_.begin() + out) - items_.begin());
    }
    begin_[n] = out;
    items_.resize(out);
  }
  stale_ = false;
}

std::vector<NodeId> DepGraph::topo_order(std::vector<NodeId>* cycle_nodes) const {
  compact();
  const size_t count = node_count();
  std::vector<int> indegree(count, 0);
  for (NodeId to : items_) {
    ++indegree[to.index];
  }
  std::vector<NodeId> order;
  order.reserve(count);
  std::vector<NodeId> ready;
  for (size_t i = count; i-- > 0;) {
    if (indegree[i] == 0) {
      ready.push_back(NodeId{static_cast<int32_t>(i)});
    }
  }
  while (!ready.empty()) {
    NodeId n = ready.back();
    ready.pop_back();
    order.push_back(n);
    for (NodeId to : users(n)) {
      if (--indegree[to.index] == 0) {
        ready.push_back(to);
      }
    }
  }
  if (cycle_nodes != nullptr) {
    cycle_nodes->clear();
    for (size_t i = 0; i < count; ++i) {
      if (indegree[i] > 0) {
        cycle_nodes->push_back(NodeId{static_cast<int32_t>(i)});
      }
    }
  }
  return order;
}

std::vector<NodeId> DepGraph::affected_by(NodeId start) const {
  std::vector<char> seen(node_count(), 0);
  std::vector<NodeId> stack{start};
  seen[start.index] = 1;
  while (!stack.empty()) {
    NodeId n = stack.back();
    stack.pop_back();
    for (NodeId to : users(n)) {
      if (!seen[to.index]) {
        seen[to.index] = 1;
        stack.push_back(to);
      }
    }
  }
  seen[start.index] = 0;
  std::vector<NodeId> out;
  for (NodeId n : topo_order()) {
    if (seen[n.index]) {
      out.push_back(n);
    }
  }
  return out;
}

NodeId Module::add_node(Node node) {
  nodes.push_back(std::move(node));
  NodeId id{static_cast<int32_t>(nodes.size() - 1)};
  deps.resize(nodes.size());
  return id;
}

ExprId Module::add_expr(Expr expr) {
  exprs.push_back(std::move(expr));
  return ExprId{static_cast<int32_t>(exprs.size() - 1)};
}

std::vector<NodeId> Module::params() const {
  std::vector<NodeId> out;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].kind == NodeKind::Param) {
      out.push_back(NodeId{static_cast<int32_t>(i)});
    }
  }
  return out;
}

NodeId Module::find_param(std::string_view bank, std::string_view name) const {
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Node& n = nodes[i];
    if (n.kind == NodeKind::Param && n.bank == bank && n.name == fmt::format("{}.{}", bank, name)) {
      return NodeId{static_cast<int32_t>(i)};
    }
  }
  return NodeId::None();
}

namespace {

EvalResult fail(std::string problem, SourceRange where) {
  EvalResult r;
  r.ok = false;
  r.problem = std::move(problem);
  r.where = where;
  return r;
}

EvalResult eval(const Module& m, ExprId id, double time, double frame) {
  const Expr& e = m.expr(id);
  switch (e.kind) {
    case ExprKind::Const:
      return {e.value};
    case ExprKind::Param:
      return {m.node(e.param).value};
    case ExprKind::Builtin:
      return {e.name == "time" ? time : frame};
    case ExprKind::Error:
      return fail("", e.range);
    case ExprKind::Unary: {
      EvalResult a = eval(m, e.lhs, time, frame);
      if (!a.ok) {
        return a;
      }
      return {e.op == '-' ? -a.value : a.value};
    }
    case ExprKind::Binary: {
      EvalResult a = eval(m, e.lhs, time, frame);
      if (!a.ok) {
        return a;
      }
      EvalResult b = eval(m, e.rhs, time, frame);
      if (!b.ok) {
        return b;
      }
      switch (e.op) {
        case '+':
          return {a.value + b.value};
        case '-':
          return {a.value - b.value};
        case '*':
          return {a.value * b.value};
        case '/':
          if (b.value == 0) {
            return fail(fmt::format("division by zero: {} / 0", a.value), e.range);
          }
          return {a.value / b.value};
        case 'i':
          if (b.value == 0) {
            return fail(fmt::format("division by zero: {} // 0", a.value), e.range);
          }
          return {std::floor(a.value / b.value)};
        case '%':
          if (b.value == 0) {
            return fail(fmt::format("remainder by zero: {} % 0", a.value), e.range);
          }
          return {std::fmod(a.value, b.value)};
        case '^': {
          double r = std::pow(a.value, b.value);
          if (std::isnan(r)) {
            return fail(fmt::format("{} ^ {} has no real value", a.value, b.value), e.range);
          }
          return {r};
        }
        default:
          return fail("unknown operator", e.range);
      }
    }
    case ExprKind::Call: {
      std::vector<double> v;
      for (ExprId arg : e.args) {
        EvalResult r = eval(m, arg, time, frame);
        if (!r.ok) {
          return r;
        }
        v.push_back(r.value);
      }
      auto need = [&](bool ok, const char* what) -> std::optional<EvalResult> {
        if (!ok) {
          return fail(fmt::format("`{}({})`: {}", func_name(e.func),
                                  fmt::join(v, ", "), what),
                      e.range);
        }
        return std::nullopt;
      };
      double x = v.empty() ? 0 : v[0];
      switch (e.func) {
        case Func::Sin: return {std::sin(x)};
        case Func::Cos: return {std::cos(x)};
        case Func::Tan: return {std::tan(x)};
        case Func::Asin:
          if (auto f = need(x >= -1 && x <= 1, "argument outside [-1, 1]")) return *f;
          return {std::asin(x)};
        case Func::Acos:
          if (auto f = need(x >= -1 && x <= 1, "argument outside [-1, 1]")) return *f;
          return {std::acos(x)};
        case Func::Atan: return {std::atan(x)};
        case Func::Atan2: return {std::atan2(v[0], v[1])};
        case Func::Sinh: return {std::sinh(x)};
        case Func::Cosh: return {std::cosh(x)};
        case Func::Tanh: return {std::tanh(x)};
        case Func::Sqrt:
          if (auto f = need(x >= 0, "square root of a negative number")) return *f;
          return {std::sqrt(x)};
        case Func::Abs: return {std::fabs(x)};
        case Func::Exp: return {std::exp(x)};
        case Func::Log:
        case Func::Ln:
          if (auto f = need(x > 0, "logarithm of a number that is not positive")) return *f;
          return {std::log(x)};
        case Func::Log10:
          if (auto f = need(x > 0, "logarithm of a number that is not positive")) return *f;
          return {std::log10(x)};
        case Func::Pow: {
          double r = std::pow(v[0], v[1]);
          if (auto f = need(!std::isnan(r), "no real value")) return *f;
          return {r};
        }
        case Func::Min: return {*std::min_element(v.begin(), v.end())};
        case Func::Max: return {*std::max_element(v.begin(), v.end())};
        case Func::Floor: return {std::floor(x)};
        case Func::Ceil: return {std::ceil(x)};
        case Func::Round: return {std::round(x)};
        case Func::Sign: return {static_cast<double>((x > 0) - (x < 0))};
        case Func::Mod:
          if (auto f = need(v[1] != 0, "remainder by zero")) return *f;
          return {std::fmod(v[0], v[1])};
      }
      return fail("unknown function", e.range);
    }
  }
  return fail("", e.range);
}

}  // namespace

EvalResult evaluate(const Module& module, ExprId expr) {
  return eval(module, expr, module.time, module.frame);
}

namespace {
int precedence(const Expr& e) {
  switch (e.kind) {
    case ExprKind::Binary:
      return e.op == '+' || e.op == '-' ? 1 : e.op == '^' ? 4 : 2;
    case ExprKind::Unary:
      return 3;
    default:
      return 5;
  }
}
}  // namespace

std::string expr_text(const Module& m, ExprId id) {
  const Expr& e = m.expr(id);
  auto sub = [&](ExprId c, int min_prec) {
    std::string s = expr_text(m, c);
    return precedence(m.expr(c)) < min_prec ? "(" + s + ")" : s;
  };
  switch (e.kind) {
    case ExprKind::Const:
      return fmt::format("{}", e.value);
    case ExprKind::Param:
      return "$" + m.node(e.param).name;
    case ExprKind::Builtin:
      return "$" + std::string(e.name);
    case ExprKind::Error:
      return "<error>";
    case ExprKind::Unary:
      return std::string(1, e.op) + sub(e.lhs, 3);
    case ExprKind::Binary: {
      int p = precedence(e);
      std::string op = e.op == 'i' ? "//" : std::string(1, e.op);
      if (e.op == '^') {
        return sub(e.lhs, 5) + " ^ " + sub(e.rhs, 3);
      }
      return sub(e.lhs, p) + " " + op + " " + sub(e.rhs, p + 1);
    }
    case ExprKind::Call: {
      std::vector<std::string> args;
      for (ExprId a : e.args) {
        args.push_back(expr_text(m, a));
      }
      return fmt::format("{}({})", func_name(e.func), fmt::join(args, ", "));
    }
  }
  return "?";
}

namespace {

std::string node_ref(const Module& m, NodeId id) {
  if (!id.is_valid()) {
    return "<none>";
  }
  const Node& n = m.node(id);
  return n.name.empty() ? fmt::format("%{}", id.index) : fmt::format("%{} `{}`", id.index, n.name);
}

bool depends_on_input(const Module& m, ExprId id) {
  const Expr& e = m.expr(id);
  if (e.kind == ExprKind::Param || e.kind == ExprKind::Builtin) {
    return true;
  }
  for (ExprId c : {e.lhs, e.rhs}) {
    if (c.is_valid() && depends_on_input(m, c)) {
      return true;
    }
  }
  for (ExprId c : e.args) {
    if (depends_on_input(m, c)) {
      return true;
    }
  }
  return false;
}

// An expression with its current value when it depends on sliders; constants print as
// their value.
std::string value_text(const Module& m, ExprId id) {
  std::string text = expr_text(m, id);
  if (!depends_on_input(m, id)) {
    EvalResult r = evaluate(m, id);
    return r.ok ? fmt::format("{}", r.value) : text;
  }
  EvalResult r = evaluate(m, id);
  return r.ok ? fmt::format("{{{} = {}}}", text, r.value) : fmt::format("{{{}}}", text);
}

std::string field_text(const Module& m, const Field& f) {
  std::vector<std::string> parts;
  switch (f.kind) {
    case FieldKind::Scalar:
    case FieldKind::Vector:
      for (ExprId e : f.exprs) {
        parts.push_back(value_text(m, e));
      }
      if (f.name == "rotate" && parts.size() == 4) {  // axis, then angle in degrees
        return fmt::format("({} {} {}) ({})", parts[0], parts[1], parts[2], parts[3]);
      }
      return f.kind == FieldKind::Scalar && parts.size() == 1
                 ? parts[0]
                 : fmt::format("({})", fmt::join(parts, " "));
    case FieldKind::Ref:
    case FieldKind::Refs:
      for (NodeId r : f.refs) {
        parts.push_back(node_ref(m, r));
      }
      return f.kind == FieldKind::Ref && parts.size() == 1
                 ? parts[0]
                 : fmt::format("({})", fmt::join(parts, " "));
    case FieldKind::Vertices:
      for (const VertexRef& v : f.vertices) {
        if (v.point.is_valid()) {
          parts.push_back(fmt::format("%{}", v.point.index));
        } else {
          std::vector<std::string> chain;
          for (NodeId i : v.instances) {
            chain.push_back(fmt::format("%{}", i.index));
          }
          parts.push_back(fmt::format("{}.{}", fmt::join(chain, "."), v.vertex));
        }
      }
      return fmt::format("({})", fmt::join(parts, " "));
    case FieldKind::Flag:
      return "";
    case FieldKind::Text:
      return f.text;
  }
  return "";
}

}  // namespace

std::string dump_ir(const Module& m, const SourceManager& sources) {
  std::string out = fmt::format("module dialect={} nodes={} exprs={} edges={}\n", m.dialect,
                                m.nodes.size(), m.exprs.size(), m.deps.edge_count());
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    const Node& n = m.nodes[i];
    if (n.kind == NodeKind::Value) {
      continue;  // shown through their fields
    }
    std::string loc;
    if (n.range.is_valid()) {
      LineCol lc = sources.line_col(n.range.file, n.range.begin);
      loc = fmt::format("  # {}:{}", lc.line, lc.column);
    }
    if (n.kind == NodeKind::Param) {
      out += fmt::format("%{} = param `{}` {} in [{}, {}] step {}{}\n", i, n.name, n.value,
                         n.min, n.max, n.step, loc);
      continue;
    }
    out += fmt::format("%{} = {} {}", i, n.keyword,
                       n.name.empty() ? std::string("<anonymous>") : "`" + n.name + "`");
    if (n.parent.is_valid()) {
      out += fmt::format(" in %{}", n.parent.index);
    }
    if (n.target.is_valid()) {
      out += " -> " + node_ref(m, n.target);
    }
    if (n.is_hidden) {
      out += " hidden";
    }
    out += loc + "\n";
    for (const Field& f : n.fields) {
      std::string text = field_text(m, f);
      out += fmt::format("    {}{}{}\n", f.name, text.empty() ? "" : " ", text);
    }
  }
  std::vector<std::string> scene;
  for (NodeId s : m.scene) {
    scene.push_back(fmt::format("%{}", s.index));
  }
  out += fmt::format("scene ({})\n", fmt::join(scene, " "));
  return out;
}

std::string dump_deps_dot(const Module& m) {
  std::string out = "digraph deps {\n  rankdir=LR;\n";
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    const Node& n = m.nodes[i];
    std::string label = n.kind == NodeKind::Value
                            ? fmt::format("value {}", n.name)
                            : fmt::format("{} {}", n.kind == NodeKind::Param ? "param" : n.keyword,
                                          n.name);
    const char* shape = n.kind == NodeKind::Param      ? "ellipse"
                        : n.kind == NodeKind::Value    ? "plaintext"
                        : n.kind == NodeKind::Instance ? "box"
                                                       : "component";
    out += fmt::format("  n{} [label=\"{}\", shape={}];\n", i, label, shape);
  }
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    for (NodeId to : m.deps.users(NodeId{static_cast<int32_t>(i)})) {
      out += fmt::format("  n{} -> n{};\n", i, to.index);
    }
  }
  out += "}\n";
  return out;
}

}  // namespace nomec::ir
