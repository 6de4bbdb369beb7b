// Scene evaluation: walks the IR scene, composes transform chains, instantiates meshes and
// generators, runs pipeline blocks through the kernel and turns kernel and generator
// failures into located diagnostics (see evaluate.h).
#include "backend/evaluate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <unordered_map>
#include <variant>

#include "backend/generators/generators.h"
#include "backend/generators/names.h"
#include "kernel/edit.h"
#include "kernel/merge.h"
#include "kernel/offset.h"
#include "kernel/topology.h"
#include "kernel/zipper.h"

namespace nomec::backend {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

std::string short_name(std::string_view qualified) {
  size_t dot = qualified.rfind('.');
  return std::string(dot == std::string_view::npos ? qualified : qualified.substr(dot + 1));
}

const ir::Field* find_field(const ir::Node& n, std::string_view name) {
  for (const ir::Field& f : n.fields) {
    if (f.name == name) {
      return &f;
    }
  }
  return nullptr;
}

// Faces collected for one scene entry or one pipeline block's input.
//
// Rationale: the soup is the kernel's input format, so faces are appended to it directly;
// the parallel arrays hold what the soup has no room for: whether a face got a colour
// (uncoloured faces get a neutral grey only if some face is coloured) and the face's scene
// path (`cf.fun3.f1`) for `delete` edits.
struct Collected {
  kernel::PolygonSoup soup;
  std::vector<uint8_t> has_color;
  std::vector<std::string> face_paths;
  int32_t curve_count = 0;
  // A pipeline block's result: `soup` already built (lets an incremental entry reuse it).
  std::shared_ptr<const kernel::Mesh> built;
};

// A pipeline block's result: the results of its clusters of input parts, in order (one
// part when it ran on its whole input).
struct BlockResult {
  std::vector<std::shared_ptr<const Collected>> parts;
};

constexpr glm::vec3 kDefaultColor{0.8f, 0.8f, 0.8f};

// Appends `part` (already in its own frame) to `out` transformed by `t`.
void append_soup(Collected& out, const kernel::PolygonSoup& part, const glm::dmat4& t,
                 const std::optional<glm::vec3>& color, bool part_colored) {
  const int32_t base = out.soup.vertex_count();
  const bool flip = glm::determinant(glm::dmat3(t)) < 0;
  for (int32_t v = 0; v < part.vertex_count(); ++v) {
    glm::dvec3 p = glm::dvec3(t * glm::dvec4(part.positions[v], 1.0));
    std::string name = part.names.empty() ? std::string() : part.names[v];
    if (!out.soup.names.empty() || !name.empty()) {
      out.soup.names.resize(out.soup.positions.size());
      out.soup.names.push_back(std::move(name));
    }
    out.soup.positions.push_back(p);
  }
  size_t at = 0;
  std::vector<int32_t> face;
  for (int32_t f = 0; f < part.face_count(); ++f) {
    face.assign(part.face_vertices.begin() + at, part.face_vertices.begin() + at + part.face_sizes[f]);
    at += part.face_sizes[f];
    for (int32_t& v : face) {
      v += base;
    }
    if (flip) {
      std::reverse(face.begin() + 1, face.end());
    }
    out.soup.add_face(face);
    out.soup.face_sources.push_back(part.face_sources.empty() ? kernel::FaceSource{}
                                                              : part.face_sources[f]);
    if (part_colored && !part.face_colors.empty()) {
      out.soup.face_colors.push_back(part.face_colors[f]);
      out.has_color.push_back(1);
    } else {
      out.soup.face_colors.push_back(color.value_or(kDefaultColor));
      out.has_color.push_back(color.has_value() ? 1 : 0);
    }
    out.face_paths.emplace_back();
  }
  for (const auto& c : part.creases) {
    out.soup.creases.push_back({c.a + base, c.b + base, c.sharpness});
  }
  for (const auto& c : part.corners) {
    out.soup.corners.push_back({c.vertex + base, c.sharpness});
  }
}

// `append_soup` of a whole collection with the identity transform (what reassembling a
// scene entry from cached parts does for every part), in bulk copies.
void append_collected(Collected& out, const Collected& c) {
  const kernel::PolygonSoup& part = c.soup;
  kernel::PolygonSoup& s = out.soup;
  const int32_t base = s.vertex_count();
  const bool part_named =
      std::any_of(part.names.begin(), part.names.end(), [](const std::string& n) { return !n.empty(); });
  if (!s.names.empty() || part_named) {
    s.names.resize(static_cast<size_t>(base));
    s.names.insert(s.names.end(), part.names.begin(), part.names.end());
    s.names.resize(static_cast<size_t>(base) + part.positions.size());
  }
  s.positions.insert(s.positions.end(), part.positions.begin(), part.positions.end());
  s.face_sizes.insert(s.face_sizes.end(), part.face_sizes.begin(), part.face_sizes.end());
  const size_t at = s.face_vertices.size();
  s.face_vertices.insert(s.face_vertices.end(), part.face_vertices.begin(), part.face_vertices.end());
  for (size_t i = at; i < s.face_vertices.size(); ++i) s.face_vertices[i] += base;
  const size_t faces = part.face_sizes.size();
  if (part.face_sources.empty()) {
    s.face_sources.insert(s.face_sources.end(), faces, kernel::FaceSource{});
  } else {
    s.face_sources.insert(s.face_sources.end(), part.face_sources.begin(), part.face_sources.end());
  }
  if (part.face_colors.empty()) {
    s.face_colors.insert(s.face_colors.end(), faces, kDefaultColor);
  } else {
    s.face_colors.insert(s.face_colors.end(), part.face_colors.begin(), part.face_colors.end());
  }
  out.has_color.insert(out.has_color.end(), c.has_color.begin(), c.has_color.end());
  out.face_paths.insert(out.face_paths.end(), c.face_paths.begin(), c.face_paths.end());
  for (const auto& k : part.creases) s.creases.push_back({k.a + base, k.b + base, k.sharpness});
  for (const auto& k : part.corners) s.corners.push_back({k.vertex + base, k.sharpness});
  out.curve_count += c.curve_count;
}

bool is_soup_edge(const kernel::PolygonSoup& s, int32_t a, int32_t b) {
  size_t at = 0;
  for (int32_t f = 0; f < s.face_count(); ++f) {
    const int32_t n = s.face_sizes[f];
    for (int32_t i = 0; i < n; ++i) {
      int32_t u = s.face_vertices[at + i], w = s.face_vertices[at + (i + 1) % n];
      if ((u == a && w == b) || (u == b && w == a)) return true;
    }
    at += n;
  }
  return false;
}

// Drops the colour array when no face was given a colour.
kernel::PolygonSoup finish(Collected& c) {
  if (std::none_of(c.has_color.begin(), c.has_color.end(), [](uint8_t b) { return b != 0; })) {
    c.soup.face_colors.clear();
  }
  if (!c.soup.names.empty()) {
    c.soup.names.resize(c.soup.positions.size());
  }
  return std::move(c.soup);
}


// One step applied to a merged mesh: Catmull-Clark levels, an offset slab or a lattice.
struct Step {
  enum class Kind : uint8_t { Subdivide, Offset, Lattice };
  Kind kind = Kind::Subdivide;
  kernel::SubdivisionOptions subdivision;
  double height = 0;
  double width = 0;
  friend bool operator==(const Step& a, const Step& b) {
    return a.kind == b.kind && a.height == b.height && a.width == b.width &&
           a.subdivision.levels == b.subdivision.levels &&
           a.subdivision.vertex_rule == b.subdivision.vertex_rule &&
           a.subdivision.is_sharpness_honoured == b.subdivision.is_sharpness_honoured;
  }
};

// A failed step: the kernel's error and which step it was.
struct StepFailure {
  kernel::KernelError error;
  size_t step = 0;
};

// Runs `steps` in order on `mesh`; counts one kernel operation per step run.
std::variant<kernel::Mesh, StepFailure> run_steps(kernel::Mesh mesh, const std::vector<Step>& steps,
                                                  int32_t& kernel_ops) {
  for (size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    if (s.kind == Step::Kind::Subdivide) {
      if (s.subdivision.levels <= 0) continue;
      ++kernel_ops;
      auto r = kernel::subdivide(mesh, s.subdivision);
      if (!r) return StepFailure{r.error(), i};
      if (!r->empty()) mesh = std::move(r->back().mesh);
    } else {
      ++kernel_ops;
      auto r = s.kind == Step::Kind::Lattice
                   ? kernel::lattice(mesh, kernel::LatticeOptions{s.width, s.height})
                   : kernel::offset(mesh, kernel::OffsetOptions{s.height});
      if (!r) return StepFailure{r.error(), i};
      mesh = std::move(r->mesh);
    }
  }
  return mesh;
}

bool same_soup(const kernel::PolygonSoup& a, const kernel::PolygonSoup& b) {
  auto same_creases = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::equal(x.begin(), x.end(), y.begin(), [](const auto& c, const auto& d) {
             return c.a == d.a && c.b == d.b && c.sharpness == d.sharpness;
           });
  };
  auto same_corners = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::equal(x.begin(), x.end(), y.begin(), [](const auto& c, const auto& d) {
             return c.vertex == d.vertex && c.sharpness == d.sharpness;
           });
  };
  return a.positions == b.positions && a.face_sizes == b.face_sizes &&
         a.face_vertices == b.face_vertices && a.face_sources == b.face_sources &&
         a.face_colors == b.face_colors && a.names == b.names && same_creases(a.creases, b.creases) &&
         same_corners(a.corners, b.corners);
}

uint64_t soup_hash(const kernel::PolygonSoup& s) {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&](const void* data, size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  mix(s.positions.data(), s.positions.size() * sizeof(glm::dvec3));
  mix(s.face_vertices.data(), s.face_vertices.size() * sizeof(int32_t));
  mix(s.face_sizes.data(), s.face_sizes.size() * sizeof(int32_t));
  return h;
}

// The results of running steps on the connected components of one block's merged mesh,
// kept for the next evaluation of the block (docs/incremental.md).
struct ComponentMemo {
  struct Entry {
    uint64_t hash = 0;
    kernel::PolygonSoup input;
    std::vector<Step> steps;
    kernel::Mesh output;
  };
  std::vector<Entry> entries;
};

// Splits `mesh` into one soup per connected component (faces in their original order).
std::vector<kernel::PolygonSoup> split_components(const kernel::Mesh& mesh) {
  std::vector<int32_t> comp = kernel::face_components(mesh);
  int32_t count = 0;
  for (int32_t c : comp) count = std::max(count, c + 1);
  kernel::PolygonSoup all = kernel::to_soup(mesh);
  std::vector<kernel::PolygonSoup> parts(count);
  std::vector<int32_t> local(all.vertex_count(), -1), owner(all.vertex_count(), -1);
  size_t at = 0;
  std::vector<int32_t> face;
  for (int32_t f = 0; f < all.face_count(); ++f) {
    kernel::PolygonSoup& p = parts[comp[f]];
    face.clear();
    for (int32_t i = 0; i < all.face_sizes[f]; ++i) {
      int32_t v = all.face_vertices[at + i];
      if (owner[v] != comp[f]) {
        owner[v] = comp[f];
        local[v] = p.add_vertex(all.positions[v], all.names.empty() ? std::string() : all.names[v]);
      }
      face.push_back(local[v]);
    }
    at += all.face_sizes[f];
    p.add_face(face);
    if (!all.face_sources.empty()) p.face_sources.push_back(all.face_sources[f]);
    if (!all.face_colors.empty()) p.face_colors.push_back(all.face_colors[f]);
  }
  for (kernel::PolygonSoup& p : parts) {
    if (all.names.empty()) p.names.clear();
  }
  for (const auto& c : all.creases) {
    if (owner[c.a] >= 0 && owner[c.a] == owner[c.b]) {
      parts[owner[c.a]].creases.push_back({local[c.a], local[c.b], c.sharpness});
    }
  }
  for (const auto& c : all.corners) {
    if (owner[c.vertex] >= 0) parts[owner[c.vertex]].corners.push_back({local[c.vertex], c.sharpness});
  }
  return parts;
}

// Runs `steps` on each connected component of `mesh` separately, reusing the result of a
// component whose input soup and steps equal an entry of `pool` (which is moved out), and
// concatenates the results in component order; every component used is appended to
// `next`. Falls back to the whole mesh (so errors are exactly those of a one-shot run)
// when a component fails or the mesh has vertices no face uses.
std::variant<kernel::Mesh, StepFailure> run_steps_by_component(const kernel::Mesh& mesh,
                                                               const std::vector<Step>& steps,
                                                               ComponentMemo& pool, ComponentMemo& next,
                                                               int32_t& kernel_ops) {
  std::vector<kernel::PolygonSoup> parts = split_components(mesh);
  size_t used_vertices = 0;
  for (const auto& p : parts) used_vertices += p.positions.size();
  if (used_vertices != static_cast<size_t>(mesh.vertex_count())) return run_steps(mesh, steps, kernel_ops);
  std::unordered_multimap<uint64_t, size_t> by_hash;
  for (size_t i = 0; i < pool.entries.size(); ++i) by_hash.emplace(pool.entries[i].hash, i);
  const size_t first = next.entries.size();
  for (kernel::PolygonSoup& p : parts) {
    const uint64_t h = soup_hash(p);
    ComponentMemo::Entry* hit = nullptr;
    auto [lo, hi] = by_hash.equal_range(h);
    for (auto it = lo; it != hi; ++it) {
      ComponentMemo::Entry& e = pool.entries[it->second];
      if (e.hash == h && e.steps == steps && same_soup(e.input, p)) {
        hit = &e;
        break;
      }
    }
    if (hit != nullptr) {
      next.entries.push_back(std::move(*hit));
      hit->hash = ~h;  // moved from; never matches again
      hit->input = {};
      continue;
    }
    auto built = kernel::build_mesh(p);
    if (!built) {
      next.entries.resize(first);
      return run_steps(mesh, steps, kernel_ops);
    }
    auto r = run_steps(std::move(*built), steps, kernel_ops);
    if (std::holds_alternative<StepFailure>(r)) {
      next.entries.resize(first);
      return run_steps(mesh, steps, kernel_ops);
    }
    next.entries.push_back({h, std::move(p), steps, std::move(std::get<kernel::Mesh>(r))});
  }
  std::vector<const kernel::Mesh*> outs;
  for (size_t i = first; i < next.entries.size(); ++i) outs.push_back(&next.entries[i].output);
  if (outs.size() == 1) return *outs[0];
  return kernel::append_disjoint(outs);
}

// The bounding boxes of a block's input part (all its used vertices, and its border
// vertices), kept with the part object they describe.
struct PartBounds {
  std::shared_ptr<const Collected> part;
  kernel::BoundingBox all;
  kernel::BoundingBox border;  // empty (min > max) if the part has no border
};

// One cluster of a block's input parts (see `run_block_by_clusters`) and its result.
struct ClusterMemo {
  std::vector<std::shared_ptr<const Collected>> parts;
  double tolerance = 0;
  std::vector<Step> steps;
  bool any_color = false;
  std::shared_ptr<const Collected> result;
  ComponentMemo components;
};

// What a block keeps between evaluations: per-part bounds and per-cluster results when it
// ran by clusters, or the per-component results when it ran on its whole input.
struct BlockMemo {
  std::unordered_map<const Collected*, PartBounds> bounds;
  std::vector<ClusterMemo> clusters;
  ComponentMemo components;
};

}  // namespace

namespace detail {

class Evaluator {
 public:
  Evaluator(const ir::Module& m, bool is_incremental) : m_(m), is_incremental_(is_incremental) {
    kids_.resize(m.nodes.size());
    for (size_t i = 0; i < m.nodes.size(); ++i) {
      ir::NodeId p = m.nodes[i].parent;
      if (p.is_valid()) {
        kids_[p.index].push_back(ir::NodeId{static_cast<int32_t>(i)});
      }
    }
    for (size_t i = 0; i < m.nodes.size(); ++i) {
      const ir::Node& n = m.nodes[i];
      if (n.kind == ir::NodeKind::Edit && n.keyword == "delete") {
        if (const ir::Field* f = find_field(n, "faces")) {
          size_t start = 0;
          const std::string& t = f->text;
          while (start < t.size()) {
            size_t end = t.find(' ', start);
            if (end == std::string::npos) end = t.size();
            if (end > start) deleted_.push_back(normalize(t.substr(start, end - start)));
            start = end + 1;
          }
        }
      }
    }
  }

  // ---- Memoization (docs/incremental.md) ----
  // Every cached value carries the parameters it read (directly, or through the cached
  // values it used) and whether its evaluation emitted a diagnostic. Values are computed
  // inside a frame that collects those reads; a cache hit adds the stored reads to the
  // enclosing frame, so a scene entry knows every parameter its meshes depend on.
  struct Deps {
    std::vector<int32_t> params;  // sorted parameter node indices
    bool is_tainted = false;      // emitted a diagnostic: recompute next pass to re-report
  };
  template <typename T>
  struct Memo {
    T value;
    Deps deps;
  };

  void begin_pass(DiagnosticEngine& diags) { diags_ = &diags; }

  // Drops every cached value that read `param` (or any tainted value when `param` < 0).
  void invalidate(int32_t param) {
    auto stale = [param](const Deps& d) {
      return d.is_tainted || std::binary_search(d.params.begin(), d.params.end(), param);
    };
    auto drop = [&](auto& map) { std::erase_if(map, [&](const auto& kv) { return stale(kv.second.deps); }); };
    drop(expr_memo_);
    drop(generated_);
    drop(sweeps_);
    drop(world_);
    drop(placements_);
    drop(pipeline_cache_);
    drop(borders_cache_);
    drop(entries_);
    drop(zippers_);
  }

  EvalCounters counters;

  // Scene entry `id` as an output mesh (null if it produced nothing), memoized when
  // incremental.
  std::shared_ptr<const OutputMesh> entry(ir::NodeId id) {
    if (auto it = entries_.find(id.index); it != entries_.end()) {
      return it->second.value;
    }
    open_frame();
    context_ = id.index;
    auto m = std::make_shared<OutputMesh>();
    entry_assembled_ = false;
    const bool ok = scene_entry(id, *m);
    Deps d = close_frame();
    std::shared_ptr<const OutputMesh> out = ok ? std::move(m) : nullptr;
    counters.nodes.insert(id.index);
    if (out) counters.new_outputs.push_back(out.get());
    if (is_incremental_) {
      entries_[id.index] = {out, std::move(d)};
      // The layout an update may patch instead of reassembling (see `patch_entry`).
      if (ok && entry_assembled_) {
        EntryLayout& l = layouts_[id.index];
        l.out = out;
        l.direct_curves = entry_direct_curves_;
        l.parts.clear();
        for (const EntryPart& p : entry_parts_) l.parts.push_back(p.part);
      } else {
        layouts_.erase(id.index);
      }
    }
    entry_parts_.clear();
    return out;
  }

  // `zipper` statement `id` as an output mesh (null on failure), memoized when incremental.
  std::shared_ptr<const OutputMesh> zipper_entry(ir::NodeId id) {
    if (auto it = zippers_.find(id.index); it != zippers_.end()) return it->second.value;
    open_frame();
    auto m = std::make_shared<OutputMesh>();
    const bool ok = zipper(id, *m);
    Deps d = close_frame();
    std::shared_ptr<const OutputMesh> out = ok ? std::move(m) : nullptr;
    counters.nodes.insert(id.index);
    if (out) counters.new_outputs.push_back(out.get());
    if (is_incremental_) zippers_[id.index] = {out, std::move(d)};
    return out;
  }

 private:
  struct Frame {
    std::vector<int32_t> params;
    size_t diag_mark = 0;
    bool is_tainted = false;
  };
  std::vector<Frame> frames_;

  void open_frame() { frames_.push_back({{}, diags_->diagnostics().size(), false}); }
  Deps close_frame() {
    Frame f = std::move(frames_.back());
    frames_.pop_back();
    std::sort(f.params.begin(), f.params.end());
    f.params.erase(std::unique(f.params.begin(), f.params.end()), f.params.end());
    Deps d{std::move(f.params), f.is_tainted || diags_->diagnostics().size() != f.diag_mark};
    note(d);
    return d;
  }
  // Adds reads to the innermost open frame.
  void note(const Deps& d) {
    if (frames_.empty()) return;
    Frame& f = frames_.back();
    f.params.insert(f.params.end(), d.params.begin(), d.params.end());
    f.is_tainted = f.is_tainted || d.is_tainted;
  }
  // The parameters an expression reads, computed once per expression.
  const std::vector<int32_t>& expr_params(ir::ExprId id) {
    if (auto it = expr_params_.find(id.index); it != expr_params_.end()) return it->second;
    std::vector<int32_t> ps;
    std::vector<ir::ExprId> todo{id};
    while (!todo.empty() && todo.size() < 100000) {
      ir::ExprId e = todo.back();
      todo.pop_back();
      if (!e.is_valid()) continue;
      const ir::Expr& x = m_.expr(e);
      if (x.kind == ir::ExprKind::Param && x.param.is_valid()) ps.push_back(x.param.index);
      todo.push_back(x.lhs);
      todo.push_back(x.rhs);
      todo.insert(todo.end(), x.args.begin(), x.args.end());
    }
    std::sort(ps.begin(), ps.end());
    ps.erase(std::unique(ps.begin(), ps.end()), ps.end());
    return expr_params_.emplace(id.index, std::move(ps)).first->second;
  }

 public:
  std::map<int32_t, std::string> instance_paths;

  // Evaluates one scene entry into an output mesh (false if it produced nothing).
  bool scene_entry(ir::NodeId id, OutputMesh& out) {
    const ir::Node& n = m_.node(id);
    Collected c;
    // Parts are appended to `c` only when needed: a patched update never copies them.
    Sink sink;
    sink.out = &c;
    sink.is_deferred = is_incremental_ && deleted_.empty();
    Sink* const saved_sink = sink_;
    sink_ = is_incremental_ ? &sink : nullptr;
    entry_parts_.clear();
    if (n.kind == ir::NodeKind::Instance) {
      instance(id, glm::dmat4(1.0), std::nullopt, "", c, 0);
    } else if (n.kind == ir::NodeKind::Pipeline) {
      pipeline(id, glm::dmat4(1.0), std::nullopt, short_name(n.name), c, 0);
    } else if (n.kind == ir::NodeKind::Group) {
      // A SLIDE world group (see evaluate_scene).
      target(id, glm::dmat4(1.0), std::nullopt, short_name(n.name), ir::NodeId::None(), c, 0);
    } else if (n.kind == ir::NodeKind::Mesh) {
      // A saved consolidated mesh that nothing instances (its vertices are world positions).
      Collected m;
      mesh(id, std::nullopt, short_name(n.name), ir::NodeId::None(), m);
      sink.is_pure = false;
      if (sink_ != nullptr) make_eager();
      transform_into(c, m, glm::dmat4(1.0));
    } else {
      sink_ = saved_sink;
      return false;
    }
    sink_ = saved_sink;
    entry_parts_ = std::move(sink.parts);
    entry_direct_curves_ = sink.direct_curves;
    const bool can_assemble = is_incremental_ && sink.is_pure && deleted_.empty() && !entry_parts_.empty();
    if (sink.is_deferred) {
      entry_direct_curves_ = c.curve_count;
      if (can_assemble && patch_entry(id, c.curve_count, out)) {
        entry_assembled_ = true;
        return true;
      }
      for (const EntryPart& p : entry_parts_) append_collected(c, *p.part);
    }
    apply_deletes(c);
    out.name = short_name(n.name);
    out.scene_node = id;
    out.curve_count = c.curve_count;
    if (c.soup.face_count() == 0 && c.curve_count == 0) {
      return false;
    }
    out.soup = finish(c);
    if (can_assemble) {
      if (auto m = assemble(out.soup)) {
        out.mesh = std::move(*m);
        entry_assembled_ = true;
        return true;
      }
    }
    auto built = kernel::build_mesh(out.soup);
    if (!built) {
      report(built.error(), out.soup, n.range, out.name);
      return false;
    }
    out.mesh = std::move(*built);
    return true;
  }

  // Converts a kernel error into a diagnostic at the face statement that caused it.
  void report(const kernel::KernelError& e, const kernel::PolygonSoup& soup, SourceRange fallback,
              std::string_view what) {
    DiagKind kind = e.kind == kernel::KernelError::Kind::NonManifoldEdge ||
                            e.kind == kernel::KernelError::Kind::NonManifoldVertex ||
                            e.kind == kernel::KernelError::Kind::NonManifoldMerge
                        ? DiagKind::NonManifoldGeometry
                        : DiagKind::GeometryFailed;
    std::vector<std::pair<SourceRange, std::string>> places;
    for (kernel::FaceId f : e.faces) {
      if (f.index < 0 || static_cast<size_t>(f.index) >= soup.face_sources.size()) continue;
      const kernel::FaceSource& s = soup.face_sources[f.index];
      SourceRange r = s.source_face >= 0 ? m_.nodes[s.source_face].range : fallback;
      std::string label;
      if (s.source_face >= 0) {
        const ir::Node& src = m_.nodes[s.source_face];
        label = src.kind == ir::NodeKind::Face ? fmt::format("face `{}`", short_name(src.name))
                                               : fmt::format("`{}` `{}`", src.keyword, short_name(src.name));
      }
      auto it = instance_paths.find(s.instance);
      if (it != instance_paths.end()) {
        label += fmt::format(" of instance `{}`", it->second);
      }
      places.emplace_back(r, label);
      if (places.size() >= 4) break;
    }
    std::string where = places.empty() ? fmt::format(" in `{}`", what) : fmt::format(" ({})", places[0].second);
    SourceRange at = places.empty() ? fallback : places[0].first;
    std::string message = fmt::format("{}{}", e.message, where);
    auto d = kind == DiagKind::NonManifoldGeometry
                 ? diags_->emit(DiagKind::NonManifoldGeometry, at, std::move(message))
                 : diags_->emit(DiagKind::GeometryFailed, at, std::move(message));
    for (size_t i = 1; i < places.size(); ++i) {
      d.note(places[i].first, fmt::format("also involves {}", places[i].second));
    }
  }

 private:
  static std::string normalize(std::string s) {
    std::replace(s.begin(), s.end(), '.', '_');
    return s;
  }

  void apply_deletes(Collected& c) {
    if (deleted_.empty()) return;
    std::vector<uint8_t> drop(c.soup.face_count(), 0);
    bool any = false;
    for (int32_t f = 0; f < c.soup.face_count(); ++f) {
      if (c.face_paths[f].empty()) continue;
      // Alternatives are separated by '|': `cube1.c4|cube1.3` (by name and by index).
      std::string all = normalize(c.face_paths[f]);
      size_t start = 0;
      while (start <= all.size()) {
        size_t end = all.find('|', start);
        if (end == std::string::npos) end = all.size();
        std::string_view p(all.data() + start, end - start);
        for (const std::string& d : deleted_) {
          if (p == d || (p.size() > d.size() && p.ends_with(d) && p[p.size() - d.size() - 1] == '_')) {
            drop[f] = 1;
            any = true;
          }
        }
        start = end + 1;
      }
    }
    if (!any) return;
    // Prefer the kernel's deletion on the built mesh: it removes unused edges and vertices
    // and splits vertices left pinched between two fans. If the full mesh cannot be built
    // (e.g. the deleted face is what made it non-manifold), drop the faces from the soup.
    if (auto full = kernel::build_mesh(c.soup)) {
      std::vector<kernel::FaceId> ids;
      for (int32_t f = 0; f < c.soup.face_count(); ++f) {
        if (drop[f]) ids.push_back(kernel::FaceId(f));
      }
      ++counters.kernel_ops;
      if (auto del = kernel::delete_faces(*full, ids)) {
        Collected k;
        k.soup = kernel::to_soup(del->mesh);
        k.curve_count = c.curve_count;
        if (k.soup.face_colors.size() != static_cast<size_t>(k.soup.face_count())) {
          k.soup.face_colors.assign(k.soup.face_count(), kDefaultColor);
        }
        for (kernel::FaceId parent : del->face_parents) {
          k.has_color.push_back(c.has_color[parent.index]);
          k.face_paths.push_back(c.face_paths[parent.index]);
        }
        c = std::move(k);
        return;
      }
    }
    Collected k;
    k.soup.positions = c.soup.positions;
    k.soup.names = c.soup.names;
    k.soup.creases = c.soup.creases;
    k.soup.corners = c.soup.corners;
    k.curve_count = c.curve_count;
    size_t at = 0;
    for (int32_t f = 0; f < c.soup.face_count(); ++f) {
      int32_t n = c.soup.face_sizes[f];
      if (!drop[f]) {
        k.soup.add_face(std::span<const int32_t>(c.soup.face_vertices.data() + at, n));
        k.soup.face_sources.push_back(c.soup.face_sources[f]);
        k.soup.face_colors.push_back(c.soup.face_colors[f]);
        k.has_color.push_back(c.has_color[f]);
        k.face_paths.push_back(c.face_paths[f]);
      }
      at += n;
    }
    // Creases whose edge vanished with the faces would be refused by the kernel.
    c = std::move(k);
  }

  double scalar(const ir::Field& f, size_t i, double fallback) {
    if (i >= f.exprs.size()) return fallback;
    const ir::ExprId e = f.exprs[i];
    auto memo = expr_memo_.find(e.index);
    if (memo == expr_memo_.end()) {
      memo = expr_memo_.emplace(e.index, Memo<ir::EvalResult>{ir::evaluate(m_, e), Deps{expr_params(e), false}}).first;
      if (f.value_node.is_valid()) counters.nodes.insert(f.value_node.index);
    }
    note(memo->second.deps);
    const ir::EvalResult& r = memo->second.value;
    if (!r.ok) {
      // An empty problem means an expression the checker could not type (it reported why,
      // e.g. a value only Tcl code defines); the geometry cannot be built without it.
      diags_->emit(DiagKind::GeometryFailed, r.where.is_valid() ? r.where : f.range,
                  r.problem.empty()
                      ? fmt::format("cannot evaluate `{}`: the value is not known to nomec (see "
                                    "the front end's diagnostics for it), so the geometry "
                                    "cannot be built",
                                    f.name)
                      : fmt::format("cannot evaluate `{}`: {}", f.name, r.problem));
      return fallback;
    }
    return r.value;
  }

  glm::dvec3 vec3(const ir::Field& f, double fallback = 0) {
    return {scalar(f, 0, fallback), scalar(f, 1, fallback), scalar(f, 2, fallback)};
  }

  // The transform chain of an instance, in written order (first written acts first).
  glm::dmat4 local(const ir::Node& inst) {
    glm::dmat4 t(1.0);
    for (const ir::Field& f : inst.fields) {
      glm::dmat4 step(1.0);
      if (f.name == "translate" && f.kind == ir::FieldKind::Vector) {
        step = glm::translate(glm::dmat4(1.0), vec3(f));
      } else if (f.name == "scale" && f.kind == ir::FieldKind::Vector) {
        step = glm::scale(glm::dmat4(1.0), vec3(f, 1));
      } else if (f.name == "rotate" && f.kind == ir::FieldKind::Vector) {
        glm::dvec3 axis = vec3(f);
        double deg = scalar(f, 3, 0);
        if (glm::length(axis) > 0) {
          step = glm::rotate(glm::dmat4(1.0), glm::radians(deg), glm::normalize(axis));
        }
      } else if (f.name == "mirror" && f.kind == ir::FieldKind::Vector) {
        glm::dvec3 n = vec3(f);
        double d = scalar(f, 3, 0);
        double len = glm::length(n);
        if (len > 0) {
          n /= len;
          d /= len;
          // x' = x - 2 (n·x - d) n
          glm::dmat3 l = glm::dmat3(1.0) - 2.0 * glm::outerProduct(n, n);
          step = glm::dmat4(l);
          step[3] = glm::dvec4(2.0 * d * n, 1.0);
        }
      } else {
        continue;
      }
      t = step * t;
    }
    return t;
  }

  // World transform of an instance as first placed in the scene (also for hidden ones).
  glm::dmat4 world_of(ir::NodeId inst, int depth = 0) {
    if (auto it = world_.find(inst.index); it != world_.end()) {
      note(it->second.deps);
      return it->second.value;
    }
    open_frame();
    const ir::Node& n = m_.node(inst);
    glm::dmat4 parent(1.0);
    if (n.parent.is_valid() && depth < 64) {
      const ir::Node& p = m_.node(n.parent);
      if (p.kind == ir::NodeKind::Group || p.kind == ir::NodeKind::Pipeline) {
        // The first instance that places the enclosing group or block.
        for (size_t i = 0; i < m_.nodes.size(); ++i) {
          const ir::Node& c = m_.nodes[i];
          if (c.kind == ir::NodeKind::Instance && c.target == n.parent) {
            parent = world_of(ir::NodeId{static_cast<int32_t>(i)}, depth + 1);
            break;
          }
        }
      }
    }
    glm::dmat4 w = parent * local(n);
    Deps d = close_frame();
    world_.emplace(inst.index, Memo<glm::dmat4>{w, std::move(d)});
    return w;
  }

  std::optional<glm::vec3> surface_color(const ir::Node& n) {
    const ir::Field* s = find_field(n, "surface");
    if (s == nullptr || s->refs.empty() || !s->refs[0].is_valid()) return std::nullopt;
    const ir::Node& surf = m_.node(s->refs[0]);
    const ir::Field* c = find_field(surf, "color");
    if (c == nullptr) return std::nullopt;
    glm::dvec3 v = vec3(*c);
    return glm::vec3(glm::clamp(v, 0.0, 1.0));
  }

  // Runs a generator once per node; errors are reported once.
  const Generated* generated(ir::NodeId gen_id, std::string_view inst_path) {
    if (auto it = generated_.find(gen_id.index); it != generated_.end()) {
      note(it->second.deps);
      return it->second.value ? &*it->second.value : nullptr;
    }
    open_frame();
    std::optional<Generated> made = generate_node(gen_id, inst_path);
    Deps d = close_frame();
    auto [it, _] = generated_.emplace(gen_id.index, Memo<std::optional<Generated>>{std::move(made), std::move(d)});
    return it->second.value ? &*it->second.value : nullptr;
  }

  // Runs the generator of node `gen_id` (uncached; see `generated`).
  std::optional<Generated> generate_node(ir::NodeId gen_id, std::string_view inst_path) {
    const ir::Node& g = m_.node(gen_id);
    GeneratorArgs args;
    args.dialect = m_.dialect;
    for (const ir::Field& f : g.fields) {
      if (f.kind == ir::FieldKind::Scalar && !f.exprs.empty()) {
        args.numbers[f.name] = scalar(f, 0, 0);
      } else if (f.kind == ir::FieldKind::Text) {
        args.texts[f.name] = f.text;
      } else if (f.kind == ir::FieldKind::Flag) {
        args.texts[f.name] = "";  // a bare flag such as `closed` is present with no text
      } else if (f.kind == ir::FieldKind::Ref && f.name == "path" && !f.refs.empty() &&
                 f.refs[0].is_valid()) {
        path_points(f.refs[0], args, inst_path);
      } else if (f.kind == ir::FieldKind::Refs) {
        for (ir::NodeId p : f.refs) {
          if (!p.is_valid() || m_.node(p).kind != ir::NodeKind::Point) continue;
          if (const ir::Field* pos = find_field(m_.node(p), "position")) {
            args.points.push_back(vec3(*pos));
            args.point_names.push_back(short_name(m_.node(p).name));
          }
        }
      }
    }
    GeneratorResult r = generate(g.keyword, args);
    ++counters.generators_run;
    counters.nodes.insert(gen_id.index);
    if (!r.ok()) {
      SourceRange at = g.range;
      if (!r.error.argument.empty()) {
        if (const ir::Field* f = find_field(g, r.error.argument)) at = f->range.is_valid() ? f->range : at;
      }
      auto d = diags_->emit(DiagKind::GeometryFailed, at,
                            fmt::format("`{}` `{}`: {}{}", g.keyword, short_name(g.name), r.error.message,
                                        inst_path.empty() ? "" : fmt::format(" (in instance `{}`)", inst_path)));
      if (!r.error.hint.empty()) d.note(SourceRange{}, r.error.hint);
      return std::nullopt;
    }
    return std::move(r.value);
  }

  // The points of a path (`rimribbon r path P …`): a polyline's vertices, or the polyline
  // of a generated curve, in order; `closed` when the path is closed.
  void path_points(ir::NodeId path_id, GeneratorArgs& args, std::string_view inst_path) {
    const ir::Node& pn = m_.node(path_id);
    if (pn.kind == ir::NodeKind::Polyline) {
      if (const ir::Field* pts = find_field(pn, "points")) {
        for (const ir::VertexRef& r : pts->vertices) {
          if (auto p = ref_position(r, inst_path)) {
            args.points.push_back(*p);
            args.point_names.push_back(r.text);
          }
        }
      }
      const ir::Field* closed = find_field(pn, "closed");
      bool is_closed = find_field(pn, "isloop") != nullptr ||
                       (closed && (closed->kind == ir::FieldKind::Flag || scalar(*closed, 0, 0) != 0));
      if (is_closed) args.numbers["closed"] = 1;
    } else if (pn.kind == ir::NodeKind::Curve || pn.kind == ir::NodeKind::Generator) {
      if (const Generated* g = generated(path_id, inst_path); g && !g->curves.empty()) {
        for (int32_t v : g->curves[0].vertices) {
          args.points.push_back(g->soup.positions[v]);
          args.point_names.push_back(g->soup.names.empty() ? std::string() : g->soup.names[v]);
        }
        if (g->curves[0].is_closed) args.numbers["closed"] = 1;
      }
    }
  }

  // A sweep (NOME3 semantics): the cross section, a curve in its xy plane, is carried along
  // the path by rotation-minimising frames (parallel transport of the normal; for a closed
  // path the holonomy is spread evenly so the tube closes), turned by `azimuth` at the start
  // and by `twist` degrees in total along the path. Quads join consecutive rings; a closed
  // cross section on an open path gets `begincap` / `endcap` faces; `reverse` flips faces.
  // The sweep of node `sweep_id`, memoized per node and instance path (its errors name the
  // instance, as before memoization).
  std::optional<kernel::PolygonSoup> sweep(ir::NodeId sweep_id, std::string_view inst_path) {
    std::string key = fmt::format("{}:{}", sweep_id.index, inst_path);
    if (auto it = sweeps_.find(key); it != sweeps_.end()) {
      note(it->second.deps);
      return it->second.value;
    }
    open_frame();
    std::optional<kernel::PolygonSoup> made = sweep_node(sweep_id, inst_path);
    ++counters.generators_run;
    counters.nodes.insert(sweep_id.index);
    Deps d = close_frame();
    sweeps_.emplace(std::move(key), Memo<std::optional<kernel::PolygonSoup>>{made, std::move(d)});
    return made;
  }

  std::optional<kernel::PolygonSoup> sweep_node(ir::NodeId sweep_id, std::string_view inst_path) {
    const ir::Node& sn = m_.node(sweep_id);
    GeneratorArgs cs, pa;
    double azimuth = 0, twist = 0;
    bool begin_cap = false, end_cap = false, reverse = false;
    SourceRange cs_range = sn.range, path_range = sn.range;
    auto read_flag = [&](const ir::Field& f) {
      return f.kind == ir::FieldKind::Flag || scalar(f, 0, 0) != 0;
    };
    auto read_parts = [&](const ir::Node& k) {
      for (const ir::Field& f : k.fields) {
        if ((f.name == "crosssection" || f.name == "shape" || f.name == "polyline" ||
             f.name == "bsplinecurve" || f.name == "beziercurve") &&
            f.kind == ir::FieldKind::Ref && !f.refs.empty() && f.refs[0].is_valid()) {
          path_points(f.refs[0], cs, inst_path);
          cs_range = f.range;
        } else if (f.name == "path" && f.kind == ir::FieldKind::Ref && !f.refs.empty() &&
                   f.refs[0].is_valid()) {
          path_points(f.refs[0], pa, inst_path);
          path_range = f.range;
        } else if (f.name == "azimuth") {
          azimuth = scalar(f, 0, 0);
        } else if (f.name == "twist") {
          twist = scalar(f, 0, 0);
        } else if (f.name == "begincap") {
          begin_cap = read_flag(f);
        } else if (f.name == "endcap") {
          end_cap = read_flag(f);
        } else if (f.name == "reverse") {
          reverse = true;
        }
      }
    };
    read_parts(sn);
    for (ir::NodeId k : kids_[sweep_id.index]) read_parts(m_.node(k));
    const bool cs_closed = cs.numbers.contains("closed");
    const bool path_closed = pa.numbers.contains("closed");
    const size_t nc = cs.points.size(), np = pa.points.size();
    if (nc < 2 || (cs_closed && nc < 3)) {
      diags_->emit(DiagKind::GeometryFailed, cs_range,
                  fmt::format("sweep `{}` needs a cross section of at least {} points, got {} (instance `{}`)",
                              short_name(sn.name), cs_closed ? 3 : 2, nc, inst_path));
      return std::nullopt;
    }
    if (np < 2 || (path_closed && np < 3)) {
      diags_->emit(DiagKind::GeometryFailed, path_range,
                  fmt::format("sweep `{}` needs a path of at least {} points, got {} (instance `{}`)",
                              short_name(sn.name), path_closed ? 3 : 2, np, inst_path));
      return std::nullopt;
    }
    const auto& P = pa.points;
    std::vector<glm::dvec3> tangent(np);
    for (size_t i = 0; i < np; ++i) {
      glm::dvec3 prev = i > 0 ? P[i - 1] : (path_closed ? P[np - 1] : P[i]);
      glm::dvec3 next = i + 1 < np ? P[i + 1] : (path_closed ? P[0] : P[i]);
      glm::dvec3 d = next - prev;
      if (glm::length(d) == 0) {
        diags_->emit(DiagKind::GeometryFailed, path_range,
                    fmt::format("sweep `{}`: the path has repeated points (instance `{}`)",
                                short_name(sn.name), inst_path));
        return std::nullopt;
      }
      tangent[i] = glm::normalize(d);
    }
    auto perpendicular = [](const glm::dvec3& t, glm::dvec3 v) {
      return v - glm::dot(v, t) * t;
    };
    glm::dvec3 n0 = std::fabs(tangent[0].z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
    n0 = glm::normalize(perpendicular(tangent[0], n0));
    n0 = glm::dvec3(glm::rotate(glm::dmat4(1.0), glm::radians(azimuth), tangent[0]) * glm::dvec4(n0, 0));
    std::vector<glm::dvec3> normal(np);
    normal[0] = n0;
    for (size_t i = 1; i < np; ++i) {
      glm::dvec3 n = perpendicular(tangent[i], normal[i - 1]);
      normal[i] = glm::length(n) > 1e-12 ? glm::normalize(n) : normal[i - 1];
    }
    double holonomy = 0;  // angle from the transported normal back to n0, closed paths
    if (path_closed) {
      glm::dvec3 back = glm::normalize(perpendicular(tangent[0], normal[np - 1]));
      holonomy = std::atan2(glm::dot(glm::cross(back, n0), tangent[0]), glm::dot(back, n0));
    }
    kernel::PolygonSoup out;
    const size_t rings = np;
    const double steps = path_closed ? static_cast<double>(np) : static_cast<double>(np - 1);
    for (size_t i = 0; i < rings; ++i) {
      double frac = static_cast<double>(i) / steps;
      double angle = glm::radians(twist) * frac + holonomy * frac;
      glm::dvec3 n = glm::dvec3(glm::rotate(glm::dmat4(1.0), angle, tangent[i]) * glm::dvec4(normal[i], 0));
      glm::dvec3 b = glm::cross(tangent[i], n);
      for (size_t j = 0; j < nc; ++j) {
        out.add_vertex(P[i] + cs.points[j].x * n + cs.points[j].y * b);
      }
    }
    auto vid = [&](size_t i, size_t j) { return static_cast<int32_t>((i % rings) * nc + (j % nc)); };
    auto add = [&](std::vector<int32_t> f) {
      if (reverse) std::reverse(f.begin(), f.end());
      out.add_face(f);
    };
    const size_t ring_edges = path_closed ? rings : rings - 1;
    const size_t cs_edges = cs_closed ? nc : nc - 1;
    for (size_t i = 0; i < ring_edges; ++i) {
      for (size_t j = 0; j < cs_edges; ++j) {
        // Outward for a cross section running counter-clockwise in its xy plane.
        add({vid(i, j), vid(i, j + 1), vid(i + 1, j + 1), vid(i + 1, j)});
      }
    }
    if (cs_closed && !path_closed) {
      if (begin_cap) {
        std::vector<int32_t> f;
        for (size_t j = nc; j-- > 0;) f.push_back(vid(0, j));
        add(f);
      }
      if (end_cap) {
        std::vector<int32_t> f;
        for (size_t j = 0; j < nc; ++j) f.push_back(vid(rings - 1, j));
        add(f);
      }
    }
    return out;
  }

  // Local position of a vertex reference of a face in a mesh.
  // The position of the first vertex in `refs` that `ref` names (by its text or by the name
  // of the point it resolves to), resolving it in turn; recursion is bounded by ref_depth_.
  std::optional<glm::dvec3> position_among(const std::vector<ir::VertexRef>& refs,
                                           const ir::VertexRef& ref, std::string_view inst_path) {
    for (const ir::VertexRef& r : refs) {
      bool named = r.text == ref.vertex ||
                   (r.point.is_valid() && short_name(m_.node(r.point).name) == ref.vertex);
      if (named && &r != &ref && ref_depth_ < 16) {
        ++ref_depth_;
        std::optional<glm::dvec3> p = ref_position(r, inst_path);
        --ref_depth_;
        if (p) return p;
      }
    }
    return std::nullopt;
  }

  std::optional<glm::dvec3> ref_position(const ir::VertexRef& ref, std::string_view inst_path) {
    if (ref.point.is_valid()) {
      if (const ir::Field* pos = find_field(m_.node(ref.point), "position")) return vec3(*pos);
      return std::nullopt;
    }
    if (ref.instances.empty() || !ref.instances[0].is_valid()) return std::nullopt;
    glm::dmat4 t = world_of(ref.instances[0]);
    for (size_t i = 1; i < ref.instances.size(); ++i) {
      if (!ref.instances[i].is_valid()) return std::nullopt;
      t = t * local(m_.node(ref.instances[i]));
    }
    ir::NodeId target = m_.node(ref.instances.back()).target;
    if (!target.is_valid()) return std::nullopt;
    const ir::Node& tn = m_.node(target);
    std::optional<glm::dvec3> p;
    if (tn.kind == ir::NodeKind::Generator || tn.kind == ir::NodeKind::Curve) {
      if (const Generated* g = generated(target, inst_path)) {
        // NOME3 aliases (`fun.v1_3`) name the same vertices as the 2016 names (`hc3`).
        const std::string wanted = canonical_vertex_name(tn.keyword, ref.vertex);
        for (size_t v = 0; v < g->soup.names.size(); ++v) {
          if (g->soup.names[v] == wanted) {
            p = g->soup.positions[v];
            break;
          }
        }
      } else {
        return std::nullopt;  // the generator's error was reported
      }
    } else if (tn.kind == ir::NodeKind::Polyline) {
      // A vertex of a polyline instance (`_l1_v4`): one of the points it lists.
      if (const ir::Field* pts = find_field(tn, "points")) {
        p = position_among(pts->vertices, ref, inst_path);
      }
    } else if (tn.kind == ir::NodeKind::Mesh) {
      for (ir::NodeId k : kids_[target.index]) {
        const ir::Node& kn = m_.node(k);
        if (kn.kind == ir::NodeKind::Point && short_name(kn.name) == ref.vertex) {
          if (const ir::Field* pos = find_field(kn, "position")) p = vec3(*pos);
        }
      }
      // A vertex the mesh's faces use (a global point, or a vertex of another instance).
      for (ir::NodeId k : kids_[target.index]) {
        if (p) break;
        const ir::Field* vf = find_field(m_.node(k), "vertices");
        if (vf == nullptr) continue;
        p = position_among(vf->vertices, ref, inst_path);
      }
    }
    if (!p) {
      diags_->emit(DiagKind::GeometryFailed, ref.range,
                  fmt::format("`{}` names no vertex of the geometry of `{}`; it has no vertex `{}`",
                              ref.text, short_name(tn.name), ref.vertex));
      return std::nullopt;
    }
    return glm::dvec3(t * glm::dvec4(*p, 1.0));
  }

  // Adds the faces of a mesh (or object / consolidate / saved mesh) in its local frame.
  void mesh(ir::NodeId mesh_id, const std::optional<glm::vec3>& color, const std::string& path,
            ir::NodeId inst, Collected& out) {
    const ir::Node& mn = m_.node(mesh_id);
    std::map<std::string, int32_t> index;  // vertex key -> soup index
    Collected local_c;
    kernel::PolygonSoup& soup = local_c.soup;
    auto vertex_index = [&](const ir::VertexRef& ref) -> std::optional<int32_t> {
      std::string key;
      if (ref.point.is_valid()) {
        key = fmt::format("p{}", ref.point.index);
      } else {
        for (ir::NodeId i : ref.instances) key += fmt::format("i{}.", i.index);
        key += ref.vertex;
      }
      if (auto it = index.find(key); it != index.end()) return it->second;
      std::optional<glm::dvec3> p = ref_position(ref, path);
      if (!p) return std::nullopt;
      int32_t v = soup.add_vertex(*p, ref.text);
      index.emplace(key, v);
      return v;
    };
    std::vector<ir::NodeId> faces;
    if (const ir::Field* objf = find_field(mn, "faces"); objf && objf->kind == ir::FieldKind::Refs) {
      for (ir::NodeId f : objf->refs) if (f.is_valid()) faces.push_back(f);
    }
    for (ir::NodeId k : kids_[mesh_id.index]) {
      const ir::Node& kn = m_.node(k);
      if (kn.keyword != "sharp" && find_field(kn, "vertices") != nullptr) faces.push_back(k);
    }
    for (ir::NodeId fid : faces) {
      const ir::Node& fn = m_.node(fid);
      const ir::Field* vf = find_field(fn, "vertices");
      if (vf == nullptr || vf->vertices.size() < 3) continue;
      std::vector<int32_t> face;
      bool ok = true;
      for (const ir::VertexRef& r : vf->vertices) {
        auto v = vertex_index(r);
        if (!v) {
          ok = false;
          break;
        }
        face.push_back(*v);
      }
      if (!ok) continue;
      soup.add_face(face);
      soup.face_sources.push_back({fid.index, inst.index});
      std::optional<glm::vec3> fc = surface_color(fn);
      soup.face_colors.push_back(fc.value_or(color.value_or(kDefaultColor)));
      local_c.has_color.push_back(fc || color ? 1 : 0);
      std::string fname = short_name(fn.name);
      std::string prefix = path.empty() ? std::string() : path + ".";
      // Face paths serve only `delete` edits; without any, they stay empty (cheap to copy).
      local_c.face_paths.push_back(deleted_.empty() ? std::string()
                                                    : fmt::format("{}{}|{}{}", prefix, fname, prefix, soup.face_count() - 1));
    }
    for (ir::NodeId k : kids_[mesh_id.index]) {
      const ir::Node& kn = m_.node(k);
      if (kn.keyword != "sharp") continue;
      const ir::Field* sf = find_field(kn, "sharpness");
      float s = sf ? static_cast<float>(scalar(*sf, 0, 0)) : 0.0f;
      for (const ir::Field& f : kn.fields) {
        if (f.name != "edges" || f.kind != ir::FieldKind::Vertices) continue;
        std::vector<int32_t> vs;
        std::vector<const ir::VertexRef*> refs;
        for (const ir::VertexRef& r : f.vertices) {
          if (auto v = vertex_index(r)) {
            vs.push_back(*v);
            refs.push_back(&r);
          }
        }
        if (vs.size() == 1) {
          soup.corners.push_back({vs[0], s});
        }
        for (size_t i = 0; i + 1 < vs.size(); ++i) {
          if (!is_soup_edge(soup, vs[i], vs[i + 1])) {
            SourceRange r = refs[i]->range;
            r.end = refs[i + 1]->range.end;
            diags_->emit(DiagKind::GeometryFailed, r,
                        fmt::format("`{}` and `{}` are not joined by an edge of mesh `{}`; `sharp` "
                                    "marks edges between consecutive vertices of a face (instance `{}`)",
                                    refs[i]->text, refs[i + 1]->text, short_name(mn.name), path));
            continue;
          }
          soup.creases.push_back({vs[i], vs[i + 1], s});
        }
      }
    }
    // Merge into `out` (identity transform: the caller transforms whole collections).
    const int32_t face_base = out.soup.face_count();
    append_soup(out, soup, glm::dmat4(1.0), std::nullopt, true);
    for (int32_t f = 0; f < soup.face_count(); ++f) {
      out.has_color[face_base + f] = local_c.has_color[f];
      out.face_paths[face_base + f] = local_c.face_paths[f];
    }
  }

  // Adds an instance of `inst` placed by `parent_t`.
  void instance(ir::NodeId inst, const glm::dmat4& parent_t, std::optional<glm::vec3> color,
                const std::string& parent_path, Collected& out, int depth) {
    const ir::Node& n = m_.node(inst);
    if (n.is_hidden || !n.target.is_valid()) return;
    if (depth > 64) {
      diags_->emit(DiagKind::GeometryFailed, n.range, "instances nest more than 64 levels deep");
      return;
    }
    std::string path = parent_path.empty() ? short_name(n.name) : parent_path + "." + short_name(n.name);
    instance_paths.try_emplace(inst.index, path);
    glm::dmat4 t = parent_t * local(n);
    if (auto c = surface_color(n)) color = c;
    chain_.push_back(inst.index);
    target(n.target, t, color, path, inst, out, depth);
    chain_.pop_back();
  }

  void target(ir::NodeId tid, const glm::dmat4& t, std::optional<glm::vec3> color,
              const std::string& path, ir::NodeId inst, Collected& out, int depth) {
    const ir::Node& tn = m_.node(tid);
    switch (tn.kind) {
      case ir::NodeKind::Mesh:
      case ir::NodeKind::Generator:
      case ir::NodeKind::Curve:
      case ir::NodeKind::Sweep:
        place(tid, t, color, path, inst, out);
        return;
      case ir::NodeKind::Polyline:
        out.curve_count += 1;
        return;
      case ir::NodeKind::Group: {
        if (auto c = surface_color(tn)) color = c;
        chain_.push_back(tid.index);
        for (ir::NodeId k : kids_[tid.index]) {
          if (m_.node(k).kind == ir::NodeKind::Instance) instance(k, t, color, path, out, depth + 1);
        }
        chain_.pop_back();
        return;
      }
      case ir::NodeKind::Pipeline:
        pipeline(tid, t, color, path, out, depth + 1);
        return;
      case ir::NodeKind::Edit:
        if (tn.keyword == "light" || tn.keyword == "camera" || tn.keyword == "window" ||
            tn.keyword == "viewport" || tn.keyword == "render" || tn.keyword == "lookat") {
          return;  // viewing set-up: no geometry (the checker already noted it)
        }
        [[fallthrough]];
      default:
        diags_->emit(DiagKind::GeometryFailed, tn.range,
                    fmt::format("`{}` `{}` produces no geometry the backend can place (instance `{}`)",
                                tn.keyword, short_name(tn.name), path));
        return;
    }
  }

  // A placed leaf (mesh, generator, curve or sweep) in its entry's frame, as appended by
  // `place`; reused while its transform, colour and the parameters it read are unchanged.
  struct Placement {
    glm::dmat4 t;
    std::optional<glm::vec3> color;
    std::shared_ptr<const Collected> part;
    std::optional<kernel::Mesh> mesh;  // `part` built, when an entry reassembles from parts
  };

  struct EntryPart {
    Placement* placement;                   // a placed leaf (built on demand), or
    std::shared_ptr<const Collected> part;  // its faces, or a part of a block's result
    const kernel::Mesh* mesh;               // a block part's built mesh
  };
  struct Sink {
    Collected* out = nullptr;
    std::vector<EntryPart> parts;
    bool is_pure = true;
    bool is_deferred = false;
    int32_t direct_curves = 0;
  };

  void place(ir::NodeId tid, const glm::dmat4& t, const std::optional<glm::vec3>& color,
             const std::string& path, ir::NodeId inst, Collected& out) {
    auto recomputed = [&] {
      ++counters.instances_placed;
      counters.nodes.insert(chain_.begin(), chain_.end());
    };
    if (!is_incremental_) {
      place_leaf(tid, t, color, path, inst, out);
      recomputed();
      return;
    }
    std::string key = std::to_string(context_);
    key += '/';
    key += std::to_string(inst.index);
    key += '/';
    key += path;
    auto it = placements_.find(key);
    if (it != placements_.end() && it->second.value.t == t && it->second.value.color == color) {
      note(it->second.deps);
    } else {
      open_frame();
      Collected part;
      place_leaf(tid, t, color, path, inst, part);
      Deps d = close_frame();
      recomputed();
      auto shared = std::make_shared<const Collected>(std::move(part));
      it = placements_.insert_or_assign(std::move(key), Memo<Placement>{Placement{t, color, std::move(shared), {}}, std::move(d)}).first;
    }
    const Placement& pl = it->second.value;
    if (collects(out)) {
      sink_->parts.push_back({&it->second.value, pl.part, nullptr});
      if (sink_->is_deferred) return;
    }
    transform_into(out, *pl.part, glm::dmat4(1.0));
  }

  // True if `out` is the faces of the entry or block being collected part by part.
  bool collects(const Collected& out) const { return sink_ != nullptr && sink_->out == &out; }

  // Appends the parts collected so far to the sink's faces and stops deferring (the entry
  // or block holds something that is not a part, which must come after them in order).
  void make_eager() {
    if (!sink_->is_deferred) return;
    sink_->is_deferred = false;
    sink_->direct_curves = sink_->out->curve_count;
    for (const EntryPart& p : sink_->parts) append_collected(*sink_->out, *p.part);
  }

  // True if `a` equals `b` except for vertex positions (the same faces, sources, colours,
  // names, creases and, for a block's result, the same built topology).
  static bool same_but_positions(const Collected& a, const Collected& b) {
    const kernel::PolygonSoup& x = a.soup;
    const kernel::PolygonSoup& y = b.soup;
    auto same_creases = [](const auto& p, const auto& q) {
      return std::equal(p.begin(), p.end(), q.begin(), q.end(), [](const auto& c, const auto& d) {
        return c.a == d.a && c.b == d.b && c.sharpness == d.sharpness;
      });
    };
    auto same_corners = [](const auto& p, const auto& q) {
      return std::equal(p.begin(), p.end(), q.begin(), q.end(), [](const auto& c, const auto& d) {
        return c.vertex == d.vertex && c.sharpness == d.sharpness;
      });
    };
    if (x.positions.size() != y.positions.size() || x.face_sizes != y.face_sizes ||
        x.face_vertices != y.face_vertices || x.face_sources != y.face_sources ||
        x.face_colors != y.face_colors || x.names != y.names || !same_creases(x.creases, y.creases) ||
        !same_corners(x.corners, y.corners) || a.has_color != b.has_color || a.face_paths != b.face_paths ||
        a.curve_count != b.curve_count || (a.built == nullptr) != (b.built == nullptr)) {
      return false;
    }
    return a.built == nullptr || kernel::has_same_topology(*a.built, *b.built);
  }

  // An update of an entry whose parts all equal the previous evaluation's, in the same
  // order, except for the positions of some (a moved instance, a re-subdivided block with
  // the same topology): the previous output mesh is copied and only those parts' vertex
  // ranges are overwritten, instead of concatenating every part and reassembling the mesh.
  // The result is exactly what reassembling gives, since everything but positions is a
  // function of the parts' topology. False (nothing done) if there is no previous layout
  // or some part differs in more than positions.
  bool patch_entry(ir::NodeId id, int32_t direct_curves, OutputMesh& out) {
    auto it = layouts_.find(id.index);
    if (it == layouts_.end()) return false;
    const EntryLayout& old = it->second;
    if (old.parts.size() != entry_parts_.size() || old.direct_curves != direct_curves) return false;
    std::vector<uint8_t> changed(entry_parts_.size(), 0);
    for (size_t i = 0; i < entry_parts_.size(); ++i) {
      if (entry_parts_[i].part == old.parts[i]) continue;
      if (!same_but_positions(*entry_parts_[i].part, *old.parts[i])) return false;
      changed[i] = 1;
    }
    ++counters.outputs_patched;
    counters.parts_patched += static_cast<int32_t>(std::count(changed.begin(), changed.end(), 1));
    if (old.out.use_count() == 1) {
      // Nobody else holds the previous output (it was made non-const by `entry`): take
      // over its storage instead of copying it.
      out = std::move(const_cast<OutputMesh&>(*old.out));
    } else {
      out = *old.out;
    }
    std::vector<glm::dvec3>& mesh_positions = kernel::MeshAccess::positions(out.mesh);
    size_t at = 0;
    for (size_t i = 0; i < entry_parts_.size(); ++i) {
      const std::vector<glm::dvec3>& p = entry_parts_[i].part->soup.positions;
      if (changed[i]) {
        std::copy(p.begin(), p.end(), out.soup.positions.begin() + static_cast<ptrdiff_t>(at));
        std::copy(p.begin(), p.end(), mesh_positions.begin() + static_cast<ptrdiff_t>(at));
      }
      at += p.size();
    }
    return true;
  }

  // The mesh of a scene entry made only of placed leaves, as the disjoint union of the
  // leaves' meshes (each built once and kept with its placement) instead of building the
  // whole entry again; nullopt if a leaf does not build (the caller builds the whole soup
  // and reports the error at the right face).
  std::optional<kernel::Mesh> assemble(const kernel::PolygonSoup& whole) {
    std::vector<const kernel::Mesh*> meshes;
    for (const EntryPart& part : entry_parts_) {
      if (part.mesh != nullptr) {
        meshes.push_back(part.mesh);
        continue;
      }
      Placement* p = part.placement;
      if (!p->mesh) {
        kernel::PolygonSoup s = p->part->soup;
        if (!s.names.empty()) s.names.resize(s.positions.size());
        auto built = kernel::build_mesh(s);
        if (!built) return std::nullopt;
        p->mesh = std::move(*built);
        // The entry's soup supplies names and colours for the whole union (below).
        kernel::MeshAccess::names(*p->mesh).clear();
        kernel::MeshAccess::face_colors(*p->mesh).clear();
      }
      meshes.push_back(&*p->mesh);
    }
    kernel::Mesh m = kernel::append_disjoint(meshes);
    if (m.vertex_count() != whole.vertex_count() || m.face_count() != whole.face_count()) return std::nullopt;
    // Faces and vertices are in the soup's order, so the soup's attributes apply as they are.
    kernel::MeshAccess::face_colors(m) = whole.face_colors;
    kernel::MeshAccess::face_sources(m) = whole.face_sources;
    if (whole.face_sources.empty()) kernel::MeshAccess::face_sources(m).assign(whole.face_count(), kernel::FaceSource{});
    kernel::MeshAccess::names(m) = whole.names;
    return m;
  }

  void place_leaf(ir::NodeId tid, const glm::dmat4& t, const std::optional<glm::vec3>& color,
                  const std::string& path, ir::NodeId inst, Collected& out) {
    const ir::Node& tn = m_.node(tid);
    switch (tn.kind) {
      case ir::NodeKind::Mesh: {
        Collected c;
        mesh(tid, color, path, inst, c);
        transform_into(out, c, t);
        return;
      }
      case ir::NodeKind::Generator:
      case ir::NodeKind::Curve: {
        const Generated* g = generated(tid, path);
        if (g == nullptr) return;
        kernel::PolygonSoup s = g->soup;
        s.face_sources.assign(s.face_count(), kernel::FaceSource{tid.index, inst.index});
        s.face_colors.clear();
        const int32_t face_base = out.soup.face_count();
        append_soup(out, s, t, color, false);
        for (int32_t f = 0; f < s.face_count(); ++f) {
          if (!deleted_.empty()) out.face_paths[face_base + f] = fmt::format("{}.{}", path, f);  // 2016 `fun2_5`
        }
        out.curve_count += static_cast<int32_t>(g->curves.size());
        return;
      }
      case ir::NodeKind::Sweep: {
        std::optional<kernel::PolygonSoup> sw = sweep(tid, path);
        if (!sw) return;
        sw->face_sources.assign(sw->face_count(), kernel::FaceSource{tid.index, inst.index});
        const int32_t face_base = out.soup.face_count();
        append_soup(out, *sw, t, color, false);
        for (int32_t f = 0; f < sw->face_count(); ++f) {
          if (!deleted_.empty()) out.face_paths[face_base + f] = fmt::format("{}.{}", path, f);
        }
        return;
      }
      default:
        return;  // `target` sends only the kinds above
    }
  }

  void transform_into(Collected& out, const Collected& c, const glm::dmat4& t) {
    if (t == glm::dmat4(1.0)) {
      append_collected(out, c);
      return;
    }
    const int32_t face_base = out.soup.face_count();
    const kernel::PolygonSoup& s = c.soup;
    append_soup(out, s, t, std::nullopt, true);
    for (int32_t f = 0; f < s.face_count(); ++f) {
      out.has_color[face_base + f] = c.has_color[f];
      out.face_paths[face_base + f] = c.face_paths[f];
    }
    out.curve_count += c.curve_count;
  }

  // Evaluates a pipeline block's instances in its own frame, runs the operation, and adds
  // the result placed by `t`.
  void pipeline(ir::NodeId pid, const glm::dmat4& t, std::optional<glm::vec3> color,
                const std::string& path, Collected& out, int depth) {
    const ir::Node& p = m_.node(pid);
    if (depth > 64) return;
    auto it = pipeline_cache_.find(pid.index);
    if (it == pipeline_cache_.end()) {
      // Paths inside a block start at the block's name (`openbox.b.top.f1`), wherever
      // it is instanced, so one evaluation serves every instance.
      open_frame();
      const int32_t saved_context = context_;
      context_ = pid.index;
      chain_.push_back(pid.index);
      std::optional<BlockResult> made = run_block(pid, short_name(p.name), depth);
      chain_.pop_back();
      context_ = saved_context;
      counters.nodes.insert(pid.index);
      Deps d = close_frame();
      std::shared_ptr<const BlockResult> shared = made ? std::make_shared<const BlockResult>(std::move(*made)) : nullptr;
      it = pipeline_cache_.emplace(pid.index, Memo<std::shared_ptr<const BlockResult>>{std::move(shared), std::move(d)}).first;
    } else {
      note(it->second.deps);
    }
    const std::shared_ptr<const BlockResult> res = it->second.value;
    if (!res) return;
    const bool is_plain = !color && t == glm::dmat4(1.0);
    if (collects(out)) {
      const bool is_built = std::all_of(res->parts.begin(), res->parts.end(),
                                        [](const auto& part) { return part->built != nullptr; });
      if (is_plain && is_built) {
        for (const auto& part : res->parts) sink_->parts.push_back({nullptr, part, part->built.get()});
        if (sink_->is_deferred) return;
      } else {
        sink_->is_pure = false;
        make_eager();
      }
    }
    for (const auto& part : res->parts) {
      if (is_plain) {
        transform_into(out, *part, t);
        continue;
      }
      Collected c = *part;
      if (color) {
        for (size_t f = 0; f < c.has_color.size(); ++f) {
          if (!c.has_color[f]) {
            c.soup.face_colors[f] = *color;
            c.has_color[f] = 1;
          }
        }
      }
      transform_into(out, c, t);
    }
  }

  // A block's steps and tolerance, read from its fields.
  struct BlockSetup {
    double tolerance = -1;  // < 0: 1e-4 x the input's bounding-box diagonal
    std::vector<Step> steps;
    SourceRange step_range;
  };

  BlockSetup block_setup(const ir::Node& p) {
    BlockSetup b;
    const std::string_view kw = p.keyword;
    b.step_range = p.range;
    if (const ir::Field* f = find_field(p, "tolerance")) b.tolerance = scalar(*f, 0, -1);
    if (kw == "subdivision") {
      Step st;
      st.subdivision.has_parent_maps = false;
      const ir::Field* lf = find_field(p, "sd_level");
      if (lf == nullptr) lf = find_field(p, "subdivisions");
      double lv = lf ? scalar(*lf, 0, 1) : 1;
      st.subdivision.levels = static_cast<int32_t>(std::lround(lv));
      std::string type;
      if (const ir::Field* tf = find_field(p, "sd_type")) type = tf->text;
      if (const ir::Field* tf = find_field(p, "type"); tf && type.empty()) type = tf->text;
      if (type == "NOME_SD_CatmullClark" || type == "NOME_SD_CC" ||
          type == "SLF_SUBDIVISION_CATMULL_CLARK") {
        st.subdivision.is_sharpness_honoured = false;
      } else if (type == "NOME_SD_DeRose") {
        st.subdivision.vertex_rule = kernel::VertexRule::DeRose;
      }
      b.steps.push_back(st);
      if (lf) b.step_range = lf->range;
    } else if (kw == "offset") {
      const ir::Field* hf = find_field(p, "height");
      const ir::Field* wf = find_field(p, "width");
      const ir::Field* tf = find_field(p, "offset_type");
      Step st;
      st.height = hf ? scalar(*hf, 0, 0.1) : 0.1;
      st.width = wf ? scalar(*wf, 0, 0) : 0;
      bool grid = tf && tf->text == "NOME_OFFSET_GRID";
      st.kind = grid && st.width > 0 ? Step::Kind::Lattice : Step::Kind::Offset;
      b.steps.push_back(st);
      if (hf) b.step_range = hf->range;
    }
    return b;
  }

  // A block's result mesh as a part, with the block's colour rule: if no input face has a
  // colour, every face gets the neutral grey.
  std::shared_ptr<const Collected> block_part(kernel::Mesh result, bool any_color, int32_t curves) {
    Collected c;
    c.soup = kernel::to_soup(result);
    c.curve_count = curves;
    if (is_incremental_) c.built = std::make_shared<const kernel::Mesh>(std::move(result));
    c.has_color.assign(c.soup.face_count(), any_color ? 1 : 0);
    if (!any_color) c.soup.face_colors.assign(c.soup.face_count(), kDefaultColor);
    if (c.soup.face_colors.size() != static_cast<size_t>(c.soup.face_count())) {
      c.soup.face_colors.assign(c.soup.face_count(), kDefaultColor);
    }
    c.face_paths.assign(c.soup.face_count(), std::string());
    return std::make_shared<const Collected>(std::move(c));
  }

  std::optional<BlockResult> run_block(ir::NodeId pid, const std::string& path, int depth) {
    const ir::Node& p = m_.node(pid);
    Collected in;
    Sink sink;
    sink.out = &in;
    sink.is_deferred = is_incremental_ && deleted_.empty();
    Sink* const saved_sink = sink_;
    sink_ = is_incremental_ ? &sink : nullptr;
    for (ir::NodeId k : kids_[pid.index]) {
      if (m_.node(k).kind == ir::NodeKind::Instance) {
        instance(k, glm::dmat4(1.0), std::nullopt, path, in, depth + 1);
      }
    }
    sink_ = saved_sink;
    const std::string_view kw = p.keyword;
    if (sink.is_deferred) {
      int32_t faces = in.soup.face_count();
      for (const EntryPart& part : sink.parts) faces += part.part->soup.face_count();
      if (sink.is_pure && faces > 0 && in.curve_count == 0 && (kw == "merge" || kw == "subdivision" || kw == "offset")) {
        BlockSetup setup = block_setup(p);
        if (auto r = run_block_by_clusters(pid, sink.parts, setup)) return r;
        for (const EntryPart& part : sink.parts) append_collected(in, *part.part);
        return run_block_whole(pid, std::move(in), setup);
      }
      for (const EntryPart& part : sink.parts) append_collected(in, *part.part);
    }
    apply_deletes(in);
    if (kw == "mirror") {
      // SLIDE `mirror … endmirror` "reverses all face orientations" to repair instances
      // mirrored by a negative scale, which SLIDE leaves inside out. nomec already
      // reverses faces placed by a transform with negative determinant, so the block's
      // repair is done: its instances pass through unchanged. (A block around unmirrored
      // instances, which SLIDE would turn inside out, therefore differs from SLIDE.)
      BlockResult r;
      r.parts.push_back(std::make_shared<const Collected>(std::move(in)));
      return r;
    }
    if (kw != "merge" && kw != "subdivision" && kw != "offset") {
      diags_->emit(DiagKind::GeometryFailed, p.range,
                  fmt::format("`{}` blocks are not implemented in the backend yet", kw));
      return std::nullopt;
    }
    if (in.soup.face_count() == 0) {
      diags_->emit(DiagKind::GeometryFailed, p.range,
                  fmt::format("`{}` `{}` has no faces to work on", kw, short_name(p.name)));
      return std::nullopt;
    }
    BlockSetup setup = block_setup(p);
    return run_block_whole(pid, std::move(in), setup);
  }

  // A block over its whole input at once: build, merge, then the steps (per connected
  // component when incremental). Reports kernel errors at the faces that caused them.
  std::optional<BlockResult> run_block_whole(ir::NodeId pid, Collected in, const BlockSetup& setup) {
    const ir::Node& p = m_.node(pid);
    const bool any_color = std::any_of(in.has_color.begin(), in.has_color.end(), [](uint8_t b) { return b != 0; });
    const int32_t curves = in.curve_count;
    kernel::PolygonSoup soup = finish(in);
    auto built = kernel::build_mesh(soup);
    if (!built) {
      report(built.error(), soup, p.range, short_name(p.name));
      return std::nullopt;
    }
    auto merged = merge_mesh(*built, setup.tolerance);
    ++counters.kernel_ops;
    if (!merged) {
      report(merged.error(), soup, p.range, short_name(p.name));
      return std::nullopt;
    }
    std::variant<kernel::Mesh, StepFailure> ran;
    if (is_incremental_) {
      BlockMemo& bm = blocks_[pid.index];
      ComponentMemo next;
      ran = run_steps_by_component(merged->mesh, setup.steps, bm.components, next, counters.kernel_ops);
      bm = BlockMemo{};
      bm.components = std::move(next);
    } else {
      ran = run_steps(std::move(merged->mesh), setup.steps, counters.kernel_ops);
    }
    if (auto* failed = std::get_if<StepFailure>(&ran)) {
      report(failed->error, soup, setup.step_range, short_name(p.name));
      return std::nullopt;
    }
    BlockResult r;
    r.parts.push_back(block_part(std::move(std::get<kernel::Mesh>(ran)), any_color, curves));
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
  std::optional<BlockResult> run_block_by_clusters(ir::NodeId pid, const std::vector<EntryPart>& parts,
                                                   const BlockSetup& setup) {
    BlockMemo& bm = blocks_[pid.index];
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
      any_color = any_color || std::any_of(hc.begin(), hc.end(), [](uint8_t c) { return c != 0; });
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
    for (size_t c = 0; c < clusters.size(); ++c) {
      auto it = previous.find(parts[clusters[c].front()].part.get());
      if (it == previous.end() || old_used[it->second]) continue;
      const ClusterMemo& old = bm.clusters[it->second];
      bool same = old.tolerance == tol && old.steps == setup.steps && old.any_color == any_color &&
                  old.parts.size() == clusters[c].size();
      for (size_t k = 0; same && k < clusters[c].size(); ++k) same = old.parts[k] == parts[clusters[c][k]].part;
      if (same) {
        reuse[c] = it->second;
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
    for (size_t c = 0; c < clusters.size(); ++c) {
      if (reuse[c]) {
        next[c] = std::move(bm.clusters[*reuse[c]]);
        ++counters.clusters_reused;
        result.parts.push_back(next[c].result);
        continue;
      }
      ClusterMemo& cm = next[c];
      cm.tolerance = tol;
      cm.steps = setup.steps;
      cm.any_color = any_color;
      Collected cc;
      int32_t curves = 0;
      for (size_t i : clusters[c]) {
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
      ++counters.kernel_ops;
      if (!merged) return std::nullopt;
      auto ran = run_steps_by_component(merged->mesh, setup.steps, pool, cm.components, counters.kernel_ops);
      if (std::holds_alternative<StepFailure>(ran)) return std::nullopt;
      cm.result = block_part(std::move(std::get<kernel::Mesh>(ran)), any_color, curves);
      result.parts.push_back(cm.result);
    }
    bm.clusters = std::move(next);
    bm.bounds = std::move(bounds);
    bm.components = {};
    return result;
  }

 public:
  // A `zipper` statement: resolves its two `border` vertex lists to chains of world
  // positions on the border loops of the instances they name, fills the strip between
  // them (kernel::zipper) and returns the faces as an output mesh of their own, so a merge
  // welds them to the instances' borders (the positions coincide).
  bool zipper(ir::NodeId zid, OutputMesh& out) {
    const ir::Node& n = m_.node(zid);
    const std::string zname = short_name(n.name);
    std::vector<const ir::Field*> borders;
    for (const ir::Field& f : n.fields) {
      if (f.name == "border" && f.kind == ir::FieldKind::Vertices) borders.push_back(&f);
    }
    if (borders.size() != 2) return false;  // the checker reported it
    kernel::ZipperChain chain[2];
    bool is_backward[2] = {false, false};
    for (int k = 0; k < 2; ++k) {
      auto c = border_chain(n, zname, *borders[k], is_backward[k]);
      if (!c) return false;
      chain[k] = std::move(*c);
    }
    // Chain A must run the way its own faces traverse the border (see kernel/zipper.h);
    // reversing both open chains keeps their end vertices paired.
    if (!chain[0].is_closed && is_backward[0]) {
      std::reverse(chain[0].points.begin(), chain[0].points.end());
      std::reverse(chain[1].points.begin(), chain[1].points.end());
    }
    kernel::ZipperOptions o;
    if (const ir::Field* pf = find_field(n, "penalty")) o.penalty = scalar(*pf, 0, 1.3);
    auto r = kernel::zipper(chain[0], chain[1], o);
    ++counters.kernel_ops;
    if (!r) {
      diags_->emit(DiagKind::GeometryFailed, n.range,
                  fmt::format("zipper `{}`: {}", zname, r.error().message));
      return false;
    }
    out.name = zname;
    out.scene_node = zid;
    out.soup = std::move(r->soup);
    out.soup.face_sources.assign(out.soup.face_count(), kernel::FaceSource{zid.index, -1});
    auto built = kernel::build_mesh(out.soup);
    if (!built) {
      report(built.error(), out.soup, n.range, zname);
      return false;
    }
    out.mesh = std::move(*built);
    return true;
  }

 private:
  // The world-space geometry of one instance (by its chain of instance nodes) with its
  // border loops as vertex sequences, each running the way its faces traverse it.
  struct InstanceBorders {
    std::string path;
    std::string keyword;  // of the instance's target, for NOME3 vertex aliases
    kernel::PolygonSoup soup;
    std::optional<kernel::Mesh> mesh;
    std::vector<std::vector<int32_t>> loops;
  };

  const InstanceBorders* instance_borders(const ir::VertexRef& ref) {
    std::string key;
    for (ir::NodeId i : ref.instances) key += fmt::format("{}.", i.index);
    if (auto it = borders_cache_.find(key); it != borders_cache_.end()) {
      note(it->second.deps);
      return &it->second.value;
    }
    open_frame();
    const int32_t saved_context = context_;
    context_ = -2;  // placements made for border lookups
    InstanceBorders b = borders_of(ref);
    context_ = saved_context;
    Deps d = close_frame();
    auto [it, _] = borders_cache_.emplace(key, Memo<InstanceBorders>{std::move(b), std::move(d)});
    return &it->second.value;
  }

  InstanceBorders borders_of(const ir::VertexRef& ref) {
    InstanceBorders b;
    glm::dmat4 t = world_of(ref.instances[0]);
    b.path = short_name(m_.node(ref.instances[0]).name);
    for (size_t i = 1; i < ref.instances.size(); ++i) {
      t = t * local(m_.node(ref.instances[i]));
      b.path += "." + short_name(m_.node(ref.instances[i]).name);
    }
    const ir::Node& last = m_.node(ref.instances.back());
    if (last.target.is_valid()) {
      b.keyword = m_.node(last.target).keyword;
      Collected c;
      target(last.target, t, std::nullopt, b.path, ref.instances.back(), c, 0);
      b.soup = finish(c);
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

  // One `border (A0 [A1 [Am]])` list as a chain; `is_backward` says an open path runs
  // against the direction its faces traverse the border.
  std::optional<kernel::ZipperChain> border_chain(const ir::Node& zn, const std::string& zname,
                                                  const ir::Field& f, bool& is_backward) {
    const auto& refs = f.vertices;
    if (refs.empty() || refs.size() > 3) return std::nullopt;  // the checker reported it
    const InstanceBorders* ib = nullptr;
    std::vector<std::pair<size_t, size_t>> where;  // (loop, position) per reference
    for (const ir::VertexRef& r : refs) {
      if (r.instances.empty() || std::any_of(r.instances.begin(), r.instances.end(),
                                             [](ir::NodeId i) { return !i.is_valid(); })) {
        diags_->emit(DiagKind::GeometryFailed, zn.range,
                    fmt::format("zipper `{}`: `{}` is not a vertex of an instance; zipper borders "
                                "name instance vertices such as `inst.v`",
                                zname, r.text));
        return std::nullopt;
      }
      const InstanceBorders* b = instance_borders(r);
      if (ib != nullptr && b != ib) {
        diags_->emit(DiagKind::GeometryFailed, zn.range,
                    fmt::format("zipper `{}`: `{}` and `{}` belong to different instances; the "
                                "vertices of one `border` must lie on one border loop",
                                zname, refs[0].text, r.text));
        return std::nullopt;
      }
      ib = b;
      const std::string wanted = canonical_vertex_name(b->keyword, r.vertex);
      int32_t v = -1;
      for (size_t i = 0; i < b->soup.names.size(); ++i) {
        if (b->soup.names[i] == wanted || b->soup.names[i] == r.vertex) {
          v = static_cast<int32_t>(i);
          break;
        }
      }
      if (v < 0) {
        diags_->emit(DiagKind::GeometryFailed, zn.range,
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
        diags_->emit(DiagKind::GeometryFailed, zn.range,
                    fmt::format("zipper `{}`: vertex `{}` is not on a border of instance `{}`",
                                zname, r.text, b->path));
        return std::nullopt;
      }
    }
    for (size_t i = 1; i < where.size(); ++i) {
      if (where[i].first != where[0].first) {
        diags_->emit(DiagKind::GeometryFailed, zn.range,
                    fmt::format("zipper `{}`: `{}` and `{}` are on different border loops of "
                                "instance `{}`",
                                zname, refs[0].text, refs[i].text, ib->path));
        return std::nullopt;
      }
    }
    const std::vector<int32_t>& loop = ib->loops[where[0].first];
    const size_t k = loop.size();
    kernel::ZipperChain c;
    is_backward = false;
    const size_t s = where[0].second;
    if (refs.size() == 1 || where[1].second == s) {
      c.is_closed = true;
      for (size_t i = 0; i < k; ++i) c.points.push_back(ib->soup.positions[loop[(s + i) % k]]);
      return c;
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
      c.points.push_back(ib->soup.positions[loop[at]]);
    }
    is_backward = !forward;
    return c;
  }

  std::map<std::string, Memo<InstanceBorders>> borders_cache_;

 public:
  static kernel::Result<kernel::MergeResult> merge_mesh(const kernel::Mesh& mesh, double tol) {
    if (tol < 0) {
      kernel::BoundingBox b = kernel::bounding_box(mesh);
      double diag = b.min.x <= b.max.x ? glm::length(b.max - b.min) : 0;
      tol = diag > 0 ? 1e-4 * diag : 1e-9;
    }
    return kernel::merge(mesh, kernel::MergeOptions{tol});
  }

 private:
  const ir::Module& m_;
  DiagnosticEngine* diags_ = nullptr;
  std::vector<std::vector<ir::NodeId>> kids_;
  std::vector<std::string> deleted_;
  const bool is_incremental_;
  int ref_depth_ = 0;
  int32_t context_ = -1;        // the scene entry or block being evaluated (placement keys)
  std::vector<int32_t> chain_;  // instances, groups and blocks on the way to the current leaf
  // The scene entry or block being collected part by part (incremental only): its faces,
  // its parts in order, whether it holds anything else (then it is built whole), whether
  // the parts are not yet appended to its faces (see `make_eager`), and the polylines
  // counted on it directly.
  Sink* sink_ = nullptr;
  // The parts of the entry just collected, its direct polylines, and whether its mesh was
  // assembled (or patched) from them.
  std::vector<EntryPart> entry_parts_;
  int32_t entry_direct_curves_ = 0;
  bool entry_assembled_ = false;
  // Per scene entry assembled from parts: its last output and parts, for `patch_entry`.
  // Not a cached value (never invalidated): a base that is checked part by part.
  struct EntryLayout {
    std::shared_ptr<const OutputMesh> out;
    std::vector<std::shared_ptr<const Collected>> parts;
    int32_t direct_curves = 0;
  };
  std::map<int32_t, EntryLayout> layouts_;
  // Memoized values (see "Memoization" above).
  std::unordered_map<int32_t, std::vector<int32_t>> expr_params_;
  std::unordered_map<int32_t, Memo<ir::EvalResult>> expr_memo_;
  std::map<int32_t, Memo<glm::dmat4>> world_;
  std::map<int32_t, Memo<std::optional<Generated>>> generated_;
  std::map<std::string, Memo<std::optional<kernel::PolygonSoup>>> sweeps_;
  std::unordered_map<std::string, Memo<Placement>> placements_;
  std::map<int32_t, Memo<std::shared_ptr<const BlockResult>>> pipeline_cache_;
  std::map<int32_t, BlockMemo> blocks_;
  std::map<int32_t, Memo<std::shared_ptr<const OutputMesh>>> entries_;
  std::map<int32_t, Memo<std::shared_ptr<const OutputMesh>>> zippers_;
};

}  // namespace detail

namespace {

// The scene entries of a module: its top-level instances and blocks, then NOME 2016 saved
// work, or for SLIDE the world groups.
std::vector<ir::NodeId> scene_entries(const ir::Module& module) {
  std::vector<ir::NodeId> entries = module.scene;
  // NOME 2016 saved work: `consolidate` / `savedworkingmesh` meshes are part of the scene
  // unless something instances them.
  std::set<int32_t> instanced;
  for (const ir::Node& n : module.nodes) {
    if (n.kind == ir::NodeKind::Instance && n.target.is_valid()) instanced.insert(n.target.index);
  }
  for (size_t i = 0; i < module.nodes.size(); ++i) {
    const ir::Node& n = module.nodes[i];
    if (n.kind == ir::NodeKind::Mesh && (n.keyword == "consolidate" || n.keyword == "savedworkingmesh") &&
        !instanced.contains(static_cast<int32_t>(i))) {
      entries.push_back(ir::NodeId{static_cast<int32_t>(i)});
    }
  }
  // SLIDE has no top-level instances: `render VIEWPORT CAMERA WORLD` draws a group. The IR
  // does not keep the render's words, so the top-level groups that nothing instances stand
  // for the world (groups holding only cameras and lights produce nothing and are dropped).
  if (entries.empty() && module.dialect == "slide") {
    for (size_t i = 0; i < module.nodes.size(); ++i) {
      const ir::Node& n = module.nodes[i];
      if (n.kind == ir::NodeKind::Group && !n.parent.is_valid() &&
          !instanced.contains(static_cast<int32_t>(i))) {
        entries.push_back(ir::NodeId{static_cast<int32_t>(i)});
      }
    }
  }
  return entries;
}

// Per-step component memos of the whole-scene pipeline (incremental evaluation only).
struct PipelineMemos {
  ComponentMemo components;
};

std::vector<OutputMesh> pipeline_impl(const std::vector<const OutputMesh*>& meshes, const PipelineOptions& o,
                                      std::string_view name, SourceRange where,
                                      DiagnosticEngine& diags, StageTimings* timings,
                                      const std::function<void(std::string_view)>& progress,
                                      PipelineMemos* memos, int32_t& kernel_ops) {
  auto say = [&](std::string_view s) {
    if (progress) progress(s);
  };
  auto fail = [&](std::string_view stage, const kernel::KernelError& e) {
    DiagKind kind = e.kind == kernel::KernelError::Kind::NonManifoldMerge ||
                            e.kind == kernel::KernelError::Kind::NonManifoldEdge ||
                            e.kind == kernel::KernelError::Kind::NonManifoldVertex
                        ? DiagKind::NonManifoldGeometry
                        : DiagKind::GeometryFailed;
    std::string message = fmt::format("--{} of the whole scene failed: {}", stage, e.message);
    if (kind == DiagKind::NonManifoldGeometry) {
      diags.emit(DiagKind::NonManifoldGeometry, where, std::move(message));
    } else {
      diags.emit(DiagKind::GeometryFailed, where, std::move(message));
    }
  };
  std::vector<const kernel::Mesh*> parts;
  int32_t curves = 0;
  for (const OutputMesh* m : meshes) {
    parts.push_back(&m->mesh);
    curves += m->curve_count;
  }
  auto t0 = Clock::now();
  say("merge");
  kernel::Mesh all = kernel::concatenate(parts);
  auto merged = detail::Evaluator::merge_mesh(all, o.merge_tolerance);
  ++kernel_ops;
  if (timings) timings->merge_ms += ms_since(t0);
  if (!merged) {
    fail("merge", merged.error());
    return {};
  }
  kernel::Mesh mesh = std::move(merged->mesh);
  // Runs one step on `mesh`.
  auto run = [&](const Step& st, std::string_view flag, double* ms) -> bool {
    auto t1 = Clock::now();
    auto r = run_steps(std::move(mesh), {st}, kernel_ops);
    if (timings) *ms += ms_since(t1);
    if (auto* failed = std::get_if<StepFailure>(&r)) {
      fail(flag, failed->error);
      return false;
    }
    mesh = std::move(std::get<kernel::Mesh>(r));
    return true;
  };
  auto subdivide = [&](int32_t levels, std::string_view flag) -> bool {
    if (levels <= 0) return true;
    say("subdivide");
    Step st;
    st.subdivision.levels = levels;
    st.subdivision.vertex_rule = o.rule;
    st.subdivision.has_parent_maps = false;
    return run(st, flag, timings ? &timings->subdivide_ms : nullptr);
  };
  bool is_done = false;
  if (memos != nullptr) {
    // Incremental: every step at once per connected component, so an unchanged component
    // is reused whole; on a failure the steps are redone one by one below, for the same
    // diagnostics as a one-shot run.
    std::vector<Step> steps;
    Step st;
    st.subdivision.vertex_rule = o.rule;
    st.subdivision.has_parent_maps = false;
    st.subdivision.levels = o.subdivide_levels;
    steps.push_back(st);
    if (o.offset_height > 0) {
      Step off;
      off.kind = Step::Kind::Offset;
      off.height = o.offset_height;
      steps.push_back(off);
    }
    st.subdivision.levels = o.subdivide_after_levels;
    steps.push_back(st);
    say("subdivide");
    auto t1 = Clock::now();
    ComponentMemo next;
    auto r = run_steps_by_component(mesh, steps, memos->components, next, kernel_ops);
    memos->components = std::move(next);
    if (timings) timings->subdivide_ms += ms_since(t1);
    if (auto* m = std::get_if<kernel::Mesh>(&r)) {
      mesh = std::move(*m);
      is_done = true;
    } else {
      memos->components.entries.clear();
    }
  }
  if (!is_done) {
    if (!subdivide(o.subdivide_levels, "subdivide")) return {};
    if (o.offset_height > 0) {
      say("offset");
      Step st;
      st.kind = Step::Kind::Offset;
      st.height = o.offset_height;
      if (!run(st, "offset", timings ? &timings->offset_ms : nullptr)) return {};
    }
    if (!subdivide(o.subdivide_after_levels, "subdivide-after")) return {};
  }
  OutputMesh out;
  out.name = std::string(name);
  out.soup = kernel::to_soup(mesh);
  out.mesh = std::move(mesh);
  out.curve_count = curves;
  std::vector<OutputMesh> result;
  result.push_back(std::move(out));
  return result;
}

}  // namespace

struct SceneEvaluator::PipelineMemosHolder {
  PipelineMemos memos;
};

SceneEvaluator::SceneEvaluator(const ir::Module& module, bool is_incremental, PipelineOptions pipeline,
                               std::string pipeline_name, SourceRange pipeline_where)
    : impl_(std::make_unique<detail::Evaluator>(module, is_incremental)),
      module_(module),
      entries_(scene_entries(module)),
      is_incremental_(is_incremental),
      pipeline_(pipeline),
      pipeline_name_(std::move(pipeline_name)),
      pipeline_where_(pipeline_where) {
  for (size_t i = 0; i < module.nodes.size(); ++i) {
    const ir::Node& n = module.nodes[i];
    if (n.kind == ir::NodeKind::Edit && n.keyword == "zipper") zippers_.push_back(ir::NodeId{static_cast<int32_t>(i)});
  }
}

SceneEvaluator::~SceneEvaluator() = default;

void SceneEvaluator::invalidate(ir::NodeId param) { impl_->invalidate(param.index); }

EvalCounters SceneEvaluator::take_counters() { return std::exchange(impl_->counters, EvalCounters{}); }

std::vector<std::shared_ptr<const OutputMesh>> SceneEvaluator::evaluate(DiagnosticEngine& diags,
                                                                        StageTimings* timings) {
  auto t0 = Clock::now();
  const int errors_before = diags.error_count();
  impl_->begin_pass(diags);
  impl_->invalidate(-1);  // values that reported a diagnostic report it again
  std::vector<std::shared_ptr<const OutputMesh>> out;
  for (ir::NodeId id : entries_) {
    if (auto m = impl_->entry(id)) out.push_back(std::move(m));
  }
  // Zipper faces: one output mesh per `zipper` statement, after the scene entries.
  for (ir::NodeId id : zippers_) {
    if (auto m = impl_->zipper_entry(id)) out.push_back(std::move(m));
  }
  if (timings) timings->evaluate_ms += ms_since(t0);
  if (!pipeline_.any() || out.empty() || diags.error_count() > errors_before) return out;
  if (is_incremental_ && out == pipeline_inputs_) {
    impl_->counters.new_outputs.clear();
    return pipeline_outputs_;
  }
  std::vector<const OutputMesh*> parts;
  for (const auto& m : out) parts.push_back(m.get());
  if (!pipeline_memos_) pipeline_memos_ = std::make_shared<PipelineMemosHolder>();

  std::vector<OutputMesh> done = pipeline_impl(parts, pipeline_, pipeline_name_, pipeline_where_, diags, timings, {},
                                               is_incremental_ ? &pipeline_memos_->memos : nullptr,
                                               impl_->counters.kernel_ops);
  std::vector<std::shared_ptr<const OutputMesh>> result;
  impl_->counters.new_outputs.clear();
  for (OutputMesh& m : done) {
    result.push_back(std::make_shared<OutputMesh>(std::move(m)));
    impl_->counters.new_outputs.push_back(result.back().get());
  }
  if (is_incremental_) {
    pipeline_inputs_ = std::move(out);
    pipeline_outputs_ = result;
  }
  return result;
}

std::vector<OutputMesh> evaluate_scene(const ir::Module& module, DiagnosticEngine& diags,
                                       StageTimings* timings) {
  std::vector<OutputMesh> out;
  {
    SceneEvaluator ev(module, false);
    for (const auto& m : ev.evaluate(diags, timings)) {
      // A one-shot evaluator keeps no reference: these objects are ours to move from.
      out.push_back(std::move(const_cast<OutputMesh&>(*m)));
    }
  }
  return out;
}

std::vector<OutputMesh> run_pipeline(std::vector<OutputMesh> meshes, const PipelineOptions& o,
                                     std::string_view name, SourceRange where,
                                     DiagnosticEngine& diags, StageTimings* timings,
                                     const std::function<void(std::string_view)>& progress) {
  if (!o.any() || meshes.empty()) return meshes;
  std::vector<const OutputMesh*> parts;
  for (const OutputMesh& m : meshes) parts.push_back(&m);
  int32_t kernel_ops = 0;
  return pipeline_impl(parts, o, name, where, diags, timings, progress, nullptr, kernel_ops);
}

}  // namespace nomec::backend
