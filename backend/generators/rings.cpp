// Ring generators: funnel and tunnel (seed report §6.3), circle, mobiusstrip.
#include <cmath>
#include <string>

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

// The dialect's name first: NOME3 funnels say `radius`/`height`, 2016 ones `ro`/`h`.
struct FunnelArgs {
  int n;
  double ro;
  double ratio;
  double h;
};

double radius_factor(const Arg& ratio) {
  if (!(1.0 + ratio.value > 0)) {
    const std::string n(ratio.name);
    fail(n, "`" + n + "` must be greater than -1 (the ring radius ro*(1+" + n +
                ") must be positive)");
  }
  return 1.0 + ratio.value;
}

FunnelArgs funnel_args(const ArgReader& a) {
  FunnelArgs f{};
  f.n = a.count({"n"}, 3);
  f.ro = a.is_nome3() ? a.positive({"radius", "ro"}) : a.positive({"ro", "radius"});
  f.ratio = radius_factor(a.number({"ratio"})) - 1.0;
  f.h = (a.is_nome3() ? a.number({"height", "h"}) : a.number({"h", "height"})).value;
  return f;
}

}  // namespace

Generated make_funnel(const ArgReader& a) {
  const FunnelArgs f = funnel_args(a);
  Generated g;
  const int32_t bc = add_ring(g.soup, "bc", f.ro, 0.0, f.n);
  const int32_t hc = add_ring(g.soup, "hc", f.ro * (1.0 + f.ratio), f.h, f.n);
  add_band(g.soup, bc, hc, f.n);
  return g;
}

Generated make_tunnel(const ArgReader& a) {
  const FunnelArgs f = funnel_args(a);
  const double low_factor = a.has("dri_low") ? radius_factor(a.number({"dri_low"})) : 1.0 + f.ratio;
  const double low_h = a.number_or({"hgt_low"}, f.h).value;
  Generated g;
  const int32_t bc = add_ring(g.soup, "bc", f.ro, 0.0, f.n);
  const int32_t hc = add_ring(g.soup, "hc", f.ro * (1.0 + f.ratio), f.h, f.n);
  const int32_t lc = add_ring(g.soup, "lc", f.ro * low_factor, -low_h, f.n);
  add_band(g.soup, bc, hc, f.n);
  add_band(g.soup, lc, bc, f.n);
  return g;
}

Generated make_circle(const ArgReader& a) {
  const double r = a.positive({"radius"});
  const int segs = a.count({"segs"}, 3);
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

Generated make_mobiusstrip(const ArgReader& a) {
  const double radius = a.positive({"radius"});
  const Arg twists_arg = a.number({"num_twists", "numTwists"});
  if (std::abs(twists_arg.value - std::round(twists_arg.value)) > 1e-9) {
    fail(twists_arg.name, "`num_twists` must be a whole number of half-twists");
  }
  const long twists = std::lround(twists_arg.value);
  const Arg cuts = a.number({"num_cuts", "numCuts"});
  if (cuts.value != 0.0) {
    fail(cuts.name, "cuts are not supported yet: `num_cuts` must be 0");
  }
  const int n = a.count({"n", "N"}, 3);
  const double w = radius / 4.0;  // half of the band's width
  Generated g;
  auto pos = [&](int i, double v) {
    const double u = 2.0 * kPi * i / n;
    const double tw = static_cast<double>(twists) * u / 2.0;
    const double rr = radius + v * std::cos(tw);
    return glm::dvec3(rr * std::cos(u), rr * std::sin(u), v * std::sin(tw));
  };
  for (int i = 0; i < n; ++i) {
    g.soup.add_vertex(pos(i, w), "v" + std::to_string(i) + "_0");
    g.soup.add_vertex(pos(i, -w), "v" + std::to_string(i) + "_1");
  }
  const bool odd = (twists % 2) != 0;
  for (int i = 0; i < n; ++i) {
    const int32_t a0 = 2 * i;
    const int32_t b0 = 2 * i + 1;
    int32_t a1 = 2 * (i + 1);
    int32_t b1 = 2 * (i + 1) + 1;
    if (i + 1 == n) {
      // Welded seam: after an odd number of half-twists the sides swap.
      a1 = odd ? 1 : 0;
      b1 = odd ? 0 : 1;
    }
    g.soup.add_face({a0, a1, b1, b0});
  }
  return g;
}

}  // namespace nomec::backend::detail
