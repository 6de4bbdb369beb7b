// The function-surface generators: a plane, the periodic Dupin example of
// nome3/genParametricSurfExample.nom (unwelded, as NOME3 made it), a graph z = f(x, y),
// implicit surfaces, and errors. The functions are given as the evaluable functions the
// backend makes of a checked `funcX [ … ]` (the text itself is lowered and checked by the
// front end: tests/unit/function_text_test.cpp).
#include <algorithm>
#include <cmath>

#include "tests/generators/helpers.h"

namespace nomec::backend::testing {
namespace {

using F = std::function<double(std::span<const double>)>;

Args param(F x, F y, F z, double umax, double vmax, int us, int vs) {
  Args a = numbers({{"u_min", 0}, {"u_max", umax}, {"v_min", 0}, {"v_max", vmax},
                    {"u_segs", double(us)}, {"v_segs", double(vs)}},
                   "nome3");
  a.functions["funcX"] = fn(std::move(x));
  a.functions["funcY"] = fn(std::move(y));
  a.functions["funcZ"] = fn(std::move(z));
  return a;
}

// A function with no value where `bad` holds (`sqrt` of a negative number, say).
ScalarFunction partial(F f, std::function<bool(std::span<const double>)> bad, std::string problem) {
  return [=](std::span<const double> v, std::string* why) -> std::optional<double> {
    if (bad(v)) {
      if (why != nullptr) *why = problem;
      return std::nullopt;
    }
    return f(v);
  };
}

TEST(GenParametricSurf, PlaneIsAGridDisk) {
  Generated g = run("genparametricsurf", param([](auto v) { return v[0]; }, [](auto v) { return 2 * v[1]; },
                                               [](auto) { return 0.0; }, 1, 1, 4, 3));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 20);
  EXPECT_EQ(r.edge_count, 4 * 4 + 5 * 3);
  EXPECT_EQ(r.face_count, 12);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_EQ(r.border_loop_count, 1);
  expect_near(named(g.soup, "v_4_3"), {1, 2, 0});
  expect_near(named(g.soup, "v_2_0"), {0.5, 0, 0});
}

TEST(GenParametricSurf, PeriodicParametrisationKeepsItsSeamsAsInNome3) {
  // nome3/genParametricSurfExample.nom (with 6.28318 for 2 pi): a Dupin cyclide.
  Generated g = run("genparametricsurf",
                    param(
                        [](auto p) {
                          const double u = p[0], v = p[1];
                          return (0.5 * (0.4 - 1 * cos(u) * cos(v)) + 0.96 * cos(u)) / (1 - 0.4 * cos(u) * cos(v));
                        },
                        [](auto p) {
                          const double u = p[0], v = p[1];
                          return (0.98 * sin(u) * (1 - 0.5 * cos(v))) / (1 - 0.4 * cos(u) * cos(v));
                        },
                        [](auto p) {
                          const double u = p[0], v = p[1];
                          return (0.98 * sin(v) * (0.4 * cos(u) - 0.5)) / (1 - 0.48 * cos(u) * cos(v));
                        },
                        6.28318, 6.28318, 20, 12));
  kernel::TopologyReport r = topo(g.soup);
  // 21 × 13 samples (6.28318 < 2π, so the seams do not even touch exactly): a disk.
  EXPECT_EQ(r.vertex_count, 21 * 13);
  EXPECT_EQ(r.face_count, 240);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_EQ(r.border_loop_count, 1);
}

TEST(GenParametricSurf, SpherePolesStayRowsOfVerticesAsInNome3) {
  Generated g = run("genparametricsurf",
                    param([](auto p) { return sin(p[1]) * cos(p[0]); }, [](auto p) { return sin(p[1]) * sin(p[0]); },
                          [](auto p) { return cos(p[1]); }, 2 * M_PI, M_PI, 8, 4));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 9 * 5);
  EXPECT_EQ(r.face_count, 32);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_FALSE(r.is_closed);
  expect_near(named(g.soup, "v_3_0"), {0, 0, 1});
  expect_near(named(g.soup, "v_8_4"), {0, 0, -1});
}

TEST(GenParametricSurf, Errors) {
  const F u = [](auto p) { return p[0]; }, v = [](auto p) { return p[1]; }, zero = [](auto) { return 0.0; };
  Args no_value = param(u, v, zero, 1, 1, 2, 2);
  no_value.functions["funcZ"] = partial([](auto p) { return std::sqrt(p[0] - 0.5); }, [](auto p) { return p[0] < 0.5; },
                                        "square root of a negative number");
  NamedError nan = run_error("genparametricsurf", no_value);
  EXPECT_EQ(nan.argument, "funcZ");
  EXPECT_EQ(nan.message, "`funcZ` cannot be evaluated at u=0, v=0: square root of a negative number");
  Args infinite = param(u, v, [](auto p) { return 1 / p[0]; }, 1, 1, 2, 2);
  EXPECT_EQ(run_error("genparametricsurf", infinite).message, "`funcZ` is not finite at u=0, v=0");
  Args missing = param(u, v, zero, 1, 1, 2, 2);
  missing.functions.erase("funcY");
  EXPECT_EQ(run_error("genparametricsurf", missing).argument, "funcY");
  EXPECT_EQ(run_error("genparametricsurf", param(u, v, zero, 1, 0, 2, 2)).argument, "v_max");
  EXPECT_EQ(run_error("genparametricsurf", param(u, v, zero, 1, 1, 0, 2)).argument, "u_segs");
}

TEST(GenCartesianSurf, GraphOfAFunction) {
  Args a = numbers({{"x_min", -1}, {"x_max", 1}, {"y_min", -1}, {"y_max", 1},
                             {"x_segs", 4}, {"y_segs", 4}});
  a.functions["func"] = fn([](auto p) { return p[0] * p[0] - p[1] * p[1]; });
  Generated g = run("gencartesiansurf", a);
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 25);
  EXPECT_EQ(r.face_count, 16);
  EXPECT_EQ(r.euler_characteristic, 1);
  expect_near(named(g.soup, "v_4_2"), {1, 0, 1});
  expect_near(named(g.soup, "v_2_0"), {0, -1, -1});
  a.functions["func"] = partial([](auto) { return 0.0; }, [](auto p) { return p[0] > 0.5; }, "division by zero: 1 / 0");
  EXPECT_EQ(run_error("gencartesiansurf", a).argument, "func");
}

// NOME3's 9 arguments with `res` cells along each axis (compat.md D2).
Args implicit(ScalarFunction func, double lo, double hi, int res) {
  Args a = numbers({{"x_min", lo}, {"x_max", hi}, {"y_min", lo}, {"y_max", hi}, {"z_min", lo}, {"z_max", hi},
                    {"nx", double(res)}, {"ny", double(res)}, {"nz", double(res)}},
                   "nome3");
  a.functions["func"] = std::move(func);
  return a;
}

Args implicit(F func, double lo, double hi, int res) { return implicit(fn(std::move(func)), lo, hi, res); }

TEST(GenImplicitSurf, SphereIsClosedAndOutward) {
  Generated g = run("genimplicitsurf", implicit([](auto p) { return p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - 1; }, -1.5, 1.5, 12));
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
      topo(run("genimplicitsurf", implicit([](auto p) { return std::pow(std::sqrt(p[0] * p[0] + p[1] * p[1]) - 1, 2) + p[2] * p[2] - 0.16; }, -1.6, 1.6, 24)).soup);
  EXPECT_EQ(torus.components.size(), 1u);
  EXPECT_EQ(torus.euler_characteristic, 0);
  EXPECT_TRUE(torus.is_closed);
  EXPECT_TRUE(torus.is_orientable);
  // A plane cut by the box is a disk; a function without zeros gives nothing.
  kernel::TopologyReport plane = topo(run("genimplicitsurf", implicit([](auto p) { return p[2] - 0.1; }, -1, 1, 4)).soup);
  EXPECT_EQ(plane.euler_characteristic, 1);
  EXPECT_EQ(plane.border_loop_count, 1);
  EXPECT_EQ(run("genimplicitsurf", implicit([](auto p) { return 1 + p[0] * p[0]; }, -1, 1, 4)).soup.face_count(), 0);
}

TEST(GenImplicitSurf, GridReachesOneCellPastMaxAsInNome3) {
  // 4 cells of (1 − (−1))/3: x runs from −1 to 5/3; the plane's disk reaches that far.
  Generated g = run("genimplicitsurf", implicit([](auto p) { return p[2] - 0.1; }, -1, 1, 4));
  double xmax = -10;
  for (const glm::dvec3& p : g.soup.positions) xmax = std::max(xmax, p.x);
  EXPECT_NEAR(xmax, 5.0 / 3.0, 1e-9);
  expect_near(named(g.soup, "v_0"), g.soup.positions[0]);
  // Cells per axis are separate: 2 × 3 × 4 cells of a plane x + y + z = 0.5.
  Args a = numbers({{"x_min", 0}, {"x_max", 1}, {"y_min", 0}, {"y_max", 1}, {"z_min", 0}, {"z_max", 1},
                    {"nx", 2}, {"ny", 3}, {"nz", 4}},
                   "nome3");
  a.functions["func"] = fn([](auto p) { return p[0] + p[1] + p[2] - 0.5; });
  kernel::TopologyReport r = topo(run("genimplicitsurf", a).soup);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_EQ(r.border_loop_count, 1);
}

TEST(GenImplicitSurf, Errors) {
  const F x = [](auto p) { return p[0]; };
  EXPECT_EQ(run_error("genimplicitsurf", implicit(x, -1, 1, 1)).argument, "nx");
  EXPECT_EQ(run_error("genimplicitsurf", implicit(x, -1, 1, 1000)).argument, "nz");
  NamedError log = run_error("genimplicitsurf", implicit(partial([](auto p) { return std::log(p[0]); },
                                                                  [](auto p) { return p[0] <= 0; },
                                                                  "logarithm of a number that is not positive"),
                                                          -1, 1, 4));
  EXPECT_EQ(log.argument, "func");
  EXPECT_EQ(log.message, "`func` cannot be evaluated at x=-1, y=-1, z=-1: logarithm of a number that is not positive");
  EXPECT_EQ(run_error("genimplicitsurf", implicit(x, 1, -1, 4)).argument, "x_max");
}

}  // namespace
}  // namespace nomec::backend::testing
