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


// Sphere-like surface of revolution: equatorial radius `ra`, polar radius `rb`.
// theta (azimuth) in [0, theta_max], phi (latitude) in [phi_min, phi_max] within
// [-90, 90] degrees.
template <typename A>
Generated spheroid(const ArgReader& a, double ra, double rb) {
  const double theta_max = a.number(A::theta_max);
  const bool wrap = full_turn(theta_max, ir::arg_index(A::theta_max), a.name(A::theta_max));
  const double phi_min = a.number(A::phi_min);
  const double phi_max = a.number(A::phi_max);
  if (phi_min < -90.0 - 1e-9 || phi_min > 90.0 + 1e-9) {
    fail(ir::arg_index(A::phi_min), "`phi_min` is a latitude and must be within [-90, 90] degrees, got " + fmt_number(phi_min));
  }
  if (phi_max > 90.0 + 1e-9 || phi_max < -90.0 - 1e-9) {
    fail(ir::arg_index(A::phi_max), "`phi_max` is a latitude and must be within [-90, 90] degrees, got " + fmt_number(phi_max));
  }
  if (!(phi_max > phi_min)) fail(ir::arg_index(A::phi_max), "`phi_max` must be greater than `phi_min`");
  const bool south = phi_min <= -90.0 + 1e-9;
  const bool north = phi_max >= 90.0 - 1e-9;
  const int ts = a.count(A::theta_segs, wrap ? 3 : 1);
  const int ps = a.count(A::phi_segs, south && north ? 2 : 1);
  const int ni = wrap ? ts : ts + 1;
  check_size(static_cast<long long>(ni) * (ps + 1), ir::arg_index(A::phi_segs));

  Generated g;
  std::vector<int32_t> row_start(ps + 1);
  std::vector<bool> is_pole(ps + 1, false);
  for (int j = 0; j <= ps; ++j) {
    const double phi = j == ps ? radians(phi_max) : radians(phi_min + (phi_max - phi_min) * j / ps);
    row_start[j] = g.soup.vertex_count();
    const bool pole = (j == 0 && south) || (j == ps && north);
    is_pole[j] = pole;
    if (pole) {
      g.soup.add_vertex({0.0, 0.0, j == 0 ? -rb : rb}, "v0_" + std::to_string(j));
      continue;
    }
    for (int i = 0; i < ni; ++i) {
      const double th = radians(theta_max * i / ts);
      g.soup.add_vertex({ra * std::cos(phi) * std::cos(th), ra * std::cos(phi) * std::sin(th),
                         rb * std::sin(phi)},
                        "v" + std::to_string(i) + "_" + std::to_string(j));
    }
  }
  auto at = [&](int i, int j) { return is_pole[j] ? row_start[j] : row_start[j] + i % ni; };
  for (int j = 0; j < ps; ++j) {
    for (int i = 0; i < ts; ++i) {
      if (is_pole[j]) {
        g.soup.add_face({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      } else if (is_pole[j + 1]) {
        g.soup.add_face({at(i, j), at(i + 1, j), at(i, j + 1)});
      } else {
        g.soup.add_face({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
    }
  }
  return g;
}

}  // namespace

Generated make_Torus(const ArgReader& a) {
  using A = ir::gen_arg::Torus;
  const double R = a.positive(A::major_radius);
  const double r = a.positive(A::minor_radius);
  const double theta_max = a.number(A::theta_max);
  const double phi_min = a.number(A::phi_min);
  const double phi_max = a.number(A::phi_max);
  const bool wrap_i = full_turn(theta_max, ir::arg_index(A::theta_max), a.name(A::theta_max));
  const bool wrap_j = full_turn(phi_max - phi_min, ir::arg_index(A::phi_max), a.name(A::phi_max));
  const int ts = a.count(A::theta_segs, wrap_i ? 3 : 1);
  const int ps = a.count(A::phi_segs, wrap_j ? 3 : 1);
  check_size(static_cast<long long>(ts + 1) * (ps + 1), ir::arg_index(A::theta_segs));
  Generated g;
  add_grid(g.soup, ts, ps, wrap_i, wrap_j, [&](int i, int j) {
    const double th = radians(theta_max * i / ts);
    const double ph = radians(phi_min + (phi_max - phi_min) * j / ps);
    const double rr = R + r * std::cos(ph);
    return glm::dvec3(rr * std::cos(th), rr * std::sin(th), r * std::sin(ph));
  });
  return g;
}

Generated make_Sphere(const ArgReader& a) {
  const double r = a.positive(ir::gen_arg::Sphere::radius);
  return spheroid<ir::gen_arg::Sphere>(a, r, r);
}

Generated make_Ellipsoid(const ArgReader& a) {
  const double ra = a.positive(ir::gen_arg::Ellipsoid::a);
  const double rb = a.positive(ir::gen_arg::Ellipsoid::b);
  return spheroid<ir::gen_arg::Ellipsoid>(a, ra, rb);
}

Generated make_Cylinder(const ArgReader& a) {
  using A = ir::gen_arg::Cylinder;
  const double r = a.positive(A::radius);
  const double h = a.positive(A::height);
  const double theta_max = a.number(A::theta_max);
  const bool wrap = full_turn(theta_max, ir::arg_index(A::theta_max), a.name(A::theta_max));
  const int ts = a.count(A::theta_segs, wrap ? 3 : 1);
  const int hs = a.count(A::height_segs, 1);
  check_size(static_cast<long long>(ts + 1) * (hs + 1), ir::arg_index(A::theta_segs));
  Generated g;
  add_grid(g.soup, ts, hs, wrap, false, [&](int i, int j) {
    const double th = radians(theta_max * i / ts);
    return glm::dvec3(r * std::cos(th), r * std::sin(th), h * j / hs);
  });
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

Generated make_Hyperboloid(const ArgReader& a) {
  using A = ir::gen_arg::Hyperboloid;
  const double ra = a.positive(A::a);
  const double rb = a.positive(A::b);
  const double rc = a.positive(A::c);
  const double h = a.positive(A::height);
  const int ts = a.count(A::theta_segs, 3);
  const int hs = a.count(A::height_segs, 1);
  check_size(static_cast<long long>(ts) * (hs + 1), ir::arg_index(A::theta_segs));
  Generated g;
  add_grid(g.soup, ts, hs, true, false, [&](int i, int j) {
    const double th = 2.0 * kPi * i / ts;
    const double z = -h / 2.0 + h * j / hs;
    const double k = std::sqrt(1.0 + z * z / (rc * rc));
    return glm::dvec3(ra * k * std::cos(th), rb * k * std::sin(th), z);
  });
  return g;
}

Generated make_Dupin(const ArgReader& a) {
  using A = ir::gen_arg::Dupin;
  const double ca = a.positive(A::a);
  const double cb = a.positive(A::b);
  const double cc = a.number(A::c);
  const double cd = a.number(A::d);
  if (!(ca > std::abs(cc))) {
    fail(ir::arg_index(A::c), "`c` must be smaller than `a` in absolute value (the cyclide is unbounded otherwise)");
  }
  const int us = a.count(A::u_segs, 3);
  const int vs = a.count(A::v_segs, 3);
  check_size(static_cast<long long>(us) * vs, ir::arg_index(A::u_segs));
  Generated g;
  add_grid(g.soup, us, vs, true, true, [&](int i, int j) {
    const double u = 2.0 * kPi * i / us;
    const double v = 2.0 * kPi * j / vs;
    const double den = ca - cc * std::cos(u) * std::cos(v);
    return glm::dvec3((cd * (cc - ca * std::cos(u) * std::cos(v)) + cb * cb * std::cos(u)) / den,
                      cb * std::sin(u) * (ca - cd * std::cos(v)) / den,
                      cb * std::sin(v) * (cc * std::cos(u) - cd) / den);
  });
  return g;
}

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
  const double p = whole_nonzero(A::symm);
  const double q = whole_nonzero(A::turns);
  const double R = a.positive(A::major_radius);
  const double r = a.positive(A::minor_radius);
  const double tube = a.positive(A::tube_radius);
  const int cs = a.count(A::circ_segs, 3);
  const int ss = a.count(A::sweep_segs, 3);
  check_size(static_cast<long long>(cs) * ss, ir::arg_index(A::sweep_segs));
  // The knot lies on a torus (R, r); its exact normal frame is the torus normal N (which
  // is periodic, so the tube closes without a twist seam) and B = T x N.
  std::vector<glm::dvec3> centre(ss), nrm(ss), bin(ss);
  for (int i = 0; i < ss; ++i) {
    const double t = 2.0 * kPi * i / ss;
    const double rr = R + r * std::cos(q * t);
    centre[i] = {rr * std::cos(p * t), rr * std::sin(p * t), r * std::sin(q * t)};
    const glm::dvec3 d(-r * q * std::sin(q * t) * std::cos(p * t) - rr * p * std::sin(p * t),
                       -r * q * std::sin(q * t) * std::sin(p * t) + rr * p * std::cos(p * t),
                       r * q * std::cos(q * t));
    const glm::dvec3 tan = d / std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    nrm[i] = {std::cos(q * t) * std::cos(p * t), std::cos(q * t) * std::sin(p * t), std::sin(q * t)};
    bin[i] = {tan.y * nrm[i].z - tan.z * nrm[i].y, tan.z * nrm[i].x - tan.x * nrm[i].z,
              tan.x * nrm[i].y - tan.y * nrm[i].x};
  }
  Generated g;
  add_grid(
      g.soup, ss, cs, true, true,
      [&](int i, int j) {
        const double ph = 2.0 * kPi * j / cs;
        return centre[i] + tube * (std::cos(ph) * nrm[i] + std::sin(ph) * bin[i]);
      },
      /*flip=*/true);
  return g;
}

}  // namespace nomec::backend::detail
