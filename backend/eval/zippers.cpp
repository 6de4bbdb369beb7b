// Zippers for the evaluator (see context.h): `zipper z border (a.v0 a.v3) border (b.v0 b.v3)`
// resolves each border list to a chain of world positions on a border loop of the instance
// it names, fills the strip between the chains (kernel::zipper) and returns the faces as an
// output mesh of their own, so a merge welds them to the instances' borders.
#include <algorithm>
#include <fmt/format.h>

#include "backend/eval/context.h"
#include "kernel/zipper.h"

namespace nomec::backend::eval {

namespace {

InstanceBorders borders_of(Context& c, const ir::VertexRef& ref) {
  InstanceBorders b;
  Placing at;
  at.t = world_of(c, ref.instances[0]);
  at.path = short_name(c.m.node(ref.instances[0]).name);
  for (size_t i = 1; i < ref.instances.size(); ++i) {
    at.t = at.t * local(c, c.m.refs(c.m.get<ir::InstanceData>(ref.instances[i]).transforms));
    at.path += "." + short_name(c.m.node(ref.instances[i]).name);
  }
  b.path = at.path;
  at.inst = ref.instances.back();
  const ir::NodeId last_target = c.m.get<ir::InstanceData>(at.inst).target;
  if (last_target.is_valid()) {
    b.target = last_target;
    Collected placed;
    target(c, last_target, at, placed, 0);
    b.soup = finish(placed);
    if (b.soup.face_count() > 0) {
      if (auto built = kernel::build_mesh(b.soup)) b.mesh = std::move(*built);
    }
  }
  if (b.mesh) {
    const kernel::Mesh& mesh = *b.mesh;
    for (int32_t l = 0; l < static_cast<int32_t>(mesh.border_loops().size()); ++l) {
      std::vector<kernel::EdgeId> es = mesh.border_loop_edges(l);
      const size_t k = es.size();
      if (k < 3) continue;
      std::vector<int32_t> seq;
      for (size_t i = 0; i < k; ++i) {
        kernel::EdgeId e = es[i], f = es[(i + 1) % k];
        kernel::VertexId e0 = mesh.edge_vertex(e, 0), e1 = mesh.edge_vertex(e, 1);
        kernel::VertexId f0 = mesh.edge_vertex(f, 0), f1 = mesh.edge_vertex(f, 1);
        seq.push_back((e0 == f0 || e0 == f1) ? e0.index : e1.index);
      }
      // Edge es[0] is traversed by its face from end 0 to end 1; make the loop agree.
      const int32_t u0 = mesh.edge_vertex(es[0], 0).index, u1 = mesh.edge_vertex(es[0], 1).index;
      auto p0 = std::find(seq.begin(), seq.end(), u0);
      if (p0 != seq.end() && seq[(p0 - seq.begin() + 1) % k] != u1) std::reverse(seq.begin(), seq.end());
      b.loops.push_back(std::move(seq));
    }
  }
  return b;
}

const InstanceBorders* instance_borders(Context& c, const ir::VertexRef& ref) {
  std::string key;
  for (ir::NodeId i : ref.instances) key += fmt::format("{}.", i.index);
  if (auto it = c.cache.borders.find(key); it != c.cache.borders.end()) {
    c.cache.recorder.note(it->second.deps);
    return &it->second.value;
  }
  c.cache.recorder.open();
  const int32_t saved_context = c.context;
  c.context = -2;  // placements made for border lookups
  InstanceBorders b = borders_of(c, ref);
  c.context = saved_context;
  Deps d = c.cache.recorder.close();
  auto [it, _] = c.cache.borders.emplace(key, Memo<InstanceBorders>{std::move(b), std::move(d)});
  return &it->second.value;
}

// A name the original gave to a vertex nomec welded onto another (Generated::aliases, e.g.
// a seam copy of a sphere or a marching-cubes copy): the border vertex at its position, or
// -1 when `wanted` is no alias of the instance's generator.
int32_t alias_vertex(Context& c, const InstanceBorders& b, const ir::Node* tn, const std::string& wanted,
                     const ir::VertexRef& r) {
  if (tn == nullptr || tn->kind != ir::NodeKind::Generator) return -1;
  const Generated* g = generated(c, b.target, b.path);
  if (g == nullptr) return -1;
  const bool is_alias = std::any_of(g->aliases.begin(), g->aliases.end(),
                                    [&](const auto& a) { return a.first == wanted; });
  if (!is_alias) return -1;
  const std::optional<glm::dvec3> p = ref_position(c, r, b.path);  // resolves: it is an alias
  if (!p) return -1;
  int32_t best = -1;
  double best_d = 0.0;
  for (size_t i = 0; i < b.soup.positions.size(); ++i) {
    const glm::dvec3 d = b.soup.positions[i] - *p;
    const double dd = d.x * d.x + d.y * d.y + d.z * d.z;
    if (best < 0 || dd < best_d) {
      best = static_cast<int32_t>(i);
      best_d = dd;
    }
  }
  const double scale = 1.0 + std::max({std::abs(p->x), std::abs(p->y), std::abs(p->z)});
  return best >= 0 && best_d <= (1e-9 * scale) * (1e-9 * scale) ? best : -1;
}

// One `border (A0 [A1 [Am]])` list as a chain; `is_backward` says an open path runs
// against the direction its faces traverse the border.
std::optional<kernel::ZipperChain> border_chain(Context& c, const ir::Node& zn, const std::string& zname,
                                                std::span<const ir::VertexRef> refs, bool& is_backward) {
  if (refs.empty() || refs.size() > 3) return std::nullopt;  // the checker reported it
  const InstanceBorders* ib = nullptr;
  std::vector<std::pair<size_t, size_t>> where;  // (loop, position) per reference
  for (const ir::VertexRef& r : refs) {
    if (r.instances.empty() || std::any_of(r.instances.begin(), r.instances.end(),
                                           [](ir::NodeId i) { return !i.is_valid(); })) {
      c.diags().emit(DiagKind::GeometryFailed, zn.range,
                  fmt::format("zipper `{}`: `{}` is not a vertex of an instance; zipper borders "
                              "name instance vertices such as `inst.v`",
                              zname, r.text));
      return std::nullopt;
    }
    const InstanceBorders* b = instance_borders(c, r);
    if (ib != nullptr && b != ib) {
      c.diags().emit(DiagKind::GeometryFailed, zn.range,
                  fmt::format("zipper `{}`: `{}` and `{}` belong to different instances; the "
                              "vertices of one `border` must lie on one border loop",
                              zname, refs[0].text, r.text));
      return std::nullopt;
    }
    ib = b;
    const ir::Node* tn = b->target.is_valid() ? &c.m.node(b->target) : nullptr;
    const std::string wanted = tn != nullptr && tn->kind == ir::NodeKind::Generator
                                   ? ir::canonical_vertex_name(tn->as<ir::GeneratorData>().gen, r.vertex)
                                   : r.vertex;
    int32_t v = -1;
    for (size_t i = 0; i < b->soup.names.size(); ++i) {
      if (b->soup.names[i] == wanted || b->soup.names[i] == r.vertex) {
        v = static_cast<int32_t>(i);
        break;
      }
    }
    if (v < 0) v = alias_vertex(c, *b, tn, wanted, r);
    if (v < 0) {
      c.diags().emit(DiagKind::GeometryFailed, zn.range,
                  fmt::format("zipper `{}`: `{}` names no vertex of instance `{}`", zname, r.text,
                              b->path));
      return std::nullopt;
    }
    bool found = false;
    for (size_t l = 0; l < b->loops.size() && !found; ++l) {
      auto p = std::find(b->loops[l].begin(), b->loops[l].end(), v);
      if (p != b->loops[l].end()) {
        where.emplace_back(l, static_cast<size_t>(p - b->loops[l].begin()));
        found = true;
      }
    }
    if (!found) {
      c.diags().emit(DiagKind::GeometryFailed, zn.range,
                  fmt::format("zipper `{}`: vertex `{}` is not on a border of instance `{}`",
                              zname, r.text, b->path));
      return std::nullopt;
    }
  }
  for (size_t i = 1; i < where.size(); ++i) {
    if (where[i].first != where[0].first) {
      c.diags().emit(DiagKind::GeometryFailed, zn.range,
                  fmt::format("zipper `{}`: `{}` and `{}` are on different border loops of "
                              "instance `{}`",
                              zname, refs[0].text, refs[i].text, ib->path));
      return std::nullopt;
    }
  }
  const std::vector<int32_t>& loop = ib->loops[where[0].first];
  const size_t k = loop.size();
  kernel::ZipperChain chain;
  is_backward = false;
  const size_t s = where[0].second;
  if (refs.size() == 1 || where[1].second == s) {
    chain.is_closed = true;
    for (size_t i = 0; i < k; ++i) chain.points.push_back(ib->soup.positions[loop[(s + i) % k]]);
    return chain;
  }
  const size_t e = where[1].second;
  const size_t forward_len = (e + k - s) % k;   // edges walking along the loop
  const size_t backward_len = (s + k - e) % k;  // edges walking against it
  bool forward = forward_len <= backward_len;
  if (refs.size() == 3) {
    const size_t mid = where[2].second;
    forward = (mid + k - s) % k <= forward_len;
  }
  const size_t len = forward ? forward_len : backward_len;
  for (size_t i = 0; i <= len; ++i) {
    size_t at = forward ? (s + i) % k : (s + k - i % k) % k;
    chain.points.push_back(ib->soup.positions[loop[at]]);
  }
  is_backward = !forward;
  return chain;
}

// A `zipper` statement: resolves its two `border` vertex lists to chains of world
// positions on the border loops of the instances they name, fills the strip between
// them (kernel::zipper) and returns the faces as an output mesh of their own, so a merge
// welds them to the instances' borders (the positions coincide).
bool zipper(Context& c, ir::NodeId zid, OutputMesh& out) {
  const ir::Node& n = c.m.node(zid);
  const std::string zname = short_name(n.name);
  const ir::ZipperData& zd = n.as<ir::ZipperData>();
  if (zd.border_count != 2) return false;  // the checker reported it
  kernel::ZipperChain chain[2];
  bool is_backward[2] = {false, false};
  for (int k = 0; k < 2; ++k) {
    auto made = border_chain(c, n, zname, c.m.refs(zd.borders[k]), is_backward[k]);
    if (!made) return false;
    chain[k] = std::move(*made);
  }
  // Chain A must run the way its own faces traverse the border (see kernel/zipper.h);
  // reversing both open chains keeps their end vertices paired.
  if (!chain[0].is_closed && is_backward[0]) {
    std::reverse(chain[0].points.begin(), chain[0].points.end());
    std::reverse(chain[1].points.begin(), chain[1].points.end());
  }
  kernel::ZipperOptions o;
  if (zd.penalty.is_valid()) o.penalty = scalar(c, zd.penalty, 0, 1.3);
  auto r = kernel::zipper(chain[0], chain[1], o);
  ++c.counters.kernel_ops;
  if (!r) {
    c.diags().emit(DiagKind::GeometryFailed, n.range,
                fmt::format("zipper `{}`: {}", zname, r.error().message));
    return false;
  }
  out.name = zname;
  out.scene_node = zid;
  out.soup = std::move(r->soup);
  out.soup.face_sources.assign(out.soup.face_count(), kernel::FaceSource{zid.index, -1});
  auto built = kernel::build_mesh(out.soup);
  if (!built) {
    report(c, built.error(), out.soup, n.range, zname);
    return false;
  }
  out.mesh = std::move(*built);
  return true;
}

}  // namespace

// `zipper` statement `id` as an output mesh (null on failure), memoized when incremental.
std::shared_ptr<const OutputMesh> zipper_entry(Context& c, ir::NodeId id) {
  if (auto it = c.cache.zippers.find(id.index); it != c.cache.zippers.end()) return it->second.value;
  c.cache.recorder.open();
  auto m = std::make_shared<OutputMesh>();
  const bool ok = zipper(c, id, *m);
  Deps d = c.cache.recorder.close();
  std::shared_ptr<const OutputMesh> out = ok ? std::move(m) : nullptr;
  c.counters.nodes.insert(id.index);
  if (out) c.counters.new_outputs.push_back(out.get());
  if (c.is_incremental) c.cache.zippers[id.index] = {out, std::move(d)};
  return out;
}

}  // namespace nomec::backend::eval
