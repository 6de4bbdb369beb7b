// Vertex references and deleted faces through instance paths (see handlers.h; language.md
// §5.1): a point of the current mesh, a global point, a dotted path through instances
// (`inst.v`, `.inst.sub.v`), or a 2016 `_`-joined one (`inst_sub_v`, which may omit the
// outer instances: `fun3_hc3` for `cf.fun3.hc3`). The last part names a vertex of the
// innermost instance's target: a generator's vertex (by the catalogue's naming), or a point
// of a mesh or polyline. A `delete` entry names a face the same way.
#include <algorithm>
#include <cctype>
#include <fmt/format.h>
#include <functional>
#include <set>

#include "frontend/check/handlers.h"

namespace nomec::check {

namespace {

// The instance named `name` directly inside `owner`'s scope (None = the top level).
ir::NodeId instance_in(const Context& c, const std::string& name, ir::NodeId owner) {
  auto it = c.instance_scopes.find(owner.index + 1);
  if (it == c.instance_scopes.end()) return ir::NodeId::None();
  auto j = it->second.find(name);
  return j == it->second.end() ? ir::NodeId::None() : j->second;
}

// The instance named `name` inside the target of instance `inst` (a group or block).
ir::NodeId child_instance(Context& c, ir::NodeId inst, const std::string& name) {
  ir::NodeId target = c.module().get<ir::InstanceData>(inst).target;
  return target.is_valid() ? instance_in(c, name, target) : ir::NodeId::None();
}

bool all_digits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char ch) { return std::isdigit(static_cast<unsigned char>(ch)); });
}

// A whole number written with digits only, saturated at 2^30 (indices beyond any mesh).
long index_of(std::string_view digits) {
  long v = 0;
  for (char ch : digits) {
    v = std::min<long>(v * 10 + (ch - '0'), 1L << 30);
  }
  return v;
}

std::string_view without_leading_dot(std::string_view s) { return s.starts_with('.') ? s.substr(1) : s; }

// Does a mesh, polyline or one of its children write vertex `vertex` (a point name, or a
// reference as written)?
bool mentions_vertex(const ir::Module& m, ir::NodeId n, const std::string& vertex, int depth = 0) {
  const ir::Node& node = m.node(n);
  auto in = [&](ir::Slice<ir::VertexRef> s) {
    return std::any_of(m.refs(s).begin(), m.refs(s).end(),
                       [&](const ir::VertexRef& v) { return without_leading_dot(v.text) == without_leading_dot(vertex); });
  };
  switch (node.kind) {
    case ir::NodeKind::Face:
      if (in(node.as<ir::FaceData>().vertices)) return true;
      break;
    case ir::NodeKind::Polyline:
      if (in(node.as<ir::PolylineData>().points)) return true;
      break;
    case ir::NodeKind::Sharp:
      for (const auto& chain : m.refs(node.as<ir::SharpData>().chains)) {
        if (in(chain)) return true;
      }
      break;
    case ir::NodeKind::Mesh:
      for (ir::NodeId f : m.refs(node.as<ir::MeshData>().faces)) {
        if (f.is_valid() && (m.node(f).name == vertex || (depth < 4 && mentions_vertex(m, f, vertex, depth + 1)))) return true;
      }
      break;
    default:
      break;
  }
  if (depth > 16) return false;
  for (ir::NodeId k : m.children(node)) {
    if (mentions_vertex(m, k, vertex, depth + 1)) return true;
  }
  return false;
}

// Does `vertex` name a vertex of the instance's target? Otherwise `why` says what it has.
bool target_has_vertex(Context& c, ir::NodeId inst, const std::string& vertex, std::string* why) {
  const ir::Module& m = c.module();
  ir::NodeId t = m.get<ir::InstanceData>(inst).target;
  if (!t.is_valid()) return true;  // target already reported
  const ir::Node& target = m.node(t);
  if (target.kind == ir::NodeKind::Generator) {
    const ir::GeneratorData& gd = target.as<ir::GeneratorData>();
    const ir::GeneratorInfo& g = ir::generator(gd.gen);
    if (g.rings.empty()) return true;  // grid names are not checked yet
    std::vector<std::string_view> prefixes;
    for (const ir::RingInfo& r : g.rings) prefixes.push_back(r.prefix);
    for (const ir::VertexAlias& al : g.aliases) prefixes.push_back(al.alias);
    for (std::string_view prefix : prefixes) {
      if (vertex.size() <= prefix.size() || vertex.compare(0, prefix.size(), prefix) != 0 ||
          !all_digits(std::string_view(vertex).substr(prefix.size()))) {
        continue;
      }
      const long idx = index_of(std::string_view(vertex).substr(prefix.size()));
      const std::string canonical = ir::canonical_vertex_name(gd.gen, vertex);
      for (const ir::RingInfo& r : g.rings) {
        if (!canonical.starts_with(r.prefix) || r.count_arg == ir::kNoArg || g.args[r.count_arg].type != ir::ArgType::Count) continue;
        const ir::GenArgBinding* b = m.gen_arg(t, r.count_arg);
        if (b == nullptr || !b->value.is_valid() || m.operand(b->value).exprs.empty()) continue;
        ir::EvalResult e = ir::evaluate(m, m.refs(m.operand(b->value).exprs)[0]);
        const long n = e.ok ? std::lround(e.value) : -1;
        if (n >= 0 && idx >= n) {
          const std::string_view count = g.display_name(r.count_arg, c.dialect());
          *why = fmt::format("`{}` `{}` has vertices {}0…{}{} with {} = {}", target.keyword, target.name, prefix, prefix, n - 1,
                             count, n);
          return false;
        }
      }
      return true;
    }
    std::vector<std::string> shown;
    for (std::string_view p : prefixes) shown.push_back(fmt::format("`{}N`", p));
    *why = fmt::format("`{}` vertices are named {}", target.keyword, fmt::join(shown, ", "));
    return false;
  }
  if (target.kind == ir::NodeKind::FlatMesh) {
    const ir::FlatMeshData& fd = target.as<ir::FlatMeshData>();
    if (fd.vertex_index(vertex) >= 0) return true;
    const size_t n = fd.geometry != nullptr ? fd.geometry->positions.size() : 0;
    *why = n == 0 ? fmt::format("the mesh file `{}` has no vertices", target.name)
                  : fmt::format("the mesh file `{}` has vertices v0…v{}", target.name, n - 1);
    return false;
  }
  if (target.kind == ir::NodeKind::Mesh || target.kind == ir::NodeKind::Polyline) {
    // Points of the mesh, and points its faces use.
    if (auto it = c.mesh_points.find(t.index); it != c.mesh_points.end() && it->second.contains(vertex)) return true;
    if (mentions_vertex(m, t, vertex)) return true;
    *why = fmt::format("`{}` `{}` has no vertex `{}`", target.keyword, target.name, vertex);
    return false;
  }
  return true;  // groups and blocks (skipped)
}

std::string dotted(const ir::Module& m, const std::vector<ir::NodeId>& chain, const std::string& last) {
  std::vector<std::string> parts;
  for (ir::NodeId n : chain) {
    std::string nm = m.node(n).name;
    if (auto d = nm.rfind('.'); d != std::string::npos) nm = nm.substr(d + 1);
    parts.push_back(nm);
  }
  parts.push_back(last);
  return fmt::format("{}", fmt::join(parts, "."));
}

// Is `inst` an instance of a mesh or object (whose vertices may carry dotted, inherited
// names), rather than of a group or block that holds further instances?
bool is_leaf_instance(Context& c, ir::NodeId inst) {
  const ir::Module& m = c.module();
  const ir::NodeId t = m.get<ir::InstanceData>(inst).target;
  return t.is_valid() && m.node(t).kind == ir::NodeKind::Mesh;
}

// NOME3 names the points of `mesh M` `M.p` (compat.md E3): is `part` the name of the mesh
// instance `inst` places, so that `inst.M.p` is its vertex `p`?
bool names_target_mesh(Context& c, ir::NodeId inst, const std::string& part) {
  const ir::NodeId t = c.module().get<ir::InstanceData>(inst).target;
  if (!t.is_valid() || c.module().node(t).kind != ir::NodeKind::Mesh) return false;
  const std::string& name = c.module().node(t).name;
  return name.substr(name.rfind('.') + 1) == part;
}

// `M.p`: the point `p` declared inside `mesh M` (a NOME3 library name, compat.md E3).
ir::NodeId mesh_owned_point(Context& c, const std::string& text, SourceRange use) {
  const size_t dot = text.rfind('.');
  if (dot == std::string::npos || dot == 0) return ir::NodeId::None();
  auto def = c.scopes[static_cast<int>(Ns::Shape)].find(text.substr(0, dot));
  if (def == c.scopes[static_cast<int>(Ns::Shape)].end()) return ir::NodeId::None();
  const ir::NodeId mesh = lookup(c, Ns::Shape, text.substr(0, dot), use, true);
  if (!mesh.is_valid() || c.module().node(mesh).kind != ir::NodeKind::Mesh) return ir::NodeId::None();
  auto points = c.mesh_points.find(mesh.index);
  if (points == c.mesh_points.end()) return ir::NodeId::None();
  auto it = points->second.find(text.substr(dot + 1));
  return it == points->second.end() ? ir::NodeId::None() : it->second;
}

// A NOME3 controlpoint used as a point (compat.md E2): its position is its point's.
ir::NodeId control_point(Context& c, std::string_view text, SourceRange use) {
  auto it = c.scopes[static_cast<int>(Ns::Shape)].find(text);
  if (it == c.scopes[static_cast<int>(Ns::Shape)].end()) return ir::NodeId::None();
  const ir::NodeId n = lookup(c, Ns::Shape, text, use, true);
  return n.is_valid() && c.module().node(n).kind == ir::NodeKind::ControlPoint ? n : ir::NodeId::None();
}

// Inside a mesh JIPCAD looked an unqualified name up as the substring `.name` of the names
// of the mesh's points (compat.md E3), so `v` found `m.v1`. The point it would have taken,
// for a hint; nomec itself needs the exact name.
std::string substring_match(Context& c, ir::NodeId mesh, const std::string& text) {
  auto points = c.mesh_points.find(mesh.index);
  if (points == c.mesh_points.end()) return {};
  const std::string& mesh_name = c.module().node(mesh).name;
  const std::string needle = "." + text;
  for (std::string_view name : sorted_names(points->second)) {  // in name order: the first match is the hint
    if ((mesh_name + "." + std::string(name)).find(needle) != std::string::npos) return std::string(name);
  }
  return {};
}

// Decides whether the part after an instance chain names something of the innermost
// instance's target (a vertex, or a face to delete).
using LeafCheck = std::function<bool(ir::NodeId inst, const std::string& rest, std::string* why)>;

struct PathMatch {
  std::vector<ir::NodeId> chain;
  std::string rest;
};

// `a.b.c`: instance `a` at the top level, `b` inside it, `c` the part after the chain.
// Returns false when `a` is no top-level instance; `error` is set when the path breaks.
bool match_dotted(Context& c, const std::string& path, PathMatch& out, std::string& error, const LeafCheck& leaf,
                  ir::NodeId owner = ir::NodeId::None()) {
  std::vector<std::string> parts;
  size_t start = 0;
  for (size_t dot; (dot = path.find('.', start)) != std::string::npos; start = dot + 1) {
    parts.push_back(path.substr(start, dot - start));
  }
  parts.push_back(path.substr(start));
  ir::NodeId cur = instance_in(c, parts[0], owner);
  if (!cur.is_valid()) return false;
  out.chain.push_back(cur);
  size_t i = 1;
  bool mesh_point = false;
  for (; i + 1 < parts.size(); ++i) {
    // 2016/NOME2 meshes keep the names of the vertices they copy (`c.bc3`), so below an
    // instance of a mesh the rest of the path is one vertex name (compat.md E4).
    if (is_nome_family(c.dialect()) && is_leaf_instance(c, cur)) break;
    if (i + 2 == parts.size() && names_target_mesh(c, cur, parts[i])) {  // `inst.M.p` (compat.md E3)
      mesh_point = true;
      break;
    }
    cur = child_instance(c, cur, parts[i]);
    if (!cur.is_valid()) {
      error = fmt::format("in `{}`: `{}` is not an instance inside `{}`", path, parts[i], parts[i - 1]);
      return true;
    }
    out.chain.push_back(cur);
  }
  out.rest = mesh_point ? parts.back() : parts[i];
  for (size_t j = i + 1; !mesh_point && j < parts.size(); ++j) out.rest += "." + parts[j];
  std::string why;
  if (!leaf(cur, out.rest, &why)) error = fmt::format("in `{}`: {}", path, why);
  return true;
}

// 2016 `_`-joined paths: `fun3_hc3`, `cf_fun3_hc3`, `_ir_i1`. Instance names are matched as
// prefixes; the remainder is the part after the chain. Every match is returned. The path
// starts in the instance scope of `owner` when given (a group or block), else at the top
// level and then in any scope.
std::vector<PathMatch> match_underscored(Context& c, const std::string& text, const LeafCheck& leaf,
                                         ir::NodeId owner = ir::NodeId::None(), std::string* first_why = nullptr) {
  std::string path = text;
  while (!path.empty() && path[0] == '_') path = path.substr(1);
  std::vector<PathMatch> matches;
  // Try the top-level scope, then any instance scope (2016 names may omit outer instances).
  std::function<void(const NameTable<ir::NodeId>&, size_t, std::vector<ir::NodeId>&)> try_scope =
      [&](const NameTable<ir::NodeId>& scope, size_t at, std::vector<ir::NodeId>& chain) {
        // The names that can match are the prefixes of `path[at:]` that end before an
        // `_`; looking each up (shortest first) costs the underscores in the reference
        // instead of every name in the scope.
        for (size_t u = path.find('_', at); u != std::string::npos; u = path.find('_', u + 1)) {
          auto found = scope.find(std::string_view(path).substr(at, u - at));
          if (found == scope.end()) continue;
          ir::NodeId inst = found->second;
          chain.push_back(inst);
          size_t rest = u + 1;
          ir::NodeId t = c.module().get<ir::InstanceData>(inst).target;
          auto sub = t.is_valid() ? c.instance_scopes.find(t.index + 1) : c.instance_scopes.end();
          size_t before = matches.size();
          if (sub != c.instance_scopes.end()) try_scope(sub->second, rest, chain);
          if (matches.size() == before) {
            std::string why;
            if (leaf(inst, path.substr(rest), &why)) {
              matches.push_back({chain, path.substr(rest)});
            } else if (first_why != nullptr && first_why->empty()) {
              *first_why = why;
            }
          }
          chain.pop_back();
        }
      };
  std::vector<ir::NodeId> chain;
  if (owner.is_valid()) {
    if (auto scope = c.instance_scopes.find(owner.index + 1); scope != c.instance_scopes.end()) try_scope(scope->second, 0, chain);
    return matches;
  }
  if (auto top = c.instance_scopes.find(0); top != c.instance_scopes.end()) try_scope(top->second, 0, chain);
  if (matches.empty()) {
    for (auto& [owner, scope] : c.instance_scopes) {
      if (owner != 0) try_scope(scope, 0, chain);
    }
  }
  return matches;
}

// Reports a 2016 path that matches several instance chains. In the NOME 2016 family the
// original took the first match in file order (compat.md E4): `matches` are sorted so, the
// first is used, and this is a warning; elsewhere it is an error.
void report_ambiguous(Context& c, const std::vector<PathMatch>& matches, std::string_view text, SourceRange use) {
  std::set<std::vector<int32_t>> distinct;
  for (const PathMatch& mt : matches) {
    std::vector<int32_t> k;
    for (ir::NodeId n : mt.chain) k.push_back(n.index);
    distinct.insert(k);
  }
  if (distinct.size() <= 1) return;
  const std::string first = dotted(c.module(), matches[0].chain, matches[0].rest);
  if (is_nome_family(c.dialect())) {
    // Shown with the groups the chains start in, which the reference left out.
    auto full = [&](const PathMatch& mt) {
      const std::string& outer = c.module().node(mt.chain.front()).name;
      const std::string tail = dotted(c.module(), mt.chain, mt.rest);
      return outer.substr(0, outer.rfind('.') + (outer.find('.') == std::string::npos ? 0 : 1)) + tail;
    };
    auto d = c.diags().emit(DiagKind::AmbiguousVertexPath, use,
                            fmt::format("`{}` matches {} instance paths; taking the first in the file, `{}`, as {} did", text,
                                        distinct.size(), full(matches[0]), c.dialect() == Dialect::Nome2 ? "NOME2" : "NOME 2016"));
    d.note(c.module().node(matches[1].chain.front()).range, fmt::format("another match: `{}`", full(matches[1])));
    return;
  }
  c.diags().emit(DiagKind::AmbiguousName, use,
                 fmt::format("`{}` matches {} instance paths; write it with dots to choose one, e.g. `{}`", text,
                             distinct.size(), first));
}

// Sorts matches into file order: by the instances of their chains, outermost first.
void sort_file_order(std::vector<PathMatch>& matches) {
  if (matches.size() < 2) return;  // most paths match once; a stable sort would still take a buffer
  std::stable_sort(matches.begin(), matches.end(), [](const PathMatch& x, const PathMatch& y) {
    return std::lexicographical_compare(x.chain.begin(), x.chain.end(), y.chain.begin(), y.chain.end(),
                                        [](ir::NodeId p, ir::NodeId q) { return p.index < q.index; });
  });
}

// 2016/NOME2 dotted paths whose first instance is not at the top level: the instances of
// enclosing groups may be left out (`a.b.v` for `g.a.b.v`), so the path may start in any
// instance scope. Every match, in file order.
std::vector<PathMatch> match_dotted_anywhere(Context& c, const std::string& path, const LeafCheck& leaf) {
  std::vector<PathMatch> matches;
  for (const auto& [owner, scope] : c.instance_scopes) {
    if (owner == 0) continue;
    PathMatch m;
    std::string error;
    if (match_dotted(c, path, m, error, leaf, ir::NodeId(owner - 1)) && error.empty()) matches.push_back(std::move(m));
  }
  sort_file_order(matches);
  return matches;
}

// The faces of a mesh or object in the order the backend collects them (an object's face
// list, then the mesh's own faces).
std::vector<ir::NodeId> faces_of(const ir::Module& m, ir::NodeId mesh) {
  std::vector<ir::NodeId> out;
  const ir::Node& n = m.node(mesh);
  for (ir::NodeId f : m.refs(n.as<ir::MeshData>().faces)) {
    if (f.is_valid()) out.push_back(f);
  }
  for (ir::NodeId k : m.children(n)) {
    if (m.node(k).kind == ir::NodeKind::Face) out.push_back(k);
  }
  return out;
}

// Does `rest` name a face of the instance's target: a face name of a mesh, or an index?
bool target_has_face(Context& c, ir::NodeId inst, const std::string& rest, std::string* why) {
  const ir::Module& m = c.module();
  ir::NodeId t = m.get<ir::InstanceData>(inst).target;
  if (!t.is_valid()) return false;
  const ir::Node& target = m.node(t);
  if (target.kind == ir::NodeKind::Mesh) {
    std::vector<ir::NodeId> faces = faces_of(m, t);
    if (all_digits(rest)) {
      if (index_of(rest) < static_cast<long>(faces.size())) return true;
      *why = fmt::format("`{}` `{}` has {} faces, numbered from 0", target.keyword, target.name, faces.size());
      return false;
    }
    for (ir::NodeId f : faces) {
      std::string_view name = m.node(f).name;
      if (name.substr(name.rfind('.') + 1) == rest) return true;
    }
    *why = fmt::format("`{}` `{}` has no face `{}`", target.keyword, target.name, rest);
    return false;
  }
  if (target.kind == ir::NodeKind::Generator) {
    if (all_digits(rest)) return true;
    *why = fmt::format("faces of `{}` `{}` are named by their number", target.keyword, target.name);
    return false;
  }
  if (target.kind == ir::NodeKind::FlatMesh) {
    const ir::FlatMeshData& fd = target.as<ir::FlatMeshData>();
    const long n = fd.geometry != nullptr ? fd.geometry->face_count() : 0;
    if (all_digits(rest) && index_of(rest) < n) return true;
    *why = fmt::format("faces of the mesh file `{}` are named by their number, 0…{}", target.name, n - 1);
    return false;
  }
  *why = fmt::format("`{}` `{}` has no faces of its own", target.keyword, target.name);
  return false;
}

// The chain and face a path matched, as a face entry: a face node of a mesh, or an index.
void fill_face(Context& c, PathMatch match, ir::DeletedFace& face) {
  face.instances = std::move(match.chain);
  const ir::Module& m = c.module();
  const ir::NodeId target = m.get<ir::InstanceData>(face.instances.back()).target;
  if (target.is_valid() && m.node(target).kind == ir::NodeKind::Mesh) {
    std::vector<ir::NodeId> faces = faces_of(m, target);
    if (all_digits(match.rest)) {
      face.face = faces[static_cast<size_t>(index_of(match.rest))];
    } else {
      for (ir::NodeId f : faces) {
        std::string_view name = m.node(f).name;
        if (name.substr(name.rfind('.') + 1) == match.rest) {
          face.face = f;
          break;
        }
      }
    }
  } else {
    face.index = static_cast<int32_t>(index_of(match.rest));
  }
}

}  // namespace

ir::VertexRef resolve_vertex(Context& c, std::string_view text, SourceRange use, ir::NodeId mesh, bool* unresolved) {
  ir::VertexRef ref;
  ref.text.assign(text);
  ref.range = use;
  if (mesh.is_valid()) {
    auto& local = c.mesh_points[mesh.index];
    if (auto it = local.find(text); it != local.end()) {
      ref.point = it->second;
      return ref;
    }
  }
  if (ir::NodeId p = lookup(c, Ns::Point, text, use, true); p.is_valid()) {
    ref.point = p;
    return ref;
  }
  if (ir::NodeId cp = control_point(c, text, use); cp.is_valid()) {
    ref.point = cp;
    return ref;
  }
  if (ir::VertexRef flat = flat_scene_vertex(c, text, use); !flat.instances.empty()) {
    ref = std::move(flat);  // every path returns `ref`, so it is built in the caller's place
    return ref;
  }
  const LeafCheck has_vertex = [&](ir::NodeId inst, const std::string& rest, std::string* why) {
    return target_has_vertex(c, inst, rest, why);
  };
  std::string path(text);
  if (!path.empty() && path[0] == '.') path = path.substr(1);
  if (path.find('.') != std::string::npos) {
    PathMatch match;
    std::string error;
    const bool at_top = match_dotted(c, path, match, error, has_vertex);
    // 2016/NOME2: a path that does not resolve from the top level may leave out the
    // instances of enclosing groups (compat.md E4).
    if ((!at_top || !error.empty()) && is_nome_family(c.dialect())) {
      if (std::vector<PathMatch> matches = match_dotted_anywhere(c, path, has_vertex); !matches.empty()) {
        if (matches.size() > 1) report_ambiguous(c, matches, text, use);
        ref.instances = std::move(matches[0].chain);
        ref.vertex = std::move(matches[0].rest);
        return ref;
      }
    }
    if (at_top) {
      if (!error.empty() && unresolved != nullptr) {
        *unresolved = true;
        return ref;
      }
      ref.instances = std::move(match.chain);
      ref.vertex = std::move(match.rest);
      if (!error.empty()) c.diags().emit(DiagKind::UnknownVertex, use, error);
      return ref;
    }
    if (ir::NodeId p = mesh_owned_point(c, path, use); p.is_valid()) {
      ref.point = p;
      return ref;
    }
  } else if (std::vector<PathMatch> matches = match_underscored(c, path, has_vertex); !matches.empty()) {
    if (is_nome_family(c.dialect())) sort_file_order(matches);
    if (matches.size() > 1) report_ambiguous(c, matches, text, use);
    ref.instances = std::move(matches[0].chain);
    ref.vertex = std::move(matches[0].rest);
    return ref;
  }
  if (unresolved != nullptr) {
    *unresolved = true;
    return ref;
  }
  if (c.dialect() == Dialect::Slide && c.has_tcl && !c.tcl_available) {
    if (c.first_tcl_report(std::string(text))) {
      c.diags().emit(DiagKind::TclDefinedName, use,
                     fmt::format("`{}` is not defined in this file; it may be created by Tcl code in a `tclinit` block, "
                                 "which nomec does not evaluate yet",
                                 text));
    }
    return ref;
  }
  std::vector<std::string_view> cands = names_in(c, Ns::Point);
  if (mesh.is_valid()) {
    for (std::string_view k : sorted_names(c.mesh_points[mesh.index])) cands.push_back(k);
  }
  std::string hint = closest_match(text, cands);
  auto d = c.diags().emit(DiagKind::UnknownVertex, use,
                          fmt::format("unknown vertex `{}`: it is not a point, and no instance path leads to it{}", text,
                                      hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
  if (!hint.empty()) d.fixit(use, hint, fmt::format("replace with `{}`", hint));
  if (mesh.is_valid()) {
    if (std::string jc = substring_match(c, mesh, std::string(text)); !jc.empty()) {
      d.note(c.module().node(c.mesh_points[mesh.index][jc]).range,
             fmt::format("JIPCAD would have taken the point `{}` here (it matched `.{}` anywhere in a point's name); "
                         "nomec needs the exact name",
                         jc, text));
    }
  }
  return ref;
}

ir::DeletedFace resolve_deleted_face(Context& c, const std::string& text, SourceRange use) {
  ir::DeletedFace face;
  face.text = text;
  face.range = use;
  const LeafCheck has_face = [&](ir::NodeId inst, const std::string& rest, std::string* why) {
    return target_has_face(c, inst, rest, why);
  };
  PathMatch match;
  std::string error;
  std::string path = text;
  if (!path.empty() && path[0] == '.') path = path.substr(1);
  bool found = false;
  const bool dotted_path = path.find('.') != std::string::npos;
  if (dotted_path) {
    found = match_dotted(c, path, match, error, has_face) && error.empty();
  } else if (std::vector<PathMatch> matches = match_underscored(c, path, has_face, ir::NodeId::None(), &error);
             !matches.empty()) {
    match = matches[0];
    found = true;
    if (matches.size() > 1) report_ambiguous(c, matches, text, use);
  }
  if (!found && !dotted_path && !error.empty()) error = fmt::format("in `{}`: {}", text, error);
  const std::string first_error = error;
  // Faces inside a block or group are named from its name on (`openbox_b_top_f1` for the
  // face `f1` of instance `top` of instance `b` in block `openbox`).
  const char sep = dotted_path ? '.' : '_';
  for (size_t cut = path.find(sep); !found && cut != std::string::npos; cut = path.find(sep, cut + 1)) {
    auto def = c.scopes[static_cast<int>(Ns::Shape)].find(path.substr(0, cut));
    if (def == c.scopes[static_cast<int>(Ns::Shape)].end()) continue;
    const ir::NodeKind k = c.module().node(def->second.node).kind;
    if (k != ir::NodeKind::Group && !ir::is_block(k)) continue;
    const std::string rest = path.substr(cut + 1);
    match = PathMatch{};
    error.clear();
    if (dotted_path) {
      found = match_dotted(c, rest, match, error, has_face, def->second.node) && error.empty();
    } else if (std::vector<PathMatch> matches = match_underscored(c, rest, has_face, def->second.node); !matches.empty()) {
      match = matches[0];
      found = true;
    }
    if (found) face.scope = def->second.node;
  }
  if (!found) error = first_error;
  if (!found) {
    c.diags().emit(DiagKind::DeleteTargetMissing, use,
                   error.empty() ? fmt::format("`delete` names `{}`, which is no face of an instance: write the instance "
                                               "and the face's name or number, e.g. `cube1_c4` or `fun2_5`; the entry is ignored",
                                               text)
                                 : fmt::format("`delete` names no face of an instance: {}; the entry is ignored", error));
    return face;
  }
  fill_face(c, std::move(match), face);
  return face;
}

ir::DeletedFace resolve_block_face(Context& c, const std::string& text, SourceRange use, ir::NodeId block) {
  ir::DeletedFace face;
  face.text = text;
  face.range = use;
  face.scope = block;
  const LeafCheck has_face = [&](ir::NodeId inst, const std::string& rest, std::string* why) {
    return target_has_face(c, inst, rest, why);
  };
  PathMatch match;
  std::string error;
  bool found = false;
  if (text.find('.') != std::string::npos) {
    found = match_dotted(c, text, match, error, has_face, block) && error.empty();
  } else if (std::vector<PathMatch> matches = match_underscored(c, text, has_face, block, &error); !matches.empty()) {
    match = matches[0];
    found = true;
  }
  if (found) {
    fill_face(c, std::move(match), face);
    return face;
  }
  // Candidates: `inst.face` for the block's own instances of meshes.
  const ir::Module& m = c.module();
  std::vector<std::string> cands;
  for (ir::NodeId k : m.children(m.node(block))) {
    if (m.node(k).kind != ir::NodeKind::Instance) continue;
    const ir::NodeId t = m.get<ir::InstanceData>(k).target;
    if (!t.is_valid() || m.node(t).kind != ir::NodeKind::Mesh) continue;
    for (ir::NodeId f : faces_of(m, t)) {
      std::string_view name = m.node(f).name;
      cands.push_back(fmt::format("{}.{}", m.node(k).name.substr(m.node(k).name.rfind('.') + 1),
                                  name.substr(name.rfind('.') + 1)));
    }
  }
  const std::string hint = closest_match(text, cands);
  const ir::Node& b = m.node(block);
  std::string why = error.empty() ? "" : ": " + error;
  why += hint.empty() ? (error.empty() ? std::string("; write the instance and the face, e.g. `c.f1`") : std::string())
                      : fmt::format("; did you mean `{}`?", hint);
  auto d = c.diags().emit(DiagKind::UnknownBlockFace, use,
                          fmt::format("`{}` `{}` names `{}`, which is no face of its instances{}", b.keyword,
                                      b.name.substr(b.name.rfind('.') + 1), text, why));
  if (!hint.empty()) d.fixit(use, hint, fmt::format("replace with `{}`", hint));
  return face;
}

ir::VertexRef resolve_block_vertex(Context& c, const std::string& text, SourceRange use, ir::NodeId block) {
  ir::VertexRef ref;
  ref.text = text;
  ref.range = use;
  const LeafCheck has_vertex = [&](ir::NodeId inst, const std::string& rest, std::string* why) {
    return target_has_vertex(c, inst, rest, why);
  };
  PathMatch match;
  std::string error;
  bool found = false;
  if (text.find('.') != std::string::npos) {
    found = match_dotted(c, text, match, error, has_vertex, block) && error.empty();
  } else if (std::vector<PathMatch> matches = match_underscored(c, text, has_vertex, block, &error); !matches.empty()) {
    match = matches[0];
    found = true;
  }
  if (found) {
    ref.instances = std::move(match.chain);
    ref.vertex = std::move(match.rest);
    return ref;
  }
  const ir::Node& b = c.module().node(block);
  c.diags().emit(DiagKind::UnknownVertex, use,
                 fmt::format("`{}` `{}` names `{}`, which is no vertex of its instances{}{}", b.keyword,
                             b.name.substr(b.name.rfind('.') + 1), text, error.empty() ? "" : ": ",
                             error.empty() ? std::string("; write the instance and the vertex, e.g. `c.v1`") : error));
  return ref;
}

}  // namespace nomec::check
