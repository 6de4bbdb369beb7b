// Funnel, tunnel, circle and Möbius strip: exact counts, topology, named vertex positions,
// NOME3 aliases and argument errors.
#include <cmath>
#include <numbers>

#include "tests/generators/helpers.h"

namespace nomec::backend::testing {
namespace {

TEST(Funnel, NomeIsAnAnnulusOfNQuads) {
  Generated g = run("funnel", numbers({{"n", 8}, {"ro", 2}, {"ratio", 0.5}, {"h", 1}}));
  EXPECT_EQ(g.soup.vertex_count(), 16);
  EXPECT_EQ(g.soup.face_count(), 8);
  for (int32_t s : g.soup.face_sizes) EXPECT_EQ(s, 4);
  kernel::TopologyReport r = topo(g.soup);
  ASSERT_EQ(r.components.size(), 1u);
  EXPECT_EQ(r.vertex_count, 16);
  EXPECT_EQ(r.edge_count, 24);
  EXPECT_EQ(r.face_count, 8);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_EQ(r.border_loop_count, 2);
  EXPECT_TRUE(r.is_orientable);
  EXPECT_FALSE(r.is_closed);
  EXPECT_EQ(r.components[0].genus, 0);
  expect_near(named(g.soup, "bc0"), {2, 0, 0});
  expect_near(named(g.soup, "hc0"), {3, 0, 1});
  expect_near(named(g.soup, "bc2"), {0, 2, 0});
  expect_near(named(g.soup, "hc6"), {0, -3, 1});
  EXPECT_TRUE(g.curves.empty());
}

TEST(Funnel, FacesPointOutward) {
  Generated g = run("funnel", numbers({{"n", 4}, {"ro", 1}, {"ratio", 0}, {"h", 1}}));
  // Face 0 = (bc0 bc1 hc1 hc0): its normal points away from the axis, towards +x+y.
  const auto& p = g.soup.positions;
  const glm::dvec3 a = p[g.soup.face_vertices[0]], b = p[g.soup.face_vertices[1]],
                   c = p[g.soup.face_vertices[2]];
  const glm::dvec3 u = b - a, v = c - a;
  const glm::dvec3 n(u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x);
  EXPECT_GT(n.x, 0);
  EXPECT_GT(n.y, 0);
}

TEST(Funnel, Nome3ArgumentNames) {
  Generated g = run("funnel",
                    numbers({{"radius", 1}, {"ratio", -0.25}, {"height", 2}, {"n", 6}}, "nome3"));
  EXPECT_EQ(g.soup.vertex_count(), 12);
  EXPECT_EQ(topo(g.soup).euler_characteristic, 0);
  expect_near(named(g.soup, "bc0"), {1, 0, 0});
  expect_near(named(g.soup, "hc0"), {0.75, 0, 2});
}

TEST(Funnel, Nome3AliasesMapToCanonicalNames) {
  const auto& aliases = ir::generator(ir::GenKind::Funnel).aliases;
  ASSERT_EQ(aliases.size(), 2u);
  EXPECT_EQ(aliases[0].alias, "v2_");
  EXPECT_EQ(aliases[0].prefix, "bc");
  EXPECT_EQ(aliases[1].alias, "v1_");
  EXPECT_EQ(aliases[1].prefix, "hc");
  EXPECT_EQ(ir::canonical_vertex_name(ir::GenKind::Funnel, "v2_3"), "bc3");
  EXPECT_EQ(ir::canonical_vertex_name(ir::GenKind::Funnel, "v1_0"), "hc0");
  EXPECT_EQ(ir::canonical_vertex_name(ir::GenKind::Funnel, "hc0"), "hc0");
  EXPECT_EQ(ir::canonical_vertex_name(ir::GenKind::Tunnel, "v3_5"), "lc5");
  EXPECT_TRUE(ir::generator(ir::GenKind::Torus).aliases.empty());
}

TEST(Funnel, ErrorsNameTheArgument) {
  NamedError e = run_error("funnel", numbers({{"n", 2}, {"ro", 1}, {"ratio", 0}, {"h", 1}}));
  EXPECT_EQ(e.argument, "n");
  EXPECT_NE(e.message.find("at least 3"), std::string::npos) << e.message;
  // Counts are rounded (as the checker's NonIntegerCount warning promises): 2.4 -> 2 is too
  // few, 4.6 -> 5 sides.
  EXPECT_EQ(run_error("funnel", numbers({{"n", 2.4}, {"ro", 1}, {"ratio", 0}, {"h", 1}})).argument, "n");
  EXPECT_EQ(run("funnel", numbers({{"n", 4.6}, {"ro", 1}, {"ratio", 0}, {"h", 1}})).soup.vertex_count(), 10);
  EXPECT_EQ(run_error("funnel", numbers({{"n", 4}, {"ro", 0}, {"ratio", 0}, {"h", 1}})).argument, "ro");
  EXPECT_EQ(run_error("funnel", numbers({{"n", 4}, {"ro", 1}, {"ratio", -1}, {"h", 1}})).argument, "ratio");
  NamedError missing = run_error("funnel", numbers({{"n", 4}, {"ro", 1}, {"ratio", 0}}));
  EXPECT_EQ(missing.argument, "h");
  EXPECT_EQ(missing.message, "missing argument `h`");
  EXPECT_EQ(run_error("funnel", numbers({{"n", 4}, {"ratio", 0}, {"height", 1}}, "nome3")).argument,
            "radius");
  EXPECT_EQ(run_error("funnel", numbers({{"n", 1e9}, {"ro", 1}, {"ratio", 0}, {"h", 1}})).argument, "n");
  EXPECT_EQ(run_error("funnel", numbers({{"n", NAN}, {"ro", 1}, {"ratio", 0}, {"h", 1}})).argument, "n");
}

TEST(Generators, KeywordsComeFromTheCatalogue) {
  EXPECT_FALSE(ir::generator_by_keyword("mesh").has_value());
  EXPECT_FALSE(ir::generator_by_keyword("teapot").has_value());
  EXPECT_EQ(ir::generator_by_keyword("funnel"), ir::GenKind::Funnel);
  EXPECT_EQ(ir::generator_by_keyword("torusknot"), ir::GenKind::Torusknot);
  EXPECT_EQ(ir::generator_by_keyword("bsplinecurve"), ir::GenKind::Bspline);
  EXPECT_EQ(ir::generator_by_end_keyword("endbspline"), ir::GenKind::Bspline);
  EXPECT_FALSE(ir::generator_by_end_keyword("funnel").has_value());
}

TEST(Tunnel, SymmetricIsAnAnnulusOfThreeRings) {
  Generated g = run("tunnel", numbers({{"n", 8}, {"ro", 1}, {"ratio", 0.5}, {"h", 2}}));
  kernel::TopologyReport r = topo(g.soup);
  ASSERT_EQ(r.components.size(), 1u);
  EXPECT_EQ(r.vertex_count, 24);
  EXPECT_EQ(r.edge_count, 40);
  EXPECT_EQ(r.face_count, 16);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_EQ(r.border_loop_count, 2);
  EXPECT_TRUE(r.is_orientable);
  EXPECT_EQ(r.components[0].mobius_edge_count, 0);
  expect_near(named(g.soup, "bc0"), {1, 0, 0});
  expect_near(named(g.soup, "hc0"), {1.5, 0, 2});
  expect_near(named(g.soup, "lc0"), {1.5, 0, -2});
}

TEST(Tunnel, AsymmetricLowerRing) {
  Generated g = run("tunnel", numbers({{"n", 4}, {"ro", 2}, {"ratio", 0.5}, {"h", 1},
                                       {"dri_low", -0.5}, {"hgt_low", 3}}));
  EXPECT_EQ(topo(g.soup).euler_characteristic, 0);
  expect_near(named(g.soup, "hc0"), {3, 0, 1});
  expect_near(named(g.soup, "lc0"), {1, 0, -3});
  EXPECT_EQ(run_error("tunnel", numbers({{"n", 4}, {"ro", 2}, {"ratio", 0.5}, {"h", 1},
                                          {"dri_low", -2}, {"hgt_low", 3}}))
                .argument,
            "dri_low");
  EXPECT_EQ(run_error("tunnel", numbers({{"n", 2}, {"ro", 1}, {"ratio", 0}, {"h", 1}})).argument, "n");
}

TEST(Circle, ClosedCurveWithoutFaces) {
  Generated g = run("circle", numbers({{"radius", 5}, {"segs", 10}}, "nome3"));
  EXPECT_EQ(g.soup.vertex_count(), 10);
  EXPECT_EQ(g.soup.face_count(), 0);
  ASSERT_EQ(g.curves.size(), 1u);
  EXPECT_TRUE(g.curves[0].is_closed);
  EXPECT_EQ(g.curves[0].vertices.size(), 10u);
  expect_near(named(g.soup, "v0"), {5, 0, 0});
  expect_near(named(g.soup, "v5"), {-5, 0, 0});
  EXPECT_EQ(run_error("circle", numbers({{"radius", 20}, {"segs", 1}}, "nome3")).argument, "segs");
  EXPECT_EQ(run_error("circle", numbers({{"radius", -1}, {"segs", 8}}, "nome3")).argument, "radius");
  // NOME2 writes the same arguments `(n ro)` and names them so in messages.
  EXPECT_EQ(run_error("circle", numbers({{"radius", 20}, {"segs", 1}}, "nome2")).argument, "n");
  EXPECT_EQ(run_error("circle", numbers({{"radius", -1}, {"segs", 8}}, "nome2")).argument, "ro");
}

// NOME2's `circle (n ro)` (compat.md D5): vertices `bc0…` (= `v0…`) at 360°·i/n, z = 0.
TEST(Circle, Nome2VerticesAtEqualAngles) {
  Generated g = run("circle", numbers({{"n", 4}, {"ro", 2}}, "nome2"));
  EXPECT_EQ(g.soup.vertex_count(), 4);
  ASSERT_EQ(g.curves.size(), 1u);
  EXPECT_TRUE(g.curves[0].is_closed);
  expect_near(named(g.soup, ir::canonical_vertex_name(ir::GenKind::Circle, "bc0")), {2, 0, 0});
  expect_near(named(g.soup, ir::canonical_vertex_name(ir::GenKind::Circle, "bc1")), {0, 2, 0});
  expect_near(named(g.soup, ir::canonical_vertex_name(ir::GenKind::Circle, "bc3")), {0, -2, 0});
}

Args ribbon(std::vector<glm::dvec3> path, std::vector<std::pair<std::string, double>> nums) {
  Args a = numbers(std::move(nums));
  a.points = std::move(path);
  for (size_t i = 0; i < a.points.size(); ++i) a.point_names.push_back("p" + std::to_string(i));
  return a;
}

TEST(RimRibbon, OpenPathGivesAStrip) {
  Generated g = run("rimribbon", ribbon({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{"width", 1}}));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 6);
  EXPECT_EQ(r.face_count, 2);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_EQ(r.border_loop_count, 1);
  expect_near(named(g.soup, "bc1"), {1, 0, 0});
  expect_near(named(g.soup, "hc1"), {1, 0, 1});
  // A quarter twist over the path turns the far edge from +z to -y.
  Generated t = run("rimribbon", ribbon({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{"width", 1}, {"twist", 90}}));
  expect_near(named(t.soup, "hc0"), {0, 0, 1});
  expect_near(named(t.soup, "hc2"), {2, -1, 0});
  // Azimuth turns the start direction about the first tangent.
  Generated az = run("rimribbon", ribbon({{0, 0, 0}, {1, 0, 0}}, {{"width", 2}, {"azimuth", -90}}));
  expect_near(named(az.soup, "hc0"), {0, 2, 0});
}

TEST(RimRibbon, ClosedPathGivesAnAnnulus) {
  std::vector<glm::dvec3> square = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  Args closed = ribbon(square, {{"width", 0.5}});
  closed.is_path_closed = true;
  Generated g = run("rimribbon", closed);
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 8);
  EXPECT_EQ(r.edge_count, 12);
  EXPECT_EQ(r.face_count, 4);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_EQ(r.border_loop_count, 2);
  EXPECT_TRUE(r.is_orientable);
  expect_near(named(g.soup, "hc2"), {-1, 0, 0.5});
}

TEST(RimRibbon, Errors) {
  EXPECT_EQ(run_error("rimribbon", ribbon({{0, 0, 0}}, {{"width", 1}})).argument, "path");
  EXPECT_EQ(run_error("rimribbon", ribbon({{0, 0, 0}, {0, 0, 0}}, {{"width", 1}})).argument, "path");
  EXPECT_EQ(run_error("rimribbon", ribbon({{0, 0, 0}, {1, 0, 0}}, {{"width", 0}})).argument, "width");
  EXPECT_EQ(run_error("rimribbon", ribbon({{0, 0, 0}, {1, 0, 0}}, {})).argument, "width");
}

}  // namespace
}  // namespace nomec::backend::testing
