// The expression evaluator and the function-surface generators: a plane, the periodic
// Dupin example of nome3/genParametricSurfExample.nom (welded into a closed surface), a
// graph z = f(x, y), and errors for bad texts.
#include <cmath>

#include "backend/generators/expr.h"
#include "tests/generators/helpers.h"

namespace nomec::backend::testing {
namespace {

double eval(std::string_view text, double u = 0, double v = 0) {
  std::string error;
  auto e = Expression::parse(text, {"u", "v"}, &error);
  EXPECT_TRUE(e.has_value()) << text << ": " << error;
  return e ? e->evaluate({u, v}) : NAN;
}

std::string parse_error(std::string_view text) {
  std::string error;
  auto e = Expression::parse(text, {"u", "v"}, &error);
  EXPECT_FALSE(e.has_value()) << text;
  return error;
}

TEST(Expression, Arithmetic) {
  EXPECT_DOUBLE_EQ(eval("1 + 2 * 3"), 7);
  EXPECT_DOUBLE_EQ(eval("(1 + 2) * 3"), 9);
  EXPECT_DOUBLE_EQ(eval("2 ^ 3 ^ 2"), 512);
  EXPECT_DOUBLE_EQ(eval("-2 ^ 2"), -4);
  EXPECT_DOUBLE_EQ(eval("2 ^ -1"), 0.5);
  EXPECT_DOUBLE_EQ(eval("8 / 4 / 2"), 1);
  EXPECT_DOUBLE_EQ(eval("10 - 4 - 3"), 3);
  EXPECT_DOUBLE_EQ(eval("--u", 3), 3);
  EXPECT_DOUBLE_EQ(eval("u * v + 1", 2, 5), 11);
  EXPECT_DOUBLE_EQ(eval("1.5e2"), 150);
  EXPECT_DOUBLE_EQ(eval(".5"), 0.5);
  EXPECT_NEAR(eval("cos(pi)"), -1, 1e-15);
  EXPECT_NEAR(eval("log(e)"), 1, 1e-15);
  EXPECT_NEAR(eval("sqrt(abs(-16)) + exp(0) + sinh(0) + cosh(0) + tanh(0)"), 6, 1e-15);
  EXPECT_NEAR(eval("asin(1) + acos(1) + atan(0) + tan(0) + sin(0)"), M_PI / 2, 1e-15);
}

TEST(Expression, Errors) {
  EXPECT_NE(parse_error("w + 1").find("unknown name `w`"), std::string::npos);
  EXPECT_NE(parse_error("foo(u)").find("unknown function `foo`"), std::string::npos);
  EXPECT_NE(parse_error("(u + 1").find("missing `)`"), std::string::npos);
  EXPECT_NE(parse_error("u +").find("unexpected end"), std::string::npos);
  EXPECT_NE(parse_error("u v").find("unexpected `v`"), std::string::npos);
  EXPECT_NE(parse_error("u $ 2").find("unexpected `$`"), std::string::npos);
  EXPECT_EQ(parse_error("   "), "empty expression");
  EXPECT_EQ(parse_error(std::string(1000, '(') + "u" + std::string(1000, ')')),
            "expression nested too deeply");
  EXPECT_EQ(parse_error(std::string(1000, '-') + "u"), "expression nested too deeply");
  std::string chain = "u";
  for (int i = 0; i < 100000; ++i) chain += "+u";
  EXPECT_EQ(parse_error(chain), "expression too long or nested too deeply");
  std::string ok = "u";
  for (int i = 0; i < 1000; ++i) ok += "+u";
  EXPECT_DOUBLE_EQ(eval(ok, 1), 1001);
}

GeneratorArgs param(std::string x, std::string y, std::string z, double umax, double vmax, int us, int vs) {
  GeneratorArgs a = numbers({{"u_min", 0}, {"u_max", umax}, {"v_min", 0}, {"v_max", vmax},
                             {"u_segs", double(us)}, {"v_segs", double(vs)}},
                            "nome3");
  a.texts["funcX"] = "[" + x + "]";
  a.texts["funcY"] = "[" + y + "]";
  a.texts["funcZ"] = z;  // brackets are optional
  return a;
}

TEST(GenParametricSurf, PlaneIsAGridDisk) {
  Generated g = run("genparametricsurf", param("u", "2*v", "0", 1, 1, 4, 3));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 20);
  EXPECT_EQ(r.edge_count, 4 * 4 + 5 * 3);
  EXPECT_EQ(r.face_count, 12);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_EQ(r.border_loop_count, 1);
  expect_near(named(g.soup, "v4_3"), {1, 2, 0});
  expect_near(named(g.soup, "v2_0"), {0.5, 0, 0});
}

TEST(GenParametricSurf, PeriodicParametrisationIsWelded) {
  // nome3/genParametricSurfExample.nom (with 6.28318 for 2 pi): a Dupin cyclide.
  Generated g = run("genparametricsurf",
                    param("(0.5*(0.4-1*cos(u)*cos(v))+0.96*cos(u))/(1-0.4*cos(u)*cos(v))",
                          "(0.98*sin(u)*(1-0.5*cos(v)))/(1-0.4*cos(u)*cos(v))",
                          "(0.98*sin(v)*(0.4*cos(u)-0.5))/(1-0.48*cos(u)*cos(v))", 6.28318,
                          6.28318, 20, 12));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 240);
  EXPECT_EQ(r.face_count, 240);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_TRUE(r.is_closed);
}

TEST(GenParametricSurf, SpherePolesCollapseToSingleVertices) {
  Generated g = run("genparametricsurf",
                    param("sin(v)*cos(u)", "sin(v)*sin(u)", "cos(v)", 2 * M_PI, M_PI, 8, 4));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 2 + 8 * 3);
  EXPECT_EQ(r.face_count, 32);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_TRUE(r.is_closed);
}

TEST(GenParametricSurf, Errors) {
  GeneratorError unknown = run_error("genparametricsurf", param("u + w", "v", "0", 1, 1, 2, 2));
  EXPECT_EQ(unknown.argument, "funcX");
  EXPECT_NE(unknown.message.find("unknown name `w`"), std::string::npos) << unknown.message;
  GeneratorError nan = run_error("genparametricsurf", param("u", "v", "sqrt(u - 0.5)", 1, 1, 2, 2));
  EXPECT_EQ(nan.argument, "funcZ");
  GeneratorArgs missing = param("u", "v", "0", 1, 1, 2, 2);
  missing.texts.erase("funcY");
  EXPECT_EQ(run_error("genparametricsurf", missing).argument, "funcY");
  EXPECT_EQ(run_error("genparametricsurf", param("u", "v", "0", 1, 0, 2, 2)).argument, "v_max");
  EXPECT_EQ(run_error("genparametricsurf", param("u", "v", "0", 1, 1, 0, 2)).argument, "u_segs");
}

TEST(GenCartesianSurf, GraphOfAFunction) {
  GeneratorArgs a = numbers({{"x_min", -1}, {"x_max", 1}, {"y_min", -1}, {"y_max", 1},
                             {"x_segs", 4}, {"y_segs", 4}});
  a.texts["func"] = "[x^2 - y^2]";
  Generated g = run("gencartesiansurf", a);
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 25);
  EXPECT_EQ(r.face_count, 16);
  EXPECT_EQ(r.euler_characteristic, 1);
  expect_near(named(g.soup, "v4_2"), {1, 0, 1});
  expect_near(named(g.soup, "v2_0"), {0, -1, -1});
  a.texts["func"] = "[u]";
  EXPECT_EQ(run_error("gencartesiansurf", a).argument, "func");
}

GeneratorArgs implicit(std::string func, double lo, double hi, int res) {
  GeneratorArgs a = numbers({{"x_min", lo}, {"x_max", hi}, {"y_min", lo}, {"y_max", hi},
                             {"z_min", lo}, {"z_max", hi}, {"resolution", double(res)}},
                            "nome3");
  a.texts["func"] = "[" + func + "]";
  return a;
}

TEST(GenImplicitSurf, SphereIsClosedAndOutward) {
  Generated g = run("genimplicitsurf", implicit("x^2 + y^2 + z^2 - 1", -1.5, 1.5, 12));
  kernel::TopologyReport r = topo(g.soup);
  ASSERT_EQ(r.components.size(), 1u);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_TRUE(r.is_closed);
  EXPECT_TRUE(r.is_orientable);
  EXPECT_EQ(r.components[0].mobius_edge_count, 0);
  EXPECT_NEAR(signed_volume(g.soup), 4.0 / 3.0 * M_PI, 0.3);
  for (const glm::dvec3& p : g.soup.positions) {
    EXPECT_NEAR(std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z), 1.0, 0.1);
  }
}

TEST(GenImplicitSurf, TorusAndClippedPlane) {
  kernel::TopologyReport torus =
      topo(run("genimplicitsurf", implicit("(sqrt(x^2 + y^2) - 1)^2 + z^2 - 0.16", -1.6, 1.6, 24)).soup);
  EXPECT_EQ(torus.components.size(), 1u);
  EXPECT_EQ(torus.euler_characteristic, 0);
  EXPECT_TRUE(torus.is_closed);
  EXPECT_TRUE(torus.is_orientable);
  // A plane cut by the box is a disk; a function without zeros gives nothing.
  kernel::TopologyReport plane = topo(run("genimplicitsurf", implicit("z - 0.1", -1, 1, 4)).soup);
  EXPECT_EQ(plane.euler_characteristic, 1);
  EXPECT_EQ(plane.border_loop_count, 1);
  EXPECT_EQ(run("genimplicitsurf", implicit("1 + x^2", -1, 1, 4)).soup.face_count(), 0);
}

TEST(GenImplicitSurf, Errors) {
  EXPECT_EQ(run_error("genimplicitsurf", implicit("x + w", -1, 1, 4)).argument, "func");
  EXPECT_EQ(run_error("genimplicitsurf", implicit("x", -1, 1, 0)).argument, "resolution");
  EXPECT_EQ(run_error("genimplicitsurf", implicit("x", -1, 1, 1000)).argument, "resolution");
  EXPECT_EQ(run_error("genimplicitsurf", implicit("log(x)", -1, 1, 4)).argument, "func");
  EXPECT_EQ(run_error("genimplicitsurf", implicit("x", 1, -1, 4)).argument, "x_max");
}

}  // namespace
}  // namespace nomec::backend::testing
