// The convex hull of a point set (SLIDE's `slide create convexhull NAME POINTS`, slide.md
// §3.12): an incremental hull with a tolerance relative to the points' extent, whose
// coplanar triangles are then merged into one convex polygon per flat side. Faces point
// outward; hull vertices keep the names of the points they come from.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <glm/geometric.hpp>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "backend/generators/impl.h"

namespace nomec::backend::detail {
namespace {

using ir::gen_arg::Convexhull;

constexpr int kMaxHullPoints = 10000;

struct Tri {
  int v[3];
  glm::dvec3 normal;  // unit, outward
  double offset;      // normal · point on the plane
};

uint64_t edge_key(int a, int b) { return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b); }

class Hull {
 public:
  Hull(const std::vector<glm::dvec3>& p, double eps) : p_(p), eps_(eps) {}

  const std::vector<Tri>& triangles() const { return tris_; }

  // A triangle (a, b, c), counter-clockwise seen from outside.
  void add(int a, int b, int c) {
    const glm::dvec3 n = glm::cross(p_[b] - p_[a], p_[c] - p_[a]);
    const double len = glm::length(n);
    const glm::dvec3 u = len > 0.0 ? n / len : glm::dvec3(0.0);
    tris_.push_back(Tri{{a, b, c}, u, glm::dot(u, p_[a])});
  }
  double distance(const Tri& t, int q) const { return glm::dot(t.normal, p_[q]) - t.offset; }

  // The tetrahedron on four points not in one plane, its faces turned outward.
  void start(int a, int b, int c, int d) {
    const int quad[4] = {a, b, c, d};
    for (int k = 0; k < 4; ++k) {
      int f[3], n = 0;
      for (int m = 0; m < 4; ++m) {
        if (m != k) f[n++] = quad[m];
      }
      add(f[0], f[1], f[2]);
      if (distance(tris_.back(), quad[k]) > 0.0) {
        tris_.pop_back();
        add(f[0], f[2], f[1]);
      }
    }
  }

  // Adds point q: the triangles it sees (from farther than the tolerance) are replaced by a
  // fan from q to their horizon. A point inside, or on the hull within the tolerance, changes
  // nothing.
  void insert(int q) {
    std::vector<uint8_t> seen(tris_.size(), 0);
    std::unordered_set<uint64_t> seen_edges;
    bool any = false;
    for (size_t t = 0; t < tris_.size(); ++t) {
      if (distance(tris_[t], q) <= eps_) continue;
      seen[t] = 1;
      any = true;
      for (int k = 0; k < 3; ++k) seen_edges.insert(edge_key(tris_[t].v[k], tris_[t].v[(k + 1) % 3]));
    }
    if (!any) return;
    std::vector<Tri> kept;
    std::vector<std::pair<int, int>> horizon;
    for (size_t t = 0; t < tris_.size(); ++t) {
      if (!seen[t]) {
        kept.push_back(tris_[t]);
        continue;
      }
      for (int k = 0; k < 3; ++k) {
        const int a = tris_[t].v[k], b = tris_[t].v[(k + 1) % 3];
        if (!seen_edges.contains(edge_key(b, a))) horizon.emplace_back(a, b);
      }
    }
    tris_ = std::move(kept);
    for (const auto& [a, b] : horizon) add(a, b, q);
  }

 private:
  const std::vector<glm::dvec3>& p_;
  double eps_;
  std::vector<Tri> tris_;
};

// Four points spanning a solid: the lowest point, the farthest from it, the farthest from
// their line, the farthest from the plane of the three; fails naming what is degenerate.
std::array<int, 4> first_tetrahedron(const std::vector<glm::dvec3>& p, double eps) {
  const int n = static_cast<int>(p.size());
  auto arg_max = [&](auto&& score) {
    int best = 0;
    double best_score = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i) {
      const double s = score(i);
      if (s > best_score) {
        best = i;
        best_score = s;
      }
    }
    return std::pair(best, best_score);
  };
  const int a = arg_max([&](int i) { return -p[i].x - 1e-3 * p[i].y - 1e-6 * p[i].z; }).first;
  const auto [b, ab] = arg_max([&](int i) { return glm::length(p[i] - p[a]); });
  const std::string count = std::to_string(n);
  if (ab <= eps) {
    fail(ir::arg_index(Convexhull::points), "all " + count + " points are at one place: their convex hull is a point");
  }
  const glm::dvec3 dir = (p[b] - p[a]) / ab;
  const auto [c, off_line] = arg_max([&](int i) { return glm::length(glm::cross(p[i] - p[a], dir)); });
  if (off_line <= eps) {
    fail(ir::arg_index(Convexhull::points), "all " + count + " points lie on one line: their convex hull is a segment");
  }
  const glm::dvec3 normal = glm::normalize(glm::cross(p[b] - p[a], p[c] - p[a]));
  const auto [d, off_plane] = arg_max([&](int i) { return std::abs(glm::dot(normal, p[i] - p[a])); });
  if (off_plane <= eps) {
    fail(ir::arg_index(Convexhull::points), "all " + count + " points lie in one plane: their convex hull is flat, not a solid");
  }
  return {a, b, c, d};
}

// The triangles of one flat side, found from `seed` across shared edges (every corner within
// `tol` of the seed's plane), as the polygon around them; the triangles themselves when
// their border is not one loop (which a convex side always is).
std::vector<std::vector<int>> merge_side(const std::vector<Tri>& tris, const std::vector<glm::dvec3>& p, size_t seed,
                                         const std::unordered_map<uint64_t, size_t>& by_edge, std::vector<uint8_t>& done,
                                         double tol) {
  std::vector<size_t> side{seed};
  done[seed] = 1;
  const Tri& s = tris[seed];
  for (size_t k = 0; k < side.size(); ++k) {
    const Tri& t = tris[side[k]];
    for (int e = 0; e < 3; ++e) {
      auto it = by_edge.find(edge_key(t.v[(e + 1) % 3], t.v[e]));
      if (it == by_edge.end() || done[it->second]) continue;
      const Tri& u = tris[it->second];
      bool flat = glm::dot(u.normal, s.normal) > 0.0;
      for (int m = 0; m < 3 && flat; ++m) flat = std::abs(glm::dot(s.normal, p[u.v[m]]) - s.offset) <= tol;
      if (!flat) continue;
      done[it->second] = 1;
      side.push_back(it->second);
    }
  }
  std::unordered_set<uint64_t> edges;
  for (size_t t : side) {
    for (int e = 0; e < 3; ++e) edges.insert(edge_key(tris[t].v[e], tris[t].v[(e + 1) % 3]));
  }
  std::unordered_map<int, int> next;
  bool loop = true;
  for (size_t t : side) {
    for (int e = 0; e < 3; ++e) {
      const int a = tris[t].v[e], b = tris[t].v[(e + 1) % 3];
      if (edges.contains(edge_key(b, a))) continue;
      loop = loop && next.emplace(a, b).second;
    }
  }
  std::vector<int> polygon;
  if (loop && !next.empty()) {
    int first = next.begin()->first;
    for (const auto& [from, to] : next) first = std::min(first, from);
    int at = first;
    do {
      polygon.push_back(at);
      auto it = next.find(at);
      at = it == next.end() ? -1 : it->second;
    } while (at != first && at != -1 && polygon.size() <= next.size());
    loop = at == first && polygon.size() == next.size();
  }
  if (loop) return {polygon};
  std::vector<std::vector<int>> out;
  for (size_t t : side) out.push_back({tris[t].v[0], tris[t].v[1], tris[t].v[2]});
  return out;
}

}  // namespace

// The hull: the first tetrahedron, then every other point in the order given. The tolerance
// is 1e-9 of the points' extent (the largest side of their bounding box): a point that close
// to the hull is on it, and not made a vertex. Flat sides merge within 1e-7 of the extent. A
// vertex left on only two sides lies on the straight edge between them and is dropped from
// both, so every corner of the result is a true corner.
Generated make_Convexhull(const ArgReader& a) {
  const std::vector<glm::dvec3>& p = a.raw().points;
  const std::vector<std::string>& names = a.raw().point_names;
  const int n = static_cast<int>(p.size());
  if (n < 4) {
    fail(ir::arg_index(Convexhull::points),
         "a convex hull needs at least 4 points (not all in one plane), got " + std::to_string(n));
  }
  // Each point is tested against every face of the hull so far: quadratic when most points
  // are corners, so the set is bounded to keep a scene's hull under about a second.
  if (n > kMaxHullPoints) {
    fail(ir::arg_index(Convexhull::points), "a convex hull of more than " + std::to_string(kMaxHullPoints) +
                                                " points is not built, got " + std::to_string(n));
  }
  glm::dvec3 lo = p[0], hi = p[0];
  for (const glm::dvec3& q : p) {
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) {
      fail(ir::arg_index(Convexhull::points), "the points must have finite coordinates");
    }
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  const double eps = 1e-9 * extent;
  const std::array<int, 4> t = first_tetrahedron(p, eps);
  Hull hull(p, eps);
  hull.start(t[0], t[1], t[2], t[3]);
  for (int q = 0; q < n; ++q) {
    if (q != t[0] && q != t[1] && q != t[2] && q != t[3]) hull.insert(q);
  }
  const std::vector<Tri>& tris = hull.triangles();
  std::unordered_map<uint64_t, size_t> by_edge;
  for (size_t k = 0; k < tris.size(); ++k) {
    for (int e = 0; e < 3; ++e) by_edge[edge_key(tris[k].v[e], tris[k].v[(e + 1) % 3])] = k;
  }
  std::vector<uint8_t> done(tris.size(), 0);
  std::vector<std::vector<int>> sides;
  for (size_t k = 0; k < tris.size(); ++k) {
    if (done[k]) continue;
    for (std::vector<int>& side : merge_side(tris, p, k, by_edge, done, 1e-7 * extent)) sides.push_back(std::move(side));
  }
  std::vector<int> sides_at(n, 0);
  for (const std::vector<int>& s : sides) {
    for (int v : s) ++sides_at[v];
  }
  Generated g;
  std::vector<int32_t> vertex(n, -1);
  auto name_of = [&](int i) {
    return i < static_cast<int>(names.size()) && !names[i].empty() ? names[i] : "v" + std::to_string(i);
  };
  for (const std::vector<int>& s : sides) {
    std::vector<int32_t> face;
    for (int v : s) {
      if (sides_at[v] <= 2) continue;
      if (vertex[v] < 0) vertex[v] = g.soup.add_vertex(p[v], name_of(v));
      face.push_back(vertex[v]);
    }
    if (face.size() < 3) {
      fail(ir::arg_index(Convexhull::points), "the points are too close to lying in one plane to make a solid hull");
    }
    g.soup.add_face(face);
  }
  // The points inside (or on a side or edge) keep their names as positions.
  std::unordered_set<std::string> used(g.soup.names.begin(), g.soup.names.end());
  for (int i = 0; i < n; ++i) {
    if (vertex[i] < 0 && used.insert(name_of(i)).second) g.aliases.emplace_back(name_of(i), p[i]);
  }
  return g;
}

}  // namespace nomec::backend::detail
