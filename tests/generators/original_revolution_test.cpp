// The NOME3 generators as the original computed them (generators-original.md §2–4): each
// test writes down the original's vertices (names and positions from the formulas of that
// page, not from nomec), its faces by name, and which of them nomec welds; then compares
// with what the generator makes: every name the original gave resolves (as a vertex or an
// alias) to the original's position, and the faces are the original's faces once
// coincident corners are merged and the faces left degenerate dropped.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "tests/generators/helpers.h"

namespace nomec::backend::testing {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct Original {
  std::map<std::string, glm::dvec3> at;             // every name the original gave
  std::vector<std::vector<std::string>> faces;      // the original's faces, by name
};

// A face as the cycle of its corners (numbers of positions), starting at the smallest,
// with corners at the same position merged; empty when fewer than 3 distinct remain.
std::vector<int> cycle(const std::vector<int>& corners) {
  std::vector<int> out;
  for (int c : corners) {
    if (std::find(out.begin(), out.end(), c) == out.end()) out.push_back(c);
  }
  if (out.size() < 3) return {};
  std::rotate(out.begin(), std::min_element(out.begin(), out.end()), out.end());
  return out;
}

double dist(const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 d = a - b;
  return std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
}

std::optional<glm::dvec3> resolve(const Generated& g, const std::string& name) {
  for (size_t v = 0; v < g.soup.names.size(); ++v) {
    if (g.soup.names[v] == name) return g.soup.positions[v];
  }
  for (const auto& [alias, p] : g.aliases) {
    if (alias == name) return p;
  }
  return std::nullopt;
}

void expect_original(const Generated& g, const Original& o, double eps = 1e-9) {
  for (const auto& [name, p] : o.at) {
    std::optional<glm::dvec3> got = resolve(g, name);
    ASSERT_TRUE(got.has_value()) << "the original's `" << name << "` names nothing";
    expect_near(*got, p, eps);
  }
  for (const std::string& n : g.soup.names) EXPECT_TRUE(o.at.contains(n)) << "a name the original did not give: " << n;
  // Number the original's distinct positions; a generated corner gets the number of the
  // original position it lies on.
  std::vector<glm::dvec3> distinct;
  auto number = [&](const glm::dvec3& p, bool add) {
    for (size_t k = 0; k < distinct.size(); ++k) {
      if (dist(distinct[k], p) <= eps) return static_cast<int>(k);
    }
    if (!add) return -1;
    distinct.push_back(p);
    return static_cast<int>(distinct.size() - 1);
  };
  std::multiset<std::vector<int>> want, got;
  for (const std::vector<std::string>& f : o.faces) {
    std::vector<int> corners;
    for (const std::string& n : f) corners.push_back(number(o.at.at(n), true));
    if (std::vector<int> c = cycle(corners); !c.empty()) want.insert(c);
  }
  size_t off = 0;
  for (int32_t n : g.soup.face_sizes) {
    std::vector<int> corners;
    for (int32_t k = 0; k < n; ++k) corners.push_back(number(g.soup.positions[g.soup.face_vertices[off + k]], false));
    got.insert(cycle(corners));
    off += n;
  }
  EXPECT_EQ(got, want);
  EXPECT_EQ(topo(g.soup).isolated_vertex_count, 0);
}

std::string nm(const char* fmt, int a, int b) {
  char buf[32];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

std::string nm1(const char* prefix, int i) { return prefix + std::to_string(i); }

// ---- funnel, tunnel, circle (§1) ----

// bc_i at radius ro, z = 0; hc_i at ro·(1 + ratio), z = h; lc_i at z = −h (tunnel); angle
// 360°·i/n. Faces (bc_i bc_{i+1} hc_{i+1} hc_i) and (lc_i lc_{i+1} bc_{i+1} bc_i).
Original rings(int n, double ro, double ratio, double h, bool tunnel) {
  Original o;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    o.at[nm1("bc", i)] = {ro * std::cos(a), ro * std::sin(a), 0};
    o.at[nm1("hc", i)] = {ro * (1 + ratio) * std::cos(a), ro * (1 + ratio) * std::sin(a), h};
    if (tunnel) o.at[nm1("lc", i)] = {ro * (1 + ratio) * std::cos(a), ro * (1 + ratio) * std::sin(a), -h};
  }
  for (int i = 0; i < n; ++i) {
    const int k = (i + 1) % n;
    o.faces.push_back({nm1("bc", i), nm1("bc", k), nm1("hc", k), nm1("hc", i)});
    if (tunnel) o.faces.push_back({nm1("lc", i), nm1("lc", k), nm1("bc", k), nm1("bc", i)});
  }
  return o;
}

TEST(OriginalRings, FunnelAndTunnelInEveryDialectWithNome3Aliases) {
  for (const char* d : {"nome", "nome2", "nome3", "slide"}) {
    Args f = numbers({{"n", 5}, {"ro", 2}, {"ratio", 0.5}, {"h", 1.5}}, d);
    expect_original(run("funnel", f), rings(5, 2, 0.5, 1.5, false));
    Args t = numbers({{"n", 4}, {"ro", 1}, {"ratio", -0.25}, {"h", 2}}, d);
    const Generated g = run("tunnel", t);
    expect_original(g, rings(4, 1, -0.25, 2, true));
    // NOME3's names: v1_ the top ring, v2_ the middle (base) ring, v3_ the lower ring.
    expect_near(named(g.soup, ir::canonical_vertex_name(ir::GenKind::Tunnel, "v1_1")), {0, 0.75, 2});
    expect_near(named(g.soup, ir::canonical_vertex_name(ir::GenKind::Tunnel, "v2_2")), {-1, 0, 0});
    expect_near(named(g.soup, ir::canonical_vertex_name(ir::GenKind::Tunnel, "v3_3")), {0, -0.75, -2});
  }
}

TEST(OriginalRings, CircleVerticesAndTheirNome2Names) {
  for (const char* d : {"nome2", "nome3", "slide"}) {
    Generated g = run("circle", numbers({{"radius", 3}, {"segs", 6}}, d));
    EXPECT_EQ(g.soup.face_count(), 0);
    ASSERT_EQ(g.curves.size(), 1u);
    EXPECT_TRUE(g.curves[0].is_closed);
    for (int i = 0; i < 6; ++i) {
      const glm::dvec3 want(3 * std::cos(M_PI * i / 3), 3 * std::sin(M_PI * i / 3), 0);
      expect_near(named(g.soup, nm1("v", i)), want);
      expect_near(named(g.soup, ir::canonical_vertex_name(ir::GenKind::Circle, nm1("bc", i))), want);
    }
  }
}

// ---- torus (§2) ----

Original torus(double R, double r, double tmax, double pmin, double pmax, int ts, int ps) {
  Original o;
  for (int i = 0; i <= ts; ++i) {
    for (int j = 0; j <= ps; ++j) {
      const double th = i * tmax / ts * kDeg, ph = (pmin + j * (pmax - pmin) / ps) * kDeg;
      o.at[nm("v%d_%d", i + 1, j)] = {(R + r * std::cos(ph)) * std::cos(th), (R + r * std::cos(ph)) * std::sin(th),
                                      -r * std::sin(ph)};
    }
  }
  auto v = [&](int i, int j) { return nm("v%d_%d", i + 1, j); };
  for (int k = 0; k < ts; ++k) {
    if (tmax == 360) {
      const int k1 = (k + 1) % ts;
      for (int j = 0; j < ps; ++j) o.faces.push_back({v(k1, j + 1), v(k1, j), v(k, j), v(k, j + 1)});
    } else {
      for (int j = 0; j <= ps; ++j) {
        const int nx = (j + 1) % (ps + 1);
        o.faces.push_back({v(k + 1, nx), v(k + 1, j), v(k, j), v(k, nx)});
      }
    }
  }
  return o;
}

Args torus_args(double R, double r, double tmax, double pmin, double pmax, int ts, int ps, std::string dialect) {
  return numbers({{"major_radius", R}, {"minor_radius", r}, {"theta_max", tmax}, {"phi_min", pmin},
                  {"phi_max", pmax}, {"theta_segs", double(ts)}, {"phi_segs", double(ps)}},
                 std::move(dialect));
}

TEST(OriginalTorus, PartialQuarterTubeIsTheLowerOneClosedAlongTheChord) {
  for (const char* d : {"nome3", "nome", "slide"}) {
    Generated g = run("torus", torus_args(2, 0.5, 90, 0, 90, 3, 3, d));
    expect_original(g, torus(2, 0.5, 90, 0, 90, 3, 3));
    expect_near(*resolve(g, "v1_1"), {2 + 0.5 * std::cos(30 * kDeg), 0, -0.25});
    EXPECT_EQ(g.soup.face_count(), 3 * 4);  // φsegs + 1 quads per θ segment
    kernel::TopologyReport t = topo(g.soup);
    EXPECT_EQ(t.border_loop_count, 2);  // open at both θ ends, closed along the chord
    EXPECT_TRUE(t.is_orientable);
  }
}

TEST(OriginalTorus, FullTorusWeldsBothSeamsKeepingTheNames) {
  Generated g = run("torus", torus_args(2, 0.5, 360, 0, 360, 4, 6, "nome3"));
  expect_original(g, torus(2, 0.5, 360, 0, 360, 4, 6));
  EXPECT_EQ(g.soup.vertex_count(), 24);
  kernel::TopologyReport t = topo(g.soup);
  EXPECT_TRUE(t.is_closed);
  EXPECT_EQ(t.euler_characteristic, 0);
  EXPECT_GT(signed_volume(g.soup), 0);
  // The observation of §2.2: NOME3 v1_1 = (2.25, 0, −0.433).
  expect_near(*resolve(g, "v1_1"), {2.25, 0, -0.4330127}, 1e-6);
  expect_near(*resolve(g, "v5_6"), *resolve(g, "v1_0"));  // the unused θ = 360 column
}

TEST(OriginalTorus, HalfTurnFullTubeDropsTheDegenerateClosingQuads) {
  // nome3/hw1.nom's torus (5 0.2 180 0 360 60 5), smaller.
  Generated g = run("torus", torus_args(5, 0.2, 180, 0, 360, 6, 5, "nome3"));
  expect_original(g, torus(5, 0.2, 180, 0, 360, 6, 5));
  EXPECT_EQ(g.soup.face_count(), 6 * 5);  // NOME3 made 6 more, each with two coincident edges
  EXPECT_EQ(topo(g.soup).border_loop_count, 2);
  EXPECT_GT(signed_volume(g.soup), 0);
}

TEST(OriginalTorus, FullTurnPartialTubeStaysOpen) {
  Generated g = run("torus", torus_args(3, 1, 360, -45, 45, 5, 2, "nome3"));
  expect_original(g, torus(3, 1, 360, -45, 45, 5, 2));
  EXPECT_EQ(topo(g.soup).border_loop_count, 2);
  EXPECT_EQ(run_error("torus", torus_args(3, 1, 90, 0, 90, 3, 1, "nome3")).argument, "phi_segs");
}

// ---- sphere and ellipsoid (§4) ----

Original spheroid(double rx, double ry, double tmax, double pmin, double pmax, int ts, int ps) {
  tmax = std::trunc(tmax), pmin = std::trunc(pmin), pmax = std::trunc(pmax);
  Original o;
  for (int j = 0; j <= ts; ++j) {
    for (int i = 0; i <= ps; ++i) {
      const double psi = ((pmin + 90) + i * (pmax - pmin) / ps) * kDeg, th = j * tmax / ts * kDeg;
      o.at[nm("v%d_%d", j, i)] = {ry * std::sin(psi) * std::cos(th), ry * std::sin(psi) * std::sin(th), rx * std::cos(psi)};
    }
  }
  const double zt = o.at["v0_0"].z, zb = o.at[nm("v%d_%d", 0, ps)].z;
  o.at["top"] = {0, 0, zt};
  o.at["bottom"] = {0, 0, zb};
  o.at["center"] = {0, 0, (zt + zb) / 2};
  auto v = [&](int j, int i) { return nm("v%d_%d", j, i); };
  const bool full = tmax == 360;
  for (int k = 0; k <= ts; ++k) {
    if (k == ts && !full) break;
    const int k1 = k == ts ? 0 : k + 1;
    for (int c = 0; c < ps; ++c) o.faces.push_back({v(k1, c + 1), v(k1, c), v(k, c), v(k, c + 1)});
    o.faces.push_back({v(k, 0), v(k1, 0), "top"});
    o.faces.push_back({"bottom", v(k1, ps), v(k, ps)});
  }
  if (!full) {
    for (int i = 0; i < ps; ++i) {
      o.faces.push_back({v(0, i + 1), v(0, i), "center"});
      o.faces.push_back({"center", v(ts, i), v(ts, i + 1)});
    }
    o.faces.push_back({"top", "center", v(0, 0)});
    o.faces.push_back({v(0, ps), "center", "bottom"});
    o.faces.push_back({v(ts, 0), "center", "top"});
    o.faces.push_back({"bottom", "center", v(ts, ps)});
  }
  return o;
}

Args sphere_args(double r, double tmax, double pmin, double pmax, double ts, double ps, std::string dialect) {
  return numbers({{"radius", r}, {"theta_max", tmax}, {"phi_min", pmin}, {"phi_max", pmax}, {"theta_segs", ts},
                  {"phi_segs", ps}},
                 std::move(dialect));
}

TEST(OriginalSphere, FullSphereHasItsNorthPoleAtPhiMinus90) {
  for (const char* d : {"nome3", "nome", "slide"}) {
    Generated g = run("sphere", sphere_args(1, 360, -90, 90, 6, 3, d));
    expect_original(g, spheroid(1, 1, 360, -90, 90, 6, 3));
    expect_near(*resolve(g, "top"), {0, 0, 1});
    expect_near(*resolve(g, "v2_0"), {0, 0, 1});  // a pole-ring name: the pole
    kernel::TopologyReport t = topo(g.soup);
    EXPECT_EQ(t.vertex_count, 6 * 2 + 2);  // two rings and the poles
    EXPECT_TRUE(t.is_closed);
    EXPECT_EQ(t.euler_characteristic, 2);
    EXPECT_GT(signed_volume(g.soup), 0);
  }
}

TEST(OriginalSphere, HemisphereIsTheSouthernOneWithALid) {
  Generated g = run("sphere", sphere_args(1, 360, 0, 90, 4, 2, "nome3"));
  expect_original(g, spheroid(1, 1, 360, 0, 90, 4, 2));
  expect_near(*resolve(g, "bottom"), {0, 0, -1});
  kernel::TopologyReport t = topo(g.soup);
  EXPECT_TRUE(t.is_closed);
  EXPECT_GT(signed_volume(g.soup), 0);
}

TEST(OriginalSphere, WedgeIsAClosedOrangeSliceWithTruncatedAngles) {
  // §4.5's wedge (1 180 -45 60 4 3), written with fractions NOME3 cut off.
  Generated g = run("sphere", sphere_args(1, 180.7, -45.9, 60.2, 4, 3, "nome3"));
  expect_original(g, spheroid(1, 1, 180, -45, 60, 4, 3));
  EXPECT_EQ(g.soup.face_count(), 30);
  kernel::TopologyReport t = topo(g.soup);
  EXPECT_TRUE(t.is_closed);
  EXPECT_EQ(t.euler_characteristic, 2);
  EXPECT_NEAR(signed_volume(g.soup), 1.618, 1e-3);
}

TEST(OriginalEllipsoid, FirstArgumentIsThePolarSemiAxis) {
  for (const char* d : {"nome3", "nome"}) {
    Generated g = run("ellipsoid", numbers({{"a", 1}, {"b", 2}, {"theta_max", 360}, {"phi_min", -90}, {"phi_max", 90},
                                            {"theta_segs", 4}, {"phi_segs", 4}},
                                           d));
    expect_original(g, spheroid(1, 2, 360, -90, 90, 4, 4));
    expect_near(*resolve(g, "top"), {0, 0, 1});
    expect_near(*resolve(g, "v0_2"), {2, 0, 0});
    EXPECT_GT(signed_volume(g.soup), 0);
  }
}

// ---- torusknot (§3) ----

glm::dvec3 knot_point(double p, double q, double R, double r, double t) {
  return {(R + r * std::cos(p * t)) * std::cos(q * t), (R + r * std::cos(p * t)) * std::sin(q * t), r * std::sin(p * t)};
}

glm::dvec3 unit(glm::dvec3 v) { return v / std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

// The original's frame with its step of 1e-4 made much smaller (its limit).
Original torusknot(double p, double q, double R, double r, double tube, int cs, int ss) {
  Original o;
  for (int i = 0; i < ss; ++i) {
    const double t = 2 * M_PI * i / ss, eps = 1e-7;
    const glm::dvec3 p0 = knot_point(p, q, R, r, t), p1 = knot_point(p, q, R, r, t + eps);
    const glm::dvec3 T = unit(p1 - p0);
    glm::dvec3 N = p0 + p1;
    N = unit(N - (N.x * T.x + N.y * T.y + N.z * T.z) * T);
    const glm::dvec3 B = unit({T.y * N.z - T.z * N.y, T.z * N.x - T.x * N.z, T.x * N.y - T.y * N.x});
    for (int j = 0; j < cs; ++j) {
      const double a = 2 * M_PI * j / cs;
      o.at[nm("v%d_%d", i + 1, j)] = p0 + tube * (std::cos(a) * N + std::sin(a) * B);
    }
  }
  for (int k = 0; k < ss; ++k) {
    const int k1 = (k + 1) % ss;
    for (int j = 0; j < cs; ++j) {
      const int j1 = (j + 1) % cs;
      o.faces.push_back({nm("v%d_%d", k1 + 1, j1), nm("v%d_%d", k1 + 1, j), nm("v%d_%d", k + 1, j), nm("v%d_%d", k + 1, j1)});
    }
  }
  return o;
}

TEST(OriginalTorusKnot, FirstArgumentTurnsAroundTheTube) {
  for (const char* d : {"nome3", "nome"}) {
    Generated g = run("torusknot", numbers({{"symm", 3}, {"turns", 2}, {"major_radius", 4}, {"minor_radius", 1.5},
                                            {"tube_radius", 0.3}, {"circ_segs", 5}, {"sweep_segs", 12}},
                                           d));
    expect_original(g, torusknot(3, 2, 4, 1.5, 0.3, 5, 12), 1e-5);
    // t = 2π/12: the centre is ((4 + 1.5 cos 90°) cos 60°, … sin 60°, 1.5 sin 90°).
    glm::dvec3 mid(0, 0, 0);
    for (int j = 0; j < 5; ++j) mid += *resolve(g, nm("v%d_%d", 2, j)) / 5.0;
    expect_near(mid, {2, 4 * std::sin(60 * kDeg), 1.5}, 1e-9);
    kernel::TopologyReport t = topo(g.soup);
    EXPECT_TRUE(t.is_closed);
    EXPECT_GT(signed_volume(g.soup), 0);
  }
}

TEST(OriginalTorusKnot, ZeroTubeRadiusIsTheKnotAsAnOpenLineStrip) {
  // §3.4: tube_radius 0 makes no tube but the knot's centre curve, an open line strip of the
  // points knotpoint{i} at t_i = 2πi/sweep_segs (i = 0 … sweep_segs − 1).
  Generated g = run("torusknot", numbers({{"symm", 2}, {"turns", 3}, {"major_radius", 2}, {"minor_radius", 0.5},
                                          {"tube_radius", 0}, {"circ_segs", 6}, {"sweep_segs", 10}},
                                         "nome3"));
  EXPECT_EQ(g.soup.face_count(), 0);
  ASSERT_EQ(g.curves.size(), 1u);
  EXPECT_FALSE(g.curves[0].is_closed);
  ASSERT_EQ(g.curves[0].vertices.size(), 10u);
  for (int i = 0; i < 10; ++i) {
    const int32_t v = g.curves[0].vertices[static_cast<size_t>(i)];
    EXPECT_EQ(g.soup.names[static_cast<size_t>(v)], "knotpoint" + std::to_string(i));
    expect_near(g.soup.positions[static_cast<size_t>(v)], knot_point(2, 3, 2, 0.5, 2 * M_PI * i / 10));
  }
  // t_0 = 0: ((2 + 0.5)·1, 0, 0).
  expect_near(*resolve(g, "knotpoint0"), {2.5, 0, 0});
}

TEST(OriginalTorusKnot, NegativeTubeRadiusIsAnError) {
  NamedError e = run_error("torusknot", numbers({{"symm", 2}, {"turns", 3}, {"major_radius", 2}, {"minor_radius", 0.5},
                                                 {"tube_radius", -0.1}, {"circ_segs", 6}, {"sweep_segs", 10}},
                                                "nome3"));
  EXPECT_EQ(e.argument, "tube_radius");
  EXPECT_NE(e.message.find("must not be negative"), std::string::npos) << e.message;
}

}  // namespace
}  // namespace nomec::backend::testing
