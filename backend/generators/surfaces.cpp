// Closed-form surfaces: torus, sphere, ellipsoid, cylinder, hyperboloid, Dupin cyclide and
// the torus-knot tube. Full 360-degree ranges weld the seam (no duplicate vertices), poles
// are single vertices with triangle fans (no degenerate faces).
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include "backend/generators/impl.h"

namespace nomec::backend::detail {
namespace {


// NOME3's sphere and ellipsoid (generators-original.md §4), in every dialect: the angles
// cut to whole degrees; a grid `v{j}_{i}` (NOME3's `v{j}-{i}`) of θ_j = j·θmax/θsegs and
// ψ_i = (φmin + 90) + i·(φmax − φmin)/φsegs at (eq·sin ψ cos θ, eq·sin ψ sin θ,
// polar·cos ψ), so row 0 is the top (φ = −90 is the north pole); `top`, `bottom` and
// `center` on the axis. Side quads, a lid fan on each end row and, below 360, two slice
// fans to `center`: a closed solid. The 360 seam column and pole rows are welded (their
// names stay aliases), which drops NOME3's degenerate faces there.
template <typename A>
Generated spheroid(const ArgReader& a, double polar, double eq) {
  // Every argument is given in NOME and NOME3; SLIDE's named fields may be left out.
  const bool slide = a.dialect() == Dialect::Slide;
  const double theta_max = std::trunc(slide ? a.number_or(A::theta_max, 360.0) : a.number(A::theta_max));
  const bool wrap = full_turn(theta_max, ir::arg_index(A::theta_max), a.name(A::theta_max));
  const double phi_min = std::trunc(slide ? a.number_or(A::phi_min, -90.0) : a.number(A::phi_min));
  const double phi_max = std::trunc(slide ? a.number_or(A::phi_max, 90.0) : a.number(A::phi_max));
  if (phi_min < -90.0 || phi_min > 90.0) {
    fail(ir::arg_index(A::phi_min), "`phi_min` is a latitude and must be within [-90, 90] degrees, got " + fmt_number(phi_min));
  }
  if (phi_max > 90.0 || phi_max < -90.0) {
    fail(ir::arg_index(A::phi_max), "`phi_max` is a latitude and must be within [-90, 90] degrees, got " + fmt_number(phi_max));
  }
  if (!(phi_max > phi_min)) fail(ir::arg_index(A::phi_max), "`phi_max` must be greater than `phi_min`");
  const bool north = phi_min == -90.0;
  const bool south = phi_max == 90.0;
  const int ts = slide && !a.has(A::theta_segs) ? 16 : a.count(A::theta_segs, wrap ? 3 : 1);
  const int ps = slide && !a.has(A::phi_segs) ? 8 : a.count(A::phi_segs, south && north ? 2 : 1);
  check_size(static_cast<long long>(ts + 1) * (ps + 1), ir::arg_index(A::phi_segs));

  OriginalMesh m;
  auto v = [&](int j, int i) { return j * (ps + 1) + i; };
  for (int j = 0; j <= ts; ++j) {
    const double th = radians(j * theta_max / ts);
    for (int i = 0; i <= ps; ++i) {
      const double psi = radians((phi_min + 90.0) + i * (phi_max - phi_min) / ps);
      m.add({eq * std::sin(psi) * std::cos(th), eq * std::sin(psi) * std::sin(th), polar * std::cos(psi)},
            "v" + std::to_string(j) + "_" + std::to_string(i));
    }
  }
  const double z_top = m.position(v(0, 0)).z;
  const double z_bottom = m.position(v(0, ps)).z;
  const int32_t top = m.add({0.0, 0.0, z_top}, "top");
  const int32_t bottom = m.add({0.0, 0.0, z_bottom}, "bottom");
  const int32_t center = m.add({0.0, 0.0, (z_top + z_bottom) / 2.0}, "center");
  for (int j = 0; j <= ts; ++j) {
    if (wrap && j == ts) {
      for (int i = 0; i <= ps; ++i) m.weld(v(ts, i), v(0, i));
    }
    if (north) m.weld(v(j, 0), top);
    if (south) m.weld(v(j, ps), bottom);
  }
  for (int k = 0; k < ts; ++k) {
    for (int c = 0; c < ps; ++c) m.face({v(k + 1, c + 1), v(k + 1, c), v(k, c), v(k, c + 1)});
    m.face({v(k, 0), v(k + 1, 0), top});
    m.face({bottom, v(k + 1, ps), v(k, ps)});
  }
  if (!wrap) {
    for (int i = 0; i < ps; ++i) {
      m.face({v(0, i + 1), v(0, i), center});
      m.face({center, v(ts, i), v(ts, i + 1)});
    }
    m.face({top, center, v(0, 0)});
    m.face({v(0, ps), center, bottom});
    m.face({v(ts, 0), center, top});
    m.face({bottom, center, v(ts, ps)});
  }
  return m.finish();
}

}  // namespace

// NOME3's torus (generators-original.md §2), in every dialect: vertex `v{i+1}_{j}` at
// ((R + r cos φ_j) cos θ_i, (R + r cos φ_j) sin θ_i, −r sin φ_j) for i = 0…θsegs,
// j = 0…φsegs. At θmax = 360 the quads wrap around the axis; below, each θ segment has
// φsegs + 1 quads, the last joining row φsegs back to row 0 (it closes a partial tube along
// the chord). Full-turn seams are welded (names kept as aliases), which drops the degenerate
// closing quads NOME3 made for a full tube.
Generated make_Torus(const ArgReader& a) {
  using A = ir::gen_arg::Torus;
  // Every argument is given in NOME and NOME3; SLIDE's named fields may be left out.
  const bool slide = a.dialect() == Dialect::Slide;
  const double R = slide && !a.has(A::major_radius) ? 1.0 : a.positive(A::major_radius);
  const double r = slide && !a.has(A::minor_radius) ? 0.25 : a.positive(A::minor_radius);
  const double theta_max = slide ? a.number_or(A::theta_max, 360.0) : a.number(A::theta_max);
  const double phi_min = slide ? a.number_or(A::phi_min, 0.0) : a.number(A::phi_min);
  const double phi_max = slide ? a.number_or(A::phi_max, 360.0) : a.number(A::phi_max);
  const bool wrap_i = full_turn(theta_max, ir::arg_index(A::theta_max), a.name(A::theta_max));
  const bool wrap_j = full_turn(phi_max - phi_min, ir::arg_index(A::phi_max), a.name(A::phi_max));
  const int ts = slide && !a.has(A::theta_segs) ? 16 : a.count(A::theta_segs, wrap_i ? 3 : 1);
  // A partial tube on a partial turn is closed by a quad back to row 0: one segment
  // would put that quad on the back of the only other one.
  const int ps = slide && !a.has(A::phi_segs) ? 8 : a.count(A::phi_segs, wrap_j ? 3 : (wrap_i ? 1 : 2));
  check_size(static_cast<long long>(ts + 1) * (ps + 1), ir::arg_index(A::theta_segs));
  OriginalMesh m;
  auto v = [&](int i, int j) { return i * (ps + 1) + j; };
  for (int i = 0; i <= ts; ++i) {
    const double th = radians(i * theta_max / ts);
    for (int j = 0; j <= ps; ++j) {
      const double ph = radians(phi_min + j * (phi_max - phi_min) / ps);
      const double rr = R + r * std::cos(ph);
      m.add({rr * std::cos(th), rr * std::sin(th), -r * std::sin(ph)}, "v" + std::to_string(i + 1) + "_" + std::to_string(j));
    }
  }
  for (int i = 0; i <= ts; ++i) {
    for (int j = 0; j <= ps; ++j) {
      if (wrap_i && i == ts) m.weld(v(i, j), v(0, j));
      if (wrap_j && j == ps) m.weld(v(i, j), v(i, 0));
    }
  }
  for (int k = 0; k < ts; ++k) {
    if (wrap_i) {
      const int k1 = (k + 1) % ts;
      for (int j = 0; j < ps; ++j) m.face({v(k1, j + 1), v(k1, j), v(k, j), v(k, j + 1)});
    } else {
      for (int j = 0; j <= ps; ++j) {
        const int next = (j + 1) % (ps + 1);
        m.face({v(k + 1, next), v(k + 1, j), v(k, j), v(k, next)});
      }
    }
  }
  return m.finish();
}

Generated make_Sphere(const ArgReader& a) {
  const bool slide_default = a.dialect() == Dialect::Slide && !a.has(ir::gen_arg::Sphere::radius);
  const double r = slide_default ? 1.0 : a.positive(ir::gen_arg::Sphere::radius);
  return spheroid<ir::gen_arg::Sphere>(a, r, r);
}

Generated make_Ellipsoid(const ArgReader& a) {
  // NOME3's `rx`, the first argument, is the polar semi-axis (Ellipsoid.cpp:10-16,41-46).
  const double polar = a.positive(ir::gen_arg::Ellipsoid::a);
  const double eq = a.positive(ir::gen_arg::Ellipsoid::b);
  return spheroid<ir::gen_arg::Ellipsoid>(a, polar, eq);
}

// NOME3's cylinder (compat.md D1, generators-original.md §5): two rings of theta_segs + 1
// vertices `v{j}_{i}` (NOME3's `v{j}-{i}`, which a file cannot write), j = 0 at z = 0 and
// j = 1 at z = height, θ_i = i·theta_max/theta_segs with theta_max truncated to whole
// degrees. At exactly 360 the last column lies on the first (an unwelded seam, as in NOME3)
// and a closing quad joins them; below 360 two wedge quads close the slice through the axis
// vertices `top_center` (0,0,0) and `bottom_center` (0,0,height). `topcap`/`begincap` caps
// the z = 0 ring (facing −z), `botcap`/`endcap` the z = height ring (facing +z). SLIDE's
// cylinder, which has named fields only, defaults to radius 1, height 1 and a full turn.
Generated make_Cylinder(const ArgReader& a) {
  using A = ir::gen_arg::Cylinder;
  const double r = a.has(A::radius) ? a.positive(A::radius) : 1.0;
  const double zmin = a.number_or(A::zmin, 0.0);
  const double h = a.has(A::zmin) ? a.number_or(A::height, 1.0) : (a.has(A::height) ? a.positive(A::height) : 1.0);
  if (!(h > zmin)) fail(ir::arg_index(A::height), "`zmax` must be greater than `zmin`");
  const double theta_max = std::trunc(a.number_or(A::theta_max, 360.0));
  const bool full = full_turn(theta_max, ir::arg_index(A::theta_max), a.name(A::theta_max));
  const int ts = a.has(A::theta_segs) ? a.count(A::theta_segs, full ? 3 : 1) : 16;
  check_size(2LL * (ts + 1), ir::arg_index(A::theta_segs));
  Generated g;
  int32_t ring[2] = {0, 0};
  for (int j = 0; j < 2; ++j) {
    ring[j] = g.soup.vertex_count();
    for (int i = 0; i <= ts; ++i) {
      const double th = radians(theta_max * i / ts);
      g.soup.add_vertex({r * std::cos(th), r * std::sin(th), j == 0 ? zmin : h}, "v" + std::to_string(j) + "_" + std::to_string(i));
    }
  }
  auto v = [&](int j, int i) { return ring[j] + i; };
  for (int c = 0; c < ts; ++c) g.soup.add_face({v(1, c + 1), v(1, c), v(0, c), v(0, c + 1)});
  int32_t top_center = -1, bottom_center = -1;
  if (full) {
    g.soup.add_face({v(1, 0), v(1, ts), v(0, ts), v(0, 0)});
  } else {
    top_center = g.soup.add_vertex({0.0, 0.0, zmin}, "top_center");
    bottom_center = g.soup.add_vertex({0.0, 0.0, h}, "bottom_center");
    g.soup.add_face({top_center, bottom_center, v(1, ts), v(0, ts)});
    g.soup.add_face({v(0, 0), v(1, 0), bottom_center, top_center});
  }
  if (a.flag(A::begincap)) {
    std::vector<int32_t> cap;
    if (!full) cap.push_back(top_center);
    for (int i = ts; i >= 0; --i) cap.push_back(v(0, i));
    g.soup.add_face(cap);
  }
  if (a.flag(A::endcap)) {
    std::vector<int32_t> cap;
    if (!full) cap.push_back(bottom_center);
    for (int i = 0; i <= ts; ++i) cap.push_back(v(1, i));
    g.soup.add_face(cap);
  }
  return g;
}

// SLIDE's cone: rings v{i}_0 (at zmin) and v{i}_1 (at zmax) of `thetaslices` vertices, v0_0
// on +x; at zmax = 1 the top ring is the single apex vertex `v0_1`. The side faces point
// away from the axis, a begincap faces −z and an endcap +z.
Generated make_Cone(const ArgReader& a) {
  using A = ir::gen_arg::Cone;
  const double r = a.has(A::radius) ? a.positive(A::radius) : 1.0;
  const double h = a.has(A::height) ? a.positive(A::height) : 1.0;
  const double zmin = a.number_or(A::zmin, 0.0);
  const double zmax = a.number_or(A::zmax, 1.0);
  if (!(zmin < zmax)) fail(ir::arg_index(A::zmax), "`zmax` must be greater than `zmin`");
  const int n = a.count_or(A::theta_segs, 3, 16);
  check_size(2LL * n, ir::arg_index(A::theta_segs));
  const bool apex = zmax >= 1.0;
  Generated g;
  auto ring = [&](double t, int j) {
    std::vector<int32_t> out;
    for (int i = 0; i < n; ++i) {
      const double th = 2.0 * kPi * i / n;
      out.push_back(g.soup.add_vertex(glm::dvec3(r * (1.0 - t) * std::cos(th), r * (1.0 - t) * std::sin(th), h * t),
                                      "v" + std::to_string(i) + "_" + std::to_string(j)));
    }
    return out;
  };
  const std::vector<int32_t> bottom = ring(zmin, 0);
  if (apex) {
    const int32_t top = g.soup.add_vertex(glm::dvec3(0.0, 0.0, h), "v0_1");
    for (int i = 0; i < n; ++i) g.soup.add_face({bottom[i], bottom[(i + 1) % n], top});
  } else {
    const std::vector<int32_t> top = ring(zmax, 1);
    for (int i = 0; i < n; ++i) g.soup.add_face({bottom[i], bottom[(i + 1) % n], top[(i + 1) % n], top[i]});
    if (a.flag(A::endcap)) g.soup.add_face(top);
  }
  if (a.flag(A::begincap)) g.soup.add_face(std::vector<int32_t>(bottom.rbegin(), bottom.rend()));
  return g;
}

namespace {

// NOME3's triangulated grid (Dupin.cpp, Hyperboloid.cpp): vertex (i, j) at `first + i*nj + j`;
// each cell (i, j) gives the triangles (i,j) (i+1,j) (i,j+1) and (i,j+1) (i+1,j) (i+1,j+1),
// reversed when `flip`; cells wrap around i or j when that direction is closed. With
// `skip_corner` the cell (ni−1, nj−1), which only exists when both directions wrap, is left
// open, as Dupin.cpp does.
void add_triangle_grid(kernel::PolygonSoup& soup, int32_t first, int ni, int nj, bool wrap_i, bool wrap_j, bool flip,
                       bool skip_corner = false) {
  auto at = [&](int i, int j) { return first + (i % ni) * nj + (j % nj); };
  auto tri = [&](int32_t p, int32_t q, int32_t s) {
    if (flip) std::swap(q, s);
    soup.add_face({p, q, s});
  };
  for (int i = 0; i < (wrap_i ? ni : ni - 1); ++i) {
    for (int j = 0; j < (wrap_j ? nj : nj - 1); ++j) {
      if (skip_corner && i == ni - 1 && j == nj - 1) continue;
      tri(at(i, j), at(i + 1, j), at(i, j + 1));
      tri(at(i, j + 1), at(i + 1, j), at(i + 1, j + 1));
    }
  }
}

}  // namespace

// NOME3's hyperboloid (compat.md D4, generators-original.md §8): rows at the whole numbers
// z = −⌊c⌋ … ⌊c⌋, each a ring of n vertices at θ_i = i·angle·π/n scaled by √(z² + 1);
// `v{i}_{j}` (NOME3's `v{i}*{j}`) with j counted from the lowest row. Triangles as NOME3,
// wrapping around the axis only for angle = 2; they face away from the axis.
Generated make_Hyperboloid(const ArgReader& a) {
  using A = ir::gen_arg::Hyperboloid;
  const int n = a.count(A::n, 3);
  const double ra = a.positive(A::a);
  const double rb = a.positive(A::b);
  const int rows = 2 * static_cast<int>(std::floor(a.number(A::c))) + 1;
  if (rows < 3) fail(ir::arg_index(A::c), "`c` must be at least 1");
  if (a.number(A::sheet) != 0.0) fail(ir::arg_index(A::sheet), "only one sheet is built: `sheet` must be 0");
  const double angle = a.number(A::angle);
  if (!(angle > 0.0 && angle <= 2.0)) fail(ir::arg_index(A::angle), "`angle` must be in (0, 2]");
  check_size(static_cast<long long>(n) * rows, ir::arg_index(A::c));
  Generated g;
  const int32_t first = g.soup.vertex_count();
  for (int i = 0; i < n; ++i) {
    const double th = i * angle * kPi / n;
    for (int j = 0; j < rows; ++j) {
      const double z = j - (rows - 1) / 2;
      const double k = std::sqrt(z * z + 1.0);
      g.soup.add_vertex({ra * k * std::cos(th), rb * k * std::sin(th), z}, "v" + std::to_string(i) + "_" + std::to_string(j));
    }
  }
  add_triangle_grid(g.soup, first, n, rows, angle == 2.0, false, /*flip=*/false);
  return g;
}

glm::dvec3 dupin_point(double a, double b, double c, double d, double u, double v) {
  const double den = a - c * std::cos(u) * std::cos(v);
  return {(d * (c - a * std::cos(u) * std::cos(v)) + b * b * std::cos(u)) / den, b * std::sin(u) * (a - d * std::cos(v)) / den,
          b * std::sin(v) * (c * std::cos(u) - d) / den};
}

// NOME3's Dupin cyclide (compat.md D4, generators-original.md §7): an n × n grid at
// θ1_i = i·u·π/n, θ2_j = j·v·π/n, vertices `v{i}_{j}` (NOME3's `v{i}*{j}`), triangles as
// NOME3, wrapping in i when u = 2 and in j when v = 2. As in NOME3 the corner cell
// (n−1, n−1) is never filled, so a full cyclide has a one-quad hole (2n² − 2 triangles).
Generated make_Dupin(const ArgReader& a) {
  using A = ir::gen_arg::Dupin;
  const double ca = a.positive(A::a);
  const double cb = a.positive(A::b);
  const double cc = a.number(A::c);
  const double cd = a.number(A::d);
  if (!(ca > std::abs(cc))) {
    fail(ir::arg_index(A::c), "`c` must be smaller than `a` in absolute value (the cyclide is unbounded otherwise)");
  }
  const double eu = a.number(A::u);
  const double ev = a.number(A::v);
  if (!(eu > 0.0 && eu <= 2.0)) fail(ir::arg_index(A::u), "`u` must be in (0, 2]");
  if (!(ev > 0.0 && ev <= 2.0)) fail(ir::arg_index(A::v), "`v` must be in (0, 2]");
  const int n = a.count(A::n, 2);
  check_size(static_cast<long long>(n) * n, ir::arg_index(A::n));
  Generated g;
  const int32_t first = g.soup.vertex_count();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      g.soup.add_vertex(dupin_point(ca, cb, cc, cd, i * eu * kPi / n, j * ev * kPi / n), "v" + std::to_string(i) + "_" + std::to_string(j));
    }
  }
  add_triangle_grid(g.soup, first, n, n, eu == 2.0, ev == 2.0, /*flip=*/false, /*skip_corner=*/true);
  return g;
}

namespace {

// The torus knot's centre at t (generators-original.md §3.1): p turns around the tube, q
// around the z axis.
glm::dvec3 knot_centre(double p, double q, double R, double r, double t) {
  const double rr = R + r * std::cos(p * t);
  return {rr * std::cos(q * t), rr * std::sin(q * t), r * std::sin(p * t)};
}

// NOME3's torus knot with tube_radius 0 (generators-original.md §3.4, TorusKnot.cpp:132-172):
// no tube, but the centre curve itself as an open line strip `knotpoint{i}`, i = 0 …
// sweep_segs − 1 at t_i = 2πi/sweep_segs, for use as a sweep path. Open as NOME3 left it: the
// strip stops one step short of its start.
Generated knot_points(double p, double q, double R, double r, int ss) {
  Generated g;
  Generated::Curve c;
  for (int i = 0; i < ss; ++i) {
    c.vertices.push_back(g.soup.add_vertex(knot_centre(p, q, R, r, 2.0 * kPi * i / ss), "knotpoint" + std::to_string(i)));
  }
  g.curves.push_back(std::move(c));
  return g;
}

}  // namespace

Generated make_Torusknot(const ArgReader& a) {
  using A = ir::gen_arg::Torusknot;
  auto whole_nonzero = [&](A arg) {
    const double v = a.number(arg);
    if (std::abs(v - std::round(v)) > 1e-9 || std::lround(v) == 0) {
      fail(ir::arg_index(arg), "`" + a.name(arg) + "` must be a non-zero whole number, got " + fmt_number(v));
    }
    if (std::abs(v) > 1000) fail(ir::arg_index(arg), "`" + a.name(arg) + "` must be at most 1000 in absolute value");
    return static_cast<double>(std::lround(v));
  };
  // NOME3 (generators-original.md §3): the first argument p turns around the tube, the
  // second q around the z axis.
  const double p = whole_nonzero(A::symm);
  const double q = whole_nonzero(A::turns);
  const double R = a.positive(A::major_radius);
  const double r = a.positive(A::minor_radius);
  const double tube = a.number(A::tube_radius);
  if (!(tube >= 0.0)) fail(ir::arg_index(A::tube_radius), "`tube_radius` must not be negative, got " + fmt_number(tube));
  const int cs = a.count(A::circ_segs, 3);
  const int ss = a.count(A::sweep_segs, 3);
  if (tube == 0.0) return knot_points(p, q, R, r, ss);
  check_size(static_cast<long long>(cs) * ss, ir::arg_index(A::sweep_segs));
  // NOME3's frame: N is the centre's position vector with its part along the tangent T
  // removed, B = T × N. NOME3 took T and N from a step of 1e-4 in t; the exact tangent is
  // its limit (docs/generators.md, differences from the original).
  auto norm = [](glm::dvec3 v) { return v / std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); };
  OriginalMesh m;
  for (int i = 0; i < ss; ++i) {
    const double t = 2.0 * kPi * i / ss;
    const double rr = R + r * std::cos(p * t);
    const glm::dvec3 c0 = knot_centre(p, q, R, r, t);
    const glm::dvec3 tan = norm({-r * p * std::sin(p * t) * std::cos(q * t) - rr * q * std::sin(q * t),
                                 -r * p * std::sin(p * t) * std::sin(q * t) + rr * q * std::cos(q * t),
                                 r * p * std::cos(p * t)});
    const double along = c0.x * tan.x + c0.y * tan.y + c0.z * tan.z;
    const glm::dvec3 nrm = norm(c0 - along * tan);
    const glm::dvec3 bin = norm({tan.y * nrm.z - tan.z * nrm.y, tan.z * nrm.x - tan.x * nrm.z, tan.x * nrm.y - tan.y * nrm.x});
    for (int j = 0; j < cs; ++j) {
      const double ph = 2.0 * kPi * j / cs;
      m.add(c0 + tube * (std::cos(ph) * nrm + std::sin(ph) * bin), "v" + std::to_string(i + 1) + "_" + std::to_string(j));
    }
  }
  auto v = [&](int i, int j) { return (i % ss) * cs + (j % cs); };
  for (int k = 0; k < ss; ++k) {
    for (int j = 0; j < cs; ++j) m.face({v(k + 1, j + 1), v(k + 1, j), v(k, j), v(k, j + 1)});
  }
  return m.finish();
}

}  // namespace nomec::backend::detail
