// Walking the scene (see context.h): an instance composes its transform chain and colour
// and adds its target; a group adds its instances; a block runs its operation; a leaf
// (mesh, flat mesh file, generator, curve, sweep) is placed in its entry's frame — memoized per entry,
// instance and path when incremental, and collected part by part so an update can patch
// only the parts that moved.
#include <fmt/format.h>

#include "backend/eval/context.h"

namespace nomec::backend::eval {

namespace {

// The curves a generator made (vertex lists into its soup), placed by `t`.
void append_generated_curves(Collected& out, const Generated& g, const glm::dmat4& t) {
  std::vector<glm::dvec3> points;
  for (const Generated::Curve& k : g.curves) {
    points.clear();
    for (int32_t v : k.vertices) {
      if (v >= 0 && v < g.soup.vertex_count()) points.push_back(g.soup.positions[v]);
    }
    if (points.size() >= 2) append_curve(out, points, k.is_closed, t);
  }
}

void place_leaf_unbudgeted(Context& c, ir::NodeId tid, const Placing& at, Collected& out);

// Appends the leaf `tid` placed by `at` to `out` (uncached), within the vertex budget.
void place_leaf(Context& c, ir::NodeId tid, const Placing& at, Collected& out) {
  if (c.is_budget_exhausted) return;
  const size_t before = out.soup.positions.size();
  place_leaf_unbudgeted(c, tid, at, out);
  // The leaf that crosses the limit is kept (its faces are whole); nothing after it is placed.
  spend_vertices(c, static_cast<int64_t>(out.soup.positions.size() - before),
                 c.m.node(at.inst.is_valid() ? at.inst : tid).range, at.path);
}

void place_leaf_unbudgeted(Context& c, ir::NodeId tid, const Placing& at, Collected& out) {
  const ir::Node& tn = c.m.node(tid);
  const int32_t face_base = out.soup.face_count();
  switch (tn.kind) {
    case ir::NodeKind::Mesh: {
      Collected local_c;
      mesh(c, tid, at, local_c);
      transform_into(out, local_c, at.t);
      if (c.has_deletes()) mark_deleted(c, out, face_base, at.inst);
      return;
    }
    case ir::NodeKind::Generator: {
      const Generated* g = generated(c, tid, at.path);
      if (g == nullptr) return;
      kernel::PolygonSoup s = g->soup;
      s.face_sources.assign(s.face_count(), kernel::FaceSource{tid.index, at.inst.index});
      s.face_colors.clear();
      append_soup(out, s, at.t, at.color, false);
      if (c.has_deletes()) mark_deleted(c, out, face_base, at.inst);
      out.curve_count += static_cast<int32_t>(g->curves.size());
      append_generated_curves(out, *g, at.t);
      return;
    }
    case ir::NodeKind::FlatMesh: {
      kernel::PolygonSoup s = flat_soup(tn.as<ir::FlatMeshData>());
      s.face_sources.assign(s.face_count(), kernel::FaceSource{tid.index, at.inst.index});
      append_soup(out, s, at.t, at.color, false);
      if (c.has_deletes()) mark_deleted(c, out, face_base, at.inst);
      return;
    }
    case ir::NodeKind::Sweep:
    case ir::NodeKind::SweepMorph: {
      std::optional<kernel::PolygonSoup> sw = sweep(c, tid, at.path);
      if (!sw) return;
      sw->face_sources.assign(sw->face_count(), kernel::FaceSource{tid.index, at.inst.index});
      append_soup(out, *sw, at.t, at.color, false);
      if (c.has_deletes()) mark_deleted(c, out, face_base, at.inst);
      return;
    }
    case ir::NodeKind::MorphVisualizer: {
      std::optional<Generated> g = morph_visualizer(c, tid, at.path);
      if (!g) return;
      append_soup(out, g->soup, at.t, at.color, false);
      out.curve_count += static_cast<int32_t>(g->curves.size());
      append_generated_curves(out, *g, at.t);
      return;
    }
    default:
      return;  // `target` sends only the kinds above
  }
}

// A placed leaf, memoized when incremental (see Placement).
void place(Context& c, ir::NodeId tid, const Placing& at, Collected& out) {
  auto recomputed = [&] {
    ++c.counters.instances_placed;
    c.counters.nodes.insert(c.chain.begin(), c.chain.end());
  };
  if (!c.is_incremental) {
    place_leaf(c, tid, at, out);
    recomputed();
    return;
  }
  std::string key = std::to_string(c.context);
  key += '/';
  key += std::to_string(at.inst.index);
  key += '/';
  key += at.path;
  auto it = c.cache.placements.find(key);
  if (it != c.cache.placements.end() && it->second.value.t == at.t && it->second.value.color == at.color) {
    c.cache.recorder.note(it->second.deps);
  } else {
    c.cache.recorder.open();
    Collected part;
    place_leaf(c, tid, at, part);
    Deps d = c.cache.recorder.close();
    recomputed();
    auto shared = std::make_shared<const Collected>(std::move(part));
    it = c.cache.placements
             .insert_or_assign(std::move(key), Memo<Placement>{Placement{at.t, at.color, std::move(shared), {}}, std::move(d)})
             .first;
  }
  const Placement& pl = it->second.value;
  if (c.collects(out)) {
    c.sink->parts.push_back({&it->second.value, pl.part, nullptr});
    if (c.sink->is_deferred) return;
  }
  transform_into(out, *pl.part, glm::dmat4(1.0));
}

}  // namespace

bool spend_vertices(Context& c, int64_t vertices, SourceRange at, std::string_view path) {
  if (c.is_budget_exhausted) return false;
  c.vertex_budget -= vertices;
  if (c.vertex_budget >= 0) return true;
  c.is_budget_exhausted = true;
  c.diags()
      .emit(DiagKind::SceneTooLarge, at,
            fmt::format("placing `{}` takes the scene past {} vertices, the limit; nomec stops placing geometry here",
                        path, c.vertex_limit))
      .note(SourceRange{}, "instances of groups multiply: lower counts or subdivision levels, or raise the limit "
                           "with `--max-vertices N`");
  return false;
}

bool is_off(Context& c, ir::OperandId lod) { return lod.is_valid() && scalar(c, lod, 0, 3) < 0.5; }

void make_eager(Context& c) {
  if (!c.sink->is_deferred) return;
  c.sink->is_deferred = false;
  c.sink->direct_curves = c.sink->out->curve_count;
  for (const EntryPart& p : c.sink->parts) append_collected(*c.sink->out, *p.part);
}

void instance(Context& c, ir::NodeId inst, const glm::dmat4& parent_t, std::optional<glm::vec3> color,
              const std::string& parent_path, Collected& out, int depth) {
  const ir::Node& n = c.m.node(inst);
  const ir::InstanceData& d = n.as<ir::InstanceData>();
  if (d.is_hidden || !d.target.is_valid() || is_off(c, d.lod)) return;
  if (depth > 64) {
    c.diags().emit(DiagKind::GeometryFailed, n.range, "instances nest more than 64 levels deep");
    return;
  }
  Placing at;
  at.path = parent_path.empty() ? short_name(n.name) : parent_path + "." + short_name(n.name);
  c.instance_paths.try_emplace(inst.index, at.path);
  at.t = parent_t * local(c, c.m.refs(d.transforms));
  at.color = color;
  if (auto sc = surface_color(c, d.surface)) at.color = sc;
  at.inst = inst;
  if (d.is_reversed && c.collects(out)) {
    // The faces are turned around after they are placed: the entry is built whole.
    make_eager(c);
    c.sink->is_pure = false;
  }
  const int32_t face_base = out.soup.face_count();
  c.chain.push_back(inst.index);
  target(c, d.target, at, out, depth);
  c.chain.pop_back();
  if (d.is_reversed) reverse_faces(out, face_base);
}

void target(Context& c, ir::NodeId tid, const Placing& at, Collected& out, int depth) {
  const ir::Node& tn = c.m.node(tid);
  switch (tn.kind) {
    case ir::NodeKind::Mesh:
    case ir::NodeKind::FlatMesh:
    case ir::NodeKind::Generator:
    case ir::NodeKind::Sweep:
    case ir::NodeKind::SweepMorph:
    case ir::NodeKind::MorphVisualizer:
      place(c, tid, at, out);
      return;
    case ir::NodeKind::Polyline: {
      out.curve_count += 1;
      PathPoints pp = path_points(c, tid, at.path);
      if (pp.points.size() >= 2) append_curve(out, pp.points, pp.is_closed, at.t);
      return;
    }
    case ir::NodeKind::Group: {
      if (is_off(c, tn.as<ir::GroupData>().lod)) return;
      std::optional<glm::vec3> color = at.color;
      if (auto sc = surface_color(c, tn.as<ir::GroupData>().surface)) color = sc;
      c.chain.push_back(tid.index);
      for (ir::NodeId k : c.m.children(tn)) {
        if (c.m.node(k).kind == ir::NodeKind::Instance) instance(c, k, at.t, color, at.path, out, depth + 1);
      }
      c.chain.pop_back();
      return;
    }
    case ir::NodeKind::Merge:
    case ir::NodeKind::Subdivision:
    case ir::NodeKind::Offset:
    case ir::NodeKind::Handle:
    case ir::NodeKind::Rind:
    case ir::NodeKind::Sierpinski:
    case ir::NodeKind::Menger:
    case ir::NodeKind::FaceReversal:
      block(c, tid, at, out, depth + 1);
      return;
    case ir::NodeKind::SceneSetup:
      return;  // viewing set-up: no geometry (the checker already noted it)
    case ir::NodeKind::SceneColor:
    case ir::NodeKind::Backface:
    case ir::NodeKind::Param:
    case ir::NodeKind::Value:
    case ir::NodeKind::Surface:
    case ir::NodeKind::Point:
    case ir::NodeKind::ControlPoint:
    case ir::NodeKind::Face:
    case ir::NodeKind::SweepPath:
    case ir::NodeKind::CrossSection:
    case ir::NodeKind::Transform:
    case ir::NodeKind::Instance:
    case ir::NodeKind::Delete:
    case ir::NodeKind::Sharp:
    case ir::NodeKind::Zipper:
      break;
  }
  c.diags().emit(DiagKind::GeometryFailed, tn.range,
                 fmt::format("`{}` `{}` produces no geometry the backend can place (instance `{}`)", tn.keyword,
                             short_name(tn.name), at.path));
}

}  // namespace nomec::backend::eval
