// Winged-edge mesh construction from a polygon soup (seed report §2.2), border-loop
// linking, and the small traversal helpers that are not hot enough to live inline.
#include "kernel/mesh.h"

#include <fmt/format.h>

#include <algorithm>
#include <numeric>
#include <optional>

#include "kernel/large_arrays.h"

namespace nomec::kernel {

int32_t PolygonSoup::add_vertex(const glm::dvec3& position, std::string name) {
  if (!name.empty() && names.size() < positions.size()) {
    names.resize(positions.size());
  }
  positions.push_back(position);
  if (!names.empty() || !name.empty()) {
    names.push_back(std::move(name));
  }
  return static_cast<int32_t>(positions.size()) - 1;
}

int32_t PolygonSoup::add_face(std::span<const int32_t> vertices) {
  face_sizes.push_back(static_cast<int32_t>(vertices.size()));
  face_vertices.insert(face_vertices.end(), vertices.begin(), vertices.end());
  return static_cast<int32_t>(face_sizes.size()) - 1;
}

Result<int32_t> PolygonSoup::add_face_by_names(std::span<const std::string> vertex_names) {
  std::vector<int32_t> ids;
  ids.reserve(vertex_names.size());
  for (const std::string& name : vertex_names) {
    auto it = std::find(names.begin(), names.end(), name);
    if (name.empty() || it == names.end()) {
      return KernelError{KernelError::Kind::UnknownVertex,
                         fmt::format("face references unknown vertex `{}`", name),
                         {},
                         {},
                         {}};
    }
    ids.push_back(static_cast<int32_t>(it - names.begin()));
  }
  return add_face(ids);
}

EdgeId Mesh::find_edge(VertexId a, VertexId b) const {
  EdgeId found = EdgeId::None();
  for_each_vertex_corner(a, [&](const VertexCorner& c) {
    EdgeId out = c.use.edge();
    EdgeId in = prev(c.use).edge();
    for (EdgeId e : {out, in}) {
      VertexId x = edge_vertex(e, 0), y = edge_vertex(e, 1);
      if ((x == a && y == b) || (x == b && y == a)) {
        found = e;
      }
    }
  });
  return found;
}

Result<bool> Mesh::set_vertex_normals(std::vector<glm::dvec3> normals) {
  if (normals.size() != positions_.size()) {
    return KernelError{
        KernelError::Kind::InvalidArgument,
        fmt::format("{} vertex normals given for {} vertices", normals.size(), positions_.size()),
        {},
        {},
        {}};
  }
  normals_ = std::move(normals);
  return true;
}

int32_t Mesh::face_size(FaceId f) const {
  int32_t n = 0;
  for_each_face_use(f, [&](EdgeUse) { ++n; });
  return n;
}

std::vector<VertexId> Mesh::face_vertices(FaceId f) const {
  std::vector<VertexId> result;
  for_each_face_use(f, [&](EdgeUse u) { result.push_back(use_tail(u)); });
  return result;
}

std::vector<VertexCorner> Mesh::vertex_ring(VertexId v) const {
  std::vector<VertexCorner> ring;
  for_each_vertex_corner(v, [&](const VertexCorner& c) { ring.push_back(c); });
  return ring;
}

int32_t Mesh::vertex_valence(VertexId v) const {
  // A closed fan of k corners has k edges; an open fan has one more.
  int32_t corners = 0;
  for_each_vertex_corner(v, [&](const VertexCorner&) { ++corners; });
  return corners + (is_boundary_vertex(v) ? 1 : 0);
}

std::vector<EdgeId> Mesh::border_loop_edges(int32_t loop) const {
  std::vector<EdgeId> edges;
  EdgeId start = border_loops_[loop];
  EdgeId e = start;
  do {
    edges.push_back(e);
    e = border_next(e);
  } while (e != start && edges.size() <= edge_vertices_.size());
  return edges;
}

bool Mesh::has_mobius_edges() const {
  return std::any_of(edge_flags_.begin(), edge_flags_.end(),
                     [](uint8_t f) { return (f & kMobiusFlag) != 0; });
}

size_t Mesh::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  size_t total = bytes(positions_) + bytes(normals_) + bytes(vertex_sharpness_) +
                 bytes(vertex_edges_) + bytes(edge_vertices_) + bytes(use_faces_) + bytes(next_) +
                 bytes(prev_) + bytes(edge_flags_) + bytes(sharpness_) + bytes(face_uses_) +
                 bytes(face_sources_) + bytes(face_colors_) + bytes(border_loops_);
  for (const std::string& n : names_) {
    total += sizeof(std::string) + (n.capacity() > 15 ? n.capacity() : 0);
  }
  return total;
}

void MeshAccess::link_borders(Mesh& m) {
  m.border_loops_.clear();
  const int32_t vertex_count = m.vertex_count();
  const int32_t edge_count = m.edge_count();
  // A closed mesh (e.g. every offset) needs neither the per-vertex table nor the loops.
  bool is_closed = true;
  for (int32_t i = 0; i < edge_count && is_closed; ++i) is_closed = m.use_faces_[2 * i + 1].is_valid();
  if (is_closed) return;
  // Up to two boundary edges per vertex (more would be a non-manifold vertex, which
  // the builder rejects before calling this).
  std::vector<EdgeId> at_vertex(2 * static_cast<size_t>(vertex_count), EdgeId::None());
  bool has_border = false;
  for (int32_t i = 0; i < edge_count; ++i) {
    EdgeId e(i);
    if (!m.is_boundary(e)) {
      continue;
    }
    has_border = true;
    for (int end = 0; end < 2; ++end) {
      int32_t v = m.edge_vertices_[2 * i + end].index;
      EdgeId* slot = &at_vertex[2 * v];
      if (!slot[0].is_valid()) {
        slot[0] = e;
      } else {
        slot[1] = e;
      }
    }
    m.next_[2 * i + 1] = EdgeUse::None();
    m.prev_[2 * i + 1] = EdgeUse::None();
  }
  if (!has_border) {
    return;
  }
  for (int32_t i = 0; i < edge_count; ++i) {
    EdgeId start(i);
    if (!m.is_boundary(start) || m.next_[2 * i + 1].is_valid()) {
      continue;
    }
    m.border_loops_.push_back(start);
    EdgeId e = start;
    VertexId at = m.edge_vertex(e, 1);
    for (int32_t guard = 0; guard <= edge_count; ++guard) {
      EdgeId* slot = &at_vertex[2 * at.index];
      EdgeId next = slot[0] == e ? slot[1] : slot[0];
      if (!next.is_valid()) {
        next = e;  // unreachable for manifold input; keeps the loop well formed
      }
      m.next_[2 * e.index + 1] = EdgeUse(next, 0);
      m.prev_[2 * next.index + 1] = EdgeUse(e, 0);
      if (next == start) {
        break;
      }
      at = m.edge_vertex(next, 0) == at ? m.edge_vertex(next, 1) : m.edge_vertex(next, 0);
      e = next;
    }
  }
}

namespace {

// The builder's auxiliary map (§2.2) as a counting sort instead of a hash table: for
// every use k (the k-th consecutive vertex pair in soup order) returns the smallest use
// index with the same unordered vertex pair. Uses are bucketed by their smaller vertex
// and each (small) bucket is scanned; unlike hashing, every pass is sequential or hits a
// per-vertex array, which keeps large builds (offsets, merges) out of cache-miss land.
// Linear for bounded valence; buckets of high-valence vertices are sorted instead.
std::vector<int32_t> first_uses(const PolygonSoup& soup) {
  const size_t use_count = soup.face_vertices.size();
  const int32_t vertex_count = soup.vertex_count();
  std::vector<int32_t> successor(use_count);
  size_t offset = 0;
  for (int32_t n : soup.face_sizes) {
    for (int32_t i = 0; i < n; ++i) {
      successor[offset + i] = soup.face_vertices[offset + (i + 1 == n ? 0 : i + 1)];
    }
    offset += n;
  }
  std::vector<int32_t> start(static_cast<size_t>(vertex_count) + 1, 0);
  for (size_t k = 0; k < use_count; ++k) {
    ++start[std::min(soup.face_vertices[k], successor[k]) + 1];
  }
  for (int32_t v = 0; v < vertex_count; ++v) {
    start[v + 1] += start[v];
  }
  struct Entry {
    int32_t hi;
    int32_t use;
  };
  std::vector<Entry> bucket(use_count);
  {
    std::vector<int32_t> cursor(start.begin(), start.end() - 1);
    for (size_t k = 0; k < use_count; ++k) {
      const int32_t a = soup.face_vertices[k], b = successor[k];
      bucket[cursor[std::min(a, b)]++] = {std::max(a, b), static_cast<int32_t>(k)};
    }
  }
  std::vector<int32_t> first(use_count);
  constexpr int32_t kSortAbove = 32;
  for (int32_t v = 0; v < vertex_count; ++v) {
    if (start[v + 1] - start[v] > kSortAbove) {
      // High-valence vertex (e.g. the pole of a fan): sort its bucket instead of the
      // quadratic scan.
      std::sort(bucket.begin() + start[v], bucket.begin() + start[v + 1],
                [](const Entry& x, const Entry& y) {
                  return x.hi != y.hi ? x.hi < y.hi : x.use < y.use;
                });
      for (int32_t i = start[v]; i < start[v + 1]; ++i) {
        const bool is_first = i == start[v] || bucket[i - 1].hi != bucket[i].hi;
        first[bucket[i].use] = is_first ? bucket[i].use : first[bucket[i - 1].use];
      }
      continue;
    }
    for (int32_t i = start[v]; i < start[v + 1]; ++i) {
      // Entries were appended in use order, so the first match is the earliest use.
      first[bucket[i].use] = bucket[i].use;
      for (int32_t j = start[v]; j < i; ++j) {
        if (bucket[j].hi == bucket[i].hi) {
          first[bucket[i].use] = bucket[j].use;
          break;
        }
      }
    }
  }
  return first;
}

std::string vertex_label(const PolygonSoup& soup, int32_t v) {
  if (v >= 0 && v < static_cast<int32_t>(soup.names.size()) && !soup.names[v].empty()) {
    return soup.names[v];
  }
  return fmt::format("v{}", v);
}


using Kind = KernelError::Kind;

// The soup's arrays agree in length, every face index is a vertex, and no face is
// degenerate (fewer than 3 vertices, or one repeated in a row), so later passes can trust
// the indices.
std::optional<KernelError> check_soup(const PolygonSoup& soup) {
  const int32_t vertex_count = soup.vertex_count();
  const int32_t face_count = soup.face_count();
  if (std::accumulate(soup.face_sizes.begin(), soup.face_sizes.end(), size_t(0)) != soup.face_vertices.size() ||
      (!soup.face_sources.empty() && soup.face_sources.size() != size_t(face_count)) ||
      (!soup.face_colors.empty() && soup.face_colors.size() != size_t(face_count)) ||
      (!soup.names.empty() && soup.names.size() != size_t(vertex_count))) {
    return KernelError{Kind::InvalidArgument, "polygon soup arrays have inconsistent lengths", {}, {}, {}};
  }
  KernelError degenerate{Kind::DegenerateFace, {}, {}, {}, {}};
  size_t offset = 0;
  for (int32_t f = 0; f < face_count; ++f) {
    const int32_t n = soup.face_sizes[f];
    const int32_t* fv = soup.face_vertices.data() + offset;
    offset += n;
    for (int32_t i = 0; i < n; ++i) {
      if (fv[i] < 0 || fv[i] >= vertex_count) {
        return KernelError{Kind::UnknownVertex,
                           fmt::format("face {} references vertex index {} but the mesh has {} vertices", f, fv[i],
                                       vertex_count),
                           {},
                           {FaceId(f)},
                           {}};
      }
    }
    bool is_degenerate = n < 3;
    for (int32_t i = 0; i < n && !is_degenerate; ++i) is_degenerate = fv[i] == fv[(i + 1) % n];
    if (is_degenerate) degenerate.faces.push_back(FaceId(f));
  }
  if (degenerate.faces.empty()) return std::nullopt;
  degenerate.message = fmt::format("{} face(s) have fewer than 3 vertices or repeat a vertex, first is face {}",
                                   degenerate.faces.size(), degenerate.faces[0].index);
  return degenerate;
}

// The error for edges that a third (or later) face uses: (edge, extra face) pairs.
KernelError non_manifold_edges(const PolygonSoup& soup, const Mesh& m,
                               std::vector<std::pair<int32_t, int32_t>> extra_faces) {
  const auto& edge_vertices = MeshAccess::edge_vertices(m);
  const auto& use_faces = MeshAccess::use_faces(m);
  KernelError error{Kind::NonManifoldEdge, {}, {}, {}, {}};
  std::sort(extra_faces.begin(), extra_faces.end());
  // The message lists the first few edges (a scene with thousands would bury the reader);
  // `error` keeps them all for the diagnostics' ranges.
  constexpr size_t kListed = 5;
  std::string listing;
  for (size_t i = 0; i < extra_faces.size(); ++i) {
    const int32_t e = extra_faces[i].first;
    const bool listed = error.edges.size() <= kListed;
    if (i > 0 && extra_faces[i - 1].first == e) {
      error.faces.push_back(FaceId(extra_faces[i].second));
      if (listed) listing += fmt::format(", {}", extra_faces[i].second);
      continue;
    }
    error.edges.push_back(EdgeId(e));
    error.vertices.push_back(edge_vertices[2 * e]);
    error.vertices.push_back(edge_vertices[2 * e + 1]);
    error.faces.push_back(use_faces[2 * e]);
    error.faces.push_back(use_faces[2 * e + 1]);
    error.faces.push_back(FaceId(extra_faces[i].second));
    if (error.edges.size() > kListed) continue;
    if (!listing.empty()) listing += "; ";
    listing += fmt::format("edge `{}`-`{}` in faces {}, {}, {}", vertex_label(soup, edge_vertices[2 * e].index),
                           vertex_label(soup, edge_vertices[2 * e + 1].index), use_faces[2 * e].index,
                           use_faces[2 * e + 1].index, extra_faces[i].second);
  }
  if (error.edges.size() > kListed) listing += fmt::format("; and {} more", error.edges.size() - kListed);
  error.message = fmt::format("{} edge(s) are shared by more than two faces: {}", error.edges.size(), listing);
  return error;
}

// One edge per vertex pair that faces share (the first face's use is side 0, the second's
// side 1; the same direction in both marks a Möbius edge); `uses` gets each corner's use.
// `first[k]` is the smallest use index with use k's unordered vertex pair (`first_uses`).
std::optional<KernelError> make_edges(const PolygonSoup& soup, Mesh& m, const std::vector<int32_t>& first,
                                      std::vector<EdgeUse>& uses) {
  auto& edge_vertices = MeshAccess::edge_vertices(m);
  auto& use_faces = MeshAccess::use_faces(m);
  auto& flags = MeshAccess::edge_flags(m);
  const size_t use_count = soup.face_vertices.size();
  const size_t expected_edges = use_count / 2 + 8;
  reserve_large(edge_vertices, 2 * expected_edges);
  reserve_large(use_faces, 2 * expected_edges);
  reserve_large(flags, expected_edges);
  reserve_large(uses, use_count);
  uses.assign(use_count, EdgeUse::None());
  std::vector<std::pair<int32_t, int32_t>> extra_faces;  // edge index -> a third face
  size_t offset = 0;
  for (int32_t f = 0; f < soup.face_count(); ++f) {
    const int32_t n = soup.face_sizes[f];
    const int32_t* fv = soup.face_vertices.data() + offset;
    for (int32_t i = 0; i < n; ++i) {
      const int32_t a = fv[i];
      const int32_t b = fv[(i + 1) % n];
      const size_t k = offset + i;
      if (first[k] == static_cast<int32_t>(k)) {
        const int32_t e = static_cast<int32_t>(flags.size());
        edge_vertices.push_back(VertexId(a));
        edge_vertices.push_back(VertexId(b));
        use_faces.push_back(FaceId(f));
        use_faces.push_back(FaceId::None());
        flags.push_back(0);
        uses[k] = EdgeUse(EdgeId(e), 0);
        continue;
      }
      const int32_t e = uses[first[k]].edge().index;
      if (use_faces[2 * e + 1].is_valid()) {
        extra_faces.emplace_back(e, f);
        continue;
      }
      use_faces[2 * e + 1] = FaceId(f);
      // Same direction as the first face means the faces have opposite orientations.
      if (edge_vertices[2 * e].index == a) flags[e] |= MeshAccess::mobius_flag();
      uses[k] = EdgeUse(EdgeId(e), 1);
    }
    offset += n;
  }
  if (!extra_faces.empty()) return non_manifold_edges(soup, m, std::move(extra_faces));
  return std::nullopt;
}

// Wings: each face's uses linked into its cyclic loop.
void link_wings(const PolygonSoup& soup, Mesh& m, const std::vector<EdgeUse>& uses) {
  auto& next = MeshAccess::next(m);
  auto& prev = MeshAccess::prev(m);
  auto& face_uses = MeshAccess::face_uses(m);
  const size_t edge_count = MeshAccess::edge_flags(m).size();
  reserve_large(next, 2 * edge_count);
  reserve_large(prev, 2 * edge_count);
  next.assign(2 * edge_count, EdgeUse::None());
  prev.assign(2 * edge_count, EdgeUse::None());
  resize_large(face_uses, soup.face_count());
  size_t offset = 0;
  for (int32_t f = 0; f < soup.face_count(); ++f) {
    const int32_t n = soup.face_sizes[f];
    const EdgeUse* fu = uses.data() + offset;
    face_uses[f] = fu[0];
    for (int32_t i = 0; i < n; ++i) {
      next[fu[i].index] = fu[(i + 1) % n];
      prev[fu[(i + 1) % n].index] = fu[i];
    }
    offset += n;
  }
}

// Vertex anchors: any incident edge, preferring boundary edges.
void anchor_vertices(Mesh& m) {
  auto& vertex_edges = MeshAccess::vertex_edges(m);
  const auto& edge_vertices = MeshAccess::edge_vertices(m);
  const auto& use_faces = MeshAccess::use_faces(m);
  reserve_large(vertex_edges, m.vertex_count());
  vertex_edges.assign(m.vertex_count(), EdgeId::None());
  for (int32_t e = 0; e < m.edge_count(); ++e) {
    const bool is_boundary = !use_faces[2 * e + 1].is_valid();
    for (int end = 0; end < 2; ++end) {
      EdgeId& anchor = vertex_edges[edge_vertices[2 * e + end].index];
      if (!anchor.is_valid() || (is_boundary && !m.is_boundary(anchor))) anchor = EdgeId(e);
    }
  }
}

// Manifold vertices: the single fan found by traversal must hold every corner, and a
// vertex lies on at most two boundary edges.
std::optional<KernelError> check_vertex_fans(const PolygonSoup& soup, const Mesh& m) {
  const int32_t vertex_count = soup.vertex_count();
  const auto& edge_vertices = MeshAccess::edge_vertices(m);
  const auto& use_faces = MeshAccess::use_faces(m);
  std::vector<int32_t> corner_count(vertex_count, 0);
  for (int32_t v : soup.face_vertices) ++corner_count[v];
  std::vector<int32_t> boundary_count(vertex_count, 0);
  for (int32_t e = 0; e < m.edge_count(); ++e) {
    if (!use_faces[2 * e + 1].is_valid()) {
      ++boundary_count[edge_vertices[2 * e].index];
      ++boundary_count[edge_vertices[2 * e + 1].index];
    }
  }
  KernelError error{Kind::NonManifoldVertex, {}, {}, {}, {}};
  for (int32_t v = 0; v < vertex_count; ++v) {
    if (corner_count[v] == 0) continue;
    int32_t walked = 0;
    m.for_each_vertex_corner(VertexId(v), [&](const VertexCorner&) { ++walked; });
    if (walked != corner_count[v] || boundary_count[v] > 2) error.vertices.push_back(VertexId(v));
  }
  if (error.vertices.empty()) return std::nullopt;
  error.message = fmt::format("{} vertex(es) join faces that do not form a single fan, first is `{}`",
                              error.vertices.size(), vertex_label(soup, error.vertices[0].index));
  return error;
}

// Face sources and colours (unless `are_faces_set`), vertex names, crease and corner sharpness.
std::optional<KernelError> copy_properties(const PolygonSoup& soup, Mesh& m, bool are_faces_set = false) {
  const int32_t vertex_count = m.vertex_count();  // the soup's positions may have moved into m
  auto& face_sources = MeshAccess::face_sources(m);
  if (are_faces_set) {
    // The caller moved the sources and colours in (`build_paired`).
  } else if (soup.face_sources.empty()) {
    resize_large(face_sources, soup.face_count());
    for (int32_t f = 0; f < soup.face_count(); ++f) face_sources[f].source_face = f;
    MeshAccess::face_colors(m) = soup.face_colors;
  } else {
    face_sources.assign(soup.face_sources.begin(), soup.face_sources.end());
    MeshAccess::face_colors(m) = soup.face_colors;
  }
  if (!soup.names.empty()) MeshAccess::names(m) = soup.names;
  auto& sharpness = MeshAccess::sharpness(m);
  if (!soup.creases.empty()) sharpness.assign(m.edge_count(), 0.0f);
  for (const PolygonSoup::Crease& c : soup.creases) {
    if (c.a < 0 || c.a >= vertex_count || c.b < 0 || c.b >= vertex_count) {
      return KernelError{Kind::UnknownVertex,
                         fmt::format("crease references vertex index {} or {} but the mesh has {} vertices", c.a,
                                     c.b, vertex_count),
                         {},
                         {},
                         {}};
    }
    const EdgeId e = m.find_edge(VertexId(c.a), VertexId(c.b));
    if (!e.is_valid()) {
      return KernelError{Kind::InvalidArgument,
                         fmt::format("crease `{}`-`{}` is not an edge of the mesh", vertex_label(soup, c.a),
                                     vertex_label(soup, c.b)),
                         {},
                         {},
                         {VertexId(c.a), VertexId(c.b)}};
    }
    sharpness[e.index] = std::max(c.sharpness, 0.0f);
  }
  for (const PolygonSoup::Corner& c : soup.corners) {
    if (c.vertex < 0 || c.vertex >= vertex_count) {
      return KernelError{Kind::UnknownVertex,
                         fmt::format("sharp corner references vertex index {} but the mesh has {} vertices",
                                     c.vertex, vertex_count),
                         {},
                         {},
                         {}};
    }
    m.set_vertex_sharpness(VertexId(c.vertex), std::max(c.sharpness, 0.0f));
  }
  return std::nullopt;
}

}  // namespace

Result<Mesh> build_mesh(const PolygonSoup& soup) {
  if (auto e = check_soup(soup)) return *e;
  Mesh m;
  reserve_large(MeshAccess::positions(m), soup.positions.size());
  MeshAccess::positions(m).assign(soup.positions.begin(), soup.positions.end());
  std::vector<EdgeUse> uses;
  if (auto e = make_edges(soup, m, first_uses(soup), uses)) return *e;
  link_wings(soup, m, uses);
  anchor_vertices(m);
  if (auto e = check_vertex_fans(soup, m)) return *e;
  if (auto e = copy_properties(soup, m)) return *e;
  MeshAccess::link_borders(m);
  return m;
}

Result<Mesh> MeshAccess::build_paired(PolygonSoup soup, std::vector<int32_t> twin) {
  // The pairing stands in for `first_uses` (each edge has at most two uses, so the first
  // of a pair is the smaller index); the caller vouches for the soup and the fans.
  std::vector<int32_t>& first = twin;
  for (size_t k = 0; k < first.size(); ++k) {
    const int32_t self = static_cast<int32_t>(k);
    first[k] = first[k] >= 0 ? std::min(self, first[k]) : self;
  }
  Mesh m;
  reserve_large(MeshAccess::positions(m), soup.positions.size());
  MeshAccess::positions(m).assign(soup.positions.begin(), soup.positions.end());
  std::vector<glm::dvec3>().swap(soup.positions);
  std::vector<EdgeUse> uses;
  if (auto e = make_edges(soup, m, first, uses)) return *e;
  link_wings(soup, m, uses);
  anchor_vertices(m);
  const bool are_faces_set = !soup.face_sources.empty();
  if (are_faces_set) {
    MeshAccess::face_sources(m).assign(soup.face_sources.begin(), soup.face_sources.end());
    std::vector<FaceSource>().swap(soup.face_sources);
    MeshAccess::face_colors(m) = std::move(soup.face_colors);
  }
  if (auto e = copy_properties(soup, m, are_faces_set)) return *e;
  MeshAccess::link_borders(m);
  return m;
}

bool has_same_topology(const Mesh& a, const Mesh& b) {
  using A = MeshAccess;
  return a.vertex_count() == b.vertex_count() && A::vertex_edges(a) == A::vertex_edges(b) &&
         A::edge_vertices(a) == A::edge_vertices(b) && A::use_faces(a) == A::use_faces(b) &&
         A::next(a) == A::next(b) && A::prev(a) == A::prev(b) && A::edge_flags(a) == A::edge_flags(b) &&
         A::sharpness(a) == A::sharpness(b) && A::vertex_sharpness(a) == A::vertex_sharpness(b) &&
         A::face_uses(a) == A::face_uses(b) && A::face_sources(a) == A::face_sources(b) &&
         A::face_colors(a) == A::face_colors(b) && a.border_loops() == b.border_loops() &&
         A::names(a) == A::names(b);
}

PolygonSoup to_soup(const Mesh& mesh) {
  PolygonSoup soup;
  soup.positions.assign(mesh.positions().begin(), mesh.positions().end());
  for (int32_t v = 0; v < mesh.vertex_count() && mesh.has_vertex_names(); ++v) {
    soup.names.emplace_back(mesh.vertex_name(VertexId(v)));
  }
  soup.face_sizes.reserve(mesh.face_count());
  soup.face_sources.reserve(mesh.face_count());
  // Every face corner is an edge use, so two per edge bound them (the untouched room a
  // border leaves costs no memory); growing by doubling copied a large mesh's corners
  // about twice over and held both copies at once.
  soup.face_vertices.reserve(2 * static_cast<size_t>(mesh.edge_count()));
  for (int32_t f = 0; f < mesh.face_count(); ++f) {
    int32_t n = 0;
    mesh.for_each_face_use(FaceId(f), [&](EdgeUse u) {
      soup.face_vertices.push_back(mesh.use_tail(u).index);
      ++n;
    });
    soup.face_sizes.push_back(n);
    soup.face_sources.push_back(mesh.face_source(FaceId(f)));
    if (mesh.has_face_colors()) {
      soup.face_colors.push_back(mesh.face_color(FaceId(f)));
    }
  }
  for (int32_t e = 0; e < mesh.edge_count(); ++e) {
    if (mesh.sharpness(EdgeId(e)) > 0.0f) {
      soup.creases.push_back({mesh.edge_vertex(EdgeId(e), 0).index,
                              mesh.edge_vertex(EdgeId(e), 1).index, mesh.sharpness(EdgeId(e))});
    }
  }
  for (int32_t v = 0; v < mesh.vertex_count(); ++v) {
    if (mesh.vertex_sharpness(VertexId(v)) > 0.0f) {
      soup.corners.push_back({v, mesh.vertex_sharpness(VertexId(v))});
    }
  }
  return soup;
}

}  // namespace nomec::kernel
