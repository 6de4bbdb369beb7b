// The module's stores and node kinds (see ir.h, nodes.h): adding nodes, expressions,
// operands and lists; names of kinds and enums; the function table.
#include <algorithm>
#include <fmt/format.h>

#include "ir/ir.h"

namespace nomec::ir {

namespace {

struct FuncInfo {
  Func func;
  std::string_view name;
  int arity;
  bool tcl_only = false;
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
    {Func::Double, "double", 1, true}, {Func::Int, "int", 1, true}, {Func::Wide, "wide", 1, true},
    {Func::Fmod, "fmod", 2, true},     {Func::Hypot, "hypot", 2, true}, {Func::Srand, "srand", 1, true},
};
constexpr std::string_view kFuncNames[] = {
    "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh", "sqrt", "abs",
    "exp", "log", "ln", "log10", "pow", "min", "max", "floor", "ceil", "round", "sign", "mod",
    "double", "int", "wide", "fmod", "hypot", "srand",
};
static_assert(std::size(kFuncs) == std::size(kFuncNames));

}  // namespace

std::string_view func_name(Func f) { return kFuncs[static_cast<int>(f)].name; }
int func_arity(Func f) { return kFuncs[static_cast<int>(f)].arity; }
bool func_is_tcl_only(Func f) { return kFuncs[static_cast<int>(f)].tcl_only; }
std::span<const std::string_view> func_names() { return kFuncNames; }
std::optional<Func> func_by_name(std::string_view name) {
  for (const FuncInfo& info : kFuncs) {
    if (info.name == name) return info.func;
  }
  return std::nullopt;
}

std::string_view node_kind_name(NodeKind kind) {
  switch (kind) {
#define NOMEC_IR_NODE(Kind, Payload, Name) \
  case NodeKind::Kind:                     \
    return Name;
#include "ir/node_kinds.def"
  }
  return "?";
}

void emplace_payload(Payload& data, NodeKind kind) {
  switch (kind) {
#define NOMEC_IR_NODE(Kind, Payload, Name) \
  case NodeKind::Kind:                     \
    data.emplace<Stored<Payload>>();       \
    return;
#include "ir/node_kinds.def"
  }
  data.emplace<std::monostate>();
}

bool is_block(NodeKind kind) {
  switch (kind) {
    case NodeKind::Merge:
    case NodeKind::Subdivision:
    case NodeKind::Offset:
    case NodeKind::Handle:
    case NodeKind::Rind:
    case NodeKind::Sierpinski:
    case NodeKind::Menger:
    case NodeKind::FaceReversal:
      return true;
    default:
      return false;
  }
}

std::string_view subdivision_rule_name(SubdivisionRule r) {
  switch (r) {
    case SubdivisionRule::CatmullClarkSharp: return "catmull-clark-sharp";
    case SubdivisionRule::CatmullClark: return "catmull-clark";
    case SubdivisionRule::DeRose: return "derose";
  }
  return "?";
}

std::string_view scene_color_name(SceneColorKind k) {
  switch (k) {
    case SceneColorKind::Front: return "front";
    case SceneColorKind::Back: return "back";
    case SceneColorKind::Background: return "background";
  }
  return "?";
}

std::string_view projection_name(Projection p) {
  switch (p) {
    case Projection::Parallel: return "parallel";
    case Projection::Perspective: return "perspective";
  }
  return "?";
}

std::string_view light_type_name(LightType t) {
  switch (t) {
    case LightType::Ambient: return "ambient";
    case LightType::Directional: return "directional";
    case LightType::Point: return "point";
    case LightType::Spot: return "spot";
  }
  return "?";
}

std::string_view offset_kind_name(OffsetKind k) {
  switch (k) {
    case OffsetKind::Plain: return "plain";
    case OffsetKind::Grid: return "grid";
  }
  return "?";
}

std::string_view flat_format_name(FlatFormat f) {
  switch (f) {
    case FlatFormat::Sif: return "sif";
    case FlatFormat::Obj: return "obj";
    case FlatFormat::Stl: return "stl";
  }
  return "?";
}

int32_t FlatMeshData::vertex_index(std::string_view name) const {
  if (geometry == nullptr || name.size() < 2 || name.size() > 11 || name[0] != 'v') return -1;
  int64_t k = 0;
  for (char ch : name.substr(1)) {
    if (ch < '0' || ch > '9') return -1;
    k = k * 10 + (ch - '0');
  }
  if (name.size() > 2 && name[1] == '0') return -1;  // `v01` is not a name the reader gives
  return k < static_cast<int64_t>(geometry->positions.size()) ? static_cast<int32_t>(k) : -1;
}

NodeId Module::add_node(NodeKind kind, std::string_view keyword, std::string name, SourceRange range,
                        NodeId parent) {
  Node& n = nodes.emplace_back();
  n.kind = kind;
  n.keyword = keyword;
  n.name = std::move(name);
  n.range = range;
  n.parent = parent;
  emplace_payload(n.data, kind);  // in place: no payload made and then moved
  NodeId id(static_cast<int32_t>(nodes.size() - 1));
  deps.resize(nodes.size());
  return id;
}

namespace {

void append_link(std::vector<Link>& links, LinkList& list, int32_t item) {
  const int32_t at = static_cast<int32_t>(links.size());
  links.push_back(Link{item, -1});
  if (list.last >= 0) {
    links[static_cast<size_t>(list.last)].next = at;
  } else {
    list.first = at;
  }
  list.last = at;
}

}  // namespace

void Module::add_child(NodeId parent, NodeId child) { append_link(links, nodes[parent.index].children, child.index); }

void Module::add_node_operand(NodeId owner, OperandId operand) {
  append_link(links, nodes[owner.index].operands, operand.index);
}

ExprId Module::add_expr(Expr expr) {
  exprs.push_back(std::move(expr));
  return ExprId(static_cast<int32_t>(exprs.size() - 1));
}

ExprId Module::add_call(Func func, std::span<const ExprId> args, SourceRange range) {
  Expr e;
  e.kind = ExprKind::Call;
  e.func = func;
  e.range = range;
  e.args = add_expr_list(args);
  return add_expr(e);
}

ExprId Module::add_external(uint32_t script, double value, std::span<const ExprId> params, SourceRange range) {
  Expr e;
  e.kind = ExprKind::External;
  e.range = range;
  e.external = static_cast<uint32_t>(externals.size());
  externals.push_back(ExternalScript{value, script, add_expr_list(params)});
  return add_expr(e);
}

Slice<ExprId> Module::add_expr_list(std::span<const ExprId> items) {
  Slice<ExprId> s{static_cast<uint32_t>(expr_lists.size()), static_cast<uint32_t>(items.size())};
  expr_lists.insert(expr_lists.end(), items.begin(), items.end());
  return s;
}

std::span<const ExprId> Module::subexprs(const Expr& e) const {
  switch (e.kind) {
    case ExprKind::Unary: return {e.operands, 1};
    case ExprKind::Binary: return {e.operands, 2};
    case ExprKind::Call: return refs(e.args);
    case ExprKind::External: return refs(externals[e.external].params);
    default: return {};
  }
}

OperandId Module::add_operand(Operand operand) {
  operands.push_back(std::move(operand));
  return OperandId(static_cast<int32_t>(operands.size() - 1));
}

Slice<VertexRef> Module::add_vertex_refs(std::vector<VertexRef> items) {
  Slice<VertexRef> s{static_cast<uint32_t>(vertex_refs.size()), static_cast<uint32_t>(items.size())};
  for (VertexRef& r : items) vertex_refs.push_back(std::move(r));
  return s;
}

Slice<NodeId> Module::add_node_refs(std::span<const NodeId> items) {
  Slice<NodeId> s{static_cast<uint32_t>(node_refs.size()), static_cast<uint32_t>(items.size())};
  node_refs.insert(node_refs.end(), items.begin(), items.end());
  return s;
}

const GenArgBinding* Module::gen_arg(NodeId id, ArgIndex arg) const {
  for (const GenArgBinding& b : refs(get<GeneratorData>(id).args)) {
    if (b.arg == arg) return &b;
  }
  return nullptr;
}

SmallVec<Slice<VertexRef>, 2> vertex_lists_of(const Module& m, const Node& n) {
  SmallVec<Slice<VertexRef>, 2> out;
  switch (n.kind) {
    case NodeKind::Face: out.push_back(n.as<FaceData>().vertices); break;
    case NodeKind::Polyline: out.push_back(n.as<PolylineData>().points); break;
    case NodeKind::Sharp:
      for (const Slice<VertexRef>& chain : m.refs(n.as<SharpData>().chains)) out.push_back(chain);
      break;
    case NodeKind::Zipper: {
      const ZipperData& z = n.as<ZipperData>();
      for (int32_t k = 0; k < std::min<int32_t>(z.border_count, 2); ++k) out.push_back(z.borders[k]);
      break;
    }
    default: break;
  }
  return out;
}

std::vector<NodeId> Module::params() const {
  std::vector<NodeId> out;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].kind == NodeKind::Param) out.push_back(NodeId(static_cast<int32_t>(i)));
  }
  return out;
}

NodeId Module::find_param(std::string_view bank, std::string_view name) const {
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Node& n = nodes[i];
    if (n.kind == NodeKind::Param && n.as<ParamData>().bank == bank && n.name == fmt::format("{}.{}", bank, name)) {
      return NodeId(static_cast<int32_t>(i));
    }
  }
  return NodeId::None();
}

}  // namespace nomec::ir
