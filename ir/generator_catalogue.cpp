// The generator catalogue's tables, built once from ir/generators.def (see
// generator_catalogue.h), and the lookups on them. The argument-domain rules are in
// generator_domains.cpp.
#include "ir/generator_catalogue.h"

#include <algorithm>
#include <unordered_map>
#include <cmath>
#include <cstdio>

namespace nomec::ir {

std::string_view arg_type_name(ArgType t) {
  switch (t) {
    case ArgType::Count: return "count";
    case ArgType::Whole: return "whole number";
    case ArgType::Real: return "number";
    case ArgType::Length: return "length";
    case ArgType::Ratio: return "ratio";
    case ArgType::Fraction: return "fraction";
    case ArgType::Angle: return "angle";
    case ArgType::Flag: return "flag";
    case ArgType::Function: return "function";
    case ArgType::Points: return "point list";
    case ArgType::Path: return "path";
  }
  return "argument";
}

namespace {

std::vector<std::string_view> split_words(std::string_view text) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && text[i] == ' ') ++i;
    size_t j = i;
    while (j < text.size() && text[j] != ' ') ++j;
    if (j > i) out.push_back(text.substr(i, j - i));
    i = j;
  }
  return out;
}

// Rationale: the .def is expanded once into plain entries (in file order), then turned into
// `GeneratorInfo`s; names written in signatures and options are resolved to argument
// indices here, once, and every unresolved name is recorded as a problem for the
// consistency test instead of being silently dropped.
struct Catalogue {
  std::vector<GeneratorInfo> infos;
  std::vector<std::string> problems;
  // Keyword → generator (the first in catalogue order), for the lookup every statement does.
  std::unordered_map<std::string_view, GenKind> by_keyword;
  std::vector<const GeneratorInfo*> with_digits;  // generators with a digit keyword, in order
};

Catalogue build() {
  // NOME is the 2016 family (NOME 2016 and NOME2); NOME2016 and NOME2 name one of them.
  constexpr DialectSet NOME = kNome | kNome2, NOME2016 = kNome, NOME2 = kNome2, NOME3 = kNome3, SLIDE = kSlide,
                       ALL = kAllDialects;
  (void)NOME;
  (void)NOME2016;
  (void)NOME2;
  (void)NOME3;
  (void)SLIDE;
  (void)ALL;
  Catalogue c;
  c.infos.resize(kGenKindCount);
  auto info = [&](GenKind k) -> GeneratorInfo& { return c.infos[static_cast<size_t>(k)]; };
  auto resolve = [&](GeneratorInfo& g, std::string_view name, std::string_view where) -> ArgIndex {
    if (auto a = g.arg_named(name)) return *a;
    c.problems.push_back(std::string(g.keyword) + ": " + std::string(where) + " names `" + std::string(name) +
                         "`, which is no argument");
    return kNoArg;
  };
  struct Pending {
    GenKind kind;
    DialectSet dialects;
    std::string_view args, optional;
    bool is_order = false;
    std::string_view era;
  };
  std::vector<Pending> signatures;
  struct PendingDigits {
    GenKind kind;
    std::string_view prefix, arg;
  };
  std::vector<PendingDigits> digit_keywords;
  struct PendingOption {
    GenKind kind;
    DialectSet dialects;
    std::string_view word, arg;
  };
  std::vector<PendingOption> options;
  struct PendingRing {
    GenKind kind;
    std::string_view prefix, count;
  };
  std::vector<PendingRing> rings;
#define NOMEC_GENERATOR(Kind, Keyword, Output, Summary)                    \
  {                                                                         \
    GeneratorInfo& g = info(GenKind::Kind);                                 \
    g.kind = GenKind::Kind;                                                 \
    g.keyword = Keyword;                                                    \
    g.keywords.push_back(Keyword);                                          \
    g.output = GenOutput::Output;                                           \
    g.summary = Summary;                                                    \
  }
#define NOMEC_GEN_KEYWORD(Kind, Keyword) info(GenKind::Kind).keywords.push_back(Keyword);
#define NOMEC_GEN_END_KEYWORD(Kind, Keyword) info(GenKind::Kind).other_ends.push_back(Keyword);
#define NOMEC_GEN_ARG(Kind, Name, Type, Aliases, Doc) \
  info(GenKind::Kind).args.push_back(ArgInfo{#Name, ArgType::Type, split_words(Aliases), Doc});
#define NOMEC_GEN_POSITIONAL(Kind, Dialects, Args, Optional) \
  signatures.push_back(Pending{GenKind::Kind, static_cast<DialectSet>(Dialects), Args, Optional, false, ""});
#define NOMEC_GEN_ORDER(Kind, Dialects, Args, Era) \
  signatures.push_back(Pending{GenKind::Kind, static_cast<DialectSet>(Dialects), Args, "", true, Era});
#define NOMEC_GEN_DIGIT_KEYWORD(Kind, Prefix, Arg) digit_keywords.push_back(PendingDigits{GenKind::Kind, Prefix, #Arg});
#define NOMEC_GEN_OPTION(Kind, Dialects, Word, Arg) \
  options.push_back(PendingOption{GenKind::Kind, static_cast<DialectSet>(Dialects), Word, #Arg});
#define NOMEC_GEN_VARIABLES(Kind, Names) info(GenKind::Kind).variables = split_words(Names);
#define NOMEC_GEN_RING(Kind, Prefix, CountArg) rings.push_back(PendingRing{GenKind::Kind, Prefix, #CountArg});
#define NOMEC_GEN_ALIAS(Kind, Alias, Prefix) info(GenKind::Kind).aliases.push_back(VertexAlias{Alias, Prefix});
#define NOMEC_GEN_SIGNAL(Kind, Dialects) info(GenKind::Kind).signals |= static_cast<DialectSet>(Dialects);
#include "ir/generators.def"
  for (const Pending& p : signatures) {
    GeneratorInfo& g = info(p.kind);
    Signature s;
    s.dialects = p.dialects;
    for (std::string_view n : split_words(p.args)) {
      s.args.push_back(resolve(g, n, "a positional list"));
      s.names.push_back(n);
    }
    for (std::string_view n : split_words(p.optional)) {
      s.optional.push_back(resolve(g, n, "a positional list"));
      s.names.push_back(n);
    }
    s.is_point_list = s.args.size() == 1 && s.optional.empty() && s.args[0] != kNoArg &&
                      g.args[s.args[0]].type == ArgType::Points;
    s.era = p.era;
    std::vector<Signature>& list = p.is_order ? g.orders : g.positional;
    for (const Signature& other : list) {
      if ((other.dialects & s.dialects) != 0) {
        c.problems.push_back(std::string(g.keyword) + ": two positional lists (or other orders) for one dialect");
      }
    }
    if (p.is_order) {
      // Another order holds the same arguments as the dialect's list, rearranged.
      const Signature* base = nullptr;
      for (const Signature& b : g.positional) {
        if ((b.dialects & s.dialects) == s.dialects) base = &b;
      }
      std::vector<ArgIndex> want = base != nullptr ? base->args : std::vector<ArgIndex>{};
      std::vector<ArgIndex> got = s.args;
      std::sort(want.begin(), want.end());
      std::sort(got.begin(), got.end());
      if (base == nullptr || want != got) {
        c.problems.push_back(std::string(g.keyword) + ": another order that is no rearrangement of a positional list");
      }
    }
    list.push_back(std::move(s));
  }
  for (const PendingDigits& d : digit_keywords) {
    GeneratorInfo& g = info(d.kind);
    g.digit_prefix = d.prefix;
    g.digit_arg = resolve(g, d.arg, "a digit keyword");
  }
  for (const PendingOption& o : options) {
    GeneratorInfo& g = info(o.kind);
    g.options.push_back(OptionInfo{o.dialects, o.word, resolve(g, o.arg, "an option")});
  }
  for (const PendingRing& r : rings) {
    GeneratorInfo& g = info(r.kind);
    g.rings.push_back(RingInfo{r.prefix, resolve(g, r.count, "a ring")});
  }
  for (GeneratorInfo& g : c.infos) {
    for (const VertexAlias& a : g.aliases) {
      bool known = std::any_of(g.rings.begin(), g.rings.end(), [&](const RingInfo& r) { return r.prefix == a.prefix; });
      if (!known) c.problems.push_back(std::string(g.keyword) + ": alias of an unknown ring `" + std::string(a.prefix) + "`");
    }
    bool has_function = std::any_of(g.args.begin(), g.args.end(), [](const ArgInfo& a) { return a.type == ArgType::Function; });
    if (has_function && g.variables.empty()) {
      c.problems.push_back(std::string(g.keyword) + ": function arguments without variables");
    }
  }
  for (const GeneratorInfo& g : c.infos) {
    for (std::string_view k : g.keywords) c.by_keyword.emplace(k, g.kind);
  }
  for (const GeneratorInfo& g : c.infos) {
    if (!g.digit_prefix.empty()) c.with_digits.push_back(&g);
  }
  return c;
}

const Catalogue& catalogue() {
  static const Catalogue c = build();
  return c;
}

}  // namespace

const GeneratorInfo& generator(GenKind kind) { return catalogue().infos[static_cast<size_t>(kind)]; }

std::span<const GeneratorInfo> generators() { return catalogue().infos; }

const std::vector<std::string>& catalogue_problems() { return catalogue().problems; }

std::optional<GenKind> generator_by_keyword(std::string_view keyword) {
  const Catalogue& c = catalogue();
  // A plain keyword of an earlier generator wins over a digit keyword of a later one, as in a
  // scan of the catalogue in order.
  const auto plain = c.by_keyword.find(keyword);
  for (const GeneratorInfo* g : c.with_digits) {
    if (plain != c.by_keyword.end() && plain->second <= g->kind) return plain->second;
    if (g->keyword_digits(keyword)) return g->kind;
  }
  if (plain != c.by_keyword.end()) return plain->second;
  return std::nullopt;
}

std::optional<int> GeneratorInfo::keyword_digits(std::string_view keyword) const {
  if (digit_prefix.empty() || !keyword.starts_with(digit_prefix)) return std::nullopt;
  const std::string_view digits = keyword.substr(digit_prefix.size());
  // One or two digits: an order of 1 … 99 (B-spline orders beyond that mean nothing).
  if (digits.empty() || digits.size() > 2) return std::nullopt;
  int v = 0;
  for (char ch : digits) {
    if (ch < '0' || ch > '9') return std::nullopt;
    v = v * 10 + (ch - '0');
  }
  return v;
}

std::optional<GenKind> generator_by_end_keyword(std::string_view keyword) {
  if (!keyword.starts_with("end")) return std::nullopt;
  return generator_by_keyword(keyword.substr(3));
}

bool GeneratorInfo::closes_with(std::string_view open, std::string_view end) const {
  if (std::find(other_ends.begin(), other_ends.end(), end) != other_ends.end()) return true;
  return end.starts_with("end") && end.substr(3) == open &&
         (std::find(keywords.begin(), keywords.end(), open) != keywords.end() || keyword_digits(open));
}

const Signature* GeneratorInfo::other_order(Dialect dialect) const {
  for (const Signature& s : orders) {
    if ((s.dialects & dialect_bit(dialect)) != 0) return &s;
  }
  return nullptr;
}

const Signature* GeneratorInfo::signature(Dialect dialect) const {
  for (const Signature& s : positional) {
    if ((s.dialects & dialect_bit(dialect)) != 0) return &s;
  }
  return nullptr;
}

std::optional<ArgIndex> GeneratorInfo::option(Dialect dialect, std::string_view word) const {
  for (const OptionInfo& o : options) {
    if ((o.dialects & dialect_bit(dialect)) != 0 && o.word == word) return o.arg;
  }
  return std::nullopt;
}

std::optional<ArgIndex> GeneratorInfo::arg_named(std::string_view name) const {
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i].name == name) return static_cast<ArgIndex>(i);
  }
  for (size_t i = 0; i < args.size(); ++i) {
    for (std::string_view a : args[i].aliases) {
      if (a == name) return static_cast<ArgIndex>(i);
    }
  }
  return std::nullopt;
}

std::string_view GeneratorInfo::display_name(ArgIndex arg, Dialect dialect) const {
  if (arg >= args.size()) return "argument";
  if (const Signature* s = signature(dialect)) {
    for (size_t i = 0; i < s->args.size(); ++i) {
      if (s->args[i] == arg) return s->names[i];
    }
    for (size_t i = 0; i < s->optional.size(); ++i) {
      if (s->optional[i] == arg) return s->names[s->args.size() + i];
    }
  }
  for (const OptionInfo& o : options) {
    if (o.arg == arg && (o.dialects & dialect_bit(dialect)) != 0) return o.word;
  }
  return args[arg].name;
}

std::vector<std::string_view> GeneratorInfo::option_words(Dialect dialect) const {
  std::vector<std::string_view> out;
  for (const OptionInfo& o : options) {
    if ((o.dialects & dialect_bit(dialect)) != 0) out.push_back(o.word);
  }
  return out;
}

std::string canonical_vertex_name(GenKind kind, std::string_view name) {
  for (const VertexAlias& a : generator(kind).aliases) {
    if (name.size() > a.alias.size() && name.substr(0, a.alias.size()) == a.alias) {
      return std::string(a.prefix) + std::string(name.substr(a.alias.size()));
    }
  }
  return std::string(name);
}

int round_count(double n) { return static_cast<int>(std::lround(n)); }

std::string format_argument(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace nomec::ir
