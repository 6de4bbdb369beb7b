// The generators' argument-domain rules (see domain.h), one function per generator, each
// listing its rules in argument order.
#include "backend/generators/domain.h"

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>

namespace nomec::backend {
namespace {

constexpr int kMaxCount = 100000;  // also detail::kMaxSegments

std::string q(std::string_view name) { return "`" + std::string(name) + "`"; }

/// Evaluates rules in order and keeps the first problem. A rule whose arguments are not
/// all known is skipped.
class Rules {
 public:
  explicit Rules(const KnownArguments& known) : known_(known) {}

  std::optional<ArgumentProblem> problem;

  /// The value of the first of `names` present (the dialect's own name first).
  const double* get(std::initializer_list<std::string_view> names, std::string_view* found = nullptr) const {
    for (std::string_view n : names) {
      auto it = known_.find(n);
      if (it != known_.end()) {
        if (found != nullptr) *found = n;
        return &it->second;
      }
    }
    return nullptr;
  }

  bool finite(std::string_view name, double v) {
    if (std::isfinite(v)) return true;
    report(name, q(name) + " must be a finite number", "check the expression that computes it");
    return false;
  }

  /// A count >= min (after rounding to a whole number) and <= kMaxCount.
  void count(std::initializer_list<std::string_view> names, int min, std::string_view why = "") {
    std::string_view n;
    const double* v = get(names, &n);
    if (v == nullptr || problem || !finite(n, *v)) return;
    if (std::round(*v) < min) {
      report(n, q(n) + " must be at least " + std::to_string(min) + ", got " + format_argument(*v),
             "use a whole number of " + std::to_string(min) + " or more" + std::string(why));
    } else if (std::round(*v) > kMaxCount) {
      report(n, q(n) + " must be at most " + std::to_string(kMaxCount) + ", got " + format_argument(*v),
             "a finer mesh than this cannot be built in reasonable memory");
    }
  }

  void positive(std::initializer_list<std::string_view> names) {
    std::string_view n;
    const double* v = get(names, &n);
    if (v == nullptr || problem || !finite(n, *v)) return;
    if (!(*v > 0)) {
      report(n, q(n) + " must be positive, got " + format_argument(*v), "sizes and radii must be greater than 0");
    }
  }

  /// `1 + ratio > 0`: the scaled ring radius stays positive.
  void above_minus_one(std::string_view n) {
    const double* v = get({n});
    if (v == nullptr || problem || !finite(n, *v)) return;
    if (!(1.0 + *v > 0)) {
      report(n, q(n) + " must be greater than -1 (the ring radius ro*(1+" + std::string(n) + ") must be positive)",
             "a ratio of -0.5 halves the radius; -1 would shrink the ring to a point");
    }
  }

  /// An angle range in degrees in (0, 360]; returns whether it is a full turn (nullopt if
  /// unknown or broken).
  std::optional<bool> span(std::string_view n, std::optional<double> value) {
    if (!value || problem || !finite(n, *value)) return std::nullopt;
    const double s = *value;
    if (!(s > 0)) {
      report(n, "angle range " + q(n) + " must be positive, got " + format_argument(s) + " degrees",
             "angle ranges are in degrees, greater than 0 and at most 360");
      return std::nullopt;
    }
    if (s > 360.0 + 1e-9) {
      report(n, "angle range " + q(n) + " must be at most 360 degrees, got " + format_argument(s),
             "use 360 for a full turn; the surface is closed seamlessly");
      return std::nullopt;
    }
    return s >= 360.0 - 1e-9;
  }
  std::optional<bool> span(std::string_view n) {
    const double* v = get({n});
    return span(n, v ? std::optional<double>(*v) : std::nullopt);
  }

  void nonzero(std::string_view n) {
    const double* v = get({n});
    if (v == nullptr || problem || !finite(n, *v)) return;
    if (*v == 0.0) report(n, q(n) + " must not be 0", "a zero here gives a degenerate curve or surface");
  }

  void whole_nonzero(std::string_view n) {
    const double* v = get({n});
    if (v == nullptr || problem || !finite(n, *v)) return;
    if (std::abs(*v - std::round(*v)) > 1e-9 || std::lround(*v) == 0) {
      report(n, q(n) + " must be a non-zero whole number, got " + format_argument(*v),
             "the knot winds a whole number of times; negative numbers wind the other way");
    } else if (std::abs(*v) > 1000) {
      report(n, q(n) + " must be at most 1000 in absolute value", "use a smaller winding number");
    }
  }

  void greater(std::string_view lo, std::string_view hi) {
    const double* a = get({lo});
    const double* b = get({hi});
    if (a == nullptr || b == nullptr || problem || !finite(lo, *a) || !finite(hi, *b)) return;
    if (!(*b > *a)) {
      report(hi, q(hi) + " must be greater than " + q(lo), "swap the two bounds, or widen the range");
    }
  }

  void report(std::string_view n, std::string message, std::string hint) {
    if (!problem) problem = ArgumentProblem{std::string(n), std::move(message), std::move(hint)};
  }

 private:
  const KnownArguments& known_;
};

void funnel(Rules& r, bool nome3, bool tunnel) {
  // Argument order of the dialect (docs/generators.md).
  if (nome3) {
    r.positive({"radius", "ro"});
    r.above_minus_one("ratio");
    r.count({"n"}, 3, " (a ring of fewer sides has no area)");
  } else {
    r.count({"n"}, 3, " (a ring of fewer sides has no area)");
    r.positive({"ro", "radius"});
    r.above_minus_one("ratio");
  }
  if (tunnel) r.above_minus_one("dri_low");
}

// Sphere and ellipsoid after their radii: azimuth range, latitudes, segment counts.
void spheroid(Rules& r) {
  const std::optional<bool> wrap = r.span("theta_max");
  const double* lo = r.get({"phi_min"});
  const double* hi = r.get({"phi_max"});
  if (lo != nullptr && !r.problem && r.finite("phi_min", *lo) && (*lo < -90.0 - 1e-9 || *lo > 90.0)) {
    r.report("phi_min", "`phi_min` is a latitude and must be within [-90, 90] degrees, got " + format_argument(*lo),
             "-90 is the south pole, 90 the north pole");
  }
  if (hi != nullptr && !r.problem && r.finite("phi_max", *hi) && (*hi > 90.0 + 1e-9 || *hi < -90.0)) {
    r.report("phi_max", "`phi_max` is a latitude and must be within [-90, 90] degrees, got " + format_argument(*hi),
             "-90 is the south pole, 90 the north pole");
  }
  r.greater("phi_min", "phi_max");
  if (wrap) r.count({"theta_segs"}, *wrap ? 3 : 1, *wrap ? " around a full turn" : "");
  if (lo != nullptr && hi != nullptr) {
    const bool both_poles = *lo <= -90.0 + 1e-9 && *hi >= 90.0 - 1e-9;
    r.count({"phi_segs"}, both_poles ? 2 : 1, both_poles ? " from pole to pole" : "");
  }
}

}  // namespace

std::string format_argument(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

int round_count(double n) { return static_cast<int>(std::lround(n)); }

std::optional<ArgumentProblem> check_generator_arguments(std::string_view k, std::string_view dialect,
                                                         const KnownArguments& known) {
  Rules r(known);
  if (k == "funnel" || k == "tunnel") {
    funnel(r, dialect == "nome3", k == "tunnel");
  } else if (k == "circle") {
    r.positive({"radius"});
    r.count({"segs"}, 3, " (a circle of fewer segments has no area)");
  } else if (k == "mobiusstrip") {
    r.positive({"radius"});
    std::string_view n;
    const double* tw = r.get({"num_twists", "numTwists"}, &n);
    if (tw != nullptr && !r.problem && r.finite(n, *tw) && std::abs(*tw - std::round(*tw)) > 1e-9) {
      r.report(n, "`num_twists` must be a whole number of half-twists", "1 gives a Möbius band, 2 a full twist");
    }
    const double* cuts = r.get({"num_cuts", "numCuts"}, &n);
    if (cuts != nullptr && !r.problem && *cuts != 0.0) {
      r.report(n, "cuts are not supported yet: `num_cuts` must be 0", "use 0 and cut the band with `delete`");
    }
    r.count({"n", "N"}, 3);
  } else if (k == "rimribbon") {
    r.nonzero("width");
  } else if (k == "sphere") {
    r.positive({"radius"});
    spheroid(r);
  } else if (k == "ellipsoid") {
    r.positive({"a"});
    r.positive({"b"});
    spheroid(r);
  } else if (k == "cylinder") {
    r.positive({"radius"});
    r.positive({"height"});
    if (auto wrap = r.span("theta_max")) r.count({"theta_segs"}, *wrap ? 3 : 1, *wrap ? " around a full turn" : "");
    r.count({"height_segs"}, 1);
  } else if (k == "hyperboloid") {
    for (std::string_view n : {"a", "b", "c", "height"}) r.positive({n});
    r.count({"theta_segs"}, 3, " around a full turn");
    r.count({"height_segs"}, 1);
  } else if (k == "dupin") {
    r.positive({"a"});
    r.positive({"b"});
    const double* a = r.get({"a"});
    const double* c = r.get({"c"});
    if (a != nullptr && c != nullptr && !r.problem && r.finite("c", *c) && !(*a > std::abs(*c))) {
      r.report("c", "`c` must be smaller than `a` in absolute value (the cyclide is unbounded otherwise)",
               "choose |c| < a");
    }
    r.count({"u_segs"}, 3, " around a full turn");
    r.count({"v_segs"}, 3, " around a full turn");
  } else if (k == "torus") {
    r.positive({"major_radius"});
    r.positive({"minor_radius"});
    const std::optional<bool> wrap_i = r.span("theta_max");
    const double* lo = r.get({"phi_min"});
    const double* hi = r.get({"phi_max"});
    std::optional<bool> wrap_j;
    if (lo != nullptr && hi != nullptr) wrap_j = r.span("phi_max", *hi - *lo);
    if (wrap_i) r.count({"theta_segs"}, *wrap_i ? 3 : 1, *wrap_i ? " around a full turn" : "");
    if (wrap_j) r.count({"phi_segs"}, *wrap_j ? 3 : 1, *wrap_j ? " around a full turn" : "");
  } else if (k == "torusknot") {
    r.whole_nonzero("symm");
    r.whole_nonzero("turns");
    for (std::string_view n : {"major_radius", "minor_radius", "tube_radius"}) r.positive({n});
    r.count({"circ_segs"}, 3, " around the tube");
    r.count({"sweep_segs"}, 3, " along the closed knot");
  } else if (k == "helix") {
    r.positive({"radius"});
    r.nonzero("turns");
    r.count({"segs"}, 1);
  } else if (k == "spiral") {
    r.positive({"growth"});
    r.nonzero("turns");
    r.count({"segs"}, 1);
  } else if (k == "genparametricsurf") {
    r.greater("u_min", "u_max");
    r.greater("v_min", "v_max");
    r.count({"u_segs"}, 1);
    r.count({"v_segs"}, 1);
  } else if (k == "gencartesiansurf") {
    r.greater("x_min", "x_max");
    r.greater("y_min", "y_max");
    r.count({"x_segs"}, 1);
    r.count({"y_segs"}, 1);
  } else if (k == "genimplicitsurf") {
    r.greater("x_min", "x_max");
    r.greater("y_min", "y_max");
    r.greater("z_min", "z_max");
    r.count({"resolution"}, 1);
    const double* res = r.get({"resolution"});
    if (res != nullptr && !r.problem && std::round(*res) > 128) {
      r.report("resolution", "`resolution` must be at most 128, got " + std::to_string(round_count(*res)),
               "the surface is sampled on a resolution³ grid; 128 is already 2 million samples");
    }
  } else if (k == "beziercurve") {
    r.count({"segs", "slices"}, 1);
  } else if (k == "bspline" || k == "bsplinecurve") {
    r.count({"order"}, 2);
  }
  return r.problem;
}

}  // namespace nomec::backend
