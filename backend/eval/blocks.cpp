// Pipeline blocks for the evaluator (see context.h): a block evaluates its instances in
// its own frame, merges them and runs its steps (subdivision levels and rule, an offset or a
// lattice), and adds the result placed by the instance that names it. Incremental
// evaluations merge and step the input by clusters of parts whose borders can meet, reusing
// the clusters (and connected components) that did not change (docs/incremental.md).
#include <algorithm>
#include <fmt/format.h>
#include <numeric>

#include "backend/eval/context.h"
#include "kernel/topology.h"

namespace nomec::backend::eval {

namespace {

// A block's steps and tolerance, read from its payload.
struct BlockSetup {
  double tolerance = -1;  // < 0: 1e-4 x the input's bounding-box diagonal
  std::vector<Step> steps;
  SourceRange step_range;
};

BlockSetup block_setup(Context& c, ir::NodeId pid) {
  const ir::Node& p = c.m.node(pid);
  BlockSetup b;
  b.step_range = p.range;
  switch (p.kind) {
    case ir::NodeKind::Merge: {
      const ir::MergeData& d = p.as<ir::MergeData>();
      if (d.tolerance.is_valid()) b.tolerance = scalar(c, d.tolerance, 0, -1);
      break;
    }
    case ir::NodeKind::Subdivision: {
      const ir::SubdivisionData& d = p.as<ir::SubdivisionData>();
      if (d.tolerance.is_valid()) b.tolerance = scalar(c, d.tolerance, 0, -1);
      Step st;
      st.subdivision.has_parent_maps = false;
      st.subdivision.levels = static_cast<int32_t>(std::lround(d.levels.is_valid() ? scalar(c, d.levels, 0, 1) : 1));
      st.subdivision.is_sharpness_honoured = d.rule != ir::SubdivisionRule::CatmullClark;
      if (d.rule == ir::SubdivisionRule::DeRose) st.subdivision.vertex_rule = kernel::VertexRule::DeRose;
      b.steps.push_back(st);
      if (d.levels.is_valid()) b.step_range = c.m.operand(d.levels).range;
      break;
    }
    case ir::NodeKind::Offset: {
      const ir::OffsetData& d = p.as<ir::OffsetData>();
      if (d.tolerance.is_valid()) b.tolerance = scalar(c, d.tolerance, 0, -1);
      Step st;
      st.height = d.height.is_valid() ? scalar(c, d.height, 0, 0.1) : 0.1;
      st.width = d.width.is_valid() ? scalar(c, d.width, 0, 0) : 0;
      st.kind = d.kind == ir::OffsetKind::Grid && st.width > 0 ? Step::Kind::Lattice : Step::Kind::Offset;
      b.steps.push_back(st);
      if (d.height.is_valid()) b.step_range = c.m.operand(d.height).range;
      break;
    }
    default:
      break;
  }
  return b;
}

// A block's result mesh as a part, with the block's colour rule: if no input face has a
// colour, every face gets the neutral grey. The input's curves pass through unchanged (a
// block steps faces only), in the same frame, so they are still drawn.
std::shared_ptr<const Collected> block_part(Context& c, kernel::Mesh result, bool any_color, int32_t curve_count,
                                            std::vector<Curve> curves) {
  Collected part;
  part.soup = kernel::to_soup(result);
  part.curve_count = curve_count;
  part.curves = std::move(curves);
  if (c.is_incremental) part.built = std::make_shared<const kernel::Mesh>(std::move(result));
  part.has_color.assign(part.soup.face_count(), any_color ? 1 : 0);
  if (!any_color) part.soup.face_colors.assign(part.soup.face_count(), kDefaultColor);
  if (part.soup.face_colors.size() != static_cast<size_t>(part.soup.face_count())) {
    part.soup.face_colors.assign(part.soup.face_count(), kDefaultColor);
  }
  part.is_deleted.assign(part.soup.face_count(), 0);
  return std::make_shared<const Collected>(std::move(part));
}

// A block over its whole input at once: build, merge, then the steps (per connected
// component when incremental). Reports kernel errors at the faces that caused them.
// The most vertices a block's subdivision may make: what is left of the evaluation's budget.
int64_t step_limit(const Context& c) { return std::max<int64_t>(c.vertex_budget, 1); }

std::optional<BlockResult> run_block_whole(Context& c, ir::NodeId pid, Collected in, const BlockSetup& setup) {
  const ir::Node& p = c.m.node(pid);
  const bool any_color = std::any_of(in.has_color.begin(), in.has_color.end(), [](uint8_t b) { return b != 0; });
  const int32_t curves = in.curve_count;
  kernel::PolygonSoup soup = finish(in);
  auto built = kernel::build_mesh(soup);
  if (!built) {
    report(c, built.error(), soup, p.range, short_name(p.name));
    return std::nullopt;
  }
  auto merged = merge_mesh(*built, setup.tolerance);
  ++c.counters.kernel_ops;
  if (!merged) {
    report(c, merged.error(), soup, p.range, short_name(p.name));
    return std::nullopt;
  }
  if (is_high_genus(p.kind)) {
    std::optional<kernel::Mesh> made = high_genus(c, pid, merged->mesh, soup, merged->vertex_map);
    if (!made) return std::nullopt;
    BlockResult r;
    r.parts.push_back(block_part(c, std::move(*made), any_color, curves, std::move(in.curves)));
    return r;
  }
  std::variant<kernel::Mesh, StepFailure> ran;
  if (c.is_incremental) {
    BlockMemo& bm = c.block_memos[pid.index];
    ComponentMemo next;
    ran = run_steps_by_component(merged->mesh, setup.steps, bm.components, next, c.counters.kernel_ops,
                                 step_limit(c));
    bm = BlockMemo{};
    bm.components = std::move(next);
  } else {
    ran = run_steps(std::move(merged->mesh), setup.steps, c.counters.kernel_ops, step_limit(c));
  }
  if (auto* failed = std::get_if<StepFailure>(&ran)) {
    report(c, failed->error, soup, setup.step_range, short_name(p.name));
    return std::nullopt;
  }
  BlockResult r;
  r.parts.push_back(block_part(c, std::move(std::get<kernel::Mesh>(ran)), any_color, curves, std::move(in.curves)));
  return r;
}

// A block over its input parts in *clusters*: parts whose border vertices cannot come
// within the merge tolerance of each other's (their border bounding boxes, grown by
// twice the tolerance, do not overlap) cannot be joined by the merge, so each cluster is
// merged and stepped on its own, and a cluster made of the very same part objects as in
// the previous evaluation (same tolerance, steps and colour rule) reuses its result
// without merging anything. The block's result is the clusters' results in order, each
// a part of its own, so an entry can patch just the changed ones. Nullopt (nothing
// reported) if a part does not build or a cluster fails: the caller then runs the whole
// input at once, which reports the error as a one-shot build does.
std::optional<BlockResult> run_block_by_clusters(Context& c, ir::NodeId pid, const std::vector<EntryPart>& parts,
                                                 const BlockSetup& setup) {
  BlockMemo& bm = c.block_memos[pid.index];
  const size_t n = parts.size();
  // Bounds per part, computed once per part object.
  std::unordered_map<const Collected*, PartBounds> bounds;
  std::vector<const PartBounds*> pb(n);
  bool any_color = false;
  kernel::BoundingBox all;
  for (size_t i = 0; i < n; ++i) {
    const Collected* key = parts[i].part.get();
    auto old = bm.bounds.find(key);
    PartBounds b;
    if (old != bm.bounds.end()) {
      b = std::move(old->second);
    } else {
      std::optional<kernel::Mesh> own;
      const kernel::Mesh* m = parts[i].part->built.get();
      if (m == nullptr) {
        auto built = kernel::build_mesh(parts[i].part->soup);
        if (!built) return std::nullopt;
        own = std::move(*built);
        m = &*own;
      }
      b.part = parts[i].part;
      b.all = kernel::bounding_box(*m);
      for (int32_t e = 0; e < m->edge_count(); ++e) {
        if (!m->is_boundary(kernel::EdgeId(e))) continue;
        for (int end = 0; end < 2; ++end) {
          const glm::dvec3& q = m->position(m->edge_vertex(kernel::EdgeId(e), end));
          b.border.min = glm::min(b.border.min, q);
          b.border.max = glm::max(b.border.max, q);
        }
      }
    }
    auto [it, _] = bounds.emplace(key, std::move(b));
    pb[i] = &it->second;
    all.min = glm::min(all.min, pb[i]->all.min);
    all.max = glm::max(all.max, pb[i]->all.max);
    const auto& hc = parts[i].part->has_color;
    any_color = any_color || std::any_of(hc.begin(), hc.end(), [](uint8_t x) { return x != 0; });
  }
  double tol = setup.tolerance;
  if (tol < 0) {
    // As `merge_mesh` on the whole input (the union of the parts' boxes is its box).
    double diag = all.min.x <= all.max.x ? glm::length(all.max - all.min) : 0;
    tol = diag > 0 ? 1e-4 * diag : 1e-9;
  }
  // Clusters: union-find over parts whose grown border boxes overlap (sweep along x).
  std::vector<size_t> root(n);
  std::iota(root.begin(), root.end(), size_t{0});
  auto find = [&](size_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  const double grow = 2 * tol;
  std::vector<size_t> order;
  for (size_t i = 0; i < n; ++i) {
    if (pb[i]->border.min.x <= pb[i]->border.max.x) order.push_back(i);  // has a border
  }
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return pb[a]->border.min.x < pb[b]->border.min.x; });
  for (size_t a = 0; a < order.size(); ++a) {
    const kernel::BoundingBox& x = pb[order[a]]->border;
    for (size_t b = a + 1; b < order.size() && pb[order[b]]->border.min.x <= x.max.x + grow; ++b) {
      const kernel::BoundingBox& y = pb[order[b]]->border;
      if (y.min.y <= x.max.y + grow && x.min.y <= y.max.y + grow && y.min.z <= x.max.z + grow &&
          x.min.z <= y.max.z + grow) {
        size_t ra = find(order[a]), rb = find(order[b]);
        if (ra != rb) root[std::max(ra, rb)] = std::min(ra, rb);
      }
    }
  }
  // Clusters in order of their first part; parts in input order.
  std::vector<std::vector<size_t>> clusters;
  std::vector<size_t> cluster_of(n, SIZE_MAX);
  for (size_t i = 0; i < n; ++i) {
    size_t r = find(i);
    if (cluster_of[r] == SIZE_MAX) {
      cluster_of[r] = clusters.size();
      clusters.emplace_back();
    }
    clusters[cluster_of[r]].push_back(i);
  }
  // Match clusters with the previous evaluation's by their first part object.
  std::unordered_map<const Collected*, size_t> previous;
  for (size_t k = 0; k < bm.clusters.size(); ++k) previous.emplace(bm.clusters[k].parts.front().get(), k);
  std::vector<uint8_t> old_used(bm.clusters.size(), 0);
  std::vector<std::optional<size_t>> reuse(clusters.size());
  for (size_t ci = 0; ci < clusters.size(); ++ci) {
    auto it = previous.find(parts[clusters[ci].front()].part.get());
    if (it == previous.end() || old_used[it->second]) continue;
    const ClusterMemo& old = bm.clusters[it->second];
    bool same = old.tolerance == tol && old.steps == setup.steps && old.any_color == any_color &&
                old.parts.size() == clusters[ci].size();
    for (size_t k = 0; same && k < clusters[ci].size(); ++k) same = old.parts[k] == parts[clusters[ci][k]].part;
    if (same) {
      reuse[ci] = it->second;
      old_used[it->second] = 1;
    }
  }
  // Components of dissolved clusters may still be reused by content.
  ComponentMemo pool;
  for (size_t k = 0; k < bm.clusters.size(); ++k) {
    if (old_used[k]) continue;
    for (auto& e : bm.clusters[k].components.entries) pool.entries.push_back(std::move(e));
  }
  std::vector<ClusterMemo> next(clusters.size());
  BlockResult result;
  for (size_t ci = 0; ci < clusters.size(); ++ci) {
    if (reuse[ci]) {
      next[ci] = std::move(bm.clusters[*reuse[ci]]);
      ++c.counters.clusters_reused;
      result.parts.push_back(next[ci].result);
      continue;
    }
    ClusterMemo& cm = next[ci];
    cm.tolerance = tol;
    cm.steps = setup.steps;
    cm.any_color = any_color;
    Collected cc;
    int32_t curves = 0;
    for (size_t i : clusters[ci]) {
      cm.parts.push_back(parts[i].part);
      append_collected(cc, *parts[i].part);
      curves += parts[i].part->curve_count;
    }
    // The whole input's soup rule (see `finish`), with the block's colour decision.
    if (!any_color) cc.soup.face_colors.clear();
    if (!cc.soup.names.empty()) cc.soup.names.resize(cc.soup.positions.size());
    auto built = kernel::build_mesh(cc.soup);
    if (!built) return std::nullopt;
    auto merged = kernel::merge(*built, kernel::MergeOptions{tol});
    ++c.counters.kernel_ops;
    if (!merged) return std::nullopt;
    auto ran = run_steps_by_component(merged->mesh, setup.steps, pool, cm.components, c.counters.kernel_ops,
                                      step_limit(c));
    if (std::holds_alternative<StepFailure>(ran)) return std::nullopt;
    cm.result = block_part(c, std::move(std::get<kernel::Mesh>(ran)), any_color, curves, std::move(cc.curves));
    result.parts.push_back(cm.result);
  }
  bm.clusters = std::move(next);
  bm.bounds = std::move(bounds);
  bm.components = {};
  return result;
}

// The blocks whose input may be merged and stepped cluster by cluster (a high-genus
// block joins faces anywhere in its input, so it runs on all of it).
bool is_clusterable(ir::NodeKind k) {
  return k == ir::NodeKind::Merge || k == ir::NodeKind::Subdivision || k == ir::NodeKind::Offset;
}

std::optional<BlockResult> run_block(Context& c, ir::NodeId pid, const std::string& path, int depth) {
  const ir::Node& p = c.m.node(pid);
  Collected in;
  Sink sink;
  sink.out = &in;
  sink.is_deferred = c.is_incremental && !c.has_deletes();
  Sink* const saved_sink = c.sink;
  c.sink = c.is_incremental ? &sink : nullptr;
  for (ir::NodeId k : c.m.children(p)) {
    if (c.is_budget_exhausted) break;
    if (c.m.node(k).kind == ir::NodeKind::Instance) instance(c, k, glm::dmat4(1.0), std::nullopt, path, in, depth + 1);
  }
  c.sink = saved_sink;
  if (c.is_budget_exhausted) return std::nullopt;  // reported where it ran out
  if (sink.is_deferred) {
    int32_t faces = in.soup.face_count();
    for (const EntryPart& part : sink.parts) faces += part.part->soup.face_count();
    if (sink.is_pure && faces > 0 && in.curve_count == 0 && is_clusterable(p.kind)) {
      BlockSetup setup = block_setup(c, pid);
      if (auto r = run_block_by_clusters(c, pid, sink.parts, setup)) return r;
      for (const EntryPart& part : sink.parts) append_collected(in, *part.part);
      return run_block_whole(c, pid, std::move(in), setup);
    }
    for (const EntryPart& part : sink.parts) append_collected(in, *part.part);
  }
  apply_deletes(c, in);
  if (p.kind == ir::NodeKind::FaceReversal) {
    // SLIDE `mirror … endmirror` "reverses all face orientations" to repair instances
    // mirrored by a negative scale, which SLIDE leaves inside out. nomec already reverses
    // faces placed by a transform with negative determinant, so the block's repair is
    // done: its instances pass through unchanged. (A block around unmirrored instances,
    // which SLIDE would turn inside out, therefore differs from SLIDE.)
    BlockResult r;
    r.parts.push_back(std::make_shared<const Collected>(std::move(in)));
    return r;
  }
  if (in.soup.face_count() == 0) {
    c.diags().emit(DiagKind::GeometryFailed, p.range, fmt::format("`{}` `{}` has no faces to work on", p.keyword, short_name(p.name)));
    return std::nullopt;
  }
  return run_block_whole(c, pid, std::move(in), block_setup(c, pid));
}

}  // namespace

void block(Context& c, ir::NodeId pid, const Placing& at, Collected& out, int depth) {
  const ir::Node& p = c.m.node(pid);
  if (depth > 64) return;
  auto it = c.cache.blocks.find(pid.index);
  if (it == c.cache.blocks.end()) {
    // Paths inside a block start at the block's name (`openbox.b.top.f1`), wherever it is
    // instanced, so one evaluation serves every instance.
    c.cache.recorder.open();
    const int32_t saved_context = c.context;
    c.context = pid.index;
    c.chain.push_back(pid.index);
    std::optional<BlockResult> made = run_block(c, pid, short_name(p.name), depth);
    c.chain.pop_back();
    c.context = saved_context;
    c.counters.nodes.insert(pid.index);
    Deps d = c.cache.recorder.close();
    std::shared_ptr<const BlockResult> shared = made ? std::make_shared<const BlockResult>(std::move(*made)) : nullptr;
    it = c.cache.blocks.emplace(pid.index, Memo<std::shared_ptr<const BlockResult>>{std::move(shared), std::move(d)}).first;
  } else {
    c.cache.recorder.note(it->second.deps);
  }
  const std::shared_ptr<const BlockResult> res = it->second.value;
  if (!res) return;
  // Each placement of the result is vertices placed, like a leaf's (the block runs once).
  int64_t placed = 0;
  for (const auto& part : res->parts) placed += static_cast<int64_t>(part->soup.positions.size());
  if (!spend_vertices(c, placed, c.m.node(at.inst.is_valid() ? at.inst : pid).range, at.path)) return;
  const bool is_plain = !at.color && at.t == glm::dmat4(1.0);
  if (c.collects(out)) {
    const bool is_built = std::all_of(res->parts.begin(), res->parts.end(), [](const auto& part) { return part->built != nullptr; });
    if (is_plain && is_built) {
      for (const auto& part : res->parts) c.sink->parts.push_back({nullptr, part, part->built.get()});
      if (c.sink->is_deferred) return;
    } else {
      c.sink->is_pure = false;
      make_eager(c);
    }
  }
  for (const auto& part : res->parts) {
    if (is_plain) {
      transform_into(out, *part, at.t);
      continue;
    }
    Collected copy = *part;
    if (at.color) {
      for (size_t f = 0; f < copy.has_color.size(); ++f) {
        if (!copy.has_color[f]) {
          copy.soup.face_colors[f] = *at.color;
          copy.has_color[f] = 1;
        }
      }
    }
    transform_into(out, copy, at.t);
  }
}

}  // namespace nomec::backend::eval
