// Function surfaces: genparametricsurf (x, y, z as functions of u, v), gencartesiansurf
// (z = f(x, y)) and genimplicitsurf (f(x, y, z) = 0). The functions arrive evaluable (the
// checker lowered their text to IR expressions; the backend evaluates them).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "backend/generators/bourke_tables.h"
#include "backend/generators/impl.h"

namespace nomec::backend::detail {
namespace {


// "u=0.5, v=1": where a function was evaluated, for messages.
std::string where(const ArgReader& a, std::span<const double> vars) {
  const auto& names = ir::generator(a.raw().kind).variables;
  std::string out;
  for (size_t i = 0; i < vars.size() && i < names.size(); ++i) {
    out += (i == 0 ? "" : ", ") + std::string(names[i]) + "=" + fmt_number(vars[i]);
  }
  return out;
}

// A function's value at `vars`, failing on the argument when it has none or is not finite.
template <typename A>
double value_at(const ArgReader& a, A arg, std::span<const double> vars) {
  std::string problem;
  std::optional<double> v = a.function(arg)(vars, &problem);
  if (!v) fail(ir::arg_index(arg), "`" + a.name(arg) + "` cannot be evaluated at " + where(a, vars) + ": " + problem);
  if (!std::isfinite(*v)) fail(ir::arg_index(arg), "`" + a.name(arg) + "` is not finite at " + where(a, vars));
  return *v;
}

struct Range {
  double lo;
  double hi;
};
template <typename A>
Range range(const ArgReader& a, A lo_arg, A hi_arg) {
  const double lo = a.number(lo_arg);
  const double hi = a.number(hi_arg);
  if (!(hi > lo)) fail(ir::arg_index(hi_arg), "`" + a.name(hi_arg) + "` must be greater than `" + a.name(lo_arg) + "`");
  return {lo, hi};
}

// NOME3's samples along one axis (GenCartesianSurf.cpp, GenParametricSurf.cpp): from lo in
// accumulated steps of (hi − lo)/segs while ≤ hi + step/5. A whole `segs` gives segs + 1
// samples ending at hi; a fractional one stops short of hi (2.5 gives lo, lo+0.4·d, lo+0.8·d)
// or, from a fraction of 0.8 on, takes one sample past it (2.9 reaches lo + (3/2.9)·d).
template <typename A>
std::vector<double> samples(const ArgReader& a, Range r, A segs_arg) {
  const double segs = a.number(segs_arg);
  if (!(segs >= 1.0)) fail(ir::arg_index(segs_arg), "`" + a.name(segs_arg) + "` must be at least 1, got " + fmt_number(segs));
  if (segs > kMaxSegments) {
    fail(ir::arg_index(segs_arg), "`" + a.name(segs_arg) + "` must be at most " + std::to_string(kMaxSegments));
  }
  const double inc = (r.hi - r.lo) / segs;
  std::vector<double> out;
  // NOME3 makes ⌊segs + 0.2⌋ + 1 samples (k·inc ≤ (segs + 0.2)·inc); the bound also ends
  // the loop when `inc` is below the precision of the values (t + inc == t).
  const size_t most = static_cast<size_t>(segs + 0.2) + 1;
  for (double t = r.lo; t <= r.hi + inc / 5.0 && out.size() < most; t += inc) out.push_back(t);
  return out;
}

// NOME3's grid of a function surface: vertex (i, j) named `v_{i}_{j}` at `pos(i, j)`, faces
// (v_i_j, v_{i+1}_j, v_{i+1}_{j+1}, v_i_{j+1}); nothing is welded.
void add_sampled_grid(kernel::PolygonSoup& soup, int ni, int nj, const std::function<glm::dvec3(int, int)>& pos) {
  const int32_t first = soup.vertex_count();
  for (int i = 0; i < ni; ++i) {
    for (int j = 0; j < nj; ++j) soup.add_vertex(pos(i, j), "v_" + std::to_string(i) + "_" + std::to_string(j));
  }
  auto at = [&](int i, int j) { return first + i * nj + j; };
  for (int i = 0; i + 1 < ni; ++i) {
    for (int j = 0; j + 1 < nj; ++j) soup.add_face({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
  }
}

}  // namespace

// NOME3's genparametricsurf (generators-original.md §11.1): (funcX, funcY, funcZ)(u, v) on
// NOME3's samples, vertices `v_{i}_{j}` (i along u), no welding.
Generated make_Genparametricsurf(const ArgReader& a) {
  using A = ir::gen_arg::Genparametricsurf;
  a.function(A::funcX);
  a.function(A::funcY);
  a.function(A::funcZ);
  const std::vector<double> u = samples(a, range(a, A::u_min, A::u_max), A::u_segs);
  const std::vector<double> v = samples(a, range(a, A::v_min, A::v_max), A::v_segs);
  check_size(static_cast<long long>(u.size()) * static_cast<long long>(v.size()), ir::arg_index(A::u_segs));
  Generated g;
  add_sampled_grid(g.soup, static_cast<int>(u.size()), static_cast<int>(v.size()), [&](int i, int j) {
    const double uv[2] = {u[i], v[j]};
    return glm::dvec3(value_at(a, A::funcX, uv), value_at(a, A::funcY, uv), value_at(a, A::funcZ, uv));
  });
  return g;
}

// NOME3's gencartesiansurf (generators-original.md §11.1): (x, y, func(x, y)) on NOME3's
// samples, vertices `v_{i}_{j}` (i along x).
Generated make_Gencartesiansurf(const ArgReader& a) {
  using A = ir::gen_arg::Gencartesiansurf;
  a.function(A::func);
  const std::vector<double> x = samples(a, range(a, A::x_min, A::x_max), A::x_segs);
  const std::vector<double> y = samples(a, range(a, A::y_min, A::y_max), A::y_segs);
  check_size(static_cast<long long>(x.size()) * static_cast<long long>(y.size()), ir::arg_index(A::x_segs));
  Generated g;
  add_sampled_grid(g.soup, static_cast<int>(x.size()), static_cast<int>(y.size()), [&](int i, int j) {
    const double xy[2] = {x[i], y[j]};
    return glm::dvec3(xy[0], xy[1], value_at(a, A::func, xy));
  });
  return g;
}

namespace {

// Marching cubes' per-cube vertices, welded (docs/generators.md, "Differences from the
// original"): a vertex within `tol` of an earlier one (the same crossing computed by the
// neighbouring cube, from the other end of the edge) becomes that vertex, which keeps its
// position and name. Faces left with a repeated corner (a crossing snapped to a grid point)
// and repeats of a face already made (a surface lying in a cube face) are dropped.
struct CubeWelder {
  double tol = 0;
  kernel::PolygonSoup soup;
  std::unordered_map<uint64_t, std::vector<int32_t>> cells;
  std::vector<std::vector<int32_t>> made;  // sorted corners of the faces made
  std::unordered_map<uint64_t, std::vector<size_t>> made_by_hash;
  /// NOME3's names of the copies welded onto a vertex made before them (`inst.v_k` for
  /// every k the original numbered still resolves, to the surviving copy's position).
  std::vector<std::pair<std::string, glm::dvec3>> aliases;

  static uint64_t key(int64_t x, int64_t y, int64_t z) {
    return static_cast<uint64_t>(x) * 73856093ULL ^ static_cast<uint64_t>(y) * 19349663ULL ^
           static_cast<uint64_t>(z) * 83492791ULL;
  }
  int32_t vertex(const glm::dvec3& p, const std::string& name) {
    const int64_t cx = static_cast<int64_t>(std::floor(p.x / tol));
    const int64_t cy = static_cast<int64_t>(std::floor(p.y / tol));
    const int64_t cz = static_cast<int64_t>(std::floor(p.z / tol));
    for (int64_t dx = -1; dx <= 1; ++dx) {
      for (int64_t dy = -1; dy <= 1; ++dy) {
        for (int64_t dz = -1; dz <= 1; ++dz) {
          auto it = cells.find(key(cx + dx, cy + dy, cz + dz));
          if (it == cells.end()) continue;
          for (int32_t w : it->second) {
            const glm::dvec3 e = soup.positions[w] - p;
            if (std::abs(e.x) <= tol && std::abs(e.y) <= tol && std::abs(e.z) <= tol) {
              aliases.emplace_back(name, soup.positions[w]);
              return w;
            }
          }
        }
      }
    }
    const int32_t v = soup.add_vertex(p, name);
    cells[key(cx, cy, cz)].push_back(v);
    return v;
  }
  void triangle(int32_t a, int32_t b, int32_t c) {
    if (a == b || b == c || a == c) return;
    std::vector<int32_t> sorted = {a, b, c};
    std::sort(sorted.begin(), sorted.end());
    const uint64_t h = key(sorted[0], sorted[1], sorted[2]);
    std::vector<size_t>& same = made_by_hash[h];
    for (size_t f : same) {
      if (made[f] == sorted) return;
    }
    same.push_back(made.size());
    made.push_back(std::move(sorted));
    soup.add_face({a, b, c});
  }
};

// True if every edge of `s` has at most two faces and the faces around each vertex form a
// single fan (what the kernel accepts as a 2-manifold with border).
bool is_manifold(const kernel::PolygonSoup& s) {
  std::unordered_map<uint64_t, int> edge_uses;
  std::vector<std::vector<std::pair<int32_t, int32_t>>> link(s.vertex_count());
  size_t off = 0;
  for (int32_t n : s.face_sizes) {
    for (int32_t k = 0; k < n; ++k) {
      const int32_t a = s.face_vertices[off + k], b = s.face_vertices[off + (k + 1) % n];
      const int32_t prev = s.face_vertices[off + (k + n - 1) % n];
      const uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
      if (++edge_uses[key] > 2) return false;
      link[a].emplace_back(prev, b);
    }
    off += n;
  }
  // The link of a vertex: its faces' (previous, next) corner pairs, as undirected edges
  // between neighbours; a single fan is a connected path or cycle.
  for (const auto& l : link) {
    if (l.size() < 2) continue;
    std::unordered_map<int32_t, std::vector<int32_t>> adj;
    for (const auto& [p, q] : l) {
      adj[p].push_back(q);
      adj[q].push_back(p);
    }
    std::vector<int32_t> stack = {l[0].first};
    std::unordered_map<int32_t, bool> seen{{l[0].first, true}};
    while (!stack.empty()) {
      const int32_t v = stack.back();
      stack.pop_back();
      for (int32_t w : adj[v]) {
        if (!seen[w]) {
          seen[w] = true;
          stack.push_back(w);
        }
      }
    }
    for (const auto& [v, ns] : adj) {
      if (!seen[v] || ns.size() > 2) return false;
    }
  }
  return true;
}

}  // namespace

// NOME3's genimplicitsurf (generators-original.md §11.3, GenImplicitSurf.cpp): nx × ny × nz
// cubes of (max − min)/(n − 1), so the grid reaches one cube past max; Bourke's marching
// cubes with inside = f ≤ 0, each cube creating its own vertices `v_{k}` (one per cut edge,
// in edge order, numbered in order of creation) and emitting Bourke's triangles reversed,
// so that they face towards f > 0. nomec then welds the cubes' copies of each crossing
// (CubeWelder); the surviving vertices keep NOME3's positions and names, and the names of
// the copies welded away become aliases of the survivors. Where the surface
// itself is singular (two sheets crossing, a cone's apex) the welded mesh is not a
// 2-manifold, and NOME3's unwelded cubes are returned as they were.
Generated make_Genimplicitsurf(const ArgReader& a) {
  using A = ir::gen_arg::Genimplicitsurf;
  a.function(A::func);
  const Range x = range(a, A::x_min, A::x_max);
  const Range y = range(a, A::y_min, A::y_max);
  const Range z = range(a, A::z_min, A::z_max);
  const int cx = a.count(A::nx, 2);
  const int cy = a.count(A::ny, 2);
  const int cz = a.count(A::nz, 2);
  if (static_cast<double>(cx) * cy * cz > 128.0 * 128.0 * 128.0) {
    fail(ir::arg_index(A::nz), "nx·ny·nz must be at most 2097152 (128³)");
  }
  const int px = cx + 1, py = cy + 1, pz = cz + 1;
  const glm::dvec3 step((x.hi - x.lo) / (cx - 1), (y.hi - y.lo) / (cy - 1), (z.hi - z.lo) / (cz - 1));
  auto gp = [&](int i, int j, int k) { return glm::dvec3(x.lo + step.x * i, y.lo + step.y * j, z.lo + step.z * k); };
  std::vector<double> val(static_cast<size_t>(px) * py * pz);
  auto vid = [&](int i, int j, int k) { return (static_cast<size_t>(i) * py + j) * pz + k; };
  for (int i = 0; i < px; ++i) {
    for (int j = 0; j < py; ++j) {
      for (int k = 0; k < pz; ++k) {
        const glm::dvec3 p = gp(i, j, k);
        const double xyz[3] = {p.x, p.y, p.z};
        val[vid(i, j, k)] = value_at(a, A::func, xyz);
      }
    }
  }
  // Bourke's corner order and edges (bourke_tables.h).
  static const int kCorner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  static const int kEdge[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  // Bourke's VertexInterp at the level 0.
  auto interpolate = [](const glm::dvec3& p1, const glm::dvec3& p2, double v1, double v2) {
    if (std::abs(v1) < 0.00001) return p1;
    if (std::abs(v2) < 0.00001) return p2;
    if (std::abs(v1 - v2) < 0.00001) return p1;
    return p1 + (-v1 / (v2 - v1)) * (p2 - p1);
  };
  // Copies of one crossing differ by rounding only; 10⁻⁹ of the smallest cell is far below
  // any distance between different crossings but those snapped to the same grid point.
  CubeWelder weld;
  weld.tol = 1e-9 * std::min({std::abs(step.x), std::abs(step.y), std::abs(step.z)});
  int32_t records = 0;  // NOME3's vertex records, for the names v_{k}
  kernel::PolygonSoup raw;  // NOME3's unwelded cubes
  for (int i = 0; i < cx; ++i) {
    for (int j = 0; j < cy; ++j) {
      for (int k = 0; k < cz; ++k) {
        glm::dvec3 p[8];
        double v[8];
        int cube = 0;
        for (int c = 0; c < 8; ++c) {
          const int ci = i + kCorner[c][0], cj = j + kCorner[c][1], ck = k + kCorner[c][2];
          p[c] = gp(ci, cj, ck);
          v[c] = val[vid(ci, cj, ck)];
          if (v[c] <= 0.0) cube |= 1 << c;
        }
        const int edges = kBourkeEdges[cube];
        if (edges == 0) continue;
        int32_t at[12];
        int32_t raw_at[12];
        for (int e = 0; e < 12; ++e) {
          if ((edges & (1 << e)) == 0) continue;
          const int c1 = kEdge[e][0], c2 = kEdge[e][1];
          const glm::dvec3 q = interpolate(p[c1], p[c2], v[c1], v[c2]);
          const std::string name = "v_" + std::to_string(records++);
          at[e] = weld.vertex(q, name);
          raw_at[e] = raw.add_vertex(q, name);
        }
        const int8_t* tri = kBourkeTriangles[cube];
        for (int t = 0; tri[t] != -1; t += 3) {
          weld.triangle(at[tri[t + 2]], at[tri[t + 1]], at[tri[t]]);
          raw.add_face({raw_at[tri[t + 2]], raw_at[tri[t + 1]], raw_at[tri[t]]});
        }
      }
    }
  }
  Generated g;
  if (is_manifold(weld.soup)) {
    g.soup = std::move(weld.soup);
    g.aliases = std::move(weld.aliases);
  } else {
    g.soup = std::move(raw);
  }
  return g;
}

}  // namespace nomec::backend::detail
