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
