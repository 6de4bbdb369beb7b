// Typed IR of one checked NOME scene. Every node says what it is: a kind from
// node_kinds.def with a typed payload (ir/nodes.h), e.g. a `Subdivision` node with its rule
// resolved to `SubdivisionRule::DeRose` and its level as an operand, or a `Generator` node
// whose `GenKind` and arguments come from the generator catalogue. Expressions, operands,
// vertex references and node lists live in the module's stores, addressed by IDs. Lowered
// from the checked syntax tree by frontend/check; read by the backend (which switches on
// kinds, never on keywords), the language server and the incremental evaluator, through
// the parameter → value → node → instance dependency graph. Knows nothing of ANTLR or the
// kernel.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "base/id.h"
#include "base/small_vec.h"
#include "frontend/source/source_manager.h"
#include "ir/dialect.h"
#include "ir/external.h"
#include "ir/nodes.h"

namespace nomec::ir {

/// Math functions available in expressions (radians).
enum class Func : uint8_t {
  Sin, Cos, Tan, Asin, Acos, Atan, Atan2, Sinh, Cosh, Tanh, Sqrt, Abs, Exp, Log, Ln, Log10,
  Pow, Min, Max, Floor, Ceil, Round, Sign, Mod,
  // Tcl's `expr` functions that the list above lacks (SLIDE `{expr …}` values only):
  Double, Int, Wide, Fmod, Hypot, Srand,
};
std::string_view func_name(Func f);
std::optional<Func> func_by_name(std::string_view name);
/// True for the functions only Tcl's `expr` has (`double`, `int`, …): SLIDE files only.
bool func_is_tcl_only(Func f);
/// Number of arguments; -1 for variadic (min, max take at least one).
int func_arity(Func f);
/// Every function name, for "did you mean" hints.
std::span<const std::string_view> func_names();

enum class ExprKind : uint8_t {
  Const,     // `0.5`, `pi`
  Param,     // `$fp.n`, `$fp_n`, `fp.n`
  Builtin,   // `$time`, `$frame`
  Variable,  // `u` in a function surface's `funcX [cos(u)*v]`
  Unary,
  Binary,
  Call,
  External,  // a script the module's `external` evaluator computes (SLIDE's Tcl); see external.h
  Error,     // could not be checked; a diagnostic was emitted
};

/// A scalar expression, e.g. `{expr $fp_ro * 2}` = Binary('*', Param fp.ro, Const 2).
// Rationale: a scene has about one per syntax expression (108 000 in a 1 MiB scene), so an
// expression is 32 bytes: the members only one kind reads share a union, and a call's
// arguments are a slice of the module's `expr_lists` (as an operand's expressions are)
// instead of a vector in every expression. Read the union member of the expression's kind.
struct Expr {
  Expr() : value(0) {}

  SourceRange range;
  ExprKind kind = ExprKind::Error;
  char op = 0;            // Unary, Binary: + - * / % ^, 'i' for `//`
  Func func = Func::Sin;  // Call
  uint8_t variable = 0;   // Variable: its index among the function's variables
  union {
    double value;            // Const
    NodeId param;            // Param: the parameter node
    std::string_view name;   // Builtin: "time" / "frame"; Variable: its name (static text)
    ExprId operands[2];      // Unary: its operand; Binary: its left and right operands
    Slice<ExprId> args;      // Call: its arguments (Module::expr_lists)
    uint32_t external;       // External: its script (Module::externals)
  };

  ExprId lhs() const { return operands[0]; }
  ExprId rhs() const { return operands[1]; }
};
static_assert(sizeof(Expr) == 32, "an expression is 32 bytes (see the rationale above)");

/// The script of an `External` expression: its index in the module's `external` evaluator,
/// its value when the scene was checked, and `Param` expressions of the parameters it
/// depends on (what the dependency graph and the caches see; not evaluated, the script
/// reads them).
struct ExternalScript {
  double value = 0;
  uint32_t script = 0;
  Slice<ExprId> params;  // Module::expr_lists
};

/// One entry of a node's list of children or of operands (Node::children, Node::operands):
/// the child's or operand's index and the entry after it in Module::links (-1 at the end).
struct Link {
  int32_t item = -1;
  int32_t next = -1;
};

/// A node's children or operands in the order they were added, e.g.
/// `for (NodeId k : module.children(node))`. Reads the module's `links` by index, so adding
/// to the module while iterating is safe (the new entries may or may not be visited).
template <typename IdT>
class LinkRange {
 public:
  class iterator {
   public:
    using value_type = IdT;
    using difference_type = std::ptrdiff_t;
    using iterator_category = std::forward_iterator_tag;
    using pointer = void;
    using reference = IdT;
    iterator() = default;
    iterator(const std::vector<Link>* links, int32_t at) : links_(links), at_(at) {}
    IdT operator*() const { return IdT((*links_)[static_cast<size_t>(at_)].item); }
    iterator& operator++() {
      at_ = (*links_)[static_cast<size_t>(at_)].next;
      return *this;
    }
    iterator operator++(int) {
      iterator old = *this;
      ++*this;
      return old;
    }
    friend bool operator==(const iterator& a, const iterator& b) { return a.at_ == b.at_; }

   private:
    const std::vector<Link>* links_ = nullptr;
    int32_t at_ = -1;
  };
  LinkRange(const std::vector<Link>* links, int32_t first) : links_(links), first_(first) {}
  iterator begin() const { return {links_, first_}; }
  iterator end() const { return {links_, -1}; }
  bool empty() const { return first_ < 0; }

 private:
  const std::vector<Link>* links_;
  int32_t first_;
};

/// A checked scene.
struct Module {
  Dialect dialect = Dialect::Nome;
  /// Values of the built-ins `$time` and `$frame` (`--time`, `--frame`; 0 by default).
  double time = 0;
  double frame = 0;
  std::vector<Expr> exprs;
  std::vector<Node> nodes;
  std::vector<Operand> operands;
  /// The lists of expressions: calls' arguments, operands' expressions, external scripts'
  /// parameters (slices: `refs(expr.args)`).
  std::vector<ExprId> expr_lists;
  std::vector<ExternalScript> externals;
  /// The nodes' lists of children and of operands (Node::children, Node::operands).
  std::vector<Link> links;
  // Rationale: the lists of references a node holds (a face's vertices, an object's faces,
  // an instance's transforms, a generator's arguments) are slices of these shared arrays,
  // so payloads stay small and fixed-size and the whole scene is a handful of allocations;
  // a list is written once, when its statement is checked.
  std::vector<VertexRef> vertex_refs;
  std::vector<NodeId> node_refs;
  std::vector<TransformOp> transforms;
  std::vector<GenArgBinding> gen_args;
  std::vector<DeletedFace> deleted_faces;
  std::vector<Slice<VertexRef>> vertex_lists;
  std::vector<NodeId> scene;  // top-level visible instances and pipeline blocks
  DepGraph deps;
  /// Evaluates the `External` expressions (null when there are none); shared by copies.
  std::shared_ptr<const ExternalEvaluator> external;

  const Node& node(NodeId id) const { return nodes[id.index]; }
  LinkRange<NodeId> children(const Node& n) const { return {&links, n.children.first}; }
  LinkRange<OperandId> operands_of(const Node& n) const { return {&links, n.operands.first}; }
  /// Appends `child` to `parent`'s children, `operand` to `owner`'s operands.
  void add_child(NodeId parent, NodeId child);
  void add_node_operand(NodeId owner, OperandId operand);
  Node& node(NodeId id) { return nodes[id.index]; }
  const Expr& expr(ExprId id) const { return exprs[id.index]; }
  const Operand& operand(OperandId id) const { return operands[id.index]; }
  Operand& operand(OperandId id) { return operands[id.index]; }
  /// A node's payload, e.g. `module.get<InstanceData>(id)`; the node must be of that kind.
  template <typename T>
  const T& get(NodeId id) const {
    return nodes[id.index].as<T>();
  }
  template <typename T>
  T& get(NodeId id) {
    return nodes[id.index].as<T>();
  }
  /// A parameter's value and range.
  const ParamData& param(NodeId id) const { return get<ParamData>(id); }
  ParamData& param(NodeId id) { return get<ParamData>(id); }

  /// Adds a node of `kind` (with the default payload of that kind).
  NodeId add_node(NodeKind kind, std::string_view keyword, std::string name, SourceRange range,
                  NodeId parent = NodeId::None());
  ExprId add_expr(Expr expr);
  /// Adds a Call of `func` to `args`.
  ExprId add_call(Func func, std::span<const ExprId> args, SourceRange range);
  /// Adds an External expression: script `script` of the `external` evaluator, whose value
  /// was `value` when checked, reading the parameters of the `Param` expressions `params`.
  ExprId add_external(uint32_t script, double value, std::span<const ExprId> params, SourceRange range);
  OperandId add_operand(Operand operand);
  /// Appends `items` to `expr_lists` and returns their slice.
  Slice<ExprId> add_expr_list(std::span<const ExprId> items);
  /// Appends `items` to a store and returns their slice.
  Slice<VertexRef> add_vertex_refs(std::vector<VertexRef> items);
  Slice<NodeId> add_node_refs(std::span<const NodeId> items);

  std::span<const VertexRef> refs(Slice<VertexRef> s) const { return {vertex_refs.data() + s.begin, s.size}; }
  std::span<const NodeId> refs(Slice<NodeId> s) const { return {node_refs.data() + s.begin, s.size}; }
  std::span<const ExprId> refs(Slice<ExprId> s) const { return {expr_lists.data() + s.begin, s.size}; }
  /// The sub-expressions of `e`: a unary's operand, a binary's two, a call's arguments, an
  /// External's parameter references (which evaluation does not visit), none for a leaf.
  std::span<const ExprId> subexprs(const Expr& e) const;
  const ExternalScript& external_script(const Expr& e) const { return externals[e.external]; }
  std::span<const TransformOp> refs(Slice<TransformOp> s) const { return {transforms.data() + s.begin, s.size}; }
  std::span<const GenArgBinding> refs(Slice<GenArgBinding> s) const { return {gen_args.data() + s.begin, s.size}; }
  std::span<const DeletedFace> refs(Slice<DeletedFace> s) const { return {deleted_faces.data() + s.begin, s.size}; }
  std::span<const Slice<VertexRef>> refs(Slice<Slice<VertexRef>> s) const {
    return {vertex_lists.data() + s.begin, s.size};
  }

  /// The binding of generator argument `arg` on generator node `id`, or null when the file
  /// does not give it.
  const GenArgBinding* gen_arg(NodeId id, ArgIndex arg) const;
  /// Every parameter node, in declaration order.
  std::vector<NodeId> params() const;
  NodeId find_param(std::string_view bank, std::string_view name) const;
};

/// Every vertex list a node holds (a face's vertices, a polyline's points, a crease chain,
/// a zipper border), for code that visits vertex references whatever the node's kind.
SmallVec<Slice<VertexRef>, 2> vertex_lists_of(const Module& module, const Node& node);

/// Result of evaluating an expression: a value or a domain problem at a sub-expression.
struct EvalResult {
  double value = 0;
  bool ok = true;
  std::string problem;   // e.g. "division by zero"
  SourceRange where;
};
/// Evaluates with the module's current parameter values and its `time`/`frame`; `variables`
/// are the values of a function's variables (`u`, `v` …) by index. Iterative: expressions
/// of any depth are evaluated without deep recursion. A value is always finite: a result
/// that overflows (`1e200 * 1e200`, `exp(1000)`, `0 ^ -1`) or a leaf that is not finite is
/// a problem at that sub-expression.
EvalResult evaluate(const Module& module, ExprId expr, std::span<const double> variables = {});
/// False when `evaluate` cannot report a problem at expression `e` itself, whatever the
/// (finite) values of its operands: a finite constant, a parameter, a built-in, `-x`, an
/// operation on constants that evaluates, a division by a constant of magnitude 1 or more,
/// a remainder by a non-zero constant, or a call of a function that is finite wherever it
/// is defined (`sin`, `atan` …). True for the rest (`a + b`, `a * b` and `hypot(a, b)` of
/// values, which may overflow, `^`, `sqrt`, `log`, `exp`, a division by a value, a script,
/// a variable, an error).
bool may_fail(const Module& module, const Expr& e);
/// Whether evaluating now the expression made of exactly `nodes` (every operand of each
/// among them, e.g. the expressions the checker lowered for one value) may fail: some node
/// may fail for a reason other than overflow, or some may overflow and the current values
/// of its constants, sliders and built-ins are large enough for that (a bound: 1 + |value|
/// of a node is at most the product of 1 + |leaf| beneath it). `$r * cos(2 * pi / 8)` with
/// `r` at 2 cannot: the checker evaluates a new value only when this is true.
bool may_fail_now(const Module& module, std::span<const Expr> nodes);

/// The values of a viewing statement (camera, light, window, viewport, render) by field, with
/// the defaults it takes for those not written (marked "(default)"), e.g. `{"projection",
/// "perspective"}`, `{"frustum", "(-1 -1 -100) (1 1 -0.02) (default)"}`: for the dump and
/// hover. `with_ids`: references as `%3 `cam``, else as `` `cam` ``.
std::vector<std::pair<std::string, std::string>> scene_fields(const Module& module, const Node& node, bool with_ids);
/// Human-readable dump (`nomec --emit ir`).
std::string dump_ir(const Module& module, const SourceManager& sources);
/// The parameter -> instance graph as DOT (`nomec --emit deps`).
std::string dump_deps_dot(const Module& module);
/// Renders an expression as source-like text, e.g. `$fp.ro * 2`.
std::string expr_text(const Module& module, ExprId expr);

}  // namespace nomec::ir
