// Tests of the generators' argument-domain rules (ir::check_arguments, from the generator
// catalogue): the same problem from the partial set of values the checker has and from
// `generate`, rules with unknown arguments skipped, dialect-dependent argument order, and
// hints present.
#include <gtest/gtest.h>

#include "ir/generator_catalogue.h"
#include "tests/generators/helpers.h"

namespace nomec::backend::testing {
namespace {

using KnownArguments = std::map<std::string, double>;

// The catalogue's rules on values given by name, the problem's argument named as the
// dialect writes it.
std::optional<NamedError> check_generator_arguments(std::string_view keyword, std::string_view dialect,
                                                    const KnownArguments& known) {
  std::optional<ir::GenKind> kind = ir::generator_by_keyword(keyword);
  if (!kind) return std::nullopt;
  const ir::GeneratorInfo& info = ir::generator(*kind);
  std::vector<std::optional<double>> values(info.args.size());
  for (const auto& [name, v] : known) {
    std::optional<ir::ArgIndex> arg = info.arg_named(name);
    EXPECT_TRUE(arg.has_value()) << keyword << " has no argument " << name;
    if (arg) values[*arg] = v;
  }
  const Dialect d = dialect_by_name(dialect).value_or(Dialect::Nome);
  std::optional<ir::ArgProblem> p = ir::check_arguments(*kind, d, values);
  if (!p) return std::nullopt;
  return NamedError{std::string(info.display_name(p->arg, d)), p->message, p->hint};
}

TEST(Domain, CircleSegmentsAtLeastThree) {
  auto p = check_generator_arguments("circle", "nome3", {{"radius", 20}, {"segs", 1}});
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->argument, "segs");
  EXPECT_EQ(p->message, "`segs` must be at least 3, got 1");
  EXPECT_FALSE(p->hint.empty());
  // `generate` reports exactly the same problem.
  NamedError e = run_error("circle", numbers({{"radius", 20}, {"segs", 1}}, "nome3"));
  EXPECT_EQ(e.argument, p->argument);
  EXPECT_EQ(e.message, p->message);
  EXPECT_EQ(e.hint, p->hint);
}

TEST(Domain, UnknownArgumentsSkipTheirRules) {
  // `segs` depends on something the checker cannot evaluate: the radius rule still runs.
  EXPECT_FALSE(check_generator_arguments("circle", "nome3", {{"radius", 2}}).has_value());
  auto p = check_generator_arguments("circle", "nome3", {{"radius", -2}});
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->argument, "radius");
  // The torus' phi range needs both ends.
  EXPECT_FALSE(check_generator_arguments("torus", "nome3", {{"phi_max", 0}}).has_value());
  EXPECT_FALSE(check_generator_arguments("torus", "nome3", {}).has_value());
}

TEST(Domain, FirstProblemInTheDialectsArgumentOrder) {
  // NOME 2016 funnel (n ro ratio h) vs NOME3 (radius ratio height n).
  KnownArguments both_bad{{"n", 2}, {"ro", -1}, {"ratio", 0}};
  EXPECT_EQ(check_generator_arguments("funnel", "nome", both_bad)->argument, "n");
  EXPECT_EQ(check_generator_arguments("funnel", "nome3", both_bad)->argument, "radius");
}

TEST(Domain, WrapDependentMinimums) {
  // A full-turn torus needs 3 segments around; a half-turn one needs 1.
  KnownArguments full{{"major_radius", 2}, {"minor_radius", 1}, {"theta_max", 360}, {"phi_min", 0},
                      {"phi_max", 360}, {"theta_segs", 2}, {"phi_segs", 8}};
  EXPECT_EQ(check_generator_arguments("torus", "nome3", full)->argument, "theta_segs");
  full["theta_max"] = 180;
  EXPECT_FALSE(check_generator_arguments("torus", "nome3", full).has_value());
  // A sphere from pole to pole needs 2 latitude bands.
  KnownArguments sphere{{"radius", 1}, {"theta_max", 360}, {"phi_min", -90}, {"phi_max", 90},
                        {"theta_segs", 8}, {"phi_segs", 1}};
  EXPECT_EQ(check_generator_arguments("sphere", "nome3", sphere)->argument, "phi_segs");
  sphere["phi_min"] = 0;
  EXPECT_FALSE(check_generator_arguments("sphere", "nome3", sphere).has_value());
}

TEST(Domain, CountsAreRoundedBeforeTheMinimum) {
  EXPECT_FALSE(check_generator_arguments("circle", "nome", {{"radius", 1}, {"segs", 2.6}}).has_value());
  EXPECT_TRUE(check_generator_arguments("circle", "nome", {{"radius", 1}, {"segs", 2.4}}).has_value());
}

TEST(Domain, OtherRules) {
  EXPECT_EQ(check_generator_arguments("dupin", "nome3", {{"a", 1}, {"b", 1}, {"c", 2}})->argument, "c");
  EXPECT_EQ(check_generator_arguments("torusknot", "nome3", {{"symm", 0}})->argument, "symm");
  // A torus knot's tube radius may be 0 (the knot itself, a line strip), not negative.
  EXPECT_FALSE(check_generator_arguments("torusknot", "nome3", {{"tube_radius", 0}}).has_value());
  EXPECT_EQ(check_generator_arguments("torusknot", "nome3", {{"tube_radius", -0.5}})->argument, "tube_radius");
  EXPECT_EQ(check_generator_arguments("helix", "nome3", {{"radius", 1}, {"theta_max", 0}})->argument, "theta_max");
  EXPECT_EQ(check_generator_arguments("spiral", "nome3", {{"rate", 1}, {"angle", -0.9}})->argument, "angle");
  EXPECT_EQ(check_generator_arguments("genimplicitsurf", "nome3", {{"nx", 1}})->argument, "nx");
  EXPECT_EQ(check_generator_arguments("genimplicitsurf", "nome3", {{"nx", 200}, {"ny", 200}, {"nz", 200}})->argument, "nz");
  EXPECT_EQ(check_generator_arguments("hyperboloid", "nome3", {{"sheet", 1}})->argument, "sheet");
  EXPECT_EQ(check_generator_arguments("dupin", "nome3", {{"u", 2.5}})->argument, "u");
  // A cylinder's theta_max is truncated: 0.9 is 0 degrees; 360.5 is a full turn.
  EXPECT_EQ(check_generator_arguments("cylinder", "nome3", {{"theta_max", 0.9}})->argument, "theta_max");
  EXPECT_FALSE(check_generator_arguments("cylinder", "nome3", {{"theta_max", 360.5}, {"theta_segs", 3}}).has_value());
  EXPECT_EQ(check_generator_arguments("gencartesiansurf", "nome3", {{"x_min", 1}, {"x_max", 1}})->argument, "x_max");
  EXPECT_EQ(check_generator_arguments("tunnel", "nome", {{"dri_low", -2}})->argument, "dri_low");
  EXPECT_FALSE(check_generator_arguments("nosuchgenerator", "nome", {{"segs", 0}}).has_value());
}

}  // namespace
}  // namespace nomec::backend::testing
