// Function surfaces: genparametricsurf (x, y, z as functions of u, v), gencartesiansurf
// (z = f(x, y)); genimplicitsurf is not supported yet.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "backend/generators/expr.h"
#include "backend/generators/impl.h"

namespace nomec::backend::detail {
namespace {

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

Expression parse_func(const ArgReader& a, std::string_view name, const std::vector<std::string>& vars) {
  std::string error;
  const std::string text = a.text(name);
  std::optional<Expression> e = Expression::parse(text, vars, &error);
  if (!e) {
    fail(name, "in `" + std::string(name) + "`: " + error);
  }
  return *e;
}

struct Range {
  double lo;
  double hi;
};
Range range(const ArgReader& a, std::string_view lo_name, std::string_view hi_name) {
  const double lo = a.number({lo_name}).value;
  const double hi = a.number({hi_name}).value;
  if (!(hi > lo)) {
    fail(hi_name, "`" + std::string(hi_name) + "` must be greater than `" + std::string(lo_name) + "`");
  }
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

Generated make_genparametricsurf(const ArgReader& a) {
  const std::vector<std::string> vars = {"u", "v"};
  const Expression fx = parse_func(a, "funcX", vars);
  const Expression fy = parse_func(a, "funcY", vars);
  const Expression fz = parse_func(a, "funcZ", vars);
  const Range u = range(a, "u_min", "u_max");
  const Range v = range(a, "v_min", "v_max");
  const int us = a.count({"u_segs"}, 1);
  const int vs = a.count({"v_segs"}, 1);
  check_size(static_cast<long long>(us + 1) * (vs + 1), "u_segs");
  Generated g;
  add_grid(g.soup, us, vs, false, false, [&](int i, int j) {
    const std::vector<double> uv = {u.lo + (u.hi - u.lo) * i / us, v.lo + (v.hi - v.lo) * j / vs};
    const glm::dvec3 p(fx.evaluate(uv), fy.evaluate(uv), fz.evaluate(uv));
    const char* bad = !std::isfinite(p.x) ? "funcX" : !std::isfinite(p.y) ? "funcY"
                    : !std::isfinite(p.z) ? "funcZ" : nullptr;
    if (bad != nullptr) {
      fail(bad, "`" + std::string(bad) + "` is not finite at u=" + num(uv[0]) + ", v=" + num(uv[1]));
    }
    return p;
  });
  weld(g.soup);
  return g;
}

Generated make_gencartesiansurf(const ArgReader& a) {
  const Expression f = parse_func(a, "func", {"x", "y"});
  const Range x = range(a, "x_min", "x_max");
  const Range y = range(a, "y_min", "y_max");
  const int xs = a.count({"x_segs"}, 1);
  const int ys = a.count({"y_segs"}, 1);
  check_size(static_cast<long long>(xs + 1) * (ys + 1), "x_segs");
  Generated g;
  add_grid(g.soup, xs, ys, false, false, [&](int i, int j) {
    const std::vector<double> xy = {x.lo + (x.hi - x.lo) * i / xs, y.lo + (y.hi - y.lo) * j / ys};
    const double z = f.evaluate(xy);
    if (!std::isfinite(z)) {
      fail("func", "`func` is not finite at x=" + num(xy[0]) + ", y=" + num(xy[1]));
    }
    return glm::dvec3(xy[0], xy[1], z);
  });
  return g;
}

Generated make_genimplicitsurf(const ArgReader&) {
  fail("", "`genimplicitsurf` is not supported yet");
}

}  // namespace nomec::backend::detail
