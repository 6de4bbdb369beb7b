// The generators' argument-domain rules (see generator_catalogue.h): the rules on argument
// values that need no geometry to decide (counts with their minimum, positive radii, angle
// ranges, latitudes, `c` < `a` for a Dupin cyclide …), e.g. `circle c (20 1)` → "`segs`
// must be at least 3, got 1". One function per generator lists its rules in the dialect's
// argument order; `--check` runs them on the values it knows and the backend on all values
// before it builds anything. Rules that follow from an argument's declared type alone
// (ir/generators.def) are applied to every generator by `type_rules`.
#include <cmath>
#include <string>

#include "ir/generator_catalogue.h"

namespace nomec::ir {
namespace {

/// Evaluates rules in order and keeps the first problem. A rule whose arguments are not
/// all known is skipped.
class Rules {
 public:
  Rules(GenKind kind, Dialect dialect, KnownArgs known) : info_(generator(kind)), dialect_(dialect), known_(known) {}

  std::optional<ArgProblem> problem;

  template <typename E>
  const double* get(E arg) const {
    const size_t i = arg_index(arg);
    return i < known_.size() && known_[i] ? &*known_[i] : nullptr;
  }

  template <typename E>
  std::string q(E arg) const {
    return "`" + std::string(info_.display_name(arg_index(arg), dialect_)) + "`";
  }

  template <typename E>
  bool finite(E arg, double v) {
    if (std::isfinite(v)) return true;
    report(arg, q(arg) + " must be a finite number", "check the expression that computes it");
    return false;
  }

  /// A count >= min (after rounding to a whole number) and <= kMaxCount.
  template <typename E>
  void count(E arg, int min, std::string_view why = "") {
    const double* v = get(arg);
    if (v == nullptr || problem || !finite(arg, *v)) return;
    if (std::round(*v) < min) {
      report(arg, q(arg) + " must be at least " + std::to_string(min) + ", got " + format_argument(*v),
             "use a whole number of " + std::to_string(min) + " or more" + std::string(why));
    } else if (std::round(*v) > kMaxCount) {
      report(arg, q(arg) + " must be at most " + std::to_string(kMaxCount) + ", got " + format_argument(*v),
             "a finer mesh than this cannot be built in reasonable memory");
    }
  }

  /// A real number in [min, kMaxCount] (NOME3's fractional step counts).
  template <typename E>
  void real_at_least(E arg, double min, std::string hint) {
    const double* v = get(arg);
    if (v == nullptr || problem || !finite(arg, *v)) return;
    if (!(*v >= min)) {
      report(arg, q(arg) + " must be at least " + format_argument(min) + ", got " + format_argument(*v), std::move(hint));
    } else if (*v > kMaxCount) {
      report(arg, q(arg) + " must be at most " + std::to_string(kMaxCount) + ", got " + format_argument(*v),
             "a finer mesh than this cannot be built in reasonable memory");
    }
  }

  /// A size that may be 0 (a torus knot's tube: 0 makes the knot itself, no tube).
  template <typename E>
  void nonnegative(E arg, std::string hint) {
    const double* v = get(arg);
    if (v == nullptr || problem || !finite(arg, *v)) return;
    if (!(*v >= 0)) report(arg, q(arg) + " must not be negative, got " + format_argument(*v), std::move(hint));
  }

  template <typename E>
  void positive(E arg) {
    const double* v = get(arg);
    if (v == nullptr || problem || !finite(arg, *v)) return;
    if (!(*v > 0)) {
      report(arg, q(arg) + " must be positive, got " + format_argument(*v), "sizes and radii must be greater than 0");
    }
  }

  /// `1 + ratio > 0`: the scaled ring radius stays positive.
  template <typename E>
  void above_minus_one(E arg) {
    const double* v = get(arg);
    if (v == nullptr || problem || !finite(arg, *v)) return;
    if (!(1.0 + *v > 0)) {
      const std::string n(info_.display_name(arg_index(arg), dialect_));
      report(arg, q(arg) + " must be greater than -1 (the ring radius ro*(1+" + n + ") must be positive)",
             "a ratio of -0.5 halves the radius; -1 would shrink the ring to a point");
    }
  }

  /// An angle range in degrees in (0, 360]; returns whether it is a full turn (nullopt if
  /// unknown or broken).
  template <typename E>
  std::optional<bool> span(E arg, std::optional<double> value) {
    if (!value || problem || !finite(arg, *value)) return std::nullopt;
    const double s = *value;
    if (!(s > 0)) {
      report(arg, "angle range " + q(arg) + " must be positive, got " + format_argument(s) + " degrees",
             "angle ranges are in degrees, greater than 0 and at most 360");
      return std::nullopt;
    }
    if (s > 360.0 + 1e-9) {
      report(arg, "angle range " + q(arg) + " must be at most 360 degrees, got " + format_argument(s),
             "use 360 for a full turn; the surface is closed seamlessly");
      return std::nullopt;
    }
    return s >= 360.0 - 1e-9;
  }
  template <typename E>
  std::optional<bool> span(E arg) {
    const double* v = get(arg);
    return span(arg, v ? std::optional<double>(*v) : std::nullopt);
  }

  /// A latitude within [-90, 90] whole degrees (NOME3 cut off the fraction).
  template <typename E>
  void latitude(E arg) {
    const double* v = get(arg);
    if (v == nullptr || problem || !finite(arg, *v)) return;
    if (std::trunc(*v) < -90.0 || std::trunc(*v) > 90.0) {
      report(arg, q(arg) + " is a latitude and must be within [-90, 90] degrees, got " + format_argument(*v),
             "-90 is the north pole (the top row), 90 the south pole, as in NOME3");
    }
  }

  /// A number in [0, 1].
  template <typename E>
  void fraction(E arg) {
    const double* v = get(arg);
    if (v == nullptr || problem || !finite(arg, *v)) return;
    if (*v < 0.0 || *v > 1.0) {
      report(arg, q(arg) + " is a fraction and must be within [0, 1], got " + format_argument(*v),
             "0 is the start, 1 the end; 0.5 is half way");
    }
  }

  template <typename E>
  void nonzero(E arg) {
    const double* v = get(arg);
    if (v == nullptr || problem || !finite(arg, *v)) return;
    if (*v == 0.0) report(arg, q(arg) + " must not be 0", "a zero here gives a degenerate curve or surface");
  }

  template <typename E>
  void whole_nonzero(E arg) {
    const double* v = get(arg);
    if (v == nullptr || problem || !finite(arg, *v)) return;
    if (std::abs(*v - std::round(*v)) > 1e-9 || std::lround(*v) == 0) {
      report(arg, q(arg) + " must be a non-zero whole number, got " + format_argument(*v),
             "the knot winds a whole number of times; negative numbers wind the other way");
    } else if (std::abs(*v) > 1000) {
      report(arg, q(arg) + " must be at most 1000 in absolute value", "use a smaller winding number");
    }
  }

  template <typename E>
  void greater(E lo, E hi) {
    const double* a = get(lo);
    const double* b = get(hi);
    if (a == nullptr || b == nullptr || problem || !finite(lo, *a) || !finite(hi, *b)) return;
    if (!(*b > *a)) report(hi, q(hi) + " must be greater than " + q(lo), "swap the two bounds, or widen the range");
  }

  template <typename E>
  void report(E arg, std::string message, std::string hint) {
    if (!problem) problem = ArgProblem{arg_index(arg), std::move(message), std::move(hint)};
  }

  Dialect dialect() const { return dialect_; }

 private:
  const GeneratorInfo& info_;
  Dialect dialect_;
  KnownArgs known_;
};

template <typename A>
void funnel_or_tunnel(Rules& r) {
  // The dialect's argument order: NOME3 writes the funnel `(radius ratio height n)`.
  if (r.dialect() == Dialect::Nome3) {
    r.positive(A::ro);
    r.above_minus_one(A::ratio);
    r.count(A::n, 3, " (a ring of fewer sides has no area)");
  } else {
    r.count(A::n, 3, " (a ring of fewer sides has no area)");
    r.positive(A::ro);
    r.above_minus_one(A::ratio);
  }
}

// Sphere and ellipsoid after their radii: azimuth range, latitudes, segment counts.
template <typename A>
void spheroid(Rules& r) {
  const std::optional<bool> wrap = r.span(A::theta_max);
  r.latitude(A::phi_min);
  r.latitude(A::phi_max);
  r.greater(A::phi_min, A::phi_max);
  if (wrap) r.count(A::theta_segs, *wrap ? 3 : 1, *wrap ? " around a full turn" : "");
  const double* lo = r.get(A::phi_min);
  const double* hi = r.get(A::phi_max);
  if (lo != nullptr && hi != nullptr) {
    const bool both_poles = *lo <= -90.0 + 1e-9 && *hi >= 90.0 - 1e-9;
    r.count(A::phi_segs, both_poles ? 2 : 1, both_poles ? " from pole to pole" : "");
  }
}

// Ring generators and ribbons.
void ring_rules(GenKind kind, Rules& r) {
  switch (kind) {
    case GenKind::Funnel:
      funnel_or_tunnel<gen_arg::Funnel>(r);
      return;
    case GenKind::Tunnel:
      funnel_or_tunnel<gen_arg::Tunnel>(r);
      r.above_minus_one(gen_arg::Tunnel::dri_low);
      return;
    case GenKind::Circle:
      r.positive(gen_arg::Circle::radius);
      r.count(gen_arg::Circle::segs, 3, " (a circle of fewer segments has no area)");
      return;
    case GenKind::Mobiusstrip: {
      // NOME3 rounds the twists and cuts up and steps π/n with a real n (generators-original.md §6).
      using A = gen_arg::Mobiusstrip;
      r.positive(A::radius);
      const double* cuts = r.get(A::num_cuts);
      if (cuts != nullptr && !r.problem && r.finite(A::num_cuts, *cuts)) {
        if (std::ceil(*cuts) < 0.0) {
          r.report(A::num_cuts, r.q(A::num_cuts) + " must not be negative, got " + format_argument(*cuts),
                   "0 gives one band, k gives k + 1 parallel bands");
        } else if (*cuts > kMaxCount) {
          r.report(A::num_cuts, r.q(A::num_cuts) + " must be at most " + std::to_string(kMaxCount),
                   "a finer mesh than this cannot be built in reasonable memory");
        }
      }
      r.real_at_least(A::n, 0.5, "the strip has 2n steps of π/n; n = 50 gives a smooth band");
      return;
    }
    case GenKind::Rimribbon:
      r.nonzero(gen_arg::Rimribbon::width);
      return;
    default:
      return;
  }
}

// SLIDE's cyclide (quadrics.cpp): a ring cyclide needs |eccentricity| < minorradius <
// majorradius; the defaults (a quarter and an eighth of majorradius) satisfy both.
void cyclide_rules(Rules& r) {
  using A = gen_arg::Cyclide;
  r.positive(A::major_radius);
  r.positive(A::minor_radius);
  const double* ma = r.get(A::major_radius);
  const double* d = r.get(A::minor_radius);
  const double* c = r.get(A::eccentricity);
  if (ma != nullptr && d != nullptr && !r.problem && !(*d < *ma)) {
    r.report(A::minor_radius, r.q(A::minor_radius) + " must be smaller than " + r.q(A::major_radius) +
                                  " (the tube would reach the axis and the cyclide intersect itself)",
             "a ring cyclide needs |eccentricity| < minorradius < majorradius");
  }
  if (c != nullptr && !r.problem && r.finite(A::eccentricity, *c) && d != nullptr && !(std::abs(*c) < *d)) {
    r.report(A::eccentricity, r.q(A::eccentricity) + " must be smaller than " + r.q(A::minor_radius) +
                                  " in absolute value (the tube would pinch to a point and the cyclide intersect itself)",
             "the tube's radius is minorradius − eccentricity at +x and minorradius + eccentricity at −x");
  }
  if (auto wrap = r.span(A::theta_max)) r.count(A::theta_segs, *wrap ? 3 : 1, *wrap ? " around a full turn" : "");
  r.count(A::phi_segs, 3, " around the tube");
}

// Surfaces of revolution, cyclides and tori.
void quadric_rules(GenKind kind, Rules& r) {
  switch (kind) {
    case GenKind::Sphere:
      r.positive(gen_arg::Sphere::radius);
      spheroid<gen_arg::Sphere>(r);
      return;
    case GenKind::Ellipsoid:
      r.positive(gen_arg::Ellipsoid::a);
      r.positive(gen_arg::Ellipsoid::b);
      spheroid<gen_arg::Ellipsoid>(r);
      return;
    case GenKind::Cylinder: {
      // NOME3 truncates theta_max to whole degrees; exactly 360 is a closed tube.
      using A = gen_arg::Cylinder;
      r.positive(A::radius);
      r.positive(A::height);
      const double* t = r.get(A::theta_max);
      if (auto wrap = r.span(A::theta_max, t ? std::optional<double>(std::trunc(*t)) : std::nullopt)) {
        r.count(A::theta_segs, *wrap ? 3 : 1, *wrap ? " around a full turn" : "");
      }
      return;
    }
    case GenKind::Cone:
      r.greater(gen_arg::Cone::zmin, gen_arg::Cone::zmax);
      r.count(gen_arg::Cone::theta_segs, 3, " (a ring of fewer sides has no area)");
      return;
    case GenKind::Disk:
      if (auto wrap = r.span(gen_arg::Disk::theta_max)) {
        r.count(gen_arg::Disk::theta_segs, *wrap ? 3 : 1, *wrap ? " around a full disk" : "");
      }
      return;
    case GenKind::Ring:
      r.positive(gen_arg::Ring::inner_radius);
      r.positive(gen_arg::Ring::outer_radius);
      r.greater(gen_arg::Ring::inner_radius, gen_arg::Ring::outer_radius);
      if (auto wrap = r.span(gen_arg::Ring::theta_max)) {
        r.count(gen_arg::Ring::theta_segs, *wrap ? 3 : 1, *wrap ? " around a full ring" : "");
      }
      return;
    case GenKind::Cyclide:
      cyclide_rules(r);
      return;
    case GenKind::Hyperboloid: {
      using A = gen_arg::Hyperboloid;
      r.count(A::n, 3, " around the axis");
      r.positive(A::a);
      r.positive(A::b);
      const double* c = r.get(A::c);
      if (c != nullptr && !r.problem && r.finite(A::c, *c) && *c < 1.0) {
        r.report(A::c, r.q(A::c) + " must be at least 1, got " + format_argument(*c),
                 "the rows sit at the whole numbers z = -c … c, so c = 1 gives three rows");
      } else if (c != nullptr && !r.problem && *c > kMaxCount) {
        r.report(A::c, r.q(A::c) + " must be at most " + std::to_string(kMaxCount), "use fewer rows");
      }
      const double* sheet = r.get(A::sheet);
      if (sheet != nullptr && !r.problem && r.finite(A::sheet, *sheet) && *sheet != 0.0) {
        r.report(A::sheet, "only one sheet is built: " + r.q(A::sheet) + " must be 0",
                 "NOME3's two-sheet formula sqrt(z²−1) has no points on the row z = 0");
      }
      const double* ang = r.get(A::angle);
      if (ang != nullptr && !r.problem && r.finite(A::angle, *ang) && !(*ang > 0.0 && *ang <= 2.0)) {
        r.report(A::angle, r.q(A::angle) + " must be in (0, 2], got " + format_argument(*ang),
                 "the angle is in units of π: 2 is a full turn, 1 a half turn");
      }
      return;
    }
    case GenKind::Dupin: {
      using A = gen_arg::Dupin;
      r.positive(A::a);
      r.positive(A::b);
      const double* a = r.get(A::a);
      const double* c = r.get(A::c);
      if (a != nullptr && c != nullptr && !r.problem && r.finite(A::c, *c) && !(*a > std::abs(*c))) {
        r.report(A::c, r.q(A::c) + " must be smaller than " + r.q(A::a) +
                           " in absolute value (the cyclide is unbounded otherwise)",
                 "choose |c| < a");
      }
      for (A ext : {A::u, A::v}) {
        const double* e = r.get(ext);
        if (e != nullptr && !r.problem && r.finite(ext, *e) && !(*e > 0.0 && *e <= 2.0)) {
          r.report(ext, r.q(ext) + " must be in (0, 2], got " + format_argument(*e),
                   "the extent is in units of π: 2 is a full turn, 1 a half turn");
        }
      }
      r.count(A::n, 2, " (an n × n grid)");
      return;
    }
    case GenKind::Torus: {
      using A = gen_arg::Torus;
      r.positive(A::major_radius);
      r.positive(A::minor_radius);
      const std::optional<bool> wrap_i = r.span(A::theta_max);
      const double* lo = r.get(A::phi_min);
      const double* hi = r.get(A::phi_max);
      std::optional<bool> wrap_j;
      if (lo != nullptr && hi != nullptr) wrap_j = r.span(A::phi_max, *hi - *lo);
      if (wrap_i) r.count(A::theta_segs, *wrap_i ? 3 : 1, *wrap_i ? " around a full turn" : "");
      // A partial tube on a partial turn is closed by a quad back to row 0 (NOME3's), which
      // needs two segments around the tube.
      if (wrap_j && *wrap_j) {
        r.count(A::phi_segs, 3, " around a full turn");
      } else if (wrap_j && wrap_i) {
        r.count(A::phi_segs, *wrap_i ? 1 : 2, *wrap_i ? "" : " (the partial tube is closed along its chord)");
      }
      return;
    }
    case GenKind::Torusknot: {
      using A = gen_arg::Torusknot;
      r.whole_nonzero(A::symm);
      r.whole_nonzero(A::turns);
      for (A a : {A::major_radius, A::minor_radius}) r.positive(a);
      r.nonnegative(A::tube_radius, "0 makes the knot itself (a line strip `knotpoint{i}`), more a tube around it");
      r.count(A::circ_segs, 3, " around the tube");
      r.count(A::sweep_segs, 3, " along the closed knot");
      return;
    }
    default:
      return;
  }
}

// Curves.
void curve_rules(GenKind kind, Rules& r) {
  switch (kind) {
    case GenKind::Helix:
      r.positive(gen_arg::Helix::radius);
      r.nonzero(gen_arg::Helix::theta_max);
      r.count(gen_arg::Helix::segs, 2, " (a line strip needs two vertices)");
      return;
    case GenKind::Spiral: {
      using A = gen_arg::Spiral;
      r.positive(A::rate);
      const double* ang = r.get(A::angle);
      if (ang != nullptr && !r.problem && r.finite(A::angle, *ang) && std::trunc(*ang) == 0.0) {
        r.report(A::angle, r.q(A::angle) + " must be at least 1 in absolute value (it is truncated to a whole number), got " +
                               format_argument(*ang),
                 "the spiral turns 2·angle radians in total");
      }
      r.count(A::segs, 1);
      return;
    }
    case GenKind::Beziercurve:
      r.count(gen_arg::Beziercurve::segs, 1);
      return;
    case GenKind::Bspline:
      r.count(gen_arg::Bspline::order, 2);
      return;
    default:
      return;
  }
}

// Function surfaces.
void function_rules(GenKind kind, Rules& r) {
  switch (kind) {
    case GenKind::Genparametricsurf: {
      using A = gen_arg::Genparametricsurf;
      r.greater(A::u_min, A::u_max);
      r.greater(A::v_min, A::v_max);
      r.real_at_least(A::u_segs, 1.0, "as in NOME3 the samples are (max − min)/segs apart; a fractional segs is not rounded");
      r.real_at_least(A::v_segs, 1.0, "as in NOME3 the samples are (max − min)/segs apart; a fractional segs is not rounded");
      return;
    }
    case GenKind::Gencartesiansurf: {
      using A = gen_arg::Gencartesiansurf;
      r.greater(A::x_min, A::x_max);
      r.greater(A::y_min, A::y_max);
      r.real_at_least(A::x_segs, 1.0, "as in NOME3 the samples are (max − min)/segs apart; a fractional segs is not rounded");
      r.real_at_least(A::y_segs, 1.0, "as in NOME3 the samples are (max − min)/segs apart; a fractional segs is not rounded");
      return;
    }
    case GenKind::Genimplicitsurf: {
      using A = gen_arg::Genimplicitsurf;
      r.greater(A::x_min, A::x_max);
      r.greater(A::y_min, A::y_max);
      r.greater(A::z_min, A::z_max);
      double cells = 1;
      bool all_known = true;
      for (A n : {A::nx, A::ny, A::nz}) {
        r.count(n, 2, " (a cell is (max − min)/(n − 1) wide)");
        const double* v = r.get(n);
        if (v == nullptr) all_known = false;
        else cells *= std::round(*v);
      }
      if (all_known && !r.problem && cells > 128.0 * 128.0 * 128.0) {
        r.report(A::nz, "nx·ny·nz must be at most 2097152 (128³), got " + format_argument(cells),
                 "the function is sampled at every grid corner; use fewer cells");
      }
      return;
    }
    default:
      return;
  }
}

// The rules of `kind` beyond those of its arguments' kinds (see `type_rules`). A generator
// with none needs no case.
void rules_for(GenKind kind, Rules& r) {
  ring_rules(kind, r);
  quadric_rules(kind, r);
  curve_rules(kind, r);
  function_rules(kind, r);
}

// What every argument of a type must satisfy, whatever the generator (after its own,
// more specific rules, whose messages say more): numbers are finite, counts at least 1 and
// at most kMaxCount, lengths positive, ratios above -1.
void type_rules(GenKind kind, Rules& r) {
  const GeneratorInfo& g = generator(kind);
  for (ArgIndex i = 0; i < g.args.size() && !r.problem; ++i) {
    switch (g.args[i].type) {
      case ArgType::Count: r.count(i, 1); break;
      case ArgType::Length: r.positive(i); break;
      case ArgType::Ratio: r.above_minus_one(i); break;
      case ArgType::Fraction: r.fraction(i); break;
      case ArgType::Whole:
      case ArgType::Real:
      case ArgType::Angle:
        if (const double* v = r.get(i)) r.finite(i, *v);
        break;
      case ArgType::Flag:
      case ArgType::Function:
      case ArgType::Points:
      case ArgType::Path: break;
    }
  }
}

}  // namespace

std::optional<ArgProblem> check_arguments(GenKind kind, Dialect dialect, KnownArgs known) {
  Rules r(kind, dialect, known);
  rules_for(kind, r);
  type_rules(kind, r);
  return r.problem;
}

}  // namespace nomec::ir
