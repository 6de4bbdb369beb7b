// Curve generators: helix, spiral, beziercurve, bspline. Output is a polyline in
// `Generated::curves` over vertices `v0…` of a soup without faces.
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

}  // namespace

// A curve winding `turns` times around the z axis while rising to `h`, sampled at `segs` + 1
// points; `radius(s)` gives the distance from the axis at progress s in [0, 1].
template <typename RadiusFn>
Generated winding_curve(double turns, double h, int segs, RadiusFn radius) {
  std::vector<glm::dvec3> pts;
  for (int i = 0; i <= segs; ++i) {
    const double s = static_cast<double>(i) / segs;
    const double th = 2.0 * kPi * turns * s;
    const double r = radius(s);
    pts.emplace_back(r * std::cos(th), r * std::sin(th), h * s);
  }
  return polyline(pts, false);
}

Generated make_Helix(const ArgReader& a) {
  using A = ir::gen_arg::Helix;
  const double r = a.positive(A::radius);
  const double h = a.number(A::height);
  const double turns = nonzero(a, A::turns);
  const int segs = a.count(A::segs, 1);
  return winding_curve(turns, h, segs, [r](double) { return r; });
}

Generated make_Spiral(const ArgReader& a) {
  using A = ir::gen_arg::Spiral;
  const double growth = a.positive(A::growth);
  const double h = a.number(A::height);
  const double turns = nonzero(a, A::turns);
  const int segs = a.count(A::segs, 1);
  // The radius grows by `growth` per turn.
  return winding_curve(turns, h, segs, [&](double s) { return growth * std::abs(turns) * s; });
}

Generated make_Beziercurve(const ArgReader& a) {
  using A = ir::gen_arg::Beziercurve;
  const auto& cps = a.raw().points;
  if (cps.size() < 2) {
    fail(ir::arg_index(A::points), "a bezier curve needs at least 2 control points, got " + std::to_string(cps.size()));
  }
  const int segs = a.count_or(A::segs, 1, 16);
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
