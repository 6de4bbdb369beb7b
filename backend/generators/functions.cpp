// Function surfaces: genparametricsurf (x, y, z as functions of u, v), gencartesiansurf
// (z = f(x, y)) and genimplicitsurf (f(x, y, z) = 0). The functions arrive evaluable (the
// checker lowered their text to IR expressions; the backend evaluates them).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

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

// Welds grid vertices that coincide within 1e-5 of the bounding-box diagonal (closing the
// seams of periodic parametrisations and collapsing poles), drops the repeated corners this
// creates and the faces left with fewer than 3 corners, and removes the welded-away vertices
// (the first vertex of each coincident set keeps its name).
void weld(kernel::PolygonSoup& s) {
  const int32_t n = s.vertex_count();
  if (n == 0) return;
  glm::dvec3 lo = s.positions[0], hi = s.positions[0];
  for (const auto& p : s.positions) {
    lo = glm::dvec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
    hi = glm::dvec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
  }
  const glm::dvec3 d = hi - lo;
  const double diag = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  const double tol = std::max(diag * 1e-5, 1e-12);
  auto key = [&](int64_t x, int64_t y, int64_t z) {
    return static_cast<uint64_t>(x) * 73856093ULL ^ static_cast<uint64_t>(y) * 19349663ULL ^
           static_cast<uint64_t>(z) * 83492791ULL;
  };
  std::unordered_map<uint64_t, std::vector<int32_t>> cells;
  std::vector<int32_t> rep(n);
  for (int32_t v = 0; v < n; ++v) {
    const glm::dvec3 q = (s.positions[v] - lo) / tol;
    const int64_t cx = static_cast<int64_t>(std::floor(q.x));
    const int64_t cy = static_cast<int64_t>(std::floor(q.y));
    const int64_t cz = static_cast<int64_t>(std::floor(q.z));
    rep[v] = v;
    for (int64_t dx = -1; dx <= 1 && rep[v] == v; ++dx) {
      for (int64_t dy = -1; dy <= 1 && rep[v] == v; ++dy) {
        for (int64_t dz = -1; dz <= 1 && rep[v] == v; ++dz) {
          auto it = cells.find(key(cx + dx, cy + dy, cz + dz));
          if (it == cells.end()) continue;
          for (int32_t w : it->second) {
            const glm::dvec3 e = s.positions[w] - s.positions[v];
            if (std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z) <= tol) {
              rep[v] = w;
              break;
            }
          }
        }
      }
    }
    if (rep[v] == v) cells[key(cx, cy, cz)].push_back(v);
  }
  kernel::PolygonSoup out;
  std::vector<int32_t> new_index(n, -1);
  for (int32_t v = 0; v < n; ++v) {
    if (rep[v] == v) {
      new_index[v] = out.add_vertex(s.positions[v], s.names.empty() ? std::string() : s.names[v]);
    }
  }
  size_t offset = 0;
  for (int32_t size : s.face_sizes) {
    std::vector<int32_t> f;
    for (int32_t k = 0; k < size; ++k) {
      const int32_t v = new_index[rep[s.face_vertices[offset + k]]];
      if (f.empty() || f.back() != v) f.push_back(v);
    }
    offset += size;
    while (f.size() > 1 && f.front() == f.back()) f.pop_back();
    if (f.size() >= 3) out.add_face(f);
  }
  s = std::move(out);
}

}  // namespace

Generated make_Genparametricsurf(const ArgReader& a) {
  using A = ir::gen_arg::Genparametricsurf;
  a.function(A::funcX);
  a.function(A::funcY);
  a.function(A::funcZ);
  const Range u = range(a, A::u_min, A::u_max);
  const Range v = range(a, A::v_min, A::v_max);
  const int us = a.count(A::u_segs, 1);
  const int vs = a.count(A::v_segs, 1);
  check_size(static_cast<long long>(us + 1) * (vs + 1), ir::arg_index(A::u_segs));
  Generated g;
  add_grid(g.soup, us, vs, false, false, [&](int i, int j) {
    const double uv[2] = {u.lo + (u.hi - u.lo) * i / us, v.lo + (v.hi - v.lo) * j / vs};
    return glm::dvec3(value_at(a, A::funcX, uv), value_at(a, A::funcY, uv), value_at(a, A::funcZ, uv));
  });
  weld(g.soup);
  return g;
}

Generated make_Gencartesiansurf(const ArgReader& a) {
  using A = ir::gen_arg::Gencartesiansurf;
  a.function(A::func);
  const Range x = range(a, A::x_min, A::x_max);
  const Range y = range(a, A::y_min, A::y_max);
  const int xs = a.count(A::x_segs, 1);
  const int ys = a.count(A::y_segs, 1);
  check_size(static_cast<long long>(xs + 1) * (ys + 1), ir::arg_index(A::x_segs));
  Generated g;
  add_grid(g.soup, xs, ys, false, false, [&](int i, int j) {
    const double xy[2] = {x.lo + (x.hi - x.lo) * i / xs, y.lo + (y.hi - y.lo) * j / ys};
    return glm::dvec3(xy[0], xy[1], value_at(a, A::func, xy));
  });
  return g;
}

// genimplicitsurf over NOME3's grid. NOME3 runs Bourke's marching cubes and gives every cube
// its own vertices; nomec splits each cube into six tetrahedra (a manifold result with no
// ambiguous cases) and shares the crossing on each grid edge, named `v_{k}` in order of
// creation (generators-original.md §11.3).
Generated make_Genimplicitsurf(const ArgReader& a) {
  using A = ir::gen_arg::Genimplicitsurf;
  a.function(A::func);
  const Range x = range(a, A::x_min, A::x_max);
  const Range y = range(a, A::y_min, A::y_max);
  const Range z = range(a, A::z_min, A::z_max);
  // NOME3's grid (compat.md D2): nx × ny × nz cells of (max − min)/(n − 1), so the last cell
  // ends one cell past max. f is sampled at the (n+1)³ corners; exact zeros are nudged so
  // that no grid value lies on the surface (this keeps the marching-tetrahedra result a
  // manifold).
  const int cx = a.count(A::nx, 2);
  const int cy = a.count(A::ny, 2);
  const int cz = a.count(A::nz, 2);
  if (static_cast<double>(cx) * cy * cz > 128.0 * 128.0 * 128.0) {
    fail(ir::arg_index(A::nz), "nx·ny·nz must be at most 2097152 (128³)");
  }
  const int px = cx + 1, py = cy + 1, pz = cz + 1;
  const glm::dvec3 step((x.hi - x.lo) / (cx - 1), (y.hi - y.lo) / (cy - 1), (z.hi - z.lo) / (cz - 1));
  auto gp = [&](int i, int j, int k) { return glm::dvec3(x.lo + step.x * i, y.lo + step.y * j, z.lo + step.z * k); };
  const size_t corners = static_cast<size_t>(px) * py * pz;
  std::vector<double> val(corners);
  auto vid = [&](int i, int j, int k) { return (static_cast<size_t>(i) * py + j) * pz + k; };
  for (int i = 0; i < px; ++i) {
    for (int j = 0; j < py; ++j) {
      for (int k = 0; k < pz; ++k) {
        const glm::dvec3 p = gp(i, j, k);
        const double xyz[3] = {p.x, p.y, p.z};
        double v = value_at(a, A::func, xyz);
        if (v == 0.0) v = 1e-300;
        val[vid(i, j, k)] = v;
      }
    }
  }
  Generated g;
  std::unordered_map<uint64_t, int32_t> edge_vertex;  // grid edge -> soup vertex
  auto crossing = [&](size_t p, size_t q) -> int32_t {
    if (p > q) std::swap(p, q);
    const uint64_t key = static_cast<uint64_t>(p) * corners + q;
    auto it = edge_vertex.find(key);
    if (it != edge_vertex.end()) return it->second;
    auto pos = [&](size_t id) {
      const int k = static_cast<int>(id % pz), j = static_cast<int>((id / pz) % py), i = static_cast<int>(id / pz / py);
      return gp(i, j, k);
    };
    // Clamped away from the corners so that crossings never coincide.
    const double t = std::clamp(val[p] / (val[p] - val[q]), 1e-3, 1.0 - 1e-3);
    const int32_t v = g.soup.add_vertex(pos(p) + t * (pos(q) - pos(p)), "v_" + std::to_string(g.soup.vertex_count()));
    edge_vertex.emplace(key, v);
    return v;
  };
  // Kuhn triangulation of each cube into 6 tetrahedra along the main diagonal (consistent
  // across neighbouring cubes).
  static const int kTets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7},
                                  {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
  for (int i = 0; i < cx; ++i) {
    for (int j = 0; j < cy; ++j) {
      for (int k = 0; k < cz; ++k) {
        size_t c[8];
        glm::dvec3 cp[8];
        for (int b = 0; b < 8; ++b) {
          // corner bit 0 = x, 1 = y, 2 = z
          c[b] = vid(i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1));
          cp[b] = gp(i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1));
        }
        for (const auto& tet : kTets) {
          std::vector<int> in, out;
          for (int t : tet) (val[c[t]] < 0 ? in : out).push_back(t);
          if (in.empty() || out.empty()) continue;
          std::vector<int32_t> poly;
          if (in.size() == 1 || out.size() == 1) {
            const std::vector<int>& lone = in.size() == 1 ? in : out;
            const std::vector<int>& rest = in.size() == 1 ? out : in;
            for (int r : rest) poly.push_back(crossing(c[lone[0]], c[r]));
          } else {
            poly = {crossing(c[in[0]], c[out[0]]), crossing(c[in[0]], c[out[1]]),
                    crossing(c[in[1]], c[out[1]]), crossing(c[in[1]], c[out[0]])};
          }
          // Orient outward (from f < 0 towards f > 0): the polygon of the crossed edges'
          // midpoints has the same cyclic order and is never degenerate, so its normal
          // decides, compared with the direction from the inside corners to the outside ones.
          auto cross = [](const glm::dvec3& u, const glm::dvec3& v) {
            return glm::dvec3(u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x);
          };
          auto dot = [](const glm::dvec3& u, const glm::dvec3& v) { return u.x * v.x + u.y * v.y + u.z * v.z; };
          std::vector<glm::dvec3> mid;
          if (in.size() == 1 || out.size() == 1) {
            const std::vector<int>& lone = in.size() == 1 ? in : out;
            const std::vector<int>& rest = in.size() == 1 ? out : in;
            for (int r : rest) mid.push_back(0.5 * (cp[lone[0]] + cp[r]));
          } else {
            mid = {0.5 * (cp[in[0]] + cp[out[0]]), 0.5 * (cp[in[0]] + cp[out[1]]),
                   0.5 * (cp[in[1]] + cp[out[1]]), 0.5 * (cp[in[1]] + cp[out[0]])};
          }
          glm::dvec3 nrm(0.0);
          for (size_t q = 1; q + 1 < mid.size(); ++q) nrm += cross(mid[q] - mid[0], mid[q + 1] - mid[0]);
          glm::dvec3 ci(0.0), co(0.0);
          for (int t : in) ci += cp[t] / static_cast<double>(in.size());
          for (int t : out) co += cp[t] / static_cast<double>(out.size());
          if (dot(nrm, co - ci) < 0) std::reverse(poly.begin(), poly.end());
          g.soup.add_face(poly);
        }
      }
    }
  }
  return g;
}

}  // namespace nomec::backend::detail
