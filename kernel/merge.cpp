// Boundary merge: spatial hashing finds coinciding boundary vertices, boundary edges are
// matched through them, a union-find over the vertex matching graph gives the merged
// vertices, and the merged polygon soup is rebuilt (the builder sets Möbius flags where
// the joined faces have opposite orientations and detects non-manifold results).
#include "kernel/merge.h"

#include <fmt/format.h>

#include <algorithm>
#include <unordered_map>
#include <cmath>
#include <glm/geometric.hpp>
#include <numeric>

namespace nomec::kernel {
namespace {

class UnionFind {
 public:
  explicit UnionFind(int32_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int32_t find(int32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(int32_t a, int32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) {
      parent_[std::max(a, b)] = std::min(a, b);
    }
  }

 private:
  std::vector<int32_t> parent_;
};

struct CellKey {
  int64_t x, y, z;
  bool operator==(const CellKey&) const = default;
};
// A well-mixed 64-bit hash of a cell (neighbouring cells land far apart).
uint64_t cell_hash(const CellKey& k) {
  uint64_t h = static_cast<uint64_t>(k.x) * 0x9E3779B97F4A7C15ull ^ static_cast<uint64_t>(k.y) * 0xC2B2AE3D27D4EB4Full ^
               static_cast<uint64_t>(k.z) * 0x165667B19E3779F9ull;
  h ^= h >> 29;
  h *= 0xBF58476D1CE4E5B9ull;
  return h ^ (h >> 32);
}

}  // namespace

Mesh concatenate(std::span<const Mesh* const> meshes) {
  PolygonSoup soup;
  bool has_colors = false;
  bool has_names = false;
  for (const Mesh* m : meshes) {
    has_colors = has_colors || (m->has_face_colors() && m->face_count() > 0);
    has_names = has_names || m->has_vertex_names();
  }
  for (const Mesh* m : meshes) {
    PolygonSoup part = to_soup(*m);
    const int32_t base = soup.vertex_count();
    for (int32_t v = 0; v < part.vertex_count(); ++v) {
      soup.positions.push_back(part.positions[v]);
      if (has_names) {
        soup.names.push_back(part.names.empty() ? std::string() : part.names[v]);
      }
    }
    soup.face_sizes.insert(soup.face_sizes.end(), part.face_sizes.begin(), part.face_sizes.end());
    for (int32_t v : part.face_vertices) {
      soup.face_vertices.push_back(v + base);
    }
    soup.face_sources.insert(soup.face_sources.end(), part.face_sources.begin(),
                             part.face_sources.end());
    if (has_colors) {
      if (part.face_colors.empty()) {
        part.face_colors.assign(part.face_sizes.size(), glm::vec3(1.0f));
      }
      soup.face_colors.insert(soup.face_colors.end(), part.face_colors.begin(),
                              part.face_colors.end());
    }
    for (PolygonSoup::Corner c : part.corners) {
      c.vertex += base;
      soup.corners.push_back(c);
    }
    for (PolygonSoup::Crease c : part.creases) {
      c.a += base;
      c.b += base;
      soup.creases.push_back(c);
    }
  }
  auto built = build_mesh(soup);
  // Each part is a valid manifold and the parts share no vertices, so this cannot fail.
  return built.has_value() ? std::move(*built) : Mesh();
}

Mesh append_disjoint(std::span<const Mesh* const> meshes) {
  using A = MeshAccess;
  Mesh out;
  bool has_names = false, has_vertex_sharpness = false, has_sharpness = false, has_colors = false;
  size_t nv = 0, ne = 0, nf = 0;
  for (const Mesh* m : meshes) {
    has_names = has_names || m->has_vertex_names();
    has_vertex_sharpness = has_vertex_sharpness || !A::vertex_sharpness(*m).empty();
    has_sharpness = has_sharpness || m->has_sharpness();
    has_colors = has_colors || (m->has_face_colors() && m->face_count() > 0);
    nv += static_cast<size_t>(m->vertex_count());
    ne += static_cast<size_t>(m->edge_count());
    nf += static_cast<size_t>(m->face_count());
  }
  A::positions(out).resize(nv);
  A::vertex_edges(out).resize(nv, EdgeId::None());
  A::edge_vertices(out).resize(2 * ne);
  A::use_faces(out).resize(2 * ne, FaceId::None());
  A::next(out).resize(2 * ne, EdgeUse::None());
  A::prev(out).resize(2 * ne, EdgeUse::None());
  A::edge_flags(out).resize(ne);
  A::face_uses(out).resize(nf);
  resize_large(A::face_sources(out), nf);
  if (has_names) A::names(out).resize(nv);
  if (has_vertex_sharpness) A::vertex_sharpness(out).assign(nv, 0.0f);
  if (has_sharpness) A::sharpness(out).assign(ne, 0.0f);
  if (has_colors) A::face_colors(out).assign(nf, glm::vec3(1.0f));
  // Copies `from` into `to` at `at`, adding `by` to every valid index.
  auto shifted = [](const auto& from, auto& to, size_t at, int32_t by) {
    for (size_t i = 0; i < from.size(); ++i) {
      const int32_t x = from[i].index;
      to[at + i].index = x >= 0 ? x + by : x;
    }
  };
  size_t vb = 0, eb = 0, fb = 0;
  for (const Mesh* m : meshes) {
    const size_t V = static_cast<size_t>(m->vertex_count()), E = static_cast<size_t>(m->edge_count()),
                 F = static_cast<size_t>(m->face_count());
    const int32_t v0 = static_cast<int32_t>(vb), e0 = static_cast<int32_t>(eb), f0 = static_cast<int32_t>(fb);
    std::copy(m->positions().begin(), m->positions().end(), A::positions(out).begin() + vb);
    shifted(A::vertex_edges(*m), A::vertex_edges(out), vb, e0);
    if (m->has_vertex_names()) {
      for (size_t v = 0; v < V; ++v) {
        A::names(out)[vb + v] = m->vertex_name(VertexId(static_cast<int32_t>(v)));
      }
    }
    // Optional arrays are empty in `out` when no mesh has them: no offset into them then.
    const auto& vs = A::vertex_sharpness(*m);
    if (!vs.empty()) std::copy(vs.begin(), vs.end(), A::vertex_sharpness(out).begin() + vb);
    shifted(A::edge_vertices(*m), A::edge_vertices(out), 2 * eb, v0);
    shifted(A::use_faces(*m), A::use_faces(out), 2 * eb, f0);
    shifted(A::next(*m), A::next(out), 2 * eb, 2 * e0);
    shifted(A::prev(*m), A::prev(out), 2 * eb, 2 * e0);
    std::copy(A::edge_flags(*m).begin(), A::edge_flags(*m).end(), A::edge_flags(out).begin() + eb);
    const auto& es = A::sharpness(*m);
    if (!es.empty()) std::copy(es.begin(), es.end(), A::sharpness(out).begin() + eb);
    shifted(A::face_uses(*m), A::face_uses(out), fb, 2 * e0);
    const auto& fs = A::face_sources(*m);
    std::copy(fs.begin(), fs.end(), A::face_sources(out).begin() + fb);
    if (has_colors) {
      const auto& fc = A::face_colors(*m);
      std::copy(fc.begin(), fc.end(), A::face_colors(out).begin() + fb);
    }
    vb += V;
    eb += E;
    fb += F;
  }
  A::link_borders(out);
  return out;
}

namespace {

using Kind = KernelError::Kind;

// The boundary vertices of a mesh in a spatial hash of cells twelve tolerances wide (see
// `near`), with each one's (at most two) boundary edges and its own cell.
class BoundaryGrid {
 public:
  // Rationale: a lookup in the table of cells is a cache miss (neighbouring cells land far
  // apart). The box searched around a vertex meets a second cell on an axis only when the
  // vertex lies within 1.5 tolerances of its cell's side: with cells twelve tolerances wide
  // that is a quarter of the time, so a search makes about one lookup besides its own cell,
  // which each vertex keeps (with cells three tolerances wide, as before, every search made
  // eight). Boundary vertices lie on curves, so a wider cell holds proportionally more of
  // them only where they are closer than a few tolerances apart.
  static constexpr double kCellTolerances = 12;

  BoundaryGrid(const Mesh& mesh, double tolerance)
      : mesh_(mesh), tol_(tolerance), tol2_(tolerance * tolerance),
        cell_(std::max(kCellTolerances * tolerance, 1e-12)),
        boundary_at_(2 * static_cast<size_t>(mesh.vertex_count()), EdgeId::None()),
        cell_at_(static_cast<size_t>(mesh.vertex_count()), -1) {
    std::vector<int32_t> verts;
    for (int32_t e = 0; e < mesh.edge_count(); ++e) {
      if (!mesh.is_boundary(EdgeId(e))) continue;
      for (int end = 0; end < 2; ++end) {
        const int32_t v = mesh.edge_vertex(EdgeId(e), end).index;
        EdgeId* slot = &boundary_at_[2 * v];
        if (!slot[0].is_valid()) {
          slot[0] = EdgeId(e);
          verts.push_back(v);
        } else {
          slot[1] = EdgeId(e);
        }
      }
    }
    // An open-addressing table of the occupied cells (at most half full), each cell's
    // vertices one run of `cell_verts_`: counted, then placed (no per-cell allocation). A
    // slot holds the cell's number and the hash's high half, the key being in `keys_`: 8
    // bytes a slot keeps the table four times smaller (its lookups are cache misses).
    size_t cap = 16;
    while (cap < 2 * verts.size()) cap *= 2;
    mask_ = cap - 1;
    slots_.assign(cap, Slot{});
    keys_.reserve(verts.size());
    std::vector<int32_t> counts;
    for (size_t i = 0; i < verts.size(); ++i) {
      const CellKey k = key_of(mesh.position(VertexId(verts[i])));
      const uint64_t h = cell_hash(k);
      size_t at = h & mask_;
      while (slots_[at].cell >= 0 && !matches(slots_[at], h, k)) at = (at + 1) & mask_;
      if (slots_[at].cell < 0) {
        slots_[at] = Slot{static_cast<uint32_t>(h >> 32), static_cast<int32_t>(counts.size())};
        keys_.push_back(k);
        counts.push_back(0);
      }
      cell_at_[static_cast<size_t>(verts[i])] = slots_[at].cell;
      ++counts[static_cast<size_t>(slots_[at].cell)];
    }
    start_.assign(counts.size() + 1, 0);
    for (size_t c = 0; c < counts.size(); ++c) start_[c + 1] = start_[c] + counts[c];
    cell_verts_.resize(verts.size());
    std::vector<int32_t> fill(start_.begin(), start_.end() - 1);
    for (const int32_t v : verts) cell_verts_[static_cast<size_t>(fill[static_cast<size_t>(cell_at_[static_cast<size_t>(v)])]++)] = v;
  }

  /// Boundary edge `k` (0 or 1) at vertex `v`, or None.
  EdgeId boundary_edge(int32_t v, int k) const { return boundary_at_[2 * v + k]; }
  bool coincide(const glm::dvec3& a, const glm::dvec3& b) const {
    const glm::dvec3 d = a - b;
    return glm::dot(d, d) <= tol2_;
  }

  /// Boundary vertices coinciding with the boundary vertex v (including v itself).
  void near(int32_t v, std::vector<int32_t>& out) const {
    out.clear();
    const glm::dvec3& p = mesh_.position(VertexId(v));
    // A coinciding vertex lies within tol of p on every axis; the cells are wider than
    // three tolerances, so the box p ± 1.5 tol (the half tolerance of margin absorbs
    // rounding) meets at most two cells per axis, one of them p's own.
    const CellKey own = key_of(p);
    const CellKey lo = key_of(p - 1.5 * tol_);
    const CellKey hi = key_of(p + 1.5 * tol_);
    for (int64_t x = lo.x; x <= hi.x; ++x) {
      for (int64_t y = lo.y; y <= hi.y; ++y) {
        for (int64_t z = lo.z; z <= hi.z; ++z) {
          const CellKey k{x, y, z};
          const int32_t c = k == own ? cell_at_[static_cast<size_t>(v)] : find(k);
          if (c < 0) continue;
          for (int32_t i = start_[static_cast<size_t>(c)]; i < start_[static_cast<size_t>(c) + 1]; ++i) {
            const int32_t w = cell_verts_[static_cast<size_t>(i)];
            if (coincide(mesh_.position(VertexId(w)), p)) out.push_back(w);
          }
        }
      }
    }
  }

 private:
  // Cell coordinates stay well inside int64 (so neighbours ±1 cannot overflow either),
  // whatever the ratio of the coordinates to the cell size.
  int64_t to_cell(double v) const {
    const double c = std::floor(v / cell_);
    constexpr double kLimit = 4.0e18;
    return c != c ? int64_t{0} : static_cast<int64_t>(std::clamp(c, -kLimit, kLimit));
  }
  CellKey key_of(const glm::dvec3& p) const { return CellKey{to_cell(p.x), to_cell(p.y), to_cell(p.z)}; }
  /// The cell's index, or -1 when no boundary vertex lies in it.
  int32_t find(const CellKey& k) const {
    const uint64_t h = cell_hash(k);
    for (size_t at = h & mask_;; at = (at + 1) & mask_) {
      if (slots_[at].cell < 0) return -1;
      if (matches(slots_[at], h, k)) return slots_[at].cell;
    }
  }

  struct Slot {
    uint32_t hash_high = 0;
    int32_t cell = -1;
  };
  bool matches(const Slot& s, uint64_t h, const CellKey& k) const {
    return s.hash_high == static_cast<uint32_t>(h >> 32) && keys_[static_cast<size_t>(s.cell)] == k;
  }

  const Mesh& mesh_;
  double tol_;
  double tol2_;
  double cell_;
  std::vector<EdgeId> boundary_at_;
  std::vector<int32_t> cell_at_;  // each boundary vertex's cell (-1 for the others)
  std::vector<Slot> slots_;
  std::vector<CellKey> keys_;  // by cell
  size_t mask_ = 0;
  std::vector<int32_t> start_;       // cell c's vertices: cell_verts_[start_[c], start_[c + 1])
  std::vector<int32_t> cell_verts_;
};

// Matches every boundary edge with the one other boundary edge (of another face) whose ends
// coincide with its ends, uniting the coinciding vertices in `uf`. Returns the edges that
// coincide with more than one; counts the joined pairs in `joined`.
std::vector<EdgeId> match_boundary_edges(const Mesh& mesh, const BoundaryGrid& grid, UnionFind& uf, int32_t& joined) {
  std::vector<EdgeId> conflicts;
  std::vector<int32_t> near_a;
  for (int32_t e = 0; e < mesh.edge_count(); ++e) {
    if (!mesh.is_boundary(EdgeId(e))) continue;
    const int32_t a = mesh.edge_vertex(EdgeId(e), 0).index;
    const int32_t b = mesh.edge_vertex(EdgeId(e), 1).index;
    grid.near(a, near_a);
    int32_t found = 0;
    EdgeId partner;
    int32_t partner_a = -1, partner_b = -1;
    for (int32_t a2 : near_a) {
      for (int k = 0; k < 2; ++k) {
        const EdgeId e2 = grid.boundary_edge(a2, k);
        if (!e2.is_valid() || e2.index == e || mesh.edge_face(e2, 0) == mesh.edge_face(EdgeId(e), 0)) continue;
        const int32_t x = mesh.edge_vertex(e2, 0).index;
        const int32_t b2 = x == a2 ? mesh.edge_vertex(e2, 1).index : x;
        if (b2 != a2 && grid.coincide(mesh.position(VertexId(b2)), mesh.position(VertexId(b)))) {
          ++found;
          partner = e2;
          partner_a = a2;
          partner_b = b2;
        }
      }
    }
    if (found > 1) {
      conflicts.push_back(EdgeId(e));
    } else if (found == 1) {
      if (e < partner.index) ++joined;
      uf.unite(a, partner_a);
      uf.unite(b, partner_b);
    }
  }
  return conflicts;
}

KernelError conflict_error(const Mesh& mesh, const std::vector<EdgeId>& conflicts) {
  KernelError error{Kind::NonManifoldMerge, {}, conflicts, {}, {}};
  for (EdgeId e : conflicts) error.faces.push_back(mesh.edge_face(e, 0));
  error.message = fmt::format(
      "{} boundary edge(s) coincide with more than one other boundary edge, first joins vertices {} and {}; "
      "joining them would put three or more faces on one edge",
      conflicts.size(), mesh.edge_vertex(conflicts[0], 0).index, mesh.edge_vertex(conflicts[0], 1).index);
  return error;
}

// The soup with one vertex per union-find class (numbered by first appearance, at the
// class's average position); `vertex_map` gets each input vertex's merged vertex.
PolygonSoup merged_soup(PolygonSoup soup, UnionFind& uf, std::vector<VertexId>& vertex_map) {
  const int32_t V = soup.vertex_count();
  vertex_map.assign(V, VertexId::None());
  PolygonSoup merged;
  std::vector<int32_t> class_size;
  for (int32_t v = 0; v < V; ++v) {
    const int32_t root = uf.find(v);
    if (root == v) {
      vertex_map[v] = VertexId(merged.vertex_count());
      merged.positions.push_back(glm::dvec3(0.0));
      if (!soup.names.empty()) merged.names.push_back(soup.names[v]);
      class_size.push_back(0);
    } else {
      vertex_map[v] = vertex_map[root];
    }
    merged.positions[vertex_map[v].index] += soup.positions[v];
    ++class_size[vertex_map[v].index];
  }
  for (size_t i = 0; i < merged.positions.size(); ++i) merged.positions[i] /= double(class_size[i]);
  merged.face_sizes = std::move(soup.face_sizes);
  merged.face_vertices.reserve(soup.face_vertices.size());
  for (int32_t v : soup.face_vertices) merged.face_vertices.push_back(vertex_map[v].index);
  merged.face_sources = std::move(soup.face_sources);
  merged.face_colors = std::move(soup.face_colors);
  // Corners and creases: keep the larger sharpness when merged elements both carry one
  // (corners are sorted by sharpness so the builder, which keeps the last, keeps the max).
  for (PolygonSoup::Corner c : soup.corners) {
    c.vertex = vertex_map[c.vertex].index;
    merged.corners.push_back(c);
  }
  std::sort(merged.corners.begin(), merged.corners.end(), [](const PolygonSoup::Corner& x, const PolygonSoup::Corner& y) {
    return x.vertex != y.vertex ? x.vertex < y.vertex : x.sharpness < y.sharpness;
  });
  std::unordered_map<uint64_t, size_t> seen;
  for (PolygonSoup::Crease c : soup.creases) {
    c.a = vertex_map[c.a].index;
    c.b = vertex_map[c.b].index;
    const uint64_t key = (uint64_t(uint32_t(std::min(c.a, c.b))) << 32) | uint32_t(std::max(c.a, c.b));
    auto [it, is_new] = seen.emplace(key, merged.creases.size());
    if (is_new) {
      merged.creases.push_back(c);
    } else {
      merged.creases[it->second].sharpness = std::max(merged.creases[it->second].sharpness, c.sharpness);
    }
  }
  return merged;
}

// The builder's refusal of the merged soup, about the input's vertices.
KernelError refused(KernelError error, const std::vector<VertexId>& vertex_map) {
  std::vector<VertexId> inputs;
  for (VertexId merged_v : error.vertices) {
    for (size_t v = 0; v < vertex_map.size(); ++v) {
      if (vertex_map[v] == merged_v) inputs.push_back(VertexId(static_cast<int32_t>(v)));
    }
  }
  error.vertices = std::move(inputs);
  error.edges.clear();
  error.message = "merge refused: " + error.message;
  error.kind = Kind::NonManifoldMerge;
  return error;
}

}  // namespace

Result<MergeResult> merge(const Mesh& mesh, const MergeOptions& options) {
  if (!(options.tolerance >= 0.0)) {
    return KernelError{Kind::InvalidArgument, fmt::format("merge tolerance {} is negative", options.tolerance), {}, {}, {}};
  }
  const BoundaryGrid grid(mesh, options.tolerance);
  UnionFind uf(mesh.vertex_count());
  MergeResult result;
  const std::vector<EdgeId> conflicts = match_boundary_edges(mesh, grid, uf, result.joined_edge_count);
  if (!conflicts.empty()) return conflict_error(mesh, conflicts);
  auto built = build_mesh(merged_soup(to_soup(mesh), uf, result.vertex_map));
  if (!built.has_value()) return refused(built.error(), result.vertex_map);
  result.mesh = std::move(*built);
  return result;
}

Result<MergeResult> merge(std::span<const Mesh* const> meshes, const MergeOptions& options) {
  return merge(concatenate(meshes), options);
}

}  // namespace nomec::kernel
