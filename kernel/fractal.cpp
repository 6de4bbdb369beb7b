// The generalized Sierpinski and Menger constructions of highgenus.h, one level at a
// time. Sierpinski is made of DLFL operators (dlfl.h) as in TopMod's
// multiConnectMidpoints; the Menger level writes its frames, tunnels and inner walls as a
// polygon soup and collapses short inner-wall edges before building.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numeric>
#include <unordered_map>

#include "kernel/dlfl.h"
#include "kernel/highgenus.h"
#include "kernel/offset.h"

namespace nomec::kernel {

namespace {

uint64_t pair_key(int32_t a, int32_t b) {
  const uint32_t lo = static_cast<uint32_t>(std::min(a, b)), hi = static_cast<uint32_t>(std::max(a, b));
  return (static_cast<uint64_t>(hi) << 32) | lo;
}

KernelError too_big(const char* what, int32_t level, int64_t faces, int64_t limit) {
  return invalid_argument(fmt::format("{} level {} would make about {} faces, more than the limit of {}", what, level, faces,
                             limit));
}

// One Sierpinski level (TopMod's multiConnectMidpoints) on `m`, self-loops of earlier
// levels kept as they are.
Result<bool> sierpinski_level(LoopMesh& m) {
  const int32_t first_midpoint = m.vertex_count();
  m.split_all_edges();
  auto is_mid = [&](int32_t v) { return v >= first_midpoint; };
  // Cut every original corner off (a corner of a vertex with a self-loop spans the loop:
  // `x v v y` is cut as one); what is left of each face is its central polygon of
  // midpoints.
  std::vector<int32_t> central;
  const int32_t faces = m.face_count();
  for (int32_t f = 0; f < faces; ++f) {
    for (;;) {
      const std::vector<int32_t>& l = m.face(f);
      const int32_t n = static_cast<int32_t>(l.size());
      // An original corner between two midpoints, unless they are joined already (both
      // corners of a vertex with two edges cut the same pair: TopMod skips the second).
      int32_t first = -1, last = -1;
      for (int32_t k = 0; k < n && first < 0; ++k) {
        const int32_t prev = l[(k + n - 1) % n];
        if (is_mid(l[k]) || prev == l[k]) continue;
        int32_t end = k;
        while (l[(end + 1) % n] == l[k] && (end + 1) % n != k) end = (end + 1) % n;
        const int32_t next = l[(end + 1) % n];
        const int32_t run = (end - k + n) % n + 1;
        if (is_mid(next) && is_mid(prev) && n - run >= 3 && m.edge_use_count(prev, next) == 0) first = k, last = end;
      }
      if (first < 0) break;
      auto cut = m.insert_edge(LoopCorner{f, (last + 1) % n}, LoopCorner{f, (first + n - 1) % n});
      if (!cut) return cut.error();
    }
    if (!m.face(f).empty()) central.push_back(f);
  }
  // Join the central polygons at each interior midpoint with a self-loop edge (all at
  // once: the same faces as inserting them one by one).
  std::vector<LoopCorner> at(static_cast<size_t>(m.vertex_count() - first_midpoint) * 2, LoopCorner{});
  for (int32_t f : central) {
    const std::vector<int32_t>& l = m.face(f);
    for (int32_t k = 0; k < static_cast<int32_t>(l.size()); ++k) {
      if (!is_mid(l[k])) continue;
      LoopCorner* slot = &at[2 * static_cast<size_t>(l[k] - first_midpoint)];
      (slot[0].face < 0 ? slot[0] : slot[1]) = LoopCorner{f, k};
    }
  }
  std::vector<std::pair<LoopCorner, LoopCorner>> loops;
  for (size_t i = 0; i < at.size(); i += 2) {
    if (at[i + 1].face >= 0) loops.emplace_back(at[i], at[i + 1]);  // border midpoints have one
  }
  if (auto ok = m.insert_edges(loops); !ok) return ok.error();
  return true;
}

// ---- Menger ----

struct SpongeBuilder {
  const Mesh& mesh;
  double t;
  PolygonSoup soup;
  std::vector<std::vector<int32_t>> q;  // per face, per corner: the inner copy's vertex
  std::unordered_map<uint64_t, std::vector<std::pair<int32_t, int32_t>>> uses;  // edge -> (face, corner)
  std::vector<std::pair<int32_t, int32_t>> links;  // inner-wall edges (q vertex pairs) per original vertex
  std::vector<int32_t> link_vertex;

  void face_part(int32_t f, FaceSource src, const glm::vec3* color, std::initializer_list<int32_t> loop) {
    soup.add_face(loop);
    soup.face_sources.push_back(src);
    if (color != nullptr) soup.face_colors.push_back(*color);
    (void)f;
  }
};

// Frame, tunnel and inner copy of every face.
void sponge_faces(SpongeBuilder& b) {
  const Mesh& mesh = b.mesh;
  std::unordered_map<uint64_t, int32_t> trisection;  // (edge key, end vertex) -> point near that end
  auto near_end = [&](int32_t from, int32_t to, double t) {
    const uint64_t k = pair_key(from, to) * 2 + (from < to ? 0 : 1);
    auto [it, added] = trisection.emplace(k, -1);
    if (added) {
      const glm::dvec3 a = mesh.position(VertexId(from)), c = mesh.position(VertexId(to));
      it->second = b.soup.add_vertex(a + t * glm::normalize(c - a));
    }
    return it->second;
  };
  b.q.resize(mesh.face_count());
  const std::vector<glm::dvec3> normals = face_normals(mesh);  // unit Newell normals (0 if degenerate)
  for (int32_t f = 0; f < mesh.face_count(); ++f) {
    const std::vector<VertexId> vs = mesh.face_vertices(FaceId(f));
    const int32_t n = static_cast<int32_t>(vs.size());
    std::vector<glm::dvec3> p;
    for (VertexId v : vs) p.push_back(mesh.position(v));
    const glm::dvec3& normal = normals[f];
    // Per edge i (v_i -> v_{i+1}): the frame width, at most 45% of the edge.
    std::vector<double> w(n);
    for (int32_t i = 0; i < n; ++i) w[i] = std::min(b.t, 0.45 * glm::length(p[(i + 1) % n] - p[i]));
    std::vector<int32_t> a(n), z(n), o(n), qq(n);
    for (int32_t i = 0; i < n; ++i) {
      const int32_t prev = (i + n - 1) % n, next = (i + 1) % n;
      a[i] = near_end(vs[i].index, vs[next].index, w[i]);
      z[i] = near_end(vs[next].index, vs[i].index, w[i]);  // near v_{i+1}
      const glm::dvec3 inset = p[i] + w[i] * glm::normalize(p[next] - p[i]) + w[prev] * glm::normalize(p[prev] - p[i]);
      o[i] = b.soup.add_vertex(inset);
      qq[i] = b.soup.add_vertex(inset - b.t * normal);
    }
    const FaceSource src = mesh.face_source(FaceId(f));
    const glm::vec3* color = mesh.has_face_colors() ? &mesh.face_color(FaceId(f)) : nullptr;
    for (int32_t i = 0; i < n; ++i) {
      const int32_t prev = (i + n - 1) % n, next = (i + 1) % n;
      b.face_part(f, src, color, {vs[i].index, a[i], o[i], z[prev]});  // corner square
      b.face_part(f, src, color, {a[i], z[i], o[next], o[i]});          // edge square
      b.face_part(f, src, color, {o[i], o[next], qq[next], qq[i]});     // tunnel wall
      b.uses[pair_key(vs[i].index, vs[next].index)].push_back({f, i});
    }
    b.q[f] = std::move(qq);
  }
}

// Inner walls along the edges and inner polygons at the vertices.
void sponge_walls(SpongeBuilder& b) {
  const Mesh& mesh = b.mesh;
  std::vector<std::vector<int32_t>> loops(mesh.face_count());
  for (int32_t f = 0; f < mesh.face_count(); ++f) {
    for (VertexId v : mesh.face_vertices(FaceId(f))) loops[f].push_back(v.index);
  }
  // Per original vertex, the directed links the walls make there.
  std::unordered_map<int32_t, std::vector<std::pair<int32_t, int32_t>>> at_vertex;
  for (int32_t e = 0; e < mesh.edge_count(); ++e) {
    const int32_t x = mesh.edge_vertex(EdgeId(e), 0).index, y = mesh.edge_vertex(EdgeId(e), 1).index;
    const auto it = b.uses.find(pair_key(x, y));
    if (it == b.uses.end() || it->second.size() != 2) continue;
    const auto [f, i] = it->second[0];
    const auto [g, k] = it->second[1];
    const int32_t nf = static_cast<int32_t>(loops[f].size()), ng = static_cast<int32_t>(loops[g].size());
    const int32_t u = loops[f][i], v = loops[f][(i + 1) % nf];
    const int32_t qf_u = b.q[f][i], qf_v = b.q[f][(i + 1) % nf];
    const bool same_way = loops[g][k] == u;  // a Möbius edge
    const int32_t qg_u = b.q[g][same_way ? k : (k + 1) % ng], qg_v = b.q[g][same_way ? (k + 1) % ng : k];
    const glm::vec3* color = mesh.has_face_colors() ? &mesh.face_color(FaceId(f)) : nullptr;
    b.face_part(f, mesh.face_source(FaceId(f)), color, {qf_u, qf_v, qg_v, qg_u});
    at_vertex[v].push_back({qf_v, qg_v});
    at_vertex[u].push_back({qg_u, qf_u});
  }
  for (auto& [v, links] : at_vertex) {
    for (const auto& l : links) {
      b.links.push_back(l);
      b.link_vertex.push_back(v);
    }
    if (links.size() < 3) continue;
    // Follow the links as a cycle, against the first wall's direction.
    std::unordered_map<int32_t, std::vector<int32_t>> next;
    for (const auto& [s, d] : links) {
      next[s].push_back(d);
      next[d].push_back(s);
    }
    if (std::any_of(next.begin(), next.end(), [](const auto& e) { return e.second.size() != 2; })) continue;
    std::vector<int32_t> polygon{links[0].second, links[0].first};
    while (polygon.size() <= links.size()) {
      const auto& nb = next[polygon.back()];
      const int32_t step = nb[0] == polygon[polygon.size() - 2] ? nb[1] : nb[0];
      if (step == polygon.front()) break;
      polygon.push_back(step);
    }
    if (polygon.size() != links.size()) continue;  // several cycles: leave the openings
    b.soup.add_face(polygon);
    b.soup.face_sources.push_back(FaceSource{});
    if (mesh.has_face_colors()) b.soup.face_colors.push_back(mesh.face_color(FaceId(0)));
  }
}

// Collapses links shorter than `limit`, then drops repeated corners and faces with fewer
// than three, and unused vertices.
PolygonSoup collapse(const PolygonSoup& in, const std::vector<std::pair<int32_t, int32_t>>& links, double limit) {
  std::vector<int32_t> root(in.positions.size());
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](int32_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  for (const auto& [a, c] : links) {
    if (glm::length(in.positions[a] - in.positions[c]) < limit) {
      const int32_t ra = find(a), rc = find(c);
      if (ra != rc) root[std::max(ra, rc)] = std::min(ra, rc);
    }
  }
  PolygonSoup out;
  std::vector<int32_t> remap(in.positions.size(), -1);
  std::vector<int32_t> loop;
  size_t at = 0;
  for (int32_t f = 0; f < in.face_count(); ++f) {
    loop.clear();
    for (int32_t k = 0; k < in.face_sizes[f]; ++k) {
      const int32_t v = find(in.face_vertices[at + k]);
      if (loop.empty() || loop.back() != v) loop.push_back(v);
    }
    at += in.face_sizes[f];
    while (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
    if (loop.size() < 3) continue;
    for (int32_t& v : loop) {
      if (remap[v] < 0) remap[v] = out.add_vertex(in.positions[v]);
      v = remap[v];
    }
    out.add_face(loop);
    out.face_sources.push_back(in.face_sources[f]);
    if (!in.face_colors.empty()) out.face_colors.push_back(in.face_colors[f]);
  }
  return out;
}

Result<Mesh> menger_level(const Mesh& mesh, double thickness, double collapse_factor) {
  SpongeBuilder b{mesh, thickness, {}, {}, {}, {}, {}};
  for (int32_t v = 0; v < mesh.vertex_count(); ++v) b.soup.add_vertex(mesh.position(VertexId(v)));
  sponge_faces(b);
  sponge_walls(b);
  const double factor = collapse_factor > 0.001 ? collapse_factor : 0.01;
  return build_mesh(collapse(b.soup, b.links, factor * thickness));
}

int64_t corner_count(const Mesh& mesh) { return 2 * static_cast<int64_t>(mesh.edge_count()); }

}  // namespace

Result<Mesh> sierpinski(const Mesh& mesh, const SierpinskiOptions& o) {
  if (o.levels < 0) return invalid_argument(fmt::format("sierpinski level must be 0 or more, not {}", o.levels));
  if (o.levels == 0) return mesh;
  LoopMesh m = LoopMesh::from_mesh(mesh);
  for (int32_t level = 1; level <= o.levels; ++level) {
    // F' = C + V ≤ 2E + V (corner triangles, one closing face per vertex).
    const int64_t estimate = 2 * m.edge_count() + m.vertex_count();
    if (o.max_faces > 0 && estimate > o.max_faces) return too_big("sierpinski", level, estimate, o.max_faces);
    if (auto ok = sierpinski_level(m); !ok) return ok.error();
  }
  return m.to_mesh();
}

Result<Mesh> menger(const Mesh& mesh, const MengerOptions& o) {
  if (o.levels < 0) return invalid_argument(fmt::format("menger level must be 0 or more, not {}", o.levels));
  if (!(o.thickness > 0) || !std::isfinite(o.thickness)) {
    return invalid_argument(fmt::format("menger thickness must be positive, not {}", o.thickness));
  }
  if (!std::isfinite(o.collapse) || o.collapse < 0) {
    return invalid_argument(fmt::format("menger collapse factor must be 0 or more, not {}", o.collapse));
  }
  Mesh current = mesh;
  double t = o.thickness;
  for (int32_t level = 1; level <= o.levels; ++level) {
    // A level makes 3 faces per corner, one per edge and one per vertex.
    const int64_t estimate = 3 * corner_count(current) + current.edge_count() + current.vertex_count();
    if (o.max_faces > 0 && estimate > o.max_faces) return too_big("menger", level, estimate, o.max_faces);
    auto next = menger_level(current, t, o.collapse);
    if (!next) return next.error();
    current = std::move(*next);
    t /= 3;
  }
  return current;
}

}  // namespace nomec::kernel
