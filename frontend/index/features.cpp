// Per-file features computed on request from the text and the index: semantic tokens
// (scanner tokens classified by the occurrences and the keyword tables), folding ranges
// (multi-line statements and `(* *)` comments) and rename (validated, then re-checked when
// the index came from `analyze`, so a rename never silently changes what a name means).
#include <algorithm>
#include <fmt/format.h>
#include <map>

#include "frontend/index/index.h"
#include "frontend/index/keywords.h"
#include "frontend/parse/parse.h"

namespace nomec::index {

namespace {

TokenType type_of(SymbolKind k) {
  return k == SymbolKind::Bank || k == SymbolKind::Parameter ? TokenType::Parameter : TokenType::Name;
}

bool is_function_name(std::string_view w) {
  for (const FunctionDoc& f : functions()) {
    if (f.name == w) return true;
  }
  return false;
}

}  // namespace

std::vector<SemanticToken> Index::semantic_tokens(FileId file) const {
  std::vector<SemanticToken> out;
  if (!file.is_valid() || file.index >= static_cast<int32_t>(sources_->file_count())) return out;
  std::string_view text = sources_->text(file);
  std::vector<LexToken> toks = lex_file(text);
  out.reserve(toks.size());
  auto occ = std::lower_bound(occurrences_.begin(), occurrences_.end(), file.index,
                              [](const Occurrence& o, int32_t f) { return o.range.file.index < f; });
  auto emit = [&](uint32_t b, uint32_t e, TokenType t, bool def) {
    out.push_back({SourceRange{file, b, e}, t, def});
  };
  for (size_t i = 0; i < toks.size(); ++i) {
    const LexToken& t = toks[i];
    while (occ != occurrences_.end() && occ->range.file == file && occ->range.begin < t.begin) ++occ;
    switch (t.kind) {
      case LexKind::LineComment:
      case LexKind::BlockComment: emit(t.begin, t.end, TokenType::Comment, false); continue;
      case LexKind::String:
      case LexKind::Raw: emit(t.begin, t.end, TokenType::String, false); continue;
      case LexKind::TclInit: {  // `tclinit` then its `{ … }` script
        const uint32_t brace = static_cast<uint32_t>(std::min<size_t>(text.find('{', t.begin), t.end));
        emit(t.begin, t.begin + 7, TokenType::Keyword, false);
        emit(brace, t.end, TokenType::String, false);
        continue;
      }
      case LexKind::Number: emit(t.begin, t.end, TokenType::Number, false); continue;
      case LexKind::Operator: emit(t.begin, t.end, TokenType::Operator, false); continue;
      case LexKind::Word:
      case LexKind::DollarRef: break;
      default: continue;
    }
    bool any = false;
    while (occ != occurrences_.end() && occ->range.file == file && occ->range.end <= t.end) {
      emit(occ->range.begin, occ->range.end, type_of(symbols_[occ->symbol].kind), occ->is_definition);
      any = true;
      ++occ;
    }
    if (any) continue;
    if (t.kind == LexKind::DollarRef) {
      emit(t.begin, t.end, TokenType::Parameter, false);
      continue;
    }
    std::string_view w = text.substr(t.begin, t.end - t.begin);
    bool call = i + 1 < toks.size() && toks[i + 1].kind == LexKind::LParen && toks[i + 1].begin == t.end;
    if (call && is_function_name(w)) {
      emit(t.begin, t.end, TokenType::Function, false);
    } else if (is_keyword(w)) {
      emit(t.begin, t.end, TokenType::Keyword, false);
    } else if (w == "pi" || w == "e") {
      emit(t.begin, t.end, TokenType::Number, false);
    } else {
      emit(t.begin, t.end, TokenType::Name, false);
    }
  }
  return out;
}

std::vector<FoldingRange> Index::folding_ranges(FileId file) const {
  std::vector<FoldingRange> all;
  if (!file.is_valid() || file.index >= static_cast<int32_t>(sources_->file_count())) return all;
  auto line = [&](uint32_t off) { return sources_->line_col(file, off).line; };
  auto add = [&](SourceRange r, bool comment) {
    if (r.end > r.begin && line(r.begin) < line(r.end > 0 ? r.end - 1 : r.end)) all.push_back({r, comment});
  };
  for (const auto& a : check_->asts) {
    if (a->file != file) continue;
    for (const ast::Item& it : a->top) {
      if (it.kind == ast::ItemKind::Tcl) add(it.range, false);
    }
    for (const ast::Stmt& s : a->stmts) {
      if (s.range.file == file) add(s.range, false);
    }
  }
  std::string_view text = sources_->text(file);
  for (const LexToken& t : lex_file(text)) {
    if (t.kind == LexKind::BlockComment) add(SourceRange{file, t.begin, t.end}, true);
  }
  std::sort(all.begin(), all.end(), [](const FoldingRange& a, const FoldingRange& b) {
    return a.range.begin != b.range.begin ? a.range.begin < b.range.begin : a.range.end > b.range.end;
  });
  // Keep a properly nested set (recovered statements may overlap oddly).
  std::vector<FoldingRange> out;
  std::vector<SourceRange> stack;
  for (const FoldingRange& f : all) {
    while (!stack.empty() && stack.back().end <= f.range.begin) stack.pop_back();
    if (!stack.empty() && f.range.end > stack.back().end) continue;
    if (!out.empty() && out.back().range == f.range) continue;
    out.push_back(f);
    stack.push_back(f.range);
  }
  return out;
}

// ---------------- rename ----------------

namespace {

bool valid_identifier(std::string_view s) {
  if (s.empty()) return false;
  char c = s[0];
  if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_')) return false;
  for (char d : s) {
    if (!((d >= 'A' && d <= 'Z') || (d >= 'a' && d <= 'z') || (d >= '0' && d <= '9') || d == '_')) return false;
  }
  return true;
}

// Symbols that share a namespace (a clash would be a redefinition).
int ns_class(SymbolKind k) {
  switch (k) {
    case SymbolKind::Bank: return 0;
    case SymbolKind::Parameter: return 1;
    case SymbolKind::Point: return 2;
    case SymbolKind::Face: return 3;
    case SymbolKind::Surface: return 4;
    case SymbolKind::Instance: return 5;
    default: return 6;
  }
}

}  // namespace

std::optional<SourceRange> Index::prepare_rename(FileId file, uint32_t offset) const {
  SourceRange r;
  SymbolId s = symbol_at(file, offset, &r);
  if (s < 0) return std::nullopt;
  if (!rename_problem(symbols_[s], symbols_[s].name).empty()) return std::nullopt;
  return r;
}

std::string Index::rename_problem(const Symbol& s, std::string_view new_name) const {
  bool has_def = false;
  for (uint32_t i = ref_begin_[s.id]; i < ref_begin_[s.id + 1]; ++i) {
    if (occurrences_[ref_items_[i]].is_definition) has_def = true;
  }
  if (!has_def) {
    if (s.kind == SymbolKind::Instance) {
      return fmt::format("this SLIDE instance is named after its target `{}`; give it a name with `id NAME` to rename it", s.name);
    }
    return fmt::format("`{}` is a fixed name and cannot be renamed", s.name);
  }
  if (!valid_identifier(new_name)) {
    return fmt::format("`{}` is not a valid name: use letters, digits and `_`, not starting with a digit", new_name);
  }
  ast::BlockKind bk;
  if (block_by_open(new_name, &bk) || block_by_close(new_name, &bk) || new_name == "set" || new_name == "list" ||
      new_name == "include" || new_name == "expr" || new_name == "tclinit" || new_name == "tclupdate") {
    return fmt::format("`{}` is a NOME keyword and cannot be used as a name", new_name);
  }
  if (is_keyword(new_name) && s.kind != SymbolKind::Parameter && s.kind != SymbolKind::Bank) {
    return fmt::format("`{}` is an option word of NOME statements; as a name it would be read as that option", new_name);
  }
  if (new_name == "pi" || new_name == "e" || ((new_name == "time" || new_name == "frame") && s.kind == SymbolKind::Bank)) {
    return fmt::format("`{}` is a built-in value and cannot be used as a name", new_name);
  }
  for (const Symbol& o : symbols_) {
    if (o.id == s.id || o.name != new_name || ns_class(o.kind) != ns_class(s.kind)) continue;
    bool same_scope = s.kind == SymbolKind::Parameter || s.kind == SymbolKind::Instance || s.kind == SymbolKind::Point
                          ? o.parent == s.parent
                          : true;
    if (!same_scope) continue;
    LineCol lc = sources_->line_col(o.name_range.file, o.name_range.begin);
    return fmt::format("`{}` is already defined as a {} (line {})", new_name, symbol_kind_name(o.kind), lc.line);
  }
  return {};
}

std::variant<std::vector<TextEdit>, std::string> Index::rename(FileId file, uint32_t offset,
                                                               std::string_view new_name) const {
  SymbolId sid = symbol_at(file, offset, nullptr);
  if (sid < 0) return std::string("there is no renamable name here");
  const Symbol& s = symbols_[sid];
  if (new_name == s.name) return std::vector<TextEdit>{};
  if (std::string why = rename_problem(s, new_name); !why.empty()) return why;
  std::vector<Occurrence> occs = references(sid, true);
  // 2016 `_`-joined vertex names (`cf_fun3_hc3`) are split at `_`: a new name with `_` could
  // change how they split.
  if (new_name.find('_') != std::string_view::npos && s.kind == SymbolKind::Instance) {
    for (const Occurrence& o : occs) {
      std::string_view t = sources_->text(o.range.file);
      bool joined = (o.range.begin > 0 && t[o.range.begin - 1] == '_') || (o.range.end < t.size() && t[o.range.end] == '_');
      if (!o.is_definition && joined) {
        return fmt::format("`{}` is used in 2016 `_`-joined vertex names; a new name containing `_` would make them ambiguous", s.name);
      }
    }
  }
  std::vector<TextEdit> edits;
  edits.reserve(occs.size());
  for (const Occurrence& o : occs) edits.push_back({o.range, std::string(new_name)});
  if (!options_) return edits;

  // Re-check the renamed text: same number of uses of the renamed symbol, no new errors.
  std::map<int32_t, std::string> texts;
  for (const TextEdit& e : edits) texts.emplace(e.range.file.index, std::string(sources_->text(e.range.file)));
  int64_t def_shift = 0;
  SourceRange def = s.name_range;
  for (auto& [f, txt] : texts) {
    int64_t shift = 0;
    std::string out;
    out.reserve(txt.size());
    uint32_t at = 0;
    for (const TextEdit& e : edits) {
      if (e.range.file.index != f) continue;
      out.append(txt, at, e.range.begin - at);
      out += e.new_text;
      at = e.range.end;
      if (e.range.file == def.file && e.range.begin < def.begin) shift += static_cast<int64_t>(e.new_text.size()) - (e.range.end - e.range.begin);
    }
    out.append(txt, at, std::string::npos);
    txt = std::move(out);
    if (f == def.file.index) def_shift = shift;
  }
  CheckOptions opts = *options_;
  FileReader inner = opts.read_file;
  std::map<std::string, std::string> by_name;
  for (auto& [f, txt] : texts) by_name.emplace(std::string(sources_->name(FileId{f})), txt);
  opts.read_file = [inner, by_name](const std::string& path) -> std::optional<std::string> {
    if (auto it = by_name.find(path); it != by_name.end()) return it->second;
    return inner ? inner(path) : std::nullopt;
  };
  FileId main = check_->asts.empty() ? FileId{0} : check_->asts.front()->file;
  std::string main_text = by_name.contains(main_path_) ? by_name[main_path_] : std::string(sources_->text(main));
  DiagnosticEngine diags;
  Analysis again = analyze(main_path_, std::move(main_text), opts, diags);
  const Index& ix = *again.index;
  // Files are added in the same order, so file ids correspond.
  FileId new_def_file = def.file;
  uint32_t new_def = static_cast<uint32_t>(static_cast<int64_t>(def.begin) + def_shift);
  std::optional<Occurrence> o = ix.occurrence_at(new_def_file, new_def);
  bool same = o && o->is_definition && ix.references(o->symbol, true).size() == occs.size();
  int errors_before = error_count_;
  if (errors_before < 0) {
    // Built without the original diagnostics: count them by checking the original text.
    DiagnosticEngine original;
    analyze(main_path_, std::string(sources_->text(main)), *options_, original);
    errors_before = original.error_count();
  }
  if (diags.error_count() > errors_before || !same) {
    return fmt::format("renaming `{}` to `{}` would change what some names refer to; rename it by hand", s.name, new_name);
  }
  return edits;
}

}  // namespace nomec::index
