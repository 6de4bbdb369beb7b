// Which dialect a file is written in (docs/dialects.md): `--dialect`, the `.slf` extension,
// then signals in its content (NOME 2016's `$bank_param`, `isloop`, saved work; NOME3's
// `$bank.param`, `list` in a bank, its commands), the `.nom` extension deciding conflicts;
// and the names SLIDE's Tcl code creates, so their uses are reported as Tcl's, not typos.
#include <fmt/format.h>
#include <regex>
#include <unordered_set>

#include "frontend/check/handlers.h"
#include "frontend/source/file_kinds.h"

namespace nomec::check {

namespace {

// The first place that signals each dialect, and what it was.
struct Signals {
  SourceRange nome_at, nome3_at;
  std::string nome_why, nome3_why;
  void nome(SourceRange r, std::string why) {
    if (!nome_at.is_valid()) {
      nome_at = r;
      nome_why = std::move(why);
    }
  }
  void nome3(SourceRange r, std::string why) {
    if (!nome3_at.is_valid()) {
      nome3_at = r;
      nome3_why = std::move(why);
    }
  }
  bool both() const { return nome_at.is_valid() && nome3_at.is_valid(); }
};

// Statements and option words that only one dialect has.
void statement_signals(const ast::Ast& a, Signals& sig) {
  for (const ast::Stmt& s : a.stmts) {
    switch (s.kind) {
      case BlockKind::Consolidate:
      case BlockKind::Savedparameter:
      case BlockKind::Savedworkingmesh:
        sig.nome(s.open_kw, fmt::format("`{}`", s.keyword));
        break;
      case BlockKind::Sweep:
      case BlockKind::Sharp:
        sig.nome3(s.open_kw, fmt::format("NOME3 command `{}`", s.keyword));
        break;
      default:
        if (std::optional<ir::GenKind> gen = generator_of(s)) {
          const ir::GeneratorInfo& g = ir::generator(*gen);
          if ((g.signals & kNome3) != 0 && s.keyword == g.keyword) {
            sig.nome3(s.open_kw, fmt::format("NOME3 command `{}`", g.keyword));
          }
          if (s.close_text != ast::end_keyword(s.keyword) && g.closes_with(s.keyword, s.close_text)) {
            sig.nome(s.close_kw, fmt::format("`{} … {}`", s.keyword, s.close_text));
          }
        }
        break;
    }
    for (const ast::Item& it : s.items) {
      if (it.kind != ItemKind::Word) continue;
      if (it.text == "isloop") sig.nome(it.range, "`isloop`");
      if (it.text == "sd_type") sig.nome3(it.range, "`sd_type`");
      if (it.text == "list" && s.kind == BlockKind::Bank) sig.nome3(it.range, "`list` in a bank");
    }
  }
}

// `$bank_param` (2016) and `$bank.param` (NOME3) references to banks of the file.
void reference_signals(const ast::Ast& a, Signals& sig) {
  std::unordered_set<std::string_view> banks;  // views of the syntax tree's text
  for (const ast::Item& it : a.top) {
    if (it.kind == ItemKind::Block && a.stmt(it.block).kind == BlockKind::Bank) {
      const ast::Stmt& s = a.stmt(it.block);
      if (!s.items.empty() && s.items[0].kind == ItemKind::Word) banks.insert(s.items[0].text);
    }
  }
  // Only the first signal of each kind is kept, so the scan stops once both are known.
  for (const ast::Expr& e : a.exprs) {
    if (sig.both()) break;
    if (e.kind != ast::ExprKind::DollarRef) continue;
    std::string_view t = e.text.substr(1);
    if (auto dot = t.find('.'); dot != std::string_view::npos) {
      if (!sig.nome3_at.is_valid() && banks.contains(t.substr(0, dot))) sig.nome3(e.range, "`$bank.param`");
    } else if (!sig.nome_at.is_valid()) {
      for (size_t u = t.find('_'); u != std::string_view::npos; u = t.find('_', u + 1)) {
        if (banks.contains(t.substr(0, u))) {
          sig.nome(e.range, "`$bank_param`");
          break;
        }
      }
    }
  }
}

}  // namespace

std::string choose_dialect(Context& c, const ast::Ast& a, const std::string& path) {
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
  statement_signals(a, sig);
  reference_signals(a, sig);
  const Dialect by_ext = ext == ".nom" ? Dialect::Nome3 : Dialect::Nome;
  if (sig.both()) {
    c.set_dialect(by_ext);
    c.diags()
        .emit(DiagKind::DialectConflict, sig.nome_at.begin < sig.nome3_at.begin ? sig.nome3_at : sig.nome_at,
              fmt::format("this file mixes NOME 2016 ({}) and NOME3 ({}) syntax; checking it as `{}`", sig.nome_why,
                          sig.nome3_why, dialect_name(c.dialect())))
        .note(sig.nome_at, fmt::format("NOME 2016 signal: {}", sig.nome_why))
        .note(sig.nome3_at, fmt::format("NOME3 signal: {}", sig.nome3_why));
    return fmt::format("conflicting signals; `{}` extension decides", ext);
  }
  if (sig.nome_at.is_valid()) {
    c.set_dialect(Dialect::Nome);
    return "content: " + sig.nome_why;
  }
  if (sig.nome3_at.is_valid()) {
    c.set_dialect(Dialect::Nome3);
    return "content: " + sig.nome3_why;
  }
  c.set_dialect(by_ext);
  return fmt::format("no signals; `{}` extension", ext.empty() ? "(none)" : ext);
}

void collect_tcl(Context& c, const ast::Ast& a) {
  // Names Tcl code creates: `CreateScale NAME PARENT VAR …` gives NAME_VAR (or, inside a
  // proc, `$name_VAR` for whatever name the proc is called with), `set var …` globals,
  // and slideui objects (`CreateSLIDESubdivisionObject oSubdivision`).
  static const std::regex scale_re(R"(CreateScale\s+(\S+)\s+\S+\s+([A-Za-z_][A-Za-z0-9_]*))");
  static const std::regex set_re(R"((?:^|[\s;{])set\s+([A-Za-z_][A-Za-z0-9_]*))");
  static const std::regex obj_re(R"(CreateSLIDE\w*Object\s+([A-Za-z_][A-Za-z0-9_]*))");
  for (const ast::Item& it : a.top) {
    if (it.kind != ItemKind::Tcl) continue;
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
