// Curve generators: helix, beziercurve, bspline, whose output is a polyline in
// `Generated::curves` over vertices `v0…` of a soup without faces; and NOME3's spiral, a
// ribbon surface that shares their winding parameters.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "backend/generators/impl.h"

namespace nomec::backend::detail {
namespace {

Generated polyline(const std::vector<glm::dvec3>& pts, bool closed) {
  Generated g;
  Generated::Curve c;
  c.is_closed = closed;
  for (size_t i = 0; i < pts.size(); ++i) {
    c.vertices.push_back(g.soup.add_vertex(pts[i], "v" + std::to_string(i)));
  }
  g.curves.push_back(std::move(c));
  return g;
}

template <typename A>
double nonzero(const ArgReader& a, A arg) {
  const double v = a.number(arg);
  if (v == 0.0) fail(ir::arg_index(arg), "`" + a.name(arg) + "` must not be 0");
  return v;
}

// de Boor evaluation of a B-spline of order k (degree k-1) with knot vector `t` at `x`.
glm::dvec3 de_boor(const std::vector<glm::dvec3>& p, const std::vector<double>& t, int k, double x) {
  const int n = static_cast<int>(p.size());
  const int deg = k - 1;
  int l = deg;
  while (l < n - 1 && x >= t[l + 1]) ++l;
  std::vector<glm::dvec3> d(k);
  for (int j = 0; j <= deg; ++j) d[j] = p[j + l - deg];
  for (int r = 1; r <= deg; ++r) {
    for (int j = deg; j >= r; --j) {
      const double den = t[j + 1 + l - r] - t[j + l - deg];
      const double alpha = den == 0.0 ? 0.0 : (x - t[j + l - deg]) / den;
      d[j] = (1.0 - alpha) * d[j - 1] + alpha * d[j];
    }
  }
  return d[deg];
}

// Cox–de Boor: the order-k basis function i on the integer knots 0, 1, 2, … at t, with
// half-open intervals [i, i+1) at order 1.
double uniform_basis(int i, int k, double t) {
  if (k == 1) return (t >= i && t < i + 1) ? 1.0 : 0.0;
  return (t - i) / (k - 1) * uniform_basis(i, k - 1, t) + (i + k - t) / (k - 1) * uniform_basis(i + 1, k - 1, t);
}

// NOME3's bspline (generators-original.md §10, BSpline.cpp): order K (default 3) on the
// uniform unclamped knots 0 … K+n−1, sampled at t_s = (s/S)·(n−K+1) + (K−1) for s = 0…S
// with S = segs (default 8 for the whole curve). The curve does not reach the end points:
// for K = 3 it runs from (P0+P1)/2 to (P_{n−2}+P_{n−1})/2.
Generated nome3_bspline(const ArgReader& a) {
  using A = ir::gen_arg::Bspline;
  const auto& cps = a.raw().points;
  const int k = a.count_or(A::order, 2, 3);
  const int n = static_cast<int>(cps.size());
  if (n < k) {
    fail(ir::arg_index(A::points), "a b-spline of order " + std::to_string(k) + " needs at least " + std::to_string(k) +
                                       " control points, got " + std::to_string(n));
  }
  if (k > 32) fail(ir::arg_index(A::order), "`order` must be at most 32");
  const int segs = a.count_or(A::segs, 1, 8);
  check_size(segs, ir::arg_index(A::segs));
  std::vector<glm::dvec3> pts;
  for (int s = 0; s <= segs; ++s) {
    const double t = static_cast<double>(s) / segs * (n - k + 1) + (k - 1);
    glm::dvec3 p(0.0);
    // Only the k basis functions whose support [i, i+k) contains t are non-zero.
    const int last = std::min(n - 1, static_cast<int>(std::floor(t)));
    for (int i = std::max(0, last - k + 1); i <= last; ++i) p += uniform_basis(i, k, t) * cps[i];
    pts.push_back(p);
  }
  return polyline(pts, false);
}

}  // namespace

// NOME3's helix (compat.md D4, generators-original.md §9): `segs` vertices `v0…v{segs−1}` at
// θ_i = (i/segs)·theta_max degrees, (r cos θ, r sin θ, spacing·θ) with θ in radians; an open
// line strip whose last vertex stops one step short of theta_max.
Generated make_Helix(const ArgReader& a) {
  using A = ir::gen_arg::Helix;
  const double r = a.positive(A::radius);
  const double spacing = a.number(A::spacing);
  const double theta_max = nonzero(a, A::theta_max);
  const int segs = a.count(A::segs, 2);
  std::vector<glm::dvec3> pts;
  for (int i = 0; i < segs; ++i) {
    const double th = radians(theta_max * i / segs);
    pts.emplace_back(r * std::cos(th), r * std::sin(th), spacing * th);
  }
  return polyline(pts, false);
}

// NOME3's spiral (compat.md D4, generators-original.md §9): a flat ribbon. Step i (0…segs) is
// at θ_i = 2·angle·i/segs radians (angle truncated to a whole number) and radius i·rate:
// `u{i}` at z = 0 and `l{i}` at z = −0.13, joined by the triangles (u{i+1}, u{i}, l{i}) and
// (l{i}, l{i+1}, u{i+1}).
Generated make_Spiral(const ArgReader& a) {
  using A = ir::gen_arg::Spiral;
  const double rate = a.positive(A::rate);
  const double angle = std::trunc(a.number(A::angle));
  if (angle == 0.0) fail(ir::arg_index(A::angle), "`angle` must be at least 1 in absolute value (it is truncated)");
  const int segs = a.count(A::segs, 1);
  check_size(2LL * (segs + 1), ir::arg_index(A::segs));
  Generated g;
  std::vector<int32_t> u(segs + 1), l(segs + 1);
  for (int i = 0; i <= segs; ++i) {
    const double th = 2.0 * angle * i / segs;
    const double r = i * rate;
    u[i] = g.soup.add_vertex({r * std::cos(th), r * std::sin(th), 0.0}, "u" + std::to_string(i));
    l[i] = g.soup.add_vertex({r * std::cos(th), r * std::sin(th), -0.13}, "l" + std::to_string(i));
  }
  for (int i = 0; i < segs; ++i) {
    g.soup.add_face({u[i + 1], u[i], l[i]});
    g.soup.add_face({l[i], l[i + 1], u[i + 1]});
  }
  return g;
}

Generated make_Beziercurve(const ArgReader& a) {
  using A = ir::gen_arg::Beziercurve;
  const auto& cps = a.raw().points;
  if (cps.size() < 2) {
    fail(ir::arg_index(A::points), "a bezier curve needs at least 2 control points, got " + std::to_string(cps.size()));
  }
  // NOME3's default is 8 segments (BezierSpline.cpp:67); the other dialects keep 16.
  const int segs = a.count_or(A::segs, 1, a.dialect() == Dialect::Nome3 ? 8 : 16);
  std::vector<glm::dvec3> pts;
  for (int i = 0; i <= segs; ++i) {
    const double t = static_cast<double>(i) / segs;
    std::vector<glm::dvec3> d = cps;
    for (size_t r = 1; r < d.size(); ++r) {
      for (size_t j = 0; j + r < d.size(); ++j) d[j] = (1.0 - t) * d[j] + t * d[j + 1];
    }
    pts.push_back(d[0]);
  }
  return polyline(pts, false);
}

Generated make_Bspline(const ArgReader& a) {
  using A = ir::gen_arg::Bspline;
  const auto& cps = a.raw().points;
  if (a.dialect() == Dialect::Nome3 && !a.flag(A::closed)) return nome3_bspline(a);
  const int k = a.count_or(A::order, 2, 4);
  const int n = static_cast<int>(cps.size());
  const bool closed = a.flag(A::closed);
  const ir::ArgIndex points = ir::arg_index(A::points);
  if (n < k) {
    fail(points, "a b-spline of order " + std::to_string(k) + " needs at least " + std::to_string(k) +
                     " control points, got " + std::to_string(n));
  }
  if (closed && n < 3) fail(points, "a closed b-spline needs at least 3 control points");
  const int spans = closed ? n : n - k + 1;
  const int segs = a.count_or(A::segs, closed ? 3 : 1, 8 * spans);
  check_size(segs, ir::arg_index(A::segs));
  std::vector<glm::dvec3> pts;
  if (!closed) {
    // Clamped uniform knots: the curve starts and ends at the end control points.
    std::vector<double> t(n + k);
    for (int i = 0; i < n + k; ++i) {
      t[i] = i < k ? 0.0 : i >= n ? 1.0 : static_cast<double>(i - k + 1) / (n - k + 1);
    }
    for (int i = 0; i <= segs; ++i) pts.push_back(de_boor(cps, t, k, static_cast<double>(i) / segs));
  } else {
    // Periodic: wrap k-1 control points, uniform knots, domain [k-1, n+k-1].
    std::vector<glm::dvec3> p = cps;
    for (int i = 0; i < k - 1; ++i) p.push_back(cps[i]);
    std::vector<double> t(p.size() + k);
    for (size_t i = 0; i < t.size(); ++i) t[i] = static_cast<double>(i);
    for (int i = 0; i < segs; ++i) {
      pts.push_back(de_boor(p, t, k, (k - 1) + static_cast<double>(n) * i / segs));
    }
  }
  return polyline(pts, closed);
}

}  // namespace nomec::backend::detail
