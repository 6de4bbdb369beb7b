// DLFL-style corner-cycle editing (see dlfl.h). Operators rewrite the one or two face
// loops they touch and keep a count of face sides per edge, so an insertion can refuse
// a double edge in constant time; finding the other side of an edge (delete, split) scans
// the faces, which the bulk constructions avoid.
#include "kernel/dlfl.h"

#include <fmt/format.h>

#include <algorithm>
#include <cassert>
#include <glm/geometric.hpp>

namespace nomec::kernel {

glm::dvec3 unit_or(const glm::dvec3& v, const glm::dvec3& fallback) {
  const double l = glm::length(v);
  return l > 1e-300 ? v / l : fallback;
}

LoopMesh LoopMesh::from_mesh(const Mesh& mesh) {
  LoopMesh m;
  m.positions_.assign(mesh.positions().begin(), mesh.positions().end());
  m.has_colors_ = mesh.has_face_colors();
  for (int32_t f = 0; f < mesh.face_count(); ++f) {
    std::vector<int32_t> loop;
    mesh.for_each_face_use(FaceId(f), [&](EdgeUse u) { loop.push_back(mesh.use_tail(u).index); });
    m.add_face(std::move(loop), mesh.face_source(FaceId(f)),
               m.has_colors_ ? mesh.face_color(FaceId(f)) : glm::vec3(0.0f));
  }
  return m;
}

int32_t LoopMesh::edge_use_count(int32_t a, int32_t b) const {
  auto it = edge_uses_.find(key(a, b));
  return it == edge_uses_.end() ? 0 : it->second;
}

void LoopMesh::count_face(int32_t f, int32_t delta) {
  const std::vector<int32_t>& l = faces_[f];
  const size_t n = l.size();
  if (n < 2) return;
  for (size_t k = 0; k < n; ++k) {
    int32_t& c = edge_uses_[key(l[k], l[(k + 1) % n])];
    c += delta;
    if (c == 0) edge_uses_.erase(key(l[k], l[(k + 1) % n]));
  }
}

int32_t LoopMesh::add_vertex(const glm::dvec3& p) {
  positions_.push_back(p);
  return vertex_count() - 1;
}

int32_t LoopMesh::add_face(std::vector<int32_t> loop, FaceSource source, glm::vec3 color) {
  faces_.push_back(std::move(loop));
  sources_.push_back(source);
  colors_.push_back(color);
  count_face(face_count() - 1, +1);
  return face_count() - 1;
}

int32_t LoopMesh::create_point_sphere(const glm::dvec3& p) {
  const int32_t v = add_vertex(p);
  const int32_t f = add_face({v});
  debug_check();
  return f;
}

bool LoopMesh::valid_corner(LoopCorner c) const {
  return c.face >= 0 && c.face < face_count() && c.index >= 0 &&
         c.index < static_cast<int32_t>(faces_[c.face].size());
}

LoopCorner LoopMesh::other_side(LoopCorner c) const {
  const std::vector<int32_t>& l = faces_[c.face];
  const int32_t u = l[c.index], v = l[(c.index + 1) % l.size()];
  for (int32_t f = 0; f < face_count(); ++f) {
    const std::vector<int32_t>& g = faces_[f];
    const size_t n = g.size();
    if (n < 2) continue;
    for (size_t k = 0; k < n; ++k) {
      if (f == c.face && static_cast<int32_t>(k) == c.index) continue;
      const int32_t a = g[k], b = g[(k + 1) % n];
      if ((a == u && b == v) || (a == v && b == u)) return LoopCorner{f, static_cast<int32_t>(k)};
    }
  }
  return LoopCorner{};
}

void LoopMesh::debug_check() const {
#ifndef NDEBUG
  const std::string p = problem();
  assert(p.empty() && "LoopMesh invariant broken");
#endif
}

Result<int32_t> LoopMesh::insert_edge(LoopCorner a, LoopCorner b) {
  if (!valid_corner(a) || !valid_corner(b)) return invalid_argument("insert_edge: a corner is out of range");
  if (a.face == b.face && a.index == b.index) return invalid_argument("insert_edge: the two corners are the same corner");
  const int32_t u = faces_[a.face][a.index], v = faces_[b.face][b.index];
  if (edge_use_count(u, v) > 0) {
    return invalid_argument(fmt::format("insert_edge: vertices {} and {} are already joined by an edge", u, v));
  }
  if (a.face == b.face) {
    const std::vector<int32_t> l = faces_[a.face];
    const int32_t n = static_cast<int32_t>(l.size());
    std::vector<int32_t> first, second;
    for (int32_t k = a.index;; k = (k + 1) % n) {
      first.push_back(l[k]);
      if (k == b.index) break;
    }
    for (int32_t k = b.index;; k = (k + 1) % n) {
      second.push_back(l[k]);
      if (k == a.index) break;
    }
    count_face(a.face, -1);
    faces_[a.face] = std::move(first);
    count_face(a.face, +1);
    const int32_t g = add_face(std::move(second), sources_[a.face], colors_[a.face]);
    debug_check();
    return g;
  }
  const std::vector<int32_t>& fa = faces_[a.face];
  const std::vector<int32_t>& fb = faces_[b.face];
  const size_t na = fa.size(), nb = fb.size();
  std::vector<int32_t> merged;
  merged.reserve(na + nb + 2);
  for (size_t k = 0; k < na; ++k) merged.push_back(fa[(a.index + k) % na]);
  if (na > 1) merged.push_back(u);
  for (size_t k = 0; k < nb; ++k) merged.push_back(fb[(b.index + k) % nb]);
  if (nb > 1) merged.push_back(v);
  count_face(a.face, -1);
  count_face(b.face, -1);
  faces_[a.face] = std::move(merged);
  faces_[b.face].clear();
  count_face(a.face, +1);
  debug_check();
  return a.face;
}

Result<bool> LoopMesh::insert_edges(const std::vector<std::pair<LoopCorner, LoopCorner>>& pairs) {
  // Darts: one per corner of an involved face, in face order; `next` is the face cycle.
  std::unordered_map<int32_t, int32_t> first_dart;  // face -> its first dart
  std::vector<int32_t> faces, vertex, next, prev;
  auto dart_of = [&](LoopCorner c) -> int32_t {
    auto [it, added] = first_dart.emplace(c.face, static_cast<int32_t>(vertex.size()));
    if (added) {
      faces.push_back(c.face);
      const std::vector<int32_t>& l = faces_[c.face];
      const int32_t base = it->second, n = static_cast<int32_t>(l.size());
      for (int32_t k = 0; k < n; ++k) {
        vertex.push_back(l[k]);
        next.push_back(base + (k + 1) % n);
        prev.push_back(base + (k + n - 1) % n);
      }
    }
    return it->second + c.index;
  };
  std::unordered_map<uint64_t, int32_t> added_edges;
  std::vector<uint8_t> used;
  std::vector<std::pair<int32_t, int32_t>> ends;
  for (const auto& [a, b] : pairs) {
    if (!valid_corner(a) || !valid_corner(b) || (a.face == b.face && a.index == b.index)) {
      return KernelError{KernelError::Kind::InvalidArgument, "insert_edges: a corner is out of range or repeated", {}, {}, {}};
    }
    const int32_t u = faces_[a.face][a.index], v = faces_[b.face][b.index];
    if (edge_use_count(u, v) > 0 || added_edges[key(u, v)]++ > 0) {
      return KernelError{KernelError::Kind::InvalidArgument,
                         fmt::format("insert_edges: vertices {} and {} are already joined by an edge", u, v), {}, {}, {}};
    }
    // One after the other: dart_of adds faces in call order, and argument evaluation order
    // is unspecified (GCC and clang differ), which made the result compiler-dependent.
    const int32_t da = dart_of(a);
    const int32_t db = dart_of(b);
    ends.emplace_back(da, db);
  }
  used.assign(vertex.size(), 0);
  for (const auto& [x, y] : ends) {
    if (used[x]++ || used[y]++) {
      return KernelError{KernelError::Kind::InvalidArgument, "insert_edges: a corner is used by two new edges", {}, {}, {}};
    }
  }
  // Each insertion adds a copy of both corners: … p → x' → y … and … q → y' → x ….
  for (const auto& [x, y] : ends) {
    const int32_t x2 = static_cast<int32_t>(vertex.size()), y2 = x2 + 1;
    vertex.push_back(vertex[x]);
    vertex.push_back(vertex[y]);
    const int32_t p = prev[x], q = prev[y];
    next.push_back(y);
    prev.push_back(p);
    next.push_back(x);
    prev.push_back(q);
    next[p] = x2;
    next[q] = y2;
    prev[y] = x2;
    prev[x] = y2;
  }
  // The new face cycles: the involved faces' ids first, in order, then new faces.
  std::vector<std::vector<int32_t>> loops;
  std::vector<int32_t> loop_face;  // the involved face each new loop starts in
  std::vector<uint8_t> seen(vertex.size(), 0);
  for (int32_t f : faces) {
    const int32_t base = first_dart[f], n = static_cast<int32_t>(faces_[f].size());
    for (int32_t d = base; d < base + n; ++d) {
      if (seen[d]) continue;
      std::vector<int32_t> l;
      for (int32_t e = d; !seen[e]; e = next[e]) {
        seen[e] = 1;
        l.push_back(vertex[e]);
      }
      loops.push_back(std::move(l));
      loop_face.push_back(f);
    }
  }
  for (int32_t f : faces) {
    count_face(f, -1);
    faces_[f].clear();
  }
  for (size_t i = 0; i < loops.size(); ++i) {
    if (i < faces.size()) {
      faces_[faces[i]] = std::move(loops[i]);
      count_face(faces[i], +1);
    } else {
      add_face(std::move(loops[i]), sources_[loop_face[i]], colors_[loop_face[i]]);
    }
  }
  debug_check();
  return true;
}

Result<int32_t> LoopMesh::delete_edge(LoopCorner c) {
  if (!valid_corner(c) || faces_[c.face].size() < 2) return invalid_argument("delete_edge: the corner is out of range");
  const LoopCorner o = other_side(c);
  if (o.face < 0) return invalid_argument("delete_edge: the edge has a face on one side only");
  const std::vector<int32_t> l = faces_[c.face];
  const int32_t n = static_cast<int32_t>(l.size());
  const int32_t u = l[c.index], v = l[(c.index + 1) % n];
  // The face rotated so that the deleted edge closes it: [v, …, u].
  std::vector<int32_t> f;
  for (int32_t k = 1; k <= n; ++k) f.push_back(l[(c.index + k) % n]);
  count_face(c.face, -1);
  if (o.face != c.face) {
    const std::vector<int32_t> g0 = faces_[o.face];
    const int32_t m = static_cast<int32_t>(g0.size());
    std::vector<int32_t> g;  // [u, …, v]
    for (int32_t k = 1; k <= m; ++k) g.push_back(g0[(o.index + k) % m]);
    if (g.front() != u) std::reverse(g.begin(), g.end());  // same direction: a Möbius edge
    for (int32_t k = 1; k + 1 < m; ++k) f.push_back(g[k]);
    count_face(o.face, -1);
    faces_[o.face].clear();
    faces_[c.face] = std::move(f);
    count_face(c.face, +1);
    debug_check();
    return c.face;
  }
  const int32_t q = ((o.index - (c.index + 1)) % n + n) % n;  // the other side's position in f
  if (f[q] == v && f[q + 1] == u) {
    // Opposite directions: the loop falls apart into [v … ] and [u … ].
    std::vector<int32_t> first = q == 0 ? std::vector<int32_t>{v} : std::vector<int32_t>(f.begin(), f.begin() + q);
    std::vector<int32_t> second =
        q + 1 == n - 1 ? std::vector<int32_t>{u} : std::vector<int32_t>(f.begin() + q + 1, f.end() - 1);
    faces_[c.face] = std::move(first);
    count_face(c.face, +1);
    add_face(std::move(second), sources_[c.face], colors_[c.face]);
  } else {
    // Both sides run the same way (a Möbius edge inside one face): one face remains.
    std::vector<int32_t> first(f.begin(), f.begin() + q + 1);  // [v … u]
    std::vector<int32_t> second(f.begin() + q + 1, f.end());  // [v … u]
    for (size_t k = second.size() - 1; k-- > 1;) first.push_back(second[k]);
    faces_[c.face] = std::move(first);
    count_face(c.face, +1);
  }
  debug_check();
  return c.face;
}

Result<int32_t> LoopMesh::split_edge(LoopCorner c, const glm::dvec3& p) {
  if (!valid_corner(c) || faces_[c.face].size() < 2) return invalid_argument("split_edge: the corner is out of range");
  const std::vector<int32_t>& l = faces_[c.face];
  if (l[c.index] == l[(c.index + 1) % l.size()]) return invalid_argument("split_edge: a self-loop cannot be split");
  LoopCorner o = other_side(c);
  const int32_t w = add_vertex(p);
  count_face(c.face, -1);
  if (o.face >= 0 && o.face != c.face) count_face(o.face, -1);
  faces_[c.face].insert(faces_[c.face].begin() + c.index + 1, w);
  if (o.face >= 0) {
    if (o.face == c.face && o.index > c.index) ++o.index;
    faces_[o.face].insert(faces_[o.face].begin() + o.index + 1, w);
    if (o.face != c.face) count_face(o.face, +1);
  }
  count_face(c.face, +1);
  debug_check();
  return w;
}

std::vector<uint8_t> LoopMesh::split_all_edges() {
  std::unordered_map<uint64_t, int32_t> midpoint;
  std::vector<uint8_t> is_new(positions_.size(), 0);
  for (int32_t f = 0; f < face_count(); ++f) {
    const std::vector<int32_t> l = faces_[f];
    const size_t n = l.size();
    if (n < 2) continue;
    count_face(f, -1);
    std::vector<int32_t> out;
    out.reserve(2 * n);
    for (size_t k = 0; k < n; ++k) {
      const int32_t a = l[k], b = l[(k + 1) % n];
      out.push_back(a);
      if (a == b) continue;
      auto [it, added] = midpoint.emplace(key(a, b), -1);
      if (added) {
        it->second = add_vertex(0.5 * (positions_[a] + positions_[b]));
        is_new.push_back(1);
      }
      out.push_back(it->second);
    }
    faces_[f] = std::move(out);
    count_face(f, +1);
  }
  debug_check();
  return is_new;
}

std::string LoopMesh::problem() const {
  std::unordered_map<uint64_t, int32_t> uses;
  for (int32_t f = 0; f < face_count(); ++f) {
    const std::vector<int32_t>& l = faces_[f];
    for (int32_t v : l) {
      if (v < 0 || v >= vertex_count()) return fmt::format("face {} uses vertex {} out of range", f, v);
    }
    if (l.size() < 2) continue;
    for (size_t k = 0; k < l.size(); ++k) ++uses[key(l[k], l[(k + 1) % l.size()])];
  }
  for (const auto& [k, n] : uses) {
    const int32_t a = static_cast<int32_t>(k & 0xffffffffu), b = static_cast<int32_t>(k >> 32);
    if (n > 2) return fmt::format("edge {}-{} has {} face sides", a, b, n);
    if (a == b && n != 2) return fmt::format("self-loop at vertex {} has {} face side", a, n);
    if (edge_use_count(a, b) != n) return fmt::format("edge {}-{}: stale side count", a, b);
  }
  if (uses.size() != edge_uses_.size()) return "stale edge side counts";
  return "";
}

Result<Mesh> LoopMesh::to_mesh() const {
  // Self-loops: each vertex with one has exactly two loop occurrences (the loop's sides).
  std::unordered_map<int32_t, std::vector<LoopCorner>> loops;
  for (int32_t f = 0; f < face_count(); ++f) {
    const std::vector<int32_t>& l = faces_[f];
    if (l.size() < 2) continue;
    for (size_t k = 0; k < l.size(); ++k) {
      if (l[k] == l[(k + 1) % l.size()]) loops[l[k]].push_back(LoopCorner{f, static_cast<int32_t>(k)});
    }
  }
  std::vector<glm::dvec3> positions = positions_;
  // Per face, the vertices to insert after a loop corner.
  std::unordered_map<uint64_t, std::pair<int32_t, int32_t>> inserted;
  auto corner_key = [](LoopCorner c) { return (static_cast<uint64_t>(c.face) << 32) | static_cast<uint32_t>(c.index); };
  for (const auto& [v, sides] : loops) {
    if (sides.size() != 2) {
      return KernelError{KernelError::Kind::InvalidArgument,
                         fmt::format("vertex {} has {} self-loop sides; one self-loop per vertex can be built", v,
                                     sides.size()),
                         {}, {}, {VertexId(v)}};
    }
    // The loop becomes the triangle v, n1, n2, placed inside the first side's face corner.
    const std::vector<int32_t>& l = faces_[sides[0].face];
    const size_t n = l.size();
    size_t before = (sides[0].index + n - 1) % n, after = (sides[0].index + 2) % n;
    while (l[before] == v && before != static_cast<size_t>(sides[0].index)) before = (before + n - 1) % n;
    while (l[after] == v && after != static_cast<size_t>(sides[0].index)) after = (after + 1) % n;
    const glm::dvec3 m = positions_[v];
    const glm::dvec3 dp = positions_[l[before]] - m, dq = positions_[l[after]] - m;
    double rho = 0.2 * std::min(glm::length(dp), glm::length(dq));
    if (!(rho > 0)) rho = 1e-3;
    const glm::dvec3 up = unit_or(dp, {1, 0, 0}), uq = unit_or(dq, {0, 1, 0});
    const glm::dvec3 mid = unit_or(up + uq, unit_or(glm::cross(up, {0.3, 0.5, 0.8}), {0, 0, 1}));
    positions.push_back(m + rho * (mid + 0.5 * up));
    positions.push_back(m + rho * (mid + 0.5 * uq));
    const int32_t n1 = static_cast<int32_t>(positions.size()) - 2, n2 = n1 + 1;
    inserted[corner_key(sides[0])] = {n1, n2};
    inserted[corner_key(sides[1])] = {n2, n1};
  }
  PolygonSoup soup;
  std::vector<int32_t> remap(positions.size(), -1);
  std::vector<int32_t> loop;
  for (int32_t f = 0; f < face_count(); ++f) {
    const std::vector<int32_t>& l = faces_[f];
    if (l.empty()) continue;
    if (l.size() < 3) {
      return KernelError{KernelError::Kind::DegenerateFace,
                         fmt::format("face {} has {} corner(s) (a point sphere or a two-sided edge)", f, l.size()),
                         {}, {FaceId(f)}, {}};
    }
    loop.clear();
    auto emit = [&](int32_t v) {
      if (remap[v] < 0) remap[v] = soup.add_vertex(positions[v]);
      loop.push_back(remap[v]);
    };
    for (size_t k = 0; k < l.size(); ++k) {
      emit(l[k]);
      auto it = inserted.find(corner_key(LoopCorner{f, static_cast<int32_t>(k)}));
      if (it != inserted.end()) {
        emit(it->second.first);
        emit(it->second.second);
      }
    }
    soup.add_face(loop);
    soup.face_sources.push_back(sources_[f]);
    if (has_colors_) soup.face_colors.push_back(colors_[f]);
  }
  return build_mesh(soup);
}

}  // namespace nomec::kernel
