// Walking the scene (see context.h): an instance composes its transform chain and colour
// and adds its target; a group adds its instances; a block runs its operation; a leaf
// (mesh, flat mesh file, generator, curve, sweep) is placed in its entry's frame — memoized per entry,
// instance and path when incremental, and collected part by part so an update can patch
// only the parts that moved. Before any of it, the plan counts what the scene entries would
// place (instances × the vertices of their leaves, memoized per node) against the vertex
// budget, so a scene that nests instances past it is refused before anything is built; the
// walk itself spends the budget leaf by leaf and stops where it runs out.
#include <algorithm>
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

// The one place SceneTooLarge is reported: once per evaluation, after which nothing more is
// placed.
void report_too_large(Context& c, SourceRange at, const std::string& message) {
  c.is_budget_exhausted = true;
  c.diags()
      .emit(DiagKind::SceneTooLarge, at, message)
      .note(SourceRange{}, "instances of groups multiply: lower counts or subdivision levels, or raise the limit "
                           "with `--max-vertices N`");
}

// ---- the plan: vertices counted before anything is placed ----

// Counts saturate here (far above any budget), so sums of them never overflow.
constexpr int64_t kPlanCap = int64_t{1} << 62;
int64_t plan_add(int64_t a, int64_t b) { return std::min(a + b, kPlanCap); }

// 12000000000 → "12,000,000,000".
std::string grouped(int64_t n) {
  std::string digits = std::to_string(n);
  std::string out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

int64_t planned_target(Context& c, ir::NodeId tid, const std::string& path, int depth);

// The vertices placing instance `inst` (under `parent_path`) would build: its target's, or
// none when it is not drawn.
int64_t planned_instance(Context& c, ir::NodeId inst, const std::string& parent_path, int depth) {
  const ir::Node& n = c.m.node(inst);
  const ir::InstanceData& d = n.as<ir::InstanceData>();
  if (d.is_hidden || !d.target.is_valid() || depth > 64 || is_off(c, d.lod)) return 0;
  if (auto it = c.cache.plans.find(d.target.index); it != c.cache.plans.end()) {
    c.cache.recorder.note(it->second.deps);
    return it->second.value;
  }
  return planned_target(c, d.target, parent_path.empty() ? short_name(n.name) : parent_path + "." + short_name(n.name),
                        depth);
}

// The vertices placing `tid` once would build, memoized per node with the parameters read
// (a group instanced a million times is counted once, and a slider move recounts only what
// read it). A leaf counts at least one, so instances of empty meshes or curves still cost;
// a block counts its input per placement (a merge may weld some of it, a subdivision's
// growth is checked when it runs). `path` names the first placement, for the messages of
// the generators and sweeps run here (and reused by the walk).
int64_t planned_target(Context& c, ir::NodeId tid, const std::string& path, int depth) {
  if (auto it = c.cache.plans.find(tid.index); it != c.cache.plans.end()) {
    c.cache.recorder.note(it->second.deps);
    return it->second.value;
  }
  if (std::find(c.planning.begin(), c.planning.end(), tid.index) != c.planning.end()) return 0;  // a cycle
  c.planning.push_back(tid.index);
  c.cache.recorder.open();
  const ir::Node& tn = c.m.node(tid);
  int64_t n = 0;
  bool is_leaf = true;
  switch (tn.kind) {
    case ir::NodeKind::Mesh: n = mesh_vertex_count(c, tid); break;
    case ir::NodeKind::FlatMesh: {
      const ir::FlatMeshData& d = tn.as<ir::FlatMeshData>();
      n = d.geometry == nullptr ? 0 : static_cast<int64_t>(d.geometry->positions.size());
      break;
    }
    case ir::NodeKind::Generator:
      if (const Generated* g = generated(c, tid, path)) n = g->soup.vertex_count();
      break;
    case ir::NodeKind::Sweep:
    case ir::NodeKind::SweepMorph:
      if (std::optional<kernel::PolygonSoup> sw = sweep(c, tid, path)) n = sw->vertex_count();
      break;
    case ir::NodeKind::Polyline: {
      const ir::PolylineData& d = tn.as<ir::PolylineData>();
      n = static_cast<int64_t>(c.m.refs(d.points).size() + c.m.refs(d.point_list).size());
      break;
    }
    case ir::NodeKind::MorphVisualizer: break;  // one cross-section's points
    case ir::NodeKind::Group:
    case ir::NodeKind::Merge:
    case ir::NodeKind::Subdivision:
    case ir::NodeKind::Offset:
    case ir::NodeKind::Handle:
    case ir::NodeKind::Rind:
    case ir::NodeKind::Sierpinski:
    case ir::NodeKind::Menger:
    case ir::NodeKind::FaceReversal: {
      is_leaf = false;
      if (tn.kind == ir::NodeKind::Group && is_off(c, tn.as<ir::GroupData>().lod)) break;
      // Paths inside a block start at the block's name (see `block`).
      const std::string inner = tn.kind == ir::NodeKind::Group ? path : short_name(tn.name);
      for (ir::NodeId k : c.m.children(tn)) {
        if (c.m.node(k).kind == ir::NodeKind::Instance) n = plan_add(n, planned_instance(c, k, inner, depth + 1));
      }
      break;
    }
    default:
      is_leaf = false;  // no geometry (the walk reports what it cannot place)
      break;
  }
  if (is_leaf) n = std::max<int64_t>(n, 1);
  Deps deps = c.cache.recorder.close();
  c.planning.pop_back();
  c.cache.plans.insert_or_assign(tid.index, Memo<int64_t>{n, std::move(deps)});
  return n;
}

// What a scene entry would build (see `entry`).
int64_t planned_entry(Context& c, ir::NodeId id) {
  const ir::Node& n = c.m.node(id);
  if (n.kind == ir::NodeKind::Instance) return planned_instance(c, id, "", 0);
  if (ir::is_block(n.kind) || n.kind == ir::NodeKind::Group) return planned_target(c, id, short_name(n.name), 0);
  if (n.kind == ir::NodeKind::Mesh) return std::max<int64_t>(mesh_vertex_count(c, id), 1);
  return 0;
}

// The instances from scene entry `id` down through the child that builds the most, as
// "`top` → `g` → `leaf`": the nesting that multiplies.
std::string heaviest_chain(Context& c, ir::NodeId id) {
  std::vector<std::string> names;
  ir::NodeId at = id;
  for (int depth = 0; depth <= 64 && at.is_valid(); ++depth) {
    const ir::Node& n = c.m.node(at);
    if (n.kind == ir::NodeKind::Instance) {
      names.push_back(short_name(n.name));
      at = n.as<ir::InstanceData>().target;
      continue;
    }
    if (n.kind != ir::NodeKind::Group && !ir::is_block(n.kind)) break;  // a leaf
    if (depth == 0) names.push_back(short_name(n.name));
    ir::NodeId heaviest;
    int64_t most = -1;
    for (ir::NodeId k : c.m.children(n)) {
      if (c.m.node(k).kind != ir::NodeKind::Instance) continue;
      const int64_t v = planned_instance(c, k, "", depth + 1);
      if (v > most) {
        most = v;
        heaviest = k;
      }
    }
    at = heaviest;
  }
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "`" : " → `") + name + "`";
  return out;
}

}  // namespace

bool spend_vertices(Context& c, int64_t vertices, SourceRange at, std::string_view path) {
  if (c.is_budget_exhausted) return false;
  c.vertex_budget -= vertices;
  if (c.vertex_budget >= 0) return true;
  report_too_large(c, at,
                   fmt::format("placing `{}` takes the scene past {} vertices, the limit; nomec stops placing geometry here",
                               path, c.vertex_limit));
  return false;
}

bool plan_fits(Context& c, std::span<const ir::NodeId> entries, const std::function<bool(ir::NodeId)>& reused) {
  int64_t total = 0;
  for (ir::NodeId id : entries) {
    int64_t n = 0;
    auto kept = c.entry_plans.find(id.index);
    if (kept != c.entry_plans.end() && reused(id)) {
      n = kept->second;
    } else {
      n = planned_entry(c, id);
      c.entry_plans[id.index] = n;
    }
    total = plan_add(total, n);
    if (total <= c.vertex_limit) continue;
    const ir::Node& e = c.m.node(id);
    const std::string what = (e.kind == ir::NodeKind::Instance ? "instance " : fmt::format("`{}` ", e.keyword)) +
                             heaviest_chain(c, id);
    const std::string limit = fmt::format("nomec builds at most {} (`--max-vertices`)", grouped(c.vertex_limit));
    report_too_large(c, e.range,
                     n == total ? fmt::format("{} would build {}{} vertices; {}", what, total >= kPlanCap ? "more than " : "",
                                              grouped(total), limit)
                                : fmt::format("{} would take the scene to {}{} vertices; {}", what,
                                              total >= kPlanCap ? "more than " : "", grouped(total), limit));
    return false;
  }
  return true;
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
  if (c.is_budget_exhausted) return;  // the walk stops with the budget
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
      PathPoints pp = path_points(c, tid, at.path);
      if (!spend_vertices(c, static_cast<int64_t>(pp.points.size()), c.m.node(at.inst.is_valid() ? at.inst : tid).range,
                          at.path)) {
        return;
      }
      out.curve_count += 1;
      if (pp.points.size() >= 2) append_curve(out, pp.points, pp.is_closed, at.t);
      return;
    }
    case ir::NodeKind::Group: {
      if (is_off(c, tn.as<ir::GroupData>().lod)) return;
      std::optional<glm::vec3> color = at.color;
      if (auto sc = surface_color(c, tn.as<ir::GroupData>().surface)) color = sc;
      c.chain.push_back(tid.index);
      for (ir::NodeId k : c.m.children(tn)) {
        if (c.is_budget_exhausted) break;
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
