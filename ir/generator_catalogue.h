// The generator catalogue (ir/generators.def) as data and functions: each generator's kind,
// keywords, arguments with their types and meanings, positional signatures and options per
// dialect, variables of its function arguments and the names of its vertices; plus the
// argument-domain rules (counts, radii, angle ranges …) that `--check` and the backend both
// apply, so they reject the same values with the same message. Read by frontend/parse
// (keywords), frontend/check (signatures, options, domains), frontend/index (hover,
// completion), backend/generators (dispatch by kind, argument names in messages) and the
// documentation test. Knows no syntax tree, no kernel.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ir/dialect.h"

namespace nomec::ir {

/// Every generator, e.g. `GenKind::Funnel` for `funnel fun (8 0.4 -0.2 0.2) endfunnel`.
enum class GenKind : uint8_t {
#define NOMEC_GENERATOR(Kind, Keyword, Output, Summary) Kind,
#include "ir/generators.def"
};

inline constexpr int kGenKindCount = 0
#define NOMEC_GENERATOR(Kind, Keyword, Output, Summary) +1
#include "ir/generators.def"
    ;

/// What a generator makes: faces, or a polyline without faces.
enum class GenOutput : uint8_t { Surface, Curve };

/// What an argument holds (ir/generators.def explains each).
enum class ArgType : uint8_t { Count, Whole, Real, Length, Ratio, Fraction, Angle, Flag, Function, Points, Path };
std::string_view arg_type_name(ArgType t);

/// An argument's index among its generator's arguments (catalogue order).
using ArgIndex = uint8_t;
inline constexpr ArgIndex kNoArg = 0xff;

/// The arguments of each generator by name, e.g. `gen_arg::Funnel::ro`, so geometry code
/// and domain rules address arguments with the compiler's help instead of by strings.
namespace gen_arg {
#define NOMEC_GENERATOR(Kind, Keyword, Output, Summary) enum class Kind : ArgIndex {
#define NOMEC_GEN_ARG(Kind, Name, Type, Aliases, Doc) Name,
#define NOMEC_GENERATOR_END(Kind) };
#include "ir/generators.def"
}  // namespace gen_arg

template <typename E>
constexpr ArgIndex arg_index(E arg) {
  return static_cast<ArgIndex>(arg);
}

struct ArgInfo {
  std::string_view name;     // canonical, e.g. `ro`
  ArgType type = ArgType::Real;
  std::vector<std::string_view> aliases;  // other names the dialects use, e.g. `radius`
  std::string_view doc;      // one sentence for hover and signature help
};

/// A parenthesised argument list, e.g. funnel in `nome`: `(n ro ratio h)`.
struct Signature {
  DialectSet dialects = 0;
  std::vector<ArgIndex> args;
  std::vector<ArgIndex> optional;           // trailing arguments that may follow
  std::vector<std::string_view> names;      // how the dialect writes `args`, then `optional`
  /// True when the list is a list of point names (a curve's control points).
  bool is_point_list = false;
  /// For another order (NOMEC_GEN_ORDER): the era whose files are read in it first
  /// (`JIPCAD`), or empty.
  std::string_view era;
};

/// A named option, e.g. `funcX [ … ]` or `slices 12`.
struct OptionInfo {
  DialectSet dialects = 0;
  std::string_view word;
  ArgIndex arg = kNoArg;
};

/// Vertices named `prefix0 … prefix{count-1}`, e.g. a funnel's `bc0…bc7` for n = 8.
struct RingInfo {
  std::string_view prefix;
  ArgIndex count_arg = kNoArg;
};

/// Another prefix for a ring's vertices, e.g. NOME3's `v2_3` for a funnel's `bc3`.
struct VertexAlias {
  std::string_view alias;
  std::string_view prefix;
};

struct GeneratorInfo {
  GenKind kind = GenKind::Funnel;
  std::string_view keyword;                  // e.g. `funnel`
  std::vector<std::string_view> keywords;    // `keyword` first, then other spellings
  std::vector<std::string_view> other_ends;  // end keywords besides `end` + a keyword
  GenOutput output = GenOutput::Surface;
  std::string_view summary;
  std::vector<ArgInfo> args;
  std::vector<Signature> positional;
  /// Other orders of the positional arguments that files of older or newer eras use (the
  /// ring generators' argument-order eras, compat.md A4).
  std::vector<Signature> orders;
  /// `digit_prefix` + digits is also a keyword of this generator, the digits setting
  /// `digit_arg` (NOME2's `bspline3`); empty when not.
  std::string_view digit_prefix;
  ArgIndex digit_arg = kNoArg;
  std::vector<OptionInfo> options;
  std::vector<std::string_view> variables;   // of the Function arguments, e.g. `u v`
  std::vector<RingInfo> rings;
  std::vector<VertexAlias> aliases;
  /// Dialects its keyword is a detection signal of (e.g. NOME3 for `torus`).
  DialectSet signals = 0;

  /// True when `end` closes this generator opened with keyword `open`: `end` + `open`, or
  /// another end keyword old files use (2016's `tunnel … endfunnel`).
  bool closes_with(std::string_view open, std::string_view end) const;
  /// The positional list in `dialect`, or null when the generator takes none there (SLIDE's
  /// `cylinder`, `rimribbon`).
  const Signature* signature(Dialect dialect) const;
  /// The other order of the positional arguments in `dialect`, or null.
  const Signature* other_order(Dialect dialect) const;
  /// The number a digit keyword carries (`bspline3` → 3), or nullopt for other keywords.
  std::optional<int> keyword_digits(std::string_view keyword) const;
  /// The argument set by option `word` in `dialect`.
  std::optional<ArgIndex> option(Dialect dialect, std::string_view word) const;
  /// The argument with this canonical name or alias.
  std::optional<ArgIndex> arg_named(std::string_view name) const;
  /// How `dialect` writes the argument: its name in the dialect's positional list, else its
  /// first option word, else its canonical name. Messages and hover use it.
  std::string_view display_name(ArgIndex arg, Dialect dialect) const;
  /// Every option word accepted in `dialect`, in catalogue order.
  std::vector<std::string_view> option_words(Dialect dialect) const;
};

const GeneratorInfo& generator(GenKind kind);
std::span<const GeneratorInfo> generators();
/// The generator a keyword opens (`funnel`, `bsplinecurve`, `bspline3` …).
std::optional<GenKind> generator_by_keyword(std::string_view keyword);
/// The generator an end keyword closes (`endfunnel`, `endbsplinecurve` …).
std::optional<GenKind> generator_by_end_keyword(std::string_view keyword);
/// `name` with an alias prefix replaced by its ring's prefix (`v1_3` → `hc3` for a funnel).
std::string canonical_vertex_name(GenKind kind, std::string_view name);

/// Problems found while building the tables from generators.def (a name in a signature or
/// option that is no argument, …); empty when the catalogue is consistent. A unit test
/// asserts it is empty.
const std::vector<std::string>& catalogue_problems();

// ---- Argument domains ----

/// A value outside its generator's domain: the argument, the message (lowercase, no
/// trailing period, the argument named as the dialect writes it) and a hint saying what is
/// accepted, e.g. `n` of a funnel = 2 → "`n` must be at least 3, got 2".
struct ArgProblem {
  ArgIndex arg = kNoArg;
  std::string message;
  std::string hint;
};

/// Argument values by ArgIndex; an unknown value is nullopt. Spans shorter than the
/// generator's argument count treat the missing ones as unknown.
using KnownArgs = std::span<const std::optional<double>>;

/// The first domain rule of `kind` broken by `known`, in the dialect's argument order.
/// Rules that involve an unknown argument are skipped, so a partial set (check time) gives
/// a subset of the problems the full set (emit time) gives.
std::optional<ArgProblem> check_arguments(GenKind kind, Dialect dialect, KnownArgs known);

/// Largest count accepted per dimension.
inline constexpr int kMaxCount = 100000;
/// `n` rounded to the nearest whole number, as a count; what a generator does with a count
/// like 8.0000001 or 7.6 (the checker warns `NonIntegerCount` for the latter).
int round_count(double n);
/// A number as messages show it (`%g`: `0.5`, `1e+06`).
std::string format_argument(double v);

}  // namespace nomec::ir
