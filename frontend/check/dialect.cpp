// Which dialect a file is written in (docs/dialects.md): `--dialect`, the `.slf` extension,
// then signals in its content, strong ones first (NOME 2016's `$bank_param`, `isloop`,
// saved work; NOME2's `bsplineK`, `reverse`, display colours; `mirror`, `slices`, the 2018
// block forms of both; NOME3's `list` in a bank and its commands; JIPCAD's colours and
// sweeps; `$bank.param` and `closed` of NOME2 and NOME3), then weak
// ones (`object`, ring arguments that read validly in only one era's order), then the
// extension; and the names SLIDE's Tcl code creates, so their uses are reported as Tcl's,
// not typos.
#include <algorithm>
#include <array>
#include <iterator>
#include <cmath>
#include <fmt/format.h>
#include <regex>
#include <unordered_set>

#include "frontend/check/handlers.h"
#include "frontend/source/file_kinds.h"

namespace nomec::check {

namespace {

// What a signal says about the file. Strong signals decide; weak ones only when no strong
// signal is present.
enum class Sig : uint8_t {
  Nome2016,    // only NOME 2016: `$bank_param`, `isloop`, saved work, `tunnel … endfunnel`
  Nome2,       // only NOME2: `bsplineK`, instance `reverse`, the display colours
  Family,      // NOME 2016 or NOME2: `mirror (a b c d)`, `slices`, `consolidatedmesh`, …
  Nome3,       // NOME3 or JIPCAD: its commands, `list` in a bank, `sd_type`
  Jipcad,      // JIPCAD (2022+): colours, back faces, morph sweeps, …
  DotRef,      // `$bank.param`, polyline flag `closed`: NOME2 or NOME3
  WeakFamily,  // `object`; a funnel or tunnel valid only in the 2016 order
  WeakNome2,   // a circle valid only as NOME2's `(n ro)`
  WeakNome3,   // a funnel valid only in NOME3's order
  Count,
};

struct Signal {
  SourceRange at;
  std::string why;
  bool is_set() const { return at.is_valid(); }
};

// The first place that signals each kind, and what it was.
struct Signals {
  std::array<Signal, static_cast<size_t>(Sig::Count)> first;
  void add(Sig k, SourceRange r, std::string why) {
    Signal& s = first[static_cast<size_t>(k)];
    if (!s.is_set()) s = Signal{r, std::move(why)};
  }
  const Signal& operator[](Sig k) const { return first[static_cast<size_t>(k)]; }
  bool has(Sig k) const { return (*this)[k].is_set(); }
};

constexpr std::string_view kJipcadWords[] = {"frontcolor", "backcolor",     "backgroundcolor", "backface",
                                             "sweepmorph", "morphvisualizer", "cutbegin",     "cutend",
                                             "mergeinstance"};

bool is_2018_block_word(std::string_view w) {
  return w == "foreground" || w == "background" || w == "insidefaces" || w == "outsidefaces" || w == "offsetfaces";
}

// A literal number of a list (`6`, `-0.5`), or nullopt for anything else.
std::optional<double> literal(const ast::Ast& a, ast::ExprId e) {
  const ast::Expr* x = &a.expr(e);
  double sign = 1;
  if (x->kind == ast::ExprKind::Unary) {
    sign = x->op == '-' ? -1 : 1;
    x = &a.expr(x->lhs());
  }
  if (x->kind != ast::ExprKind::Number) return std::nullopt;
  return sign * x->number();
}

// Whether a ring generator's literal arguments read validly in its `sig` order: nullopt
// when the count is not a literal.
std::optional<bool> ring_valid(const ast::Ast& a, const ast::ParenList& list, const ir::GeneratorInfo& g,
                               const ir::Signature* sig) {
  if (sig == nullptr || list.elems.size() != sig->args.size()) return std::nullopt;
  for (size_t i = 0; i < sig->args.size(); ++i) {
    if (sig->args[i] == ir::kNoArg || g.args[sig->args[i]].type != ir::ArgType::Count) continue;
    std::optional<double> v = literal(a, list.elems[i]);
    if (!v) return std::nullopt;
    return std::fabs(*v - std::round(*v)) < 1e-9 && *v >= 3;
  }
  return std::nullopt;
}

// Ring generators whose literal arguments are a valid count in only one era's order.
void ring_signals(const ast::Ast& a, const ast::Stmt& s, ir::GenKind gen, Signals& sig) {
  if (gen != ir::GenKind::Funnel && gen != ir::GenKind::Tunnel && gen != ir::GenKind::Circle) return;
  const ast::Item* list = nullptr;
  for (const ast::Item& it : s.items) {
    if (it.kind == ItemKind::List) {
      list = &it;
      break;
    }
  }
  if (list == nullptr) return;
  const ir::GeneratorInfo& g = ir::generator(gen);
  const ast::ParenList& l = a.list(list->list);
  const std::optional<bool> old_order = ring_valid(a, l, g, g.signature(Dialect::Nome));
  const std::optional<bool> new_order = ring_valid(a, l, g, g.other_order(Dialect::Nome));
  if (!old_order || !new_order || *old_order == *new_order) return;
  const std::string what = fmt::format("`{} {}`", s.keyword, Context::clip(std::string_view(
                                                                 s.items.empty() || s.items[0].kind != ItemKind::Word ? "" : s.items[0].text)));
  if (gen == ir::GenKind::Circle) {
    if (*old_order) sig.add(Sig::WeakNome2, l.range, fmt::format("{} read as NOME2's `(n ro)`", what));
  } else if (*old_order) {
    sig.add(Sig::WeakFamily, l.range, fmt::format("{} read in the 2016 order `(n ro ratio h)`", what));
  } else if (gen == ir::GenKind::Funnel) {
    sig.add(Sig::WeakNome3, l.range, fmt::format("{} read in NOME3's order `(radius ratio height n)`", what));
  }
}

// Every word `word_signals` looks for, by first letter and length: most words of a file are
// names (`v0`, `fb0_hc0`) that share no first letter and length with any of them, and are
// passed over with one table lookup instead of a score of comparisons.
class SignalWords {
 public:
  constexpr SignalWords() {
    // Keep in step with the comparisons in `word_signals`.
    constexpr std::string_view kOthers[] = {"isloop",  "sd_type", "list",         "consolidatedmesh", "closed",
                                            "mirror",  "reverse", "subdivisions", "epsilon",          "min",
                                            "max",     "step",    "direction",    "crosssection",     "slices"};
    for (std::string_view w : kOthers) add(w);
    for (std::string_view w : kJipcadWords) add(w);
  }
  constexpr void add(std::string_view w) { lengths_[static_cast<unsigned char>(w[0])] |= 1u << w.size(); }
  constexpr bool may_be(std::string_view w) const {
    return !w.empty() && w.size() < 32 && (lengths_[static_cast<unsigned char>(w[0])] & (1u << w.size())) != 0;
  }

 private:
  uint32_t lengths_[256] = {};
};
constexpr SignalWords kSignalWords;

bool is_jipcad_word(std::string_view w) {
  // Asked of every statement's keyword: most are passed over by the table, the rest
  // compared in turn.
  if (!kSignalWords.may_be(w)) return false;
  return std::find(std::begin(kJipcadWords), std::end(kJipcadWords), w) != std::end(kJipcadWords);
}

// Words inside statements that only some dialects have.
void word_signals(const ast::Stmt& s, std::optional<ir::GenKind> gen, Signals& sig) {
  for (size_t i = 0; i < s.items.size(); ++i) {
    const ast::Item& it = s.items[i];
    if (it.kind != ItemKind::Word) continue;
    const std::string_view w = it.text;
    if (!kSignalWords.may_be(w)) continue;
    if (w == "isloop") sig.add(Sig::Nome2016, it.range, "`isloop`");
    if (w == "sd_type") sig.add(Sig::Nome3, it.range, "`sd_type`");
    if (w == "list" && s.kind == BlockKind::Bank) sig.add(Sig::Nome3, it.range, "`list` in a bank");
    if (is_jipcad_word(w)) sig.add(Sig::Jipcad, it.range, fmt::format("JIPCAD's `{}`", w));
    if (w == "consolidatedmesh" && (s.kind == BlockKind::Mesh || s.kind == BlockKind::Instance)) {
      sig.add(Sig::Family, it.range, "`consolidatedmesh`");
    }
    switch (s.kind) {
      case BlockKind::Polyline:
        if (w == "closed") sig.add(Sig::DotRef, it.range, "polyline flag `closed`");
        break;
      case BlockKind::Instance:
        if (w == "mirror") sig.add(Sig::Family, it.range, "`mirror` on an instance");
        if (w == "reverse") sig.add(Sig::Nome2, it.range, "instance transform `reverse`");
        break;
      case BlockKind::Subdivision:
        if (w == "subdivisions" && i > 0) sig.add(Sig::Family, it.range, "`type … subdivisions` in a subdivision");
        break;
      case BlockKind::Merge:
        if (w == "epsilon") sig.add(Sig::Family, it.range, "`merge epsilon`");
        break;
      case BlockKind::Offset:
        if (w == "min" || w == "max" || w == "step") sig.add(Sig::Family, it.range, "`min … max … step` in an offset");
        break;
      case BlockKind::Light:
        if (w == "direction") sig.add(Sig::Jipcad, it.range, "light `direction`");
        break;
      case BlockKind::Controlpoint:
        if (w == "crosssection") sig.add(Sig::Jipcad, it.range, "`crosssection` in a controlpoint");
        break;
      default:
        if (gen && (*gen == ir::GenKind::Beziercurve || *gen == ir::GenKind::Bspline) && w == "slices") {
          sig.add(Sig::Family, it.range, "`slices` on a curve");
        }
        break;
    }
  }
}

// Statements and words that only some dialects have: every statement of the trees, then
// every top-level word (only the first signal of each kind is kept, so the order counts).
void statement_signals(std::span<const ast::Ast> trees, Signals& sig) {
  for (const ast::Ast& a : trees) {
    for (const ast::Stmt& s : a.stmts) {
      std::optional<ir::GenKind> gen = generator_of(s);
      switch (s.kind) {
        case BlockKind::Consolidate:
        case BlockKind::Savedparameter:
        case BlockKind::Savedworkingmesh:
          sig.add(Sig::Nome2016, s.open_kw, fmt::format("`{}`", s.keyword));
          break;
        case BlockKind::Sweep:
        case BlockKind::Sharp:
          sig.add(Sig::Nome3, s.open_kw, fmt::format("NOME3 command `{}`", s.keyword));
          break;
        case BlockKind::Object:
          sig.add(Sig::WeakFamily, s.open_kw, "`object`");
          break;
        default:
          if (is_2018_block_word(s.keyword)) sig.add(Sig::Nome2, s.open_kw, fmt::format("NOME2 statement `{}`", s.keyword));
          if (is_jipcad_word(s.keyword)) sig.add(Sig::Jipcad, s.open_kw, fmt::format("JIPCAD's `{}`", s.keyword));
          if (gen) {
            const ir::GeneratorInfo& g = ir::generator(*gen);
            if ((g.signals & kNome3) != 0 && s.keyword == g.keyword) {
              sig.add(Sig::Nome3, s.open_kw, fmt::format("NOME3 command `{}`", g.keyword));
            }
            if (g.keyword_digits(s.keyword)) sig.add(Sig::Nome2, s.open_kw, fmt::format("NOME2's `{}`", s.keyword));
            if (s.close_text != ast::end_keyword(s.keyword) && g.closes_with(s.keyword, s.close_text)) {
              sig.add(Sig::Nome2016, s.close_kw, fmt::format("`{} … {}`", s.keyword, s.close_text));
            }
            ring_signals(a, s, *gen, sig);
          }
          break;
      }
      word_signals(s, gen, sig);
    }
  }
  // Statements nomec does not know are words at the top level (`frontcolor (1 0 0) …`).
  for (const ast::Ast& a : trees) {
    for (const ast::Item& it : a.top) {
      if (it.kind == ItemKind::Word && is_jipcad_word(it.text)) sig.add(Sig::Jipcad, it.range, fmt::format("JIPCAD's `{}`", it.text));
      if (it.kind == ItemKind::Word && is_2018_block_word(it.text)) {
        sig.add(Sig::Nome2, it.range, fmt::format("NOME2 statement `{}`", it.text));
      }
    }
  }
}

// `$bank_param` (2016) and `$bank.param` (NOME2, NOME3) references to banks of the file.
void reference_signals(std::span<const ast::Ast> trees, Signals& sig) {
  std::unordered_set<std::string_view> banks;  // views of the syntax trees' text
  for (const ast::Ast& a : trees) {
    for (const ast::Item& it : a.top) {
      if (it.kind == ItemKind::Block && a.stmt(it.block).kind == BlockKind::Bank) {
        const ast::Stmt& s = a.stmt(it.block);
        if (!s.items.empty() && s.items[0].kind == ItemKind::Word) banks.insert(s.items[0].text);
      }
    }
  }
  // Only the first signal of each kind is kept, so the scan stops once both are known.
  for (const ast::Ast& a : trees) {
    for (const ast::Expr& e : a.exprs) {
      if (sig.has(Sig::DotRef) && sig.has(Sig::Nome2016)) break;
      if (e.kind != ast::ExprKind::DollarRef) continue;
      std::string_view t = e.text.substr(1);
      if (auto dot = t.find('.'); dot != std::string_view::npos) {
        if (banks.contains(t.substr(0, dot))) sig.add(Sig::DotRef, e.range, "`$bank.param`");
      } else if (!sig.has(Sig::Nome2016)) {
        for (size_t u = t.find('_'); u != std::string_view::npos; u = t.find('_', u + 1)) {
          if (banks.contains(t.substr(0, u))) {
            sig.add(Sig::Nome2016, e.range, "`$bank_param`");
            break;
          }
        }
      }
    }
  }
}

std::string_view side_name(Dialect d) {
  switch (d) {
    case Dialect::Nome: return "NOME 2016";
    case Dialect::Nome2: return "NOME2";
    case Dialect::Nome3: return "NOME3";
    case Dialect::Slide: return "SLIDE";
  }
  return "";
}

// One side of a decision: a dialect and the signal that names it.
struct Choice {
  Dialect dialect;
  const Signal* signal;
};

// Of two sides with signals, the one whose signal comes first in the file: the file's
// opening is where its author's dialect shows first, and later edits add the other.
Choice settle(Context& c, Choice x, Choice y) {
  const bool x_first = x.signal->at.begin <= y.signal->at.begin;
  const Choice& win = x_first ? x : y;
  const Choice& lose = x_first ? y : x;
  c.diags()
      .emit(DiagKind::DialectConflict, lose.signal->at,
            fmt::format("this file mixes {} ({}) and {} ({}) syntax; checking it as `{}`, whose signal comes first",
                        side_name(x.dialect), x.signal->why, side_name(y.dialect), y.signal->why, dialect_name(win.dialect)))
      .note(x.signal->at, fmt::format("{} signal: {}", side_name(x.dialect), x.signal->why))
      .note(y.signal->at, fmt::format("{} signal: {}", side_name(y.dialect), y.signal->why));
  return win;
}

// The NOME 2016 family's side: NOME2 or NOME 2016, by the strongest signal present.
std::optional<Choice> family_side(Context& c, const Signals& sig, bool& conflict) {
  if (sig.has(Sig::Nome2) && sig.has(Sig::Nome2016)) {
    conflict = true;
    return settle(c, {Dialect::Nome2, &sig[Sig::Nome2]}, {Dialect::Nome, &sig[Sig::Nome2016]});
  }
  if (sig.has(Sig::Nome2)) return Choice{Dialect::Nome2, &sig[Sig::Nome2]};
  if (sig.has(Sig::Nome2016)) return Choice{Dialect::Nome, &sig[Sig::Nome2016]};
  if (sig.has(Sig::Family)) {
    // `mirror`, `slices`, …: NOME2 when `$bank.param` or `closed` is there too.
    return Choice{sig.has(Sig::DotRef) ? Dialect::Nome2 : Dialect::Nome, &sig[Sig::Family]};
  }
  return std::nullopt;
}

}  // namespace

std::string choose_dialect(Context& c, std::span<const ast::Ast> trees, const std::string& path) {
  std::string ext(path_extension(path));
  if (c.options().dialect) {
    c.set_dialect(*c.options().dialect);
    return "chosen with --dialect";
  }
  if (ext == ".slf") {
    c.set_dialect(Dialect::Slide);
    return "`.slf` extension";
  }
  Signals sig;
  statement_signals(trees, sig);
  reference_signals(trees, sig);
  c.is_jipcad = sig.has(Sig::Jipcad);
  auto decided = [&](Choice ch, std::string_view how) {
    c.set_dialect(ch.dialect);
    return fmt::format("{}: {}", how, ch.signal->why);
  };
  // 1. Strong signals: the family (2016 or NOME2) against NOME3/JIPCAD.
  bool conflict = false;
  std::optional<Choice> family = family_side(c, sig, conflict);
  const Signal* nome3 = sig.has(Sig::Jipcad) ? &sig[Sig::Jipcad] : sig.has(Sig::Nome3) ? &sig[Sig::Nome3] : nullptr;
  if (family && nome3 != nullptr) return decided(settle(c, *family, {Dialect::Nome3, nome3}), "conflicting signals; first");
  if (family && family->dialect == Dialect::Nome2 && !conflict && !sig.has(Sig::Nome2)) {
    c.set_dialect(Dialect::Nome2);
    return fmt::format("content: {} with {}", family->signal->why, sig[Sig::DotRef].why);
  }
  if (family) return decided(*family, conflict ? "conflicting signals; first" : "content");
  if (nome3 != nullptr) return decided({Dialect::Nome3, nome3}, "content");
  // 2. `$bank.param` or `closed` without 2016 constructs is NOME3, with them NOME2.
  const bool weak_family = sig.has(Sig::WeakFamily) || sig.has(Sig::WeakNome2);
  if (sig.has(Sig::DotRef)) {
    if (weak_family) {
      const Signal& w = sig.has(Sig::WeakNome2) ? sig[Sig::WeakNome2] : sig[Sig::WeakFamily];
      c.set_dialect(Dialect::Nome2);
      return fmt::format("content: {} with {}", sig[Sig::DotRef].why, w.why);
    }
    return decided({Dialect::Nome3, &sig[Sig::DotRef]}, "content");
  }
  // 3. Weak signals: `object`, ring arguments valid in one era's order only.
  if (sig.has(Sig::WeakNome2)) return decided({Dialect::Nome2, &sig[Sig::WeakNome2]}, "weak content signal");
  if (sig.has(Sig::WeakFamily) && !sig.has(Sig::WeakNome3)) {
    return decided({Dialect::Nome, &sig[Sig::WeakFamily]}, "weak content signal");
  }
  if (sig.has(Sig::WeakNome3) && !sig.has(Sig::WeakFamily)) {
    return decided({Dialect::Nome3, &sig[Sig::WeakNome3]}, "weak content signal");
  }
  // 4. Nothing in the content decides: the extension (all generations saved `.nom`, so
  // for a `.nom` file this is a guess that matters only where such a file is ambiguous).
  const Dialect by_ext = ext == ".nom" ? Dialect::Nome3 : Dialect::Nome;
  c.set_dialect(by_ext);
  return fmt::format("no signals; `{}` extension", ext.empty() ? "(none)" : ext);
}

void collect_tcl(Context& c, const ast::Ast& a) {
  // Names Tcl code creates: `CreateScale NAME PARENT VAR …` gives NAME_VAR (or, inside a
  // proc, `$name_VAR` for whatever name the proc is called with), `set var …` globals,
  // and slideui objects (`CreateSLIDESubdivisionObject oSubdivision`).
  for (const ast::Item& it : a.top) {
    if (it.kind != ItemKind::Tcl) continue;
    // Compiled on the first Tcl block a process sees: compiling them is a sixth of the cost
    // of checking a small file, which most files (no Tcl) need not pay.
    static const std::regex scale_re(R"(CreateScale\s+(\S+)\s+\S+\s+([A-Za-z_][A-Za-z0-9_]*))");
    static const std::regex set_re(R"((?:^|[\s;{])set\s+([A-Za-z_][A-Za-z0-9_]*))");
    static const std::regex obj_re(R"(CreateSLIDE\w*Object\s+([A-Za-z_][A-Za-z0-9_]*))");
    std::string text(it.text);
    for (std::sregex_iterator i(text.begin(), text.end(), scale_re), e; i != e; ++i) {
      std::string owner = (*i)[1];
      std::string var = (*i)[2];
      if (!owner.empty() && owner[0] == '$') {
        c.tcl_suffixes.insert("_" + var);
      } else {
        c.tcl_vars.insert(owner + "_" + var);
      }
    }
    for (std::sregex_iterator i(text.begin(), text.end(), set_re), e; i != e; ++i) c.tcl_vars.insert((*i)[1]);
    for (std::sregex_iterator i(text.begin(), text.end(), obj_re), e; i != e; ++i) c.tcl_vars.insert((*i)[1]);
    c.has_tcl = true;
  }
}

}  // namespace nomec::check
