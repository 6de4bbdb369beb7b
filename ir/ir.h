// Typed IR of one checked NOME scene: parameters, expressions, and nodes (points, faces,
// meshes, generators, groups, instances with transform chains, pipeline blocks), all
// addressed by IDs. Lowered from the checked AST by frontend/check; read by the backend,
// the language server and the incremental evaluator. Knows nothing of ANTLR or the kernel.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "base/id.h"
#include "base/small_vec.h"
#include "frontend/source/source_manager.h"

namespace nomec::ir {

struct ExprTag;
struct NodeTag;
using ExprId = Id<ExprTag>;
using NodeId = Id<NodeTag>;

/// Math functions available in expressions (radians).
enum class Func : uint8_t {
  Sin, Cos, Tan, Asin, Acos, Atan, Atan2, Sinh, Cosh, Tanh, Sqrt, Abs, Exp, Log, Ln, Log10,
  Pow, Min, Max, Floor, Ceil, Round, Sign, Mod,
};
std::string_view func_name(Func f);
std::optional<Func> func_by_name(std::string_view name);
/// Number of arguments; -1 for variadic (min, max take at least one).
int func_arity(Func f);

enum class ExprKind : uint8_t {
  Const,    // `0.5`, `pi`
  Param,    // `$fp.n`, `$fp_n`, `fp.n`
  Builtin,  // `$time`, `$frame`
  Unary,
  Binary,
  Call,
  Error,    // could not be checked; a diagnostic was emitted
};

/// A scalar expression, e.g. `{expr $fp_ro * 2}` = Binary('*', Param fp.ro, Const 2).
struct Expr {
  ExprKind kind = ExprKind::Error;
  char op = 0;  // + - * / % ^, 'i' for `//`
  Func func = Func::Sin;
  double value = 0;
  NodeId param;      // Param node
  std::string_view name;  // Builtin: "time" / "frame" (static text)
  ExprId lhs;
  ExprId rhs;
  SmallVec<ExprId, 2> args;
  SourceRange range;
};

/// A vertex reference in a face, polyline or consolidate block: either a point node, or a
/// path through instances to a generated/mesh vertex (`fun3.hc3`, 2016 `cf_fun3_hc3`).
struct VertexRef {
  std::string text;               // as written
  NodeId point;                   // resolved point, if it names a point
  std::vector<NodeId> instances;  // resolved instance chain, outermost first
  std::string vertex;             // vertex name inside the innermost instance target
  SourceRange range;
};

enum class FieldKind : uint8_t {
  Scalar,    // one expression
  Vector,    // several expressions, e.g. a point position or a transform argument
  Ref,       // a named node (surface, path, cross section, target)
  Refs,      // a list of named nodes
  Vertices,  // vertex references
  Flag,      // a word present, e.g. `closed`, `hidden`, `mintorsion`
  Text,      // a symbolic value or raw text, e.g. `NOME_SD_CC_sharp`, `[u*v]`
};

/// A named, typed argument of a node, e.g. `n` of a funnel or `translate` of an instance.
struct Field {
  std::string name;
  FieldKind kind = FieldKind::Scalar;
  SmallVec<ExprId, 4> exprs;
  SmallVec<NodeId, 2> refs;
  std::vector<VertexRef> vertices;
  std::string text;
  SourceRange range;
  NodeId value_node;  // the Value node of this field when it depends on parameters
};

enum class NodeKind : uint8_t {
#define NOMEC_IR_NODE(Kind, Name) Kind,
#include "ir/node_kinds.def"
};
std::string_view node_kind_name(NodeKind kind);

/// One IR node. Examples: Param `fp.n`; Generator `funnel fun`; Instance `cf.fun1` whose
/// target is the Generator and whose `fields` hold the transform chain in written order.
struct Node {
  NodeKind kind = NodeKind::Value;
  std::string_view keyword;  // source statement, e.g. "funnel", "instance" (static text)
  std::string name;     // qualified name, e.g. "cubeMadeByFunnel.fun1"; "" if anonymous
  SourceRange range;
  NodeId parent;                // enclosing mesh/group/pipeline
  std::vector<NodeId> children; // mesh points/faces, group/pipeline instances
  NodeId target;                // Instance: the instanced node
  std::vector<Field> fields;
  bool is_hidden = false;
  // Param only.
  double value = 0, min = 0, max = 0, step = 0;
  std::string bank;
  // Value only: the field owner and the expression.
  NodeId owner;
};

/// The dependency graph: an edge A -> B means B must be re-evaluated when A changes
/// (parameter -> value -> point -> face -> mesh -> instance -> group …).
class DepGraph {
 public:
  /// Makes room for nodes 0..n-1 (the graph only grows).
  void resize(size_t n) {
    if (n > last_to_.size()) last_to_.resize(n, -1);
  }
  void reserve(size_t n) { last_to_.reserve(n); }
  void add_edge(NodeId from, NodeId to);
  /// Sorts every adjacency list and removes duplicate edges; call once after building, and
  /// before sharing the graph between threads (the queries below build their arrays lazily).
  void finalize();
  std::span<const NodeId> users(NodeId n) const {
    compact();
    return {items_.data() + begin_[n.index], items_.data() + begin_[n.index + 1]};
  }
  size_t node_count() const { return last_to_.size(); }
  size_t edge_count() const {
    compact();
    return items_.size();
  }
  /// Kahn's topological order; nodes on cycles are returned in `cycle_nodes` instead.
  std::vector<NodeId> topo_order(std::vector<NodeId>* cycle_nodes = nullptr) const;
  /// Every node reachable from `start` (excluding `start`), in topological order.
  std::vector<NodeId> affected_by(NodeId start) const;

 private:
  // Rationale: edges are appended to one array while the checker builds the graph (no
  // allocation per node: a large scene has tens of thousands), and turned into compressed
  // adjacency arrays (CSR: users of n are items_[begin_[n] .. begin_[n+1]]) on first query.
  // `finalize` also sorts each list and removes duplicates (O(E log E)), so counts in
  // `--emit deps` and re-evaluation counts are exact without a search per insertion.
  void compact() const;
  std::vector<std::pair<int32_t, int32_t>> edges_;  // (from, to) in insertion order
  std::vector<int32_t> last_to_;                    // per node: the last `to` added from it
  bool sorted_ = false;                             // finalize() was called
  mutable bool stale_ = true;                       // begin_/items_ lag behind edges_
  mutable std::vector<uint32_t> begin_;
  mutable std::vector<NodeId> items_;
};

/// A checked scene.
struct Module {
  std::string dialect;
  /// Values of the built-ins `$time` and `$frame` (`--time`, `--frame`; 0 by default).
  double time = 0;
  double frame = 0;
  std::vector<Expr> exprs;
  std::vector<Node> nodes;
  std::vector<NodeId> scene;  // top-level visible instances and pipeline blocks
  DepGraph deps;

  const Node& node(NodeId id) const { return nodes[id.index]; }
  Node& node(NodeId id) { return nodes[id.index]; }
  const Expr& expr(ExprId id) const { return exprs[id.index]; }
  NodeId add_node(Node node);
  ExprId add_expr(Expr expr);
  /// Every parameter node, in declaration order.
  std::vector<NodeId> params() const;
  NodeId find_param(std::string_view bank, std::string_view name) const;
};

/// Result of evaluating an expression: a value or a domain problem at a sub-expression.
struct EvalResult {
  double value = 0;
  bool ok = true;
  std::string problem;   // e.g. "division by zero"
  SourceRange where;
};
/// Evaluates with the module's current parameter values and its `time`/`frame`.
EvalResult evaluate(const Module& module, ExprId expr);

/// Human-readable dump (`nomec --emit ir`).
std::string dump_ir(const Module& module, const SourceManager& sources);
/// The parameter -> instance graph as DOT (`nomec --emit deps`).
std::string dump_deps_dot(const Module& module);
/// Renders an expression as source-like text, e.g. `$fp.ro * 2`.
std::string expr_text(const Module& module, ExprId expr);

}  // namespace nomec::ir
