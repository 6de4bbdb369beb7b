// Ring generators: funnel and tunnel (seed report §6.3), circle, mobiusstrip.
#include <cmath>
#include <string>
#include <vector>

#include "backend/generators/impl.h"

namespace nomec::backend::detail {
namespace {

glm::dvec3 on_ring(double radius, double z, int i, int n) {
  const double t = 2.0 * kPi * i / n;
  return {radius * std::cos(t), radius * std::sin(t), z};
}

int32_t add_ring(kernel::PolygonSoup& s, std::string_view prefix, double radius, double z, int n) {
  const int32_t base = s.vertex_count();
  for (int i = 0; i < n; ++i) {
    s.add_vertex(on_ring(radius, z, i, n), std::string(prefix) + std::to_string(i));
  }
  return base;
}

// Quads (lo_i, lo_{i+1}, hi_{i+1}, hi_i): outward normals when `hi` is above `lo`.
void add_band(kernel::PolygonSoup& s, int32_t lo, int32_t hi, int n) {
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    s.add_face({lo + i, lo + j, hi + j, hi + i});
  }
}

// Ring radius factor 1 + ratio, which must stay positive.
template <typename A>
double radius_factor(const ArgReader& a, A ratio) {
  const double v = a.number(ratio);
  if (!(1.0 + v > 0)) {
    const std::string n = a.name(ratio);
    fail(ir::arg_index(ratio), "`" + n + "` must be greater than -1 (the ring radius ro*(1+" + n + ") must be positive)");
  }
  return 1.0 + v;
}

struct FunnelArgs {
  int n;
  double ro;
  double ratio;
  double h;
};

// Funnels and tunnels share their first four arguments.
template <typename A>
FunnelArgs funnel_args(const ArgReader& a) {
  FunnelArgs f{};
  f.n = a.count(A::n, 3);
  f.ro = a.positive(A::ro);
  f.ratio = radius_factor(a, A::ratio) - 1.0;
  f.h = a.number(A::h);
  return f;
}

}  // namespace

Generated make_Funnel(const ArgReader& a) {
  const FunnelArgs f = funnel_args<ir::gen_arg::Funnel>(a);
  Generated g;
  const int32_t bc = add_ring(g.soup, "bc", f.ro, 0.0, f.n);
  const int32_t hc = add_ring(g.soup, "hc", f.ro * (1.0 + f.ratio), f.h, f.n);
  add_band(g.soup, bc, hc, f.n);
  return g;
}

Generated make_Tunnel(const ArgReader& a) {
  using A = ir::gen_arg::Tunnel;
  const FunnelArgs f = funnel_args<A>(a);
  const double low_factor = a.has(A::dri_low) ? radius_factor(a, A::dri_low) : 1.0 + f.ratio;
  const double low_h = a.number_or(A::hgt_low, f.h);
  Generated g;
  const int32_t bc = add_ring(g.soup, "bc", f.ro, 0.0, f.n);
  const int32_t hc = add_ring(g.soup, "hc", f.ro * (1.0 + f.ratio), f.h, f.n);
  const int32_t lc = add_ring(g.soup, "lc", f.ro * low_factor, -low_h, f.n);
  add_band(g.soup, bc, hc, f.n);
  add_band(g.soup, lc, bc, f.n);
  return g;
}

Generated make_Circle(const ArgReader& a) {
  using A = ir::gen_arg::Circle;
  const double r = a.positive(A::radius);
  const int segs = a.count(A::segs, 3);
  Generated g;
  const int32_t base = add_ring(g.soup, "v", r, 0.0, segs);
  Generated::Curve c;
  c.is_closed = true;
  for (int i = 0; i < segs; ++i) {
    c.vertices.push_back(base + i);
  }
  g.curves.push_back(std::move(c));
  return g;
}

// NOME3's Möbius strip (generators-original.md §6, MobiusStrip.cpp): twists = ⌈num_twists⌉
// half-turns and cuts = ⌈num_cuts⌉. u runs from 0 in steps of π/n while u < 2π + step/3
// (2n + 1 samples for a whole n, the last at 2π); v runs from −radius in steps of
// 2·radius/(2·cuts + 1) while v ≤ radius + step/3. The centre circle has radius 1 and
// `radius` is the band's full width: (1 + (v/2)cos(tw·u/2))(cos u, sin u) and
// z = (v/2)sin(tw·u/2). Every `v_{a}_{b}` has a twin `vt_{a}_{b}` radius/10 above it; each
// u step and cut gives the strip quad, its `vt` copy with the same winding and two side
// walls. As in NOME3 the seam is not welded and the walls do not agree in orientation
// with the strips (the kernel accepts such edges as Möbius edges).
Generated make_Mobiusstrip(const ArgReader& a) {
  using A = ir::gen_arg::Mobiusstrip;
  const double radius = a.positive(A::radius);
  const double twists = std::ceil(a.number(A::num_twists));
  const double cuts = std::ceil(a.number(A::num_cuts));
  if (cuts < 0.0) fail(ir::arg_index(A::num_cuts), "`" + a.name(A::num_cuts) + "` must not be negative");
  if (cuts > kMaxSegments) fail(ir::arg_index(A::num_cuts), "`" + a.name(A::num_cuts) + "` must be at most " + std::to_string(kMaxSegments));
  const double n = a.number(A::n);
  if (!(n >= 0.5)) fail(ir::arg_index(A::n), "`" + a.name(A::n) + "` must be at least 0.5 (one step of the strip), got " + fmt_number(n));
  if (n > kMaxSegments) fail(ir::arg_index(A::n), "`" + a.name(A::n) + "` must be at most " + std::to_string(kMaxSegments));
  std::vector<double> us, vs;
  const double du = kPi / n;
  for (double u = 0.0; u < 2.0 * kPi + du / 3.0; u += du) us.push_back(u);
  const double dv = 2.0 * radius / (2.0 * cuts + 1.0);
  for (double v = -radius; v <= radius + dv / 3.0; v += dv) vs.push_back(v);
  const int nu = static_cast<int>(us.size());
  const int nv = static_cast<int>(vs.size());
  check_size(2LL * nu * nv, ir::arg_index(A::n));
  Generated g;
  std::vector<int32_t> bottom(static_cast<size_t>(nu) * nv), top(bottom.size());
  auto at = [&](int i, int j) { return static_cast<size_t>(i) * nv + j; };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = us[i], v = vs[j];
      const double rr = 1.0 + (v / 2.0) * std::cos(twists * u / 2.0);
      const glm::dvec3 p(rr * std::cos(u), rr * std::sin(u), (v / 2.0) * std::sin(twists * u / 2.0));
      const std::string ij = std::to_string(i) + "_" + std::to_string(j);
      bottom[at(i, j)] = g.soup.add_vertex(p, "v_" + ij);
      top[at(i, j)] = g.soup.add_vertex(p + glm::dvec3(0.0, 0.0, radius / 10.0), "vt_" + ij);
    }
  }
  for (int i = 0; i + 1 < nu; ++i) {
    for (int c = 0; 2 * c + 1 < nv; ++c) {
      const int b0 = 2 * c, b1 = 2 * c + 1;
      for (const auto* layer : {&bottom, &top}) {
        const auto& l = *layer;
        g.soup.add_face({l[at(i, b0)], l[at(i + 1, b0)], l[at(i + 1, b1)], l[at(i, b1)]});
      }
      for (int b : {b0, b1}) g.soup.add_face({bottom[at(i, b)], bottom[at(i + 1, b)], top[at(i + 1, b)], top[at(i, b)]});
    }
  }
  return g;
}

}  // namespace nomec::backend::detail

namespace nomec::backend::detail {
namespace {

glm::dvec3 cross3(const glm::dvec3& u, const glm::dvec3& v) {
  return {u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
}
double dot3(const glm::dvec3& u, const glm::dvec3& v) { return u.x * v.x + u.y * v.y + u.z * v.z; }
double len3(const glm::dvec3& u) { return std::sqrt(dot3(u, u)); }
// Rotates `v` (perpendicular to unit `axis`) by `angle` radians about `axis`.
glm::dvec3 rotate_about(const glm::dvec3& v, const glm::dvec3& axis, double angle) {
  return std::cos(angle) * v + std::sin(angle) * cross3(axis, v);
}

}  // namespace

Generated make_Rimribbon(const ArgReader& a) {
  using A = ir::gen_arg::Rimribbon;
  const auto& pts = a.raw().points;
  const int m = static_cast<int>(pts.size());
  const bool closed = a.raw().is_path_closed;
  const ir::ArgIndex path = ir::arg_index(A::path);
  if (m < (closed ? 3 : 2)) {
    fail(path, "a rim ribbon needs a path of at least " + std::string(closed ? "3" : "2") + " points, got " +
                   std::to_string(m));
  }
  for (int k = 0; k + 1 < m + (closed ? 1 : 0); ++k) {
    if (len3(pts[(k + 1) % m] - pts[k]) == 0.0) {
      fail(path, "the path repeats point " + std::to_string(k) + " (zero-length segment)");
    }
  }
  const double width = a.number(A::width);
  if (width == 0.0) fail(ir::arg_index(A::width), "`width` must not be 0");
  const double azimuth = radians(a.number_or(A::azimuth, 0.0));
  const double twist = radians(a.number_or(A::twist, 0.0));
  // Unit tangents (central differences) and arc length.
  std::vector<glm::dvec3> tan(m);
  std::vector<double> arc(m + 1, 0.0);
  for (int k = 0; k < m; ++k) {
    const glm::dvec3 prev = (k > 0 || closed) ? pts[k] - pts[(k + m - 1) % m] : glm::dvec3(0.0);
    const glm::dvec3 next = (k + 1 < m || closed) ? pts[(k + 1) % m] - pts[k] : glm::dvec3(0.0);
    glm::dvec3 t = (len3(prev) > 0 ? prev / len3(prev) : prev) + (len3(next) > 0 ? next / len3(next) : next);
    if (len3(t) < 1e-12) t = next;  // a path that doubles back: use the outgoing segment
    tan[k] = t / len3(t);
    if (k + 1 < m || closed) arc[k + 1] = arc[k] + len3(next);
  }
  const double total = closed ? arc[m] : arc[m - 1];
  // Start direction: +z (else +x) made perpendicular to the first tangent, turned by azimuth.
  glm::dvec3 ref(0, 0, 1);
  if (std::abs(dot3(ref, tan[0])) > 0.99) ref = glm::dvec3(1, 0, 0);
  glm::dvec3 n0 = ref - dot3(ref, tan[0]) * tan[0];
  n0 = rotate_about(n0 / len3(n0), tan[0], azimuth);
  // Parallel transport by projection; for a closed path the holonomy (the angle the
  // transported direction is off by after one loop) is spread evenly along the path.
  std::vector<glm::dvec3> nrm(m);
  nrm[0] = n0;
  for (int k = 1; k < m; ++k) {
    glm::dvec3 v = nrm[k - 1] - dot3(nrm[k - 1], tan[k]) * tan[k];
    if (len3(v) < 1e-12) v = cross3(tan[k], cross3(nrm[k - 1], tan[k]));
    nrm[k] = v / len3(v);
  }
  double holonomy = 0.0;
  if (closed) {
    glm::dvec3 back = nrm[m - 1] - dot3(nrm[m - 1], tan[0]) * tan[0];
    if (len3(back) > 1e-12) {
      back = back / len3(back);
      holonomy = std::atan2(dot3(cross3(back, n0), tan[0]), dot3(back, n0));
    }
  }
  Generated g;
  for (int k = 0; k < m; ++k) {
    g.soup.add_vertex(pts[k], "bc" + std::to_string(k));
  }
  for (int k = 0; k < m; ++k) {
    const double s = total > 0 ? arc[k] / total : 0.0;
    const glm::dvec3 d = rotate_about(nrm[k], tan[k], twist * s + holonomy * s);
    g.soup.add_vertex(pts[k] + width * d, "hc" + std::to_string(k));
  }
  add_band(g.soup, 0, m, m);
  if (!closed) {
    g.soup.face_sizes.pop_back();
    g.soup.face_vertices.resize(g.soup.face_vertices.size() - 4);
  }
  return g;
}

}  // namespace nomec::backend::detail
