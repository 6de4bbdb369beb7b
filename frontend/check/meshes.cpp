// Mesh statements (see handlers.h): surfaces, points (and SLIDE's `vertex`), controlpoints,
// polylines, faces, objects, meshes and the meshes of 2016 saved work (`consolidate`,
// `savedworkingmesh`), creases (`sharp`) and `delete` blocks, whose faces are resolved
// once every instance is known.
#include <fmt/format.h>

#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "frontend/check/handlers.h"

namespace nomec::check {

namespace {

// Appends `ref` to the vertex list `s` of one node, keeping the list contiguous in the
// module's array (a list built from nested `vertex` statements grows one at a time).
void append_vertex(ir::Module& m, ir::Slice<ir::VertexRef>& s, ir::VertexRef ref) {
  if (s.empty()) {
    s.begin = static_cast<uint32_t>(m.vertex_refs.size());
  } else if (s.begin + s.size != m.vertex_refs.size()) {
    const uint32_t begin = static_cast<uint32_t>(m.vertex_refs.size());
    for (uint32_t i = 0; i < s.size; ++i) m.vertex_refs.push_back(m.vertex_refs[s.begin + i]);
    s.begin = begin;
  }
  m.vertex_refs.push_back(std::move(ref));
  ++s.size;
}

void add_vertex_edges(Context& c, ir::NodeId id, const ir::VertexRef& ref) {
  if (ref.point.is_valid()) c.module().deps.add_edge(ref.point, id);
  if (!ref.instances.empty()) c.module().deps.add_edge(ref.instances.front(), id);
}

// A face of saved work (`consolidateface`, or a `face` of `consolidate`/`savedworkingmesh`),
// whose vertices name the base scene's.
bool is_saved_face(Context& c, const Ctx& ctx) {
  if (ctx.parent_kind == BlockKind::Consolidateface) return true;
  if (!ctx.parent.is_valid()) return false;
  const ir::NodeId mesh = c.module().node(ctx.parent).parent;
  if (!mesh.is_valid() || c.module().node(mesh).kind != ir::NodeKind::Mesh) return false;
  const ir::MeshForm form = c.module().get<ir::MeshData>(mesh).form;
  return form == ir::MeshForm::Consolidate || form == ir::MeshForm::SavedWorkingMesh;
}

// SLIDE loaded faces that repeat a vertex, such as the "dummy quads" `( q6 q6 s_4 s_4 )`
// (slide.md §3.3; their topology is unknown): nomec drops the repeats that follow each other
// round the face (`(a a b c)` → `(a b c)`), and leaves the face out when fewer than 3
// vertices remain or one still comes back later round it (`(a b a c)`), with a warning.
void slide_repeated_vertices(Context& c, ir::NodeId face, SourceRange where) {
  ir::Module& m = c.module();
  std::span<const ir::VertexRef> vs = m.refs(m.get<ir::FaceData>(face).vertices);
  if (vs.size() < 2) return;
  std::vector<ir::VertexRef> kept;
  for (size_t i = 0; i < vs.size(); ++i) {
    if (vs[i].text != vs[(i + vs.size() - 1) % vs.size()].text) kept.push_back(vs[i]);
  }
  if (kept.empty()) kept.push_back(vs[0]);  // every vertex the same
  std::unordered_set<std::string_view> seen;
  bool again = false;
  for (const ir::VertexRef& v : kept) again = again || !seen.insert(v.text).second;
  if (kept.size() == vs.size() && !again) return;
  std::string written;
  for (const ir::VertexRef& v : vs) written += (written.empty() ? "" : " ") + v.text;
  if (again || kept.size() < 3) {
    c.diags()
        .emit(DiagKind::SlideFaceRepeatedVertex, where,
              fmt::format("this face `({})` repeats a vertex; {}, so nomec leaves the face out", written,
                          again ? "a vertex comes back later round the face" : "fewer than 3 different vertices remain"))
        .note(where, "SLIDE loaded such faces, but how it joined them to their neighbours is not known (slide.md §3.3)");
    m.get<ir::FaceData>(face).vertices = m.add_vertex_refs({});
    return;
  }
  std::string now;
  for (const ir::VertexRef& v : kept) now += (now.empty() ? "" : " ") + v.text;
  c.diags()
      .emit(DiagKind::SlideFaceRepeatedVertex, where,
            fmt::format("this face `({})` repeats a vertex next to itself; nomec reads it as `({})`", written, now))
      .note(where, "SLIDE loaded such faces, but how it joined them to their neighbours is not known (slide.md §3.3)");
  m.get<ir::FaceData>(face).vertices = m.add_vertex_refs(std::move(kept));
}

// `dropped`: vertices of saved work left out of the face (see handle_vertex); a face they
// leave with fewer than 3 vertices is left out too, with a warning when there is a base.
void check_face_vertices(Context& c, ir::NodeId face, SourceRange at, SourceRange list_range, int dropped = 0) {
  const ir::Module& m = c.module();
  std::span<const ir::VertexRef> vs = m.refs(m.get<ir::FaceData>(face).vertices);
  if (vs.size() < 3 && dropped > 0) {
    if (c.base_loaded) {
      c.diags().emit(DiagKind::ConsolidateVertexMissing, at,
                     fmt::format("this saved face keeps {} vertices once the missing ones are dropped; it is left out",
                                 vs.size()));
    }
    return;
  }
  if (vs.size() < 3) {
    c.diags().emit(DiagKind::FaceTooFewVertices, list_range.is_valid() ? list_range : at,
                   fmt::format("a face needs at least 3 vertices, got {}", vs.size()));
  }
  if (c.dialect() == Dialect::Slide) {
    slide_repeated_vertices(c, face, list_range.is_valid() ? list_range : at);
    return;
  }
  // Each repeat against the vertex's first use, in one pass: a face of millions of
  // repeats (a hostile file) costs linear time and at most kShownRepeats errors.
  constexpr int kShownRepeats = 10;
  std::unordered_map<std::string_view, size_t> first_use;
  int repeats = 0;
  for (size_t j = 0; j < vs.size(); ++j) {
    auto [it, is_first] = first_use.try_emplace(vs[j].text, j);
    if (is_first || ++repeats > kShownRepeats) continue;
    auto d = c.diags().emit(DiagKind::FaceRepeatedVertex, vs[j].range,
                            fmt::format("vertex `{}` appears twice in this face", vs[j].text));
    d.note(vs[it->second].range, "first use is here");
    if (repeats == kShownRepeats) d.note(SourceRange{}, "further repeats in this face are not reported one by one");
  }
}

// `face inst_face endface` inside `delete`: remembered, resolved when every instance is known.
ir::NodeId delete_entry(Context& c, const ast::Stmt& s, const Ctx& ctx) {
  if (s.items.size() == 1 && s.items[0].kind == ItemKind::Word) {
    c.pending_deletes.push_back({ctx.parent, std::string(s.items[0].text), s.items[0].range});
  } else {
    c.diags().emit(DiagKind::MissingArgument, s.open_kw, "a face to delete is named alone: `face inst_f endface`");
  }
  return ir::NodeId::None();
}

// The stored options of a point: its texture.
OptionSink point_options(Context& c, ir::NodeId id) {
  return [&c, id](const OptionValue& v) {
    if (v.spec->key == Opt::Texture) c.module().get<ir::PointData>(id).texture = v.operand;
  };
}

// A further `mesh consolidatedmesh` block (compat.md §E5): its mesh starts with the faces
// of the one before it (an object's face list), sees its points, and takes the name from
// here on, so each `instance X consolidatedmesh` gets the faces accumulated so far. Returns
// the earlier block's node, or None for the first block.
ir::NodeId accumulate_consolidated(Context& c, const ast::Stmt& s, ir::NodeId id) {
  auto& scope = c.scopes[static_cast<int>(Ns::Shape)];
  auto it = scope.find("consolidatedmesh");
  if (it == scope.end() || it->second.node == id || !it->second.node.is_valid()) return ir::NodeId::None();
  const ir::NodeId earlier = it->second.node;
  ir::Module& m = c.module();
  if (m.node(earlier).kind != ir::NodeKind::Mesh) return ir::NodeId::None();
  std::vector<ir::NodeId> faces;
  for (ir::NodeId f : m.refs(m.get<ir::MeshData>(earlier).faces)) faces.push_back(f);
  for (ir::NodeId k : m.children(m.node(earlier))) {
    if (m.node(k).kind == ir::NodeKind::Face) faces.push_back(k);
  }
  m.get<ir::MeshData>(id).faces = m.add_node_refs(faces);
  if (auto p = c.mesh_points.find(earlier.index); p != c.mesh_points.end()) {
    auto copy = p->second;
    c.mesh_points[id.index].insert(copy.begin(), copy.end());
  }
  it->second = Symbol{id, s.items[0].range, c.order, s.keyword};
  c.note_declared(it->first, s.items[0].range, true, true);  // later blocks add to this one
  return earlier;
}

}  // namespace

ir::Slice<ir::VertexRef> read_vertices(Context& c, const ast::Ast& a, const ast::Item& list_item, ir::NodeId owner,
                                       ir::NodeId mesh) {
  const ast::ParenList& list = a.list(list_item.list);
  c.check_commas(a, list_item.list);
  // Resolved straight into the module's array (resolving one adds no other reference), so
  // a face's list costs no vector of its own.
  std::vector<ir::VertexRef>& all = c.module().vertex_refs;
  const uint32_t first = static_cast<uint32_t>(all.size());
  for (ast::ExprId e : list.elems) {
    const ast::Expr& x = a.expr(e);
    if (x.kind != ast::ExprKind::Name) {
      c.diags().emit(DiagKind::ExpectedNameList, x.range,
                     fmt::format("expected a vertex name in this list, found `{}`", Context::clip(c.sources().text(x.range))));
      continue;
    }
    all.push_back(resolve_vertex(c, x.text, x.range, mesh));
    add_vertex_edges(c, owner, all.back());
  }
  return ir::Slice<ir::VertexRef>{first, static_cast<uint32_t>(all.size()) - first};
}

ir::Slice<ir::NodeId> read_names(Context& c, const ast::Ast& a, const ast::Item& list_item, ir::NodeId owner, Ns ns) {
  const ast::ParenList& list = a.list(list_item.list);
  c.check_commas(a, list_item.list);
  std::vector<ir::NodeId> refs;
  for (ast::ExprId e : list.elems) {
    const ast::Expr& x = a.expr(e);
    if (x.kind != ast::ExprKind::Name) {
      c.diags().emit(DiagKind::ExpectedNameList, x.range,
                     fmt::format("expected a name in this list, found `{}`",
                                 Context::clip(x.text.empty() ? c.sources().text(x.range) : x.text)));
      continue;
    }
    ir::NodeId t = ns == Ns::Count  ? resolve_any(c, x.text, x.range)
                   : ns == Ns::Face ? resolve(c, Ns::Face, x.text, x.range, "a face")
                                    : resolve_point_like(c, x.text, x.range);
    refs.push_back(t);
    if (t.is_valid()) c.module().deps.add_edge(t, owner);
  }
  return c.module().add_node_refs(refs);
}

ir::NodeId handle_surface(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string name = c.read_name(s, pos, "surface S color (1 0 0) endsurface").value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  read_body(c, a, s, pos, id, options_for(s.kind), [&c, id](const OptionValue& v) {
    ir::SurfaceData& d = c.module().get<ir::SurfaceData>(id);
    switch (v.spec->key) {
      case Opt::Color: d.color = v.operand; break;
      case Opt::Reflectivity: d.reflectivity = v.operand; break;
      case Opt::Exponent: d.exponent = v.operand; break;
      case Opt::Metallic: d.metallic = v.operand; break;
      default: break;  // `bitmap`: a texture file, not used
    }
  });
  return id;
}

ir::NodeId handle_point(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  auto name = c.read_name(s, pos, "point p (1 0 0) endpoint");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name.value_or("")), ctx);
  if (!ctx.top) {
    if (ctx.parent_kind != BlockKind::Mesh) c.misplaced(s, ctx);
    if (name) c.mesh_points[ctx.parent.index][*name] = id;
  }
  if (pos < s.items.size() && s.items[pos].kind == ItemKind::List) {
    const ast::ParenList& list = a.list(s.items[pos].list);
    c.check_commas(a, s.items[pos].list);
    if (list.elems.size() != 3) {
      c.diags().emit(DiagKind::ListArity, list.range,
                     fmt::format("`position` needs 3 numbers, got {}{}", list.elems.size(), c.split_text(a, list)));
    }
    SmallVec<ir::ExprId, 4> exprs;
    for (ast::ExprId e : list.elems) exprs.push_back(lower_expr(c, a, e, false));
    c.module().get<ir::PointData>(id).position = c.add_operand(id, "position", std::move(exprs), list.range);
    ++pos;
  } else {
    c.diags().emit(DiagKind::MissingArgument, name ? s.items[0].range : s.open_kw, "a point needs a position `(x y z)`");
  }
  read_body(c, a, s, pos, id, options_for(s.kind), point_options(c, id));
  return id;
}

// `vertex` is a SLIDE mesh point (`vertex p (x y z) endvertex`) or a 2016 saved-work vertex
// reference (`vertex fun3_hc3 endvertex`) of the enclosing face.
ir::NodeId handle_vertex(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  if (ctx.parent_kind == BlockKind::Mesh) return handle_point(c, a, s, ctx);
  if (s.items.size() != 1 || s.items[0].kind != ItemKind::Word) {
    c.diags().emit(DiagKind::MissingArgument, s.open_kw, "`vertex` names one vertex: `vertex fun3_hc3 endvertex`");
    return ir::NodeId::None();
  }
  if (ctx.parent.is_valid() && c.module().node(ctx.parent).kind == ir::NodeKind::Face) {
    // compat.md §G2: saved work drops a vertex its scene lacks (NOME 2016's warning 9), and
    // says nothing when there is no base scene to look in.
    const bool saved = is_saved_face(c, ctx);
    bool unresolved = false;
    ir::VertexRef ref = resolve_vertex(c, s.items[0].text, s.items[0].range, ir::NodeId::None(),
                                       saved ? &unresolved : nullptr);
    if (unresolved) {
      ++c.dropped_saved_vertices;
      if (c.base_loaded) {
        c.diags().emit(DiagKind::ConsolidateVertexMissing, s.items[0].range,
                       fmt::format("the base scene has no vertex `{}`; it is dropped from this face, as NOME 2016 did",
                                   s.items[0].text));
      }
      return ir::NodeId::None();
    }
    add_vertex_edges(c, ctx.parent, ref);
    append_vertex(c.module(), c.module().get<ir::FaceData>(ctx.parent).vertices, std::move(ref));
  }
  return ir::NodeId::None();
}

ir::NodeId handle_controlpoint(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string name = c.read_name(s, pos, "controlpoint cp point p endcontrolpoint").value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  read_body(c, a, s, pos, id, options_for(s.kind), [&c, id](const OptionValue& v) {
    ir::ControlPointData& d = c.module().get<ir::ControlPointData>(id);
    switch (v.spec->key) {
      case Opt::Point: d.point = v.ref; break;
      case Opt::Scale: d.scale = v.operand; break;
      case Opt::Rotate: d.rotate = v.operand; break;
      case Opt::Translate: d.translate = v.operand; break;
      case Opt::CrossSection:
        d.cross_section = v.ref;
        d.cross_section_range = v.value_range;
        break;
      case Opt::Reverse: d.reverse = true; break;
      default: break;
    }
  });
  return id;
}

ir::NodeId handle_polyline(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string name = c.read_name(s, pos, "polyline l (p1 p2) endpolyline").value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  auto positional = [&](const ast::Item& it) {
    if (it.kind != ItemKind::List) return false;
    c.module().get<ir::PolylineData>(id).points = read_vertices(c, a, it, id, ir::NodeId::None());
    if (a.list(it.list).elems.size() < 2) c.diags().emit(DiagKind::ListArity, it.range, "a polyline needs at least 2 points");
    return true;
  };
  read_body(c, a, s, pos, id, options_for(s.kind), [&c, id](const OptionValue& v) {
    ir::PolylineData& d = c.module().get<ir::PolylineData>(id);
    if (v.spec->key == Opt::Closed) d.closed = ir::FlagArg{true, v.operand, v.word};
    if (v.spec->key == Opt::PointList) d.point_list = v.names;
  }, positional);
  return id;
}

ir::NodeId handle_face(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  if (ctx.parent_kind == BlockKind::Delete) return delete_entry(c, s, ctx);
  auto face_options = [&c](ir::NodeId id) {
    return [&c, id](const OptionValue& v) {
      if (v.spec->key == Opt::Surface) c.module().get<ir::FaceData>(id).surface = v.ref;
      if (v.spec->key == Opt::Backface) c.module().get<ir::FaceData>(id).backface = v.ref;
    };
  };
  size_t pos = 0;
  if (ctx.parent_kind == BlockKind::Savedworkingmesh) {
    // An anonymous face listing its vertices as nested `vertex` statements.
    ir::NodeId id = c.node_for(s, c.qualify(ctx, ""), ctx);
    const int dropped = c.dropped_saved_vertices;
    read_body(c, a, s, pos, id, options_for(s.kind), face_options(id));
    check_face_vertices(c, id, s.open_kw, SourceRange{}, c.dropped_saved_vertices - dropped);
    return id;
  }
  auto name = c.read_name(s, pos, "face f (p1 p2 p3) endface");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name.value_or("")), ctx);
  if (pos < s.items.size() && s.items[pos].kind == ItemKind::List) {
    const ast::Item& list = s.items[pos];
    c.module().get<ir::FaceData>(id).vertices =
        read_vertices(c, a, list, id, ctx.parent_kind == BlockKind::Mesh ? ctx.parent : ir::NodeId::None());
    ++pos;
    check_face_vertices(c, id, s.range, list.range);
  } else if (name) {
    c.diags().emit(DiagKind::MissingArgument, s.items[0].range, "a face needs its vertices `(v1 v2 v3 …)`");
  }
  read_body(c, a, s, pos, id, options_for(s.kind), face_options(id));
  return id;
}

ir::NodeId handle_object(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string name = c.read_name(s, pos, "object o (f1 f2) endobject").value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  c.module().get<ir::MeshData>(id).form = ir::MeshForm::Object;
  auto positional = [&](const ast::Item& it) {
    if (it.kind != ItemKind::List) return false;
    c.module().get<ir::MeshData>(id).faces = read_names(c, a, it, id, Ns::Face);
    return true;
  };
  read_body(c, a, s, pos, id, options_for(s.kind), [&c, id](const OptionValue& v) {
    if (v.spec->key == Opt::Surface) c.module().get<ir::MeshData>(id).surface = v.ref;
  }, positional);
  return id;
}

// `mesh`, and the meshes of 2016 saved work: `consolidate` (the mesh `consolidatemesh`),
// its `consolidateface`s, `savedworkingmesh`.
ir::NodeId handle_mesh(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string name;
  if (s.kind == BlockKind::Mesh) name = c.read_name(s, pos, "mesh m … endmesh").value_or("");
  if (s.kind == BlockKind::Savedworkingmesh) name = c.read_name(s, pos, "savedworkingmesh m … endsavedworkingmesh").value_or("");
  if (s.kind == BlockKind::Consolidate) {
    name = "consolidatemesh";
    // `consolidate` defines the mesh `consolidatemesh` (language.md §6.5).
    if (!c.scopes[static_cast<int>(Ns::Shape)].contains(name)) {
      ir::NodeId id = c.node_for(s, name, ctx);
      define(c, Ns::Shape, name, Symbol{id, s.open_kw, c.order, s.keyword});
      if (ir::NodeId* d = c.declared_slot(s)) *d = id;
    }
  }
  ir::NodeId id = c.node_for(s, s.kind == BlockKind::Consolidate ? name : c.qualify(ctx, name), ctx);
  if (s.kind == BlockKind::Consolidateface) {
    const int dropped = c.dropped_saved_vertices;
    read_body(c, a, s, pos, id, options_for(s.kind), {});
    check_face_vertices(c, id, s.open_kw, SourceRange{}, c.dropped_saved_vertices - dropped);
  } else {
    ir::MeshData& d = c.module().get<ir::MeshData>(id);
    d.form = s.kind == BlockKind::Consolidate        ? ir::MeshForm::Consolidate
             : s.kind == BlockKind::Savedworkingmesh ? ir::MeshForm::SavedWorkingMesh
                                                     : ir::MeshForm::Mesh;
    const ir::NodeId earlier = is_consolidated_mesh(c, s) && ctx.top ? accumulate_consolidated(c, s, id) : ir::NodeId::None();
    read_body(c, a, s, pos, id, options_for(s.kind), {});
    if (earlier.is_valid()) c.module().deps.add_edge(earlier, id);
  }
  if (ctx.parent.is_valid()) c.module().deps.add_edge(id, ctx.parent);
  return id;
}

ir::NodeId handle_sharp(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  if (ctx.parent_kind != BlockKind::Mesh) {
    c.diags().emit(DiagKind::MisplacedStatement, s.open_kw, "`sharp` marks edges of a mesh and must be inside `mesh … endmesh`");
  }
  ir::NodeId id = c.node_for(s, "", ctx);
  size_t pos = 0;
  if (pos < s.items.size() && s.items[pos].kind == ItemKind::Value) {
    SmallVec<ir::ExprId, 4> exprs;
    exprs.push_back(scalar_of_item(c, a, s.items[pos], false));
    c.module().get<ir::SharpData>(id).sharpness = c.add_operand(id, "sharpness", std::move(exprs), s.items[pos].range);
    ++pos;
  } else {
    c.diags().emit(DiagKind::MissingArgument, s.open_kw, "`sharp` needs a sharpness value first: `sharp 9 (v1 v2 v3) endsharp`");
  }
  std::vector<ir::Slice<ir::VertexRef>> chains;
  for (; pos < s.items.size(); ++pos) {
    if (s.items[pos].kind == ItemKind::List) {
      chains.push_back(read_vertices(c, a, s.items[pos], id, ctx.parent));
    } else {
      c.diags().emit(DiagKind::UnexpectedItem, s.items[pos].range, "`sharp` takes vertex lists `(v1 v2 …)` after its sharpness");
    }
  }
  if (chains.empty()) c.diags().emit(DiagKind::MissingArgument, s.open_kw, "`sharp` needs at least one vertex list `(v1 v2 …)`");
  ir::Module& m = c.module();
  m.get<ir::SharpData>(id).chains = {static_cast<uint32_t>(m.vertex_lists.size()), static_cast<uint32_t>(chains.size())};
  m.vertex_lists.insert(m.vertex_lists.end(), chains.begin(), chains.end());
  c.adopt(ctx.parent, id);
  return id;
}

ir::NodeId handle_delete(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  ir::NodeId id = c.node_for(s, "", ctx);
  read_body(c, a, s, 0, id, options_for(s.kind), {});
  if (ctx.parent.is_valid()) c.module().deps.add_edge(id, ctx.parent);
  return id;
}

void resolve_pending_deletes(Context& c) {
  // Entries are grouped by their `delete` node, in file order, so each node's faces are one
  // contiguous slice.
  ir::Module& m = c.module();
  for (size_t i = 0; i < c.pending_deletes.size();) {
    const ir::NodeId owner = c.pending_deletes[i].owner;
    const uint32_t begin = static_cast<uint32_t>(m.deleted_faces.size());
    for (; i < c.pending_deletes.size() && c.pending_deletes[i].owner == owner; ++i) {
      const PendingDelete& p = c.pending_deletes[i];
      ir::DeletedFace f = resolve_deleted_face(c, p.text, p.range);
      for (ir::NodeId inst : f.instances) m.deps.add_edge(inst, owner);
      m.deleted_faces.push_back(std::move(f));
    }
    if (owner.is_valid()) {
      m.get<ir::DeleteData>(owner).faces = {begin, static_cast<uint32_t>(m.deleted_faces.size()) - begin};
    }
  }
  c.pending_deletes.clear();
}

}  // namespace nomec::check
