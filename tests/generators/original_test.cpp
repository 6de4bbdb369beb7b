// First-principles tests of the generators ported from NOME3 (generators-original.md §5–§11):
// every expected position, face and name is computed here from the formulas of that page
// (closed forms, not the generator's own loops), for each dialect that accepts the
// generator.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "tests/generators/helpers.h"

namespace nomec::backend::testing {
namespace {

using Face = std::vector<std::string>;

// The soup's faces as lists of vertex names, in order.
std::vector<Face> face_names(const kernel::PolygonSoup& s) {
  std::vector<Face> out;
  size_t off = 0;
  for (int32_t n : s.face_sizes) {
    Face f;
    for (int32_t k = 0; k < n; ++k) f.push_back(s.names[s.face_vertices[off + k]]);
    out.push_back(f);
    off += n;
  }
  return out;
}

glm::dvec3 lerp(const glm::dvec3& a, const glm::dvec3& b, double t) { return (1 - t) * a + t * b; }

// ---- §6 mobiusstrip ----

Args mobius(double radius, double twists, double cuts, double n, const std::string& dialect) {
  return numbers({{"radius", radius}, {"num_twists", twists}, {"num_cuts", cuts}, {"n", n}}, dialect);
}

// Position of sample (a, b): u = a·π/n, v = −radius + b·2·radius/(2·cuts + 1), centre radius 1.
glm::dvec3 mobius_point(double radius, int tw, int cuts, double n, int a, int b) {
  const double u = a * M_PI / n;
  const double v = -radius + b * 2 * radius / (2 * cuts + 1);
  return {(1 + v / 2 * std::cos(tw * u / 2)) * std::cos(u), (1 + v / 2 * std::cos(tw * u / 2)) * std::sin(u),
          v / 2 * std::sin(tw * u / 2)};
}

TEST(OriginalMobiusStrip, OneTwistEightStepsAsNome3) {
  for (const char* dialect : {"nome3", "nome"}) {
    SCOPED_TRACE(dialect);
    Generated g = run("mobiusstrip", mobius(1, 1, 0, 8, dialect));
    // 2n + 1 = 17 u samples × 2 v samples × 2 layers; 4 quads per step.
    EXPECT_EQ(g.soup.vertex_count(), 68);
    EXPECT_EQ(g.soup.face_count(), 64);
    for (int a = 0; a <= 16; ++a) {
      for (int b = 0; b < 2; ++b) {
        const std::string ab = std::to_string(a) + "_" + std::to_string(b);
        const glm::dvec3 p = mobius_point(1, 1, 0, 8, a, b);
        expect_near(named(g.soup, "v_" + ab), p, 1e-12);
        expect_near(named(g.soup, "vt_" + ab), p + glm::dvec3(0, 0, 0.1), 1e-12);
      }
    }
    // The centre circle has radius 1 and `radius` is the full width: v_0_0 at x = 0.5.
    expect_near(named(g.soup, "v_0_0"), {0.5, 0, 0});
    expect_near(named(g.soup, "v_16_0"), {1.5, 0, 0}, 1e-12);  // the unwelded seam: on v_0_1
    std::vector<Face> want;
    for (int a = 0; a < 16; ++a) {
      auto nm = [&](const char* p, int i, int b) { return std::string(p) + std::to_string(i) + "_" + std::to_string(b); };
      want.push_back({nm("v_", a, 0), nm("v_", a + 1, 0), nm("v_", a + 1, 1), nm("v_", a, 1)});
      want.push_back({nm("vt_", a, 0), nm("vt_", a + 1, 0), nm("vt_", a + 1, 1), nm("vt_", a, 1)});
      for (int b : {0, 1}) want.push_back({nm("v_", a, b), nm("v_", a + 1, b), nm("vt_", a + 1, b), nm("vt_", a, b)});
    }
    EXPECT_EQ(face_names(g.soup), want);
    // The strip faces −z at u = 0 (Newell normal of the first face).
    const glm::dvec3 p0 = named(g.soup, "v_0_0"), p1 = named(g.soup, "v_1_0"), p2 = named(g.soup, "v_1_1");
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0;
    EXPECT_LT(e1.x * e2.y - e1.y * e2.x, 0);
    // NOME3's slab is accepted by the kernel. Its faces are not consistently oriented: per
    // step, the strip and the wall b = 0 both run v_a_0 → v_{a+1}_0, and the `vt` copy and
    // the wall b = 1 both run vt_{a+1}_1 → vt_a_1: 2 × 16 Möbius edges.
    kernel::TopologyReport r = topo(g.soup);
    EXPECT_EQ(r.face_count, 64);
    ASSERT_EQ(r.components.size(), 1u);
    EXPECT_EQ(r.components[0].mobius_edge_count, 32);
  }
}

TEST(OriginalMobiusStrip, CutsTwistsAndStepsRoundUpOrStayFractional) {
  // twists ⌈1.2⌉ = 2, cuts ⌈0.5⌉ = 1: v has 2·1 + 2 = 4 samples 2·0.6/3 apart; n = 2.5 gives
  // u samples k·π/2.5 while < 2π + step/3: k = 0…5.
  Generated g = run("mobiusstrip", mobius(0.6, 1.2, 0.5, 2.5, "nome3"));
  EXPECT_EQ(g.soup.vertex_count(), 6 * 4 * 2);
  EXPECT_EQ(g.soup.face_count(), 4 * 5 * 2);
  for (int a = 0; a <= 5; ++a) {
    for (int b = 0; b < 4; ++b) {
      const std::string ab = std::to_string(a) + "_" + std::to_string(b);
      expect_near(named(g.soup, "v_" + ab), mobius_point(0.6, 2, 1, 2.5, a, b), 1e-12);
      expect_near(named(g.soup, "vt_" + ab), mobius_point(0.6, 2, 1, 2.5, a, b) + glm::dvec3(0, 0, 0.06), 1e-12);
    }
  }
  // The second band is v_*_2 … v_*_3; v_*_1 and v_*_2 are not joined (a gap).
  const std::vector<Face> f = face_names(g.soup);
  EXPECT_EQ(f[4], (Face{"v_0_2", "v_1_2", "v_1_3", "v_0_3"}));
  for (const Face& face : f) {
    const bool has1 = std::any_of(face.begin(), face.end(), [](const std::string& s) { return s.ends_with("_1"); });
    const bool has2 = std::any_of(face.begin(), face.end(), [](const std::string& s) { return s.ends_with("_2"); });
    EXPECT_FALSE(has1 && has2);
  }
  EXPECT_EQ(run_error("mobiusstrip", mobius(1, 1, -2, 8, "nome3")).argument, "num_cuts");
  EXPECT_EQ(run_error("mobiusstrip", mobius(1, 1, 0, 0, "nome3")).argument, "n");
}

// ---- §10 beziercurve and bspline ----

std::vector<glm::dvec3> curve_points(const Generated& g) {
  std::vector<glm::dvec3> out;
  if (g.curves.size() != 1) {
    ADD_FAILURE() << "expected one curve";
    return out;
  }
  for (int32_t v : g.curves[0].vertices) out.push_back(g.soup.positions[v]);
  return out;
}

Args with_points(std::vector<glm::dvec3> pts, std::vector<std::pair<std::string, double>> nums, const std::string& dialect) {
  Args a = numbers(std::move(nums), dialect);
  for (size_t i = 0; i < pts.size(); ++i) a.point_names.push_back("p" + std::to_string(i));
  a.points = std::move(pts);
  return a;
}

const std::vector<glm::dvec3> kCtrl = {{0, 0, 0}, {1, 2, 0}, {2, 0, 1}, {3, 3, 1}, {5, 1, -1}};

TEST(OriginalBezierCurve, DefaultSegsIsEightInNome3AndSixteenElsewhere) {
  const std::vector<glm::dvec3> p(kCtrl.begin(), kCtrl.begin() + 4);
  // Bernstein form of the cubic at t = i/segs.
  auto bernstein = [&](double t) {
    return std::pow(1 - t, 3) * p[0] + 3 * t * (1 - t) * (1 - t) * p[1] + 3 * t * t * (1 - t) * p[2] + t * t * t * p[3];
  };
  for (auto [dialect, segs] : {std::pair{"nome3", 8}, std::pair{"nome", 16}, std::pair{"slide", 16}}) {
    SCOPED_TRACE(dialect);
    Generated g = run("beziercurve", with_points(p, {}, dialect));
    const std::vector<glm::dvec3> got = curve_points(g);
    ASSERT_EQ(got.size(), static_cast<size_t>(segs + 1));
    for (int i = 0; i <= segs; ++i) {
      expect_near(got[i], bernstein(static_cast<double>(i) / segs), 1e-12);
      expect_near(named(g.soup, "v" + std::to_string(i)), got[i]);
    }
  }
}

// Uniform quadratic and cubic B-spline segments in closed form: t in [j, j+1), s = t − j.
glm::dvec3 uniform_quadratic(const std::vector<glm::dvec3>& p, double t) {
  int j = static_cast<int>(std::floor(t));
  if (j > static_cast<int>(p.size()) - 1) j = static_cast<int>(p.size()) - 1;
  const double s = t - j;
  return (1 - s) * (1 - s) / 2 * p[j - 2] + (-2 * s * s + 2 * s + 1) / 2 * p[j - 1] + s * s / 2 * p[j];
}
glm::dvec3 uniform_cubic(const std::vector<glm::dvec3>& p, double t) {
  int j = static_cast<int>(std::floor(t));
  if (j > static_cast<int>(p.size()) - 1) j = static_cast<int>(p.size()) - 1;
  const double s = t - j;
  return std::pow(1 - s, 3) / 6 * p[j - 3] + (3 * s * s * s - 6 * s * s + 4) / 6 * p[j - 2] +
         (-3 * s * s * s + 3 * s * s + 3 * s + 1) / 6 * p[j - 1] + s * s * s / 6 * p[j];
}

TEST(OriginalBSpline, Nome3DefaultsToAQuadraticOnUnclampedKnotsWithEightSegments) {
  Generated g = run("bspline", with_points(kCtrl, {}, "nome3"));
  const std::vector<glm::dvec3> got = curve_points(g);
  ASSERT_EQ(got.size(), 9u);
  // n = 5, K = 3: t_s = (s/8)·3 + 2.
  for (int s = 0; s <= 8; ++s) {
    expect_near(got[s], uniform_quadratic(kCtrl, s / 8.0 * 3 + 2), 1e-12);
    expect_near(named(g.soup, "v" + std::to_string(s)), got[s]);
  }
  // It runs between the midpoints of the first and last legs, not through the end points.
  expect_near(got.front(), lerp(kCtrl[0], kCtrl[1], 0.5), 1e-12);
  expect_near(got.back(), lerp(kCtrl[3], kCtrl[4], 0.5), 1e-12);
}

TEST(OriginalBSpline, Nome3OrderAndSegs) {
  Generated g = run("bspline", with_points(kCtrl, {{"order", 4}, {"segs", 4}}, "nome3"));
  const std::vector<glm::dvec3> got = curve_points(g);
  ASSERT_EQ(got.size(), 5u);
  for (int s = 0; s <= 4; ++s) expect_near(got[s], uniform_cubic(kCtrl, s / 4.0 * 2 + 3), 1e-12);
  // The other dialects keep nomec's clamped spline: it ends on the end points.
  Generated clamped = run("bspline", with_points(kCtrl, {{"order", 4}}, "slide"));
  const std::vector<glm::dvec3> c = curve_points(clamped);
  ASSERT_FALSE(c.empty());
  expect_near(c.front(), kCtrl.front());
  expect_near(c.back(), kCtrl.back());
}

// ---- §11 gencartesiansurf and genparametricsurf ----

TEST(OriginalGenCartesianSurf, SamplesNamesAndFacesAsNome3) {
  Args a = numbers({{"x_min", 0}, {"x_max", 1}, {"y_min", -1}, {"y_max", 1}, {"x_segs", 2}, {"y_segs", 2.5}}, "nome3");
  a.functions["func"] = fn([](std::span<const double> v) { return v[0] * v[1] + 1; });
  Generated g = run("gencartesiansurf", a);
  // x: 0, 0.5, 1; y: −1 in steps of 2/2.5 = 0.8 while ≤ 1 + 0.16: −1, −0.2, 0.6.
  const double xs[] = {0, 0.5, 1};
  const double ys[] = {-1, -0.2, 0.6};
  ASSERT_EQ(g.soup.vertex_count(), 9);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      expect_near(named(g.soup, "v_" + std::to_string(i) + "_" + std::to_string(j)), {xs[i], ys[j], xs[i] * ys[j] + 1}, 1e-12);
    }
  }
  // A fraction of 0.8 or more takes one sample past the end: 2.9 over [0, 1] gives
  // k/2.9 for k ≤ 2.9 + 0.2, so k = 0…3 and the last sample lies at 3/2.9.
  Args past = a;
  past.numbers = {{"x_min", 0}, {"x_max", 1}, {"y_min", 0}, {"y_max", 1}, {"x_segs", 2.9}, {"y_segs", 1}};
  Generated p = run("gencartesiansurf", past);
  EXPECT_EQ(p.soup.vertex_count(), 4 * 2);
  expect_near(named(p.soup, "v_3_1"), {3 / 2.9, 1, 3 / 2.9 + 1}, 1e-12);
  EXPECT_EQ(face_names(g.soup), (std::vector<Face>{{"v_0_0", "v_1_0", "v_1_1", "v_0_1"},
                                                   {"v_0_1", "v_1_1", "v_1_2", "v_0_2"},
                                                   {"v_1_0", "v_2_0", "v_2_1", "v_1_1"},
                                                   {"v_1_1", "v_2_1", "v_2_2", "v_1_2"}}));
}

TEST(OriginalGenParametricSurf, SamplesNamesAndFacesAsNome3WithoutWelding) {
  Args a = numbers({{"u_min", 0}, {"u_max", 2 * M_PI}, {"v_min", 0}, {"v_max", 1}, {"u_segs", 4}, {"v_segs", 1}}, "nome3");
  a.functions["funcX"] = fn([](std::span<const double> v) { return std::cos(v[0]); });
  a.functions["funcY"] = fn([](std::span<const double> v) { return std::sin(v[0]); });
  a.functions["funcZ"] = fn([](std::span<const double> v) { return v[1]; });
  Generated g = run("genparametricsurf", a);
  // An open tube of 5 × 2 vertices: the column at u = 2π lies on the one at u = 0, unwelded.
  ASSERT_EQ(g.soup.vertex_count(), 10);
  ASSERT_EQ(g.soup.face_count(), 4);
  for (int i = 0; i <= 4; ++i) {
    for (int j = 0; j <= 1; ++j) {
      expect_near(named(g.soup, "v_" + std::to_string(i) + "_" + std::to_string(j)),
                  {std::cos(i * M_PI / 2), std::sin(i * M_PI / 2), j}, 1e-12);
    }
  }
  EXPECT_EQ(face_names(g.soup)[3], (Face{"v_3_0", "v_4_0", "v_4_1", "v_3_1"}));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.border_loop_count, 1);  // the seam is a border
  EXPECT_EQ(run_error("genparametricsurf", [&] { Args b = a; b.numbers[4].second = 0.5; return b; }()).argument, "u_segs");
  // A step below the precision of the values ends after ⌊segs⌋ + 1 samples, as NOME3's would.
  Args far = numbers({{"u_min", 1e17}, {"u_max", 1e17 + 64}, {"v_min", 0}, {"v_max", 1}, {"u_segs", 1000}, {"v_segs", 1}}, "nome3");
  far.functions = a.functions;
  EXPECT_EQ(run("genparametricsurf", far).soup.vertex_count(), 1001 * 2);
}

// ---- §5 cylinder, §7 dupin, §8 hyperboloid, §9 spiral: face lists ----

std::vector<Face> sorted_faces(const kernel::PolygonSoup& s) {
  std::vector<Face> f = face_names(s);
  std::sort(f.begin(), f.end());
  return f;
}

std::string ij(int i, int j) { return "v" + std::to_string(i) + "_" + std::to_string(j); }

TEST(OriginalCylinder, WedgeWithBothCapsAsNome3) {
  for (const char* dialect : {"nome3", "nome"}) {
    SCOPED_TRACE(dialect);
    Args a = numbers({{"radius", 1}, {"height", 2}, {"theta_max", 90}, {"theta_segs", 2}}, dialect);
    a.flags = {"topcap", "botcap"};
    Generated g = run("cylinder", a);
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i <= 2; ++i) {
        expect_near(named(g.soup, ij(j, i)), {std::cos(i * M_PI / 4), std::sin(i * M_PI / 4), 2.0 * j});
      }
    }
    expect_near(named(g.soup, "top_center"), {0, 0, 0});
    expect_near(named(g.soup, "bottom_center"), {0, 0, 2});
    std::vector<Face> want = {
        {"v1_1", "v1_0", "v0_0", "v0_1"},
        {"v1_2", "v1_1", "v0_1", "v0_2"},
        {"top_center", "bottom_center", "v1_2", "v0_2"},
        {"v0_0", "v1_0", "bottom_center", "top_center"},
        {"top_center", "v0_2", "v0_1", "v0_0"},     // topcap: z = 0, facing −z
        {"bottom_center", "v1_0", "v1_1", "v1_2"},  // botcap: z = height, facing +z
    };
    std::sort(want.begin(), want.end());
    EXPECT_EQ(sorted_faces(g.soup), want);
  }
}

TEST(OriginalDupin, FullGridSkipsTheCornerCell) {
  const double A = 1, B = 0.98, C = 0.4, D = 0.5;
  const int n = 3;
  Generated g = run("dupin", numbers({{"a", A}, {"b", B}, {"c", C}, {"d", D}, {"u", 2}, {"v", 2}, {"n", n}}, "nome3"));
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double t1 = i * 2 * M_PI / n, t2 = j * 2 * M_PI / n;
      const double den = A - C * std::cos(t1) * std::cos(t2);
      expect_near(named(g.soup, ij(i, j)),
                  {(D * (C - A * std::cos(t1) * std::cos(t2)) + B * B * std::cos(t1)) / den,
                   B * std::sin(t1) * (A - D * std::cos(t2)) / den, B * std::sin(t2) * (C * std::cos(t1) - D) / den},
                  1e-12);
    }
  }
  std::vector<Face> want;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (i == n - 1 && j == n - 1) continue;
      const int i1 = (i + 1) % n, j1 = (j + 1) % n;
      want.push_back({ij(i, j), ij(i1, j), ij(i, j1)});
      want.push_back({ij(i, j1), ij(i1, j), ij(i1, j1)});
    }
  }
  std::sort(want.begin(), want.end());
  EXPECT_EQ(sorted_faces(g.soup), want);  // 2n² − 2 = 16 triangles
}

TEST(OriginalHyperboloid, WholeNumberRowsAndTriangles) {
  Generated g = run("hyperboloid", numbers({{"n", 4}, {"a", 1}, {"b", 2}, {"c", 1.9}, {"sheet", 0}, {"angle", 2}}, "nome3"));
  // Rows z = −1, 0, 1 (⌊1.9⌋ = 1), j counted from the lowest; θ_i = i·2π/4.
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double z = j - 1, k = std::sqrt(z * z + 1), th = i * 2 * M_PI / 4;
      expect_near(named(g.soup, ij(i, j)), {k * std::cos(th), 2 * k * std::sin(th), z}, 1e-12);
    }
  }
  std::vector<Face> want;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 2; ++j) {
      const int i1 = (i + 1) % 4;
      want.push_back({ij(i, j), ij(i1, j), ij(i, j + 1)});
      want.push_back({ij(i, j + 1), ij(i1, j), ij(i1, j + 1)});
    }
  }
  std::sort(want.begin(), want.end());
  EXPECT_EQ(sorted_faces(g.soup), want);
}

TEST(OriginalSpiral, RibbonOfTwoRows) {
  Generated g = run("spiral", numbers({{"rate", 0.5}, {"angle", 3.7}, {"segs", 4}}, "nome3"));
  std::vector<Face> want;
  for (int i = 0; i <= 4; ++i) {
    const double th = 2.0 * 3 * i / 4, r = 0.5 * i;  // angle truncated to 3
    expect_near(named(g.soup, "u" + std::to_string(i)), {r * std::cos(th), r * std::sin(th), 0}, 1e-12);
    expect_near(named(g.soup, "l" + std::to_string(i)), {r * std::cos(th), r * std::sin(th), -0.13}, 1e-12);
    if (i < 4) {
      const std::string a = std::to_string(i), b = std::to_string(i + 1);
      want.push_back({"u" + b, "u" + a, "l" + a});
      want.push_back({"l" + a, "l" + b, "u" + b});
    }
  }
  EXPECT_EQ(face_names(g.soup), want);
}

// ---- §11.3 genimplicitsurf ----

Args implicit_args(std::function<double(std::span<const double>)> f, double lo, double hi, double n) {
  Args a = numbers({{"x_min", lo}, {"x_max", hi}, {"y_min", lo}, {"y_max", hi}, {"z_min", lo}, {"z_max", hi},
                    {"nx", n}, {"ny", n}, {"nz", n}},
                   "nome3");
  a.functions["func"] = fn(std::move(f));
  return a;
}

TEST(OriginalGenImplicitSurf, OneInsideCornerIsBourkesCaseOneReversed) {
  // Cells of (1 − 0)/(2 − 1) = 1, two per axis (the grid reaches 2). Only the corner
  // (0,0,0) has f ≤ 0: Bourke's case 1, triangle over edges 0, 8, 3, whose crossings are at
  // the middle of the three edges from that corner. The cube creates its vertices in edge
  // order (v_0 on edge 0 along x, v_1 on edge 3 along y, v_2 on edge 8 along z) and emits the
  // triangle reversed, (edge 3, edge 8, edge 0), facing towards f > 0.
  Generated g = run("genimplicitsurf", implicit_args([](auto p) { return p[0] + p[1] + p[2] - 0.5; }, 0, 1, 2));
  ASSERT_EQ(g.soup.vertex_count(), 3);
  expect_near(named(g.soup, "v_0"), {0.5, 0, 0});
  expect_near(named(g.soup, "v_1"), {0, 0.5, 0});
  expect_near(named(g.soup, "v_2"), {0, 0, 0.5});
  EXPECT_EQ(face_names(g.soup), (std::vector<Face>{{"v_1", "v_2", "v_0"}}));
}

TEST(OriginalGenImplicitSurf, UnitSphereOnAHalfGridAsNome3AfterWelding) {
  // generators-original.md §11.3: x²+y²+z²−1 on a 0.5 grid gives 152 triangles in NOME3, 48 of
  // them degenerate (the sphere passes through grid points, where crossings snap). nomec
  // welds the cubes' copies and drops the degenerate triangles: 104 remain, a closed sphere.
  Generated g = run("genimplicitsurf",
                    implicit_args([](auto p) { return p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - 1; }, -1.5, 1.5, 7));
  EXPECT_EQ(g.soup.face_count(), 152 - 48);
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_TRUE(r.is_closed);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_GT(signed_volume(g.soup), 0);  // faces point towards f > 0, outward
  // Every crossing lies on a grid edge: two of its coordinates are multiples of 0.5.
  for (const glm::dvec3& p : g.soup.positions) {
    int on_grid = 0;
    for (double c : {p.x, p.y, p.z}) on_grid += std::abs(c * 2 - std::round(c * 2)) < 1e-12 ? 1 : 0;
    EXPECT_GE(on_grid, 2);
  }
}

TEST(OriginalGenImplicitSurf, EveryRecordNameOfNome3ResolvesAfterWelding) {
  // generators-original.md §11.3: on the same 0.5 grid NOME3 makes 312 vertex records
  // v_0 … v_311, every cube its own (78 float-distinct positions: a crossing computed from
  // both ends of its edge rounds differently). The crossings themselves: the 6 grid points
  // (±1,0,0)…; on grid lines with the other two coordinates in {0, ±0.5}, not both 0, the
  // points ±√(1 − a² − b²): 4 lines with one 0.5 and 4 with two per axis, 2 points each,
  // 3 axes: 24 + 24. So 54 vertices after welding, and each of the 312 names is a surviving
  // vertex or an alias of one, at that vertex's position.
  Generated g = run("genimplicitsurf",
                    implicit_args([](auto p) { return p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - 1; }, -1.5, 1.5, 7));
  EXPECT_EQ(g.soup.vertex_count(), 6 + 24 + 24);
  std::vector<std::string> names(g.soup.names.begin(), g.soup.names.end());
  for (const auto& alias : g.aliases) {
    const std::string& name = alias.first;
    const glm::dvec3& position = alias.second;  // a plain reference: lambdas may capture it
    names.push_back(name);
    const auto same = std::find_if(g.soup.positions.begin(), g.soup.positions.end(),
                                   [&](const glm::dvec3& q) {
                                     const glm::dvec3 d = q - position;
                                     return d.x * d.x + d.y * d.y + d.z * d.z < 1e-24;
                                   });
    EXPECT_NE(same, g.soup.positions.end()) << name << " is an alias of no surviving vertex";
  }
  std::sort(names.begin(), names.end());
  std::vector<std::string> expected;
  for (int k = 0; k < 312; ++k) expected.push_back("v_" + std::to_string(k));
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(names, expected);
}

TEST(OriginalGenImplicitSurf, SingularSurfaceKeepsNome3sUnweldedCubes) {
  // x² − y² = 0 is two planes crossing along the z axis: welded, four sheets would share
  // its edges. nomec then returns NOME3's cubes as they were: every cut edge of every cube
  // has its own vertex v_k, in order, and the kernel accepts the pieces.
  Generated g = run("genimplicitsurf", implicit_args([](auto p) { return p[0] * p[0] - p[1] * p[1]; }, -1, 1, 9));
  ASSERT_GT(g.soup.vertex_count(), 0);
  for (int32_t v = 0; v < g.soup.vertex_count(); ++v) EXPECT_EQ(g.soup.names[v], "v_" + std::to_string(v));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.face_count, g.soup.face_count());
  EXPECT_GT(r.components.size(), 1u);
}

}  // namespace
}  // namespace nomec::backend::testing
