// Argument domains of the generators: the rules on argument values that do not need any
// geometry to decide (counts with their minimum, positive radii, angle ranges, latitudes,
// `c` < `a` for a Dupin cyclide …), e.g. `circle c (20 1)` -> "`segs` must be at least 3,
// got 1". One source of truth for two clients: `generate` runs these rules before building
// anything (so `--emit` reports them), and the front end's checker runs them on the
// arguments whose values it knows (so `--check` rejects the same files with the same
// message). Header-only dependencies: no kernel, no IR, no syntax.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace nomec::backend {

/// A value outside its generator's domain: the argument's name (as in docs/generators.md),
/// the message (lowercase, no trailing period) and a hint saying what is accepted.
struct ArgumentProblem {
  std::string argument;
  std::string message;
  std::string hint;
};

/// Numbers by argument name; arguments whose value is unknown are simply absent.
using KnownArguments = std::map<std::string, double, std::less<>>;

/// The first domain rule of generator `keyword` broken by `known`, in argument order.
/// Rules that involve an absent argument are skipped, so a partial map (check time) gives
/// a subset of the problems the full map (emit time) gives. `dialect` is "nome", "nome3"
/// or "slide" (it decides the funnel's argument names). Unknown keywords have no rules.
std::optional<ArgumentProblem> check_generator_arguments(std::string_view keyword, std::string_view dialect,
                                                         const KnownArguments& known);

/// `n` rounded to the nearest whole number, as a count; what a generator does with a
/// count like 8.0000001 or 7.6 (the checker warns `NonIntegerCount` for the latter).
int round_count(double n);

/// The number as it appears in messages (`%g`: `0.5`, `1e+06`).
std::string format_argument(double v);

}  // namespace nomec::backend
