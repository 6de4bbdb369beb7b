// Incremental checks (see incremental.h). A top-level item (`ast::Ast::top`: a statement,
// or a stray word) is the unit: the basis keeps, per item, its text span, the diagnostics
// checking it made (and those that resolved at the end, such as `delete` paths), the names
// it defines and the items it may read. A new version is checked in a context where every
// item is declared but only these are processed: the changed items, everything that reads
// them (transitively), and everything those read (transitively).
#include "frontend/check/incremental.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fmt/format.h>

#include "frontend/check/handlers.h"
#include "frontend/parse/parse.h"

namespace nomec {

namespace {

using check::NameTable;

struct Span {
  uint32_t begin = 0, end = 0;
  friend bool operator==(const Span&, const Span&) = default;
};

Span span_of(const ast::Ast& a, const ast::Item& it) {
  const SourceRange r = it.kind == ast::ItemKind::Block ? a.stmt(it.block).range : it.range;
  return {r.begin, r.end};
}

// The item whose span holds [begin, end), or -1.
int32_t item_at(std::span<const Span> spans, uint32_t begin, uint32_t end) {
  auto it = std::upper_bound(spans.begin(), spans.end(), begin, [](uint32_t x, const Span& s) { return x < s.begin; });
  if (it == spans.begin()) return -1;
  --it;
  return begin >= it->begin && end <= it->end ? static_cast<int32_t>(it - spans.begin()) : -1;
}

// How an item was read, relative to where it starts: its statements at any depth (kind, how
// their end was found), their items and the values and list elements in them (kind and
// place). Equal texts can be read differently after an edit elsewhere (an unclosed bracket
// above changes how the parser recovers), so items the edit left alone must also have kept
// their fingerprints.
uint64_t fingerprint(const ast::Ast& a, const ast::Item& top, uint32_t base, std::vector<const ast::Item*>& todo) {
  uint64_t h = 0xcbf29ce484222325ull;
  auto mix = [&](uint64_t v) {
    h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
  };
  auto range = [&](SourceRange r) { mix((static_cast<uint64_t>(r.begin - base) << 32) | (r.end - base)); };
  auto expr = [&](ast::ExprId e) {
    const ast::Expr& x = a.expr(e);
    mix(static_cast<uint64_t>(x.kind));
    range(x.range);
  };
  todo.assign(1, &top);
  while (!todo.empty()) {
    const ast::Item& it = *todo.back();
    todo.pop_back();
    mix(static_cast<uint64_t>(it.kind));
    range(it.range);
    if (it.kind == ast::ItemKind::Value) expr(it.expr);
    if (it.kind == ast::ItemKind::List) {
      for (ast::ExprId e : a.list(it.list).elems) expr(e);
    }
    if (it.kind != ast::ItemKind::Block) continue;
    const ast::Stmt& s = a.stmt(it.block);
    mix(static_cast<uint64_t>(s.kind) << 8 | static_cast<uint64_t>(s.close_repair));
    range(s.range);
    for (const ast::Item& sub : s.items) todo.push_back(&sub);
  }
  return h;
}

bool word_char(char ch) {
  return std::isalnum(static_cast<unsigned char>(ch)) != 0 || ch == '_' || ch == '.';
}

// Every name a word may look up: the word and each part of it ending before an `_` or `.`
// (`fb0_hc0` → `fb0`, `fb0_hc0`), also without leading `_`/`.` (2016 `_ir_i1`); in a run
// that starts with a digit, the same from each letter that follows a number (`2x`).
template <typename F>
void for_each_key(std::string_view w, F&& f) {
  auto prefixes = [&](std::string_view s) {
    for (size_t u = 1; u < s.size(); ++u) {
      if (s[u] == '_' || s[u] == '.') f(s.substr(0, u));
    }
    if (!s.empty()) f(s);
  };
  auto both = [&](std::string_view s) {
    prefixes(s);
    size_t lead = 0;
    while (lead < s.size() && (s[lead] == '_' || s[lead] == '.')) ++lead;
    if (lead > 0) prefixes(s.substr(lead));
  };
  if (!std::isdigit(static_cast<unsigned char>(w[0]))) {
    both(w);
    return;
  }
  for (size_t t = 1; t < w.size(); ++t) {
    const bool letter = std::isalpha(static_cast<unsigned char>(w[t])) != 0 || w[t] == '_';
    if (letter && (std::isdigit(static_cast<unsigned char>(w[t - 1])) != 0 || w[t - 1] == '.')) both(w.substr(t));
  }
}

// A compact list of int lists (one per item).
struct Lists {
  std::vector<uint32_t> start{0};
  std::vector<int32_t> values;
  std::span<const int32_t> of(size_t i) const { return {values.data() + start[i], values.data() + start[i + 1]}; }
  void close() { start.push_back(static_cast<uint32_t>(values.size())); }
};

// A definition with the item that makes it.
struct Decl {
  std::string name;
  Span span;
  bool top_scope = false;
  bool while_checking = false;
};

}  // namespace

class IncrementalBasis {
 public:
  std::shared_ptr<const SourceManager> sources;  // holds `text`
  std::string_view text;
  FileId file;
  Dialect dialect = Dialect::Nome;
  std::vector<Span> spans;
  std::vector<ast::ItemKind> kinds;
  std::vector<ast::BlockKind> blocks;
  std::vector<std::string> keywords;
  std::vector<uint64_t> prints;  // each item's fingerprint
  // The diagnostics each item made while it was checked, and those that resolved at the end
  // of the check within its text.
  std::vector<std::vector<Diagnostic>> during, after;
  std::vector<std::vector<Decl>> decls;  // per item
  NameTable<std::vector<int32_t>> defines;      // name → the items that define it
  NameTable<std::vector<int32_t>> defines_top;  // the same for the file's own scope
  // Items that define a name only when they are checked (`consolidate`): checked every time,
  // so that every name is known (a "did you mean" hint chooses among all of them).
  std::vector<int32_t> always;
  Lists reads, readers;
};

namespace {

// The items item `self` (whose text is `text[span]`, defining `decls`) may read.
void reads_of(const IncrementalBasis& b, std::string_view text, Span span, int32_t self, std::span<const Decl> decls,
              std::vector<int32_t>& out) {
  out.clear();
  auto add_all = [&](const NameTable<std::vector<int32_t>>& table, std::string_view key) {
    auto it = table.find(key);
    if (it == table.end()) return;
    for (int32_t i : it->second) {
      if (i != self) out.push_back(i);
    }
  };
  for (uint32_t pos = span.begin; pos < span.end;) {
    if (!word_char(text[pos])) {
      ++pos;
      continue;
    }
    const uint32_t wb = pos;
    while (pos < span.end && word_char(text[pos])) ++pos;
    const std::string_view w = text.substr(wb, pos - wb);
    // The word that names a definition reads nothing, except that a second definition of a
    // name in the file's scope is a duplicate of the others.
    auto d = std::find_if(decls.begin(), decls.end(),
                          [&](const Decl& x) { return x.span.begin == wb && x.span.end == pos && x.name == w; });
    if (d != decls.end()) {
      if (d->top_scope) add_all(b.defines_top, w);
      continue;
    }
    for_each_key(w, [&](std::string_view key) { add_all(b.defines, key); });
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

// Marks the items whose text mentions `name` as a word or a word's part ending before `_`
// or `.`, except where the word defines an instance of that name inside a group or block
// (`is_nested_definition(item, begin, end)`): names in other scopes than the file's do not
// meet there.
template <typename NestedDefinition>
void mentions(std::string_view text, std::span<const Span> spans, std::string_view name, std::vector<uint8_t>& into,
              const NestedDefinition& is_nested_definition) {
  if (name.empty()) return;
  // Where `for_each_key` starts a key: a word's start, after its leading `_`/`.`, or a
  // letter after a number.
  auto key_start = [&](size_t at) {
    size_t ws = at;
    while (ws > 0 && word_char(text[ws - 1])) --ws;
    if (ws == at) return true;
    if (std::all_of(text.begin() + static_cast<std::ptrdiff_t>(ws), text.begin() + static_cast<std::ptrdiff_t>(at),
                    [](char ch) { return ch == '_' || ch == '.'; })) {
      return true;
    }
    return std::isdigit(static_cast<unsigned char>(text[ws])) != 0 &&
           (std::isdigit(static_cast<unsigned char>(text[at - 1])) != 0 || text[at - 1] == '.');
  };
  for (size_t at = text.find(name); at != std::string_view::npos; at = text.find(name, at + 1)) {
    const size_t e = at + name.size();
    if (e < text.size() && word_char(text[e]) && text[e] != '_' && text[e] != '.') continue;
    if (!key_start(at)) continue;
    const int32_t i = item_at(spans, static_cast<uint32_t>(at), static_cast<uint32_t>(e));
    if (i < 0 || into[static_cast<size_t>(i)]) continue;
    const bool whole_word = (at == 0 || !word_char(text[at - 1])) && (e == text.size() || !word_char(text[e]));
    if (whole_word && is_nested_definition(i, static_cast<uint32_t>(at), static_cast<uint32_t>(e))) continue;
    into[static_cast<size_t>(i)] = 1;
  }
}

// Spreads `marked` along `edges` (item → the items it points to) until nothing changes.
void close_over(std::vector<uint8_t>& marked, const std::function<std::span<const int32_t>(size_t)>& edges) {
  std::vector<int32_t> todo;
  for (size_t i = 0; i < marked.size(); ++i) {
    if (marked[i]) todo.push_back(static_cast<int32_t>(i));
  }
  while (!todo.empty()) {
    const size_t i = static_cast<size_t>(todo.back());
    todo.pop_back();
    for (int32_t j : edges(i)) {
      if (!marked[static_cast<size_t>(j)]) {
        marked[static_cast<size_t>(j)] = 1;
        todo.push_back(j);
      }
    }
  }
}

// Splits the diagnostics a check made from `first` on into each item's: those made while
// the item was checked (`marks`) and those that resolved at the end, by where they lie.
// False when one lies outside the item that made it, or outside every item.
bool split_by_item(std::vector<Diagnostic> diags, size_t first, std::span<const std::pair<int32_t, uint32_t>> marks,
                   std::span<const Span> spans, FileId file, std::vector<std::vector<Diagnostic>>& during,
                   std::vector<std::vector<Diagnostic>>& after) {
  during.assign(spans.size(), {});
  after.assign(spans.size(), {});
  auto inside = [&](const Diagnostic& d, int32_t item) {
    return d.range.file == file && d.range.begin >= spans[static_cast<size_t>(item)].begin &&
           d.range.end <= spans[static_cast<size_t>(item)].end;
  };
  size_t at = first;
  for (const auto& [item, end] : marks) {
    for (; at < end && at < diags.size(); ++at) {
      if (!inside(diags[at], item)) return false;
      during[static_cast<size_t>(item)].push_back(std::move(diags[at]));
    }
  }
  for (; at < diags.size(); ++at) {
    const Diagnostic& d = diags[at];
    const int32_t item = d.range.file == file ? item_at(spans, d.range.begin, d.range.end) : -1;
    if (item < 0) return false;
    after[static_cast<size_t>(item)].push_back(std::move(diags[at]));
  }
  return true;
}

// The definitions `names` grouped by the item whose text holds them; false when one lies
// outside every item.
bool decls_by_item(std::span<const DeclaredName> names, std::span<const Span> spans, FileId file,
                   std::vector<std::vector<Decl>>& out) {
  out.assign(spans.size(), {});
  for (const DeclaredName& n : names) {
    const int32_t item = n.range.file == file ? item_at(spans, n.range.begin, n.range.end) : -1;
    if (item < 0) return false;
    out[static_cast<size_t>(item)].push_back({n.name, {n.range.begin, n.range.end}, n.top_scope, n.while_checking});
  }
  return true;
}

}  // namespace

std::shared_ptr<const IncrementalBasis> make_incremental_basis(std::shared_ptr<const SourceManager> sources,
                                                               const CheckResult& result,
                                                               std::vector<Diagnostic> diagnostics) {
  if (!result.incremental_ok || result.cancelled || result.asts.empty()) return nullptr;
  const ast::Ast& a = *result.asts.front();
  auto b = std::make_shared<IncrementalBasis>();
  b->file = a.file;
  b->text = sources->text(a.file);
  b->sources = std::move(sources);
  b->dialect = result.dialect;
  const size_t n = a.top.size();
  b->spans.reserve(n);
  std::vector<const ast::Item*> todo;
  for (const ast::Item& it : a.top) {
    b->spans.push_back(span_of(a, it));
    b->kinds.push_back(it.kind);
    const bool block = it.kind == ast::ItemKind::Block;
    b->blocks.push_back(block ? a.stmt(it.block).kind : ast::BlockKind::Bank);
    b->keywords.emplace_back(block ? a.stmt(it.block).keyword : std::string_view());
    b->prints.push_back(fingerprint(a, it, b->spans.back().begin, todo));
  }
  for (size_t i = 1; i < n; ++i) {
    if (b->spans[i].begin < b->spans[i - 1].end) return nullptr;  // not in order: not ours to split
  }
  if (!split_by_item(std::move(diagnostics), result.first_statement_diagnostic, result.item_marks, b->spans, b->file, b->during,
                     b->after)) {
    return nullptr;
  }
  if (!decls_by_item(result.declared_names, b->spans, b->file, b->decls)) return nullptr;
  for (size_t i = 0; i < n; ++i) {
    if (std::any_of(b->decls[i].begin(), b->decls[i].end(), [](const Decl& d) { return d.while_checking; })) {
      b->always.push_back(static_cast<int32_t>(i));
    }
    for (const Decl& d : b->decls[i]) {
      b->defines[d.name].push_back(static_cast<int32_t>(i));
      if (d.top_scope) b->defines_top[d.name].push_back(static_cast<int32_t>(i));
    }
  }
  std::vector<int32_t> one;
  std::vector<std::vector<int32_t>> readers(n);
  for (size_t i = 0; i < n; ++i) {
    reads_of(*b, b->text, b->spans[i], static_cast<int32_t>(i), b->decls[i], one);
    b->reads.values.insert(b->reads.values.end(), one.begin(), one.end());
    b->reads.close();
    for (int32_t j : one) readers[static_cast<size_t>(j)].push_back(static_cast<int32_t>(i));
  }
  for (const std::vector<int32_t>& r : readers) {
    b->readers.values.insert(b->readers.values.end(), r.begin(), r.end());
    b->readers.close();
  }
  return b;
}

IncrementalOutcome check_incrementally(const IncrementalBasis& b, SourceManager& sources, const std::string& path,
                                       std::string text, const CheckOptions& options, DiagnosticEngine& diags,
                                       ParseCache* cache) {
  IncrementalOutcome out;
  auto give_up = [&](std::string why) {
    out.done = false;
    out.why = std::move(why);
    return out;
  };
  // The edit: the old text's [p, old_n - q) became the new text's [p, new_n - q).
  const std::string_view old_text = b.text;
  const size_t old_n = old_text.size(), new_n = text.size();
  // Compared a block at a time (memcmp), then byte by byte in the block that differs.
  constexpr size_t kBlock = 256;
  const size_t common = std::min(old_n, new_n);
  size_t p = 0;
  while (p + kBlock <= common && std::memcmp(old_text.data() + p, text.data() + p, kBlock) == 0) p += kBlock;
  while (p < common && old_text[p] == text[p]) ++p;
  size_t q = 0;
  while (q + kBlock <= common - p &&
         std::memcmp(old_text.data() + old_n - q - kBlock, text.data() + new_n - q - kBlock, kBlock) == 0) {
    q += kBlock;
  }
  while (q < common - p && old_text[old_n - 1 - q] == text[new_n - 1 - q]) ++q;
  const int64_t delta = static_cast<int64_t>(new_n) - static_cast<int64_t>(old_n);
  const size_t old_tail = old_n - q;  // the old text from here on is unchanged, `delta` later
  // Where a span of the old text lies against the edit, and where one after it moved to.
  auto before_edit = [&](Span s) { return s.end < p; };
  auto after_edit = [&](Span s) { return s.begin > old_tail; };
  auto shifted = [&](Span s, int64_t by) {
    return Span{static_cast<uint32_t>(s.begin + by), static_cast<uint32_t>(s.end + by)};
  };

  const FileId file = sources.add_file(path, std::move(text));
  const std::string_view now_text = sources.text(file);
  const double parse_start = thread_cpu_ms();
  ast::Ast a = cache != nullptr ? cache->parse(sources, file, diags) : parse_file(sources, file, diags);
  out.parse_ms = thread_cpu_ms() - parse_start;
  if (options.parsed) options.parsed();

  // Items before the edit keep their place, those after it move by `delta`; those it touches
  // changed, and must still be the same kind of statement.
  const size_t n = b.spans.size();
  if (a.top.size() != n) return give_up("the edit added or removed a top-level statement");
  std::vector<Span> spans(n);
  std::vector<uint8_t> changed(n, 0);
  std::vector<int32_t> changed_list;
  std::vector<const ast::Item*> todo;
  // The statements on either side of the edit count as changed too: how a statement's end
  // is found can depend on the line after it (NOME 2016's statements that end at the end of
  // their line).
  size_t first_touched = n, last_touched = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!before_edit(b.spans[i]) && !after_edit(b.spans[i])) {
      first_touched = std::min(first_touched, i);
      last_touched = i;
    }
  }
  if (first_touched == n) {  // the edit lies between two statements
    first_touched = static_cast<size_t>(std::upper_bound(b.spans.begin(), b.spans.end(), static_cast<uint32_t>(p),
                                                         [](uint32_t x, const Span& sp) { return x < sp.begin; }) -
                                        b.spans.begin());
    last_touched = first_touched;
    if (first_touched > 0) --first_touched;
    else if (n > 0) last_touched = 0;
  }
  const size_t lo = first_touched > 0 ? first_touched - 1 : 0, hi = std::min(n == 0 ? 0 : n - 1, last_touched + 1);
  for (size_t i = 0; i < n; ++i) {
    const ast::Item& it = a.top[i];
    spans[i] = span_of(a, it);
    const Span old = b.spans[i];
    const bool near = n > 0 && i >= lo && i <= hi;
    if (it.kind != b.kinds[i]) return give_up("the edit changed what a statement is");
    if (!near && before_edit(old)) {
      if (spans[i] != old) return give_up("a statement before the edit moved");
    } else if (!near && after_edit(old)) {
      if (spans[i] != shifted(old, delta)) return give_up("a statement after the edit moved");
      // The parser reads forwards: what the edit can change beyond the statements beside it
      // lies after it.
      if (fingerprint(a, it, spans[i].begin, todo) != b.prints[i]) {
        return give_up("a statement the edit left alone was read differently");
      }
    } else {
      if (it.kind == ast::ItemKind::Block && (a.stmt(it.block).kind != b.blocks[i] || a.stmt(it.block).keyword != b.keywords[i])) {
        return give_up("the edit changed what a statement is");
      }
      changed[i] = 1;
      changed_list.push_back(static_cast<int32_t>(i));
    }
  }
  out.changed = changed_list.size();
  if (changed_list.size() > 16) return give_up("the edit changed more than 16 statements");

  // Moves a range of the old text to the new one; false when the edit touched it.
  auto move_range = [&](SourceRange& r) {
    if (!r.is_valid()) return true;
    if (r.file != b.file) return false;
    if (r.end <= p) {
      r.file = file;
      return true;
    }
    if (r.begin >= old_tail) {
      r = SourceRange{file, static_cast<uint32_t>(r.begin + delta), static_cast<uint32_t>(r.end + delta)};
      return true;
    }
    return false;
  };

  // The names each changed item defined, where the edit left them, assumed to be defined
  // there still (checked below); a name the edit touched is assumed to be a use.
  std::vector<std::vector<Decl>> assumed(n);
  for (int32_t k : changed_list) {
    for (const Decl& d : b.decls[static_cast<size_t>(k)]) {
      SourceRange r{b.file, d.span.begin, d.span.end};
      if (move_range(r) && now_text.substr(r.begin, r.end - r.begin) == d.name) {
        assumed[static_cast<size_t>(k)].push_back({d.name, {r.begin, r.end}, d.top_scope, d.while_checking});
      }
    }
  }
  std::vector<std::vector<int32_t>> new_reads(n);
  for (int32_t k : changed_list) {
    reads_of(b, now_text, spans[static_cast<size_t>(k)], k, assumed[static_cast<size_t>(k)], new_reads[static_cast<size_t>(k)]);
  }

  // A word of the new text that defines an instance inside a group or block: in an item the
  // edit left alone, where the basis found one; in a changed item, where it is assumed.
  auto nested_definition = [&](int32_t item, uint32_t begin, uint32_t end) {
    const size_t i = static_cast<size_t>(item);
    const std::string_view w = now_text.substr(begin, end - begin);
    if (changed[i]) {
      return std::any_of(assumed[i].begin(), assumed[i].end(), [&](const Decl& d) {
        return !d.top_scope && d.span == Span{begin, end} && d.name == w;
      });
    }
    const Span old = before_edit(b.spans[i]) ? Span{begin, end} : shifted(Span{begin, end}, -delta);
    return std::any_of(b.decls[i].begin(), b.decls[i].end(),
                       [&](const Decl& d) { return !d.top_scope && d.span == old && d.name == w; });
  };
  // To re-check: the changed items, the items that mention a definition whose name the edit
  // touched (a rename), and everything that reads those. A name being typed where there was
  // none is found after the check (the names the changed items define now).
  std::vector<uint8_t> recheck = changed;
  // A "did you mean" hint chooses among every name of its kind: when a definition is
  // renamed, the statements with a problem are re-checked too.
  auto with_problems = [&](std::vector<uint8_t>& into) {
    for (size_t i = 0; i < n; ++i) {
      if (!b.during[i].empty() || !b.after[i].empty()) into[i] = 1;
    }
  };
  bool renamed = false;
  for (int32_t k : changed_list) {
    const std::vector<Decl>& kept = assumed[static_cast<size_t>(k)];
    for (const Decl& d : b.decls[static_cast<size_t>(k)]) {
      const bool moved_intact = std::any_of(kept.begin(), kept.end(), [&](const Decl& x) { return x.name == d.name; });
      if (moved_intact) continue;
      mentions(now_text, spans, d.name, recheck, nested_definition);
      renamed = true;
    }
  }
  if (renamed) with_problems(recheck);
  close_over(recheck, [&](size_t i) { return b.readers.of(i); });
  std::vector<uint8_t> check_items = recheck;
  for (int32_t i : b.always) check_items[static_cast<size_t>(i)] = 1;
  close_over(check_items, [&](size_t i) -> std::span<const int32_t> {
    if (changed[i]) return new_reads[i];
    return b.reads.of(i);
  });
  out.rechecked = static_cast<size_t>(std::count(recheck.begin(), recheck.end(), 1));
  out.checked = static_cast<size_t>(std::count(check_items.begin(), check_items.end(), 1));
  if (out.checked * 3 > n + 30) return give_up(fmt::format("{} of {} statements depend on the edit", out.checked, n));

  // The check: every item declared, the chosen ones processed.
  CheckOptions opts = options;
  opts.record_names = true;
  opts.parsed = nullptr;
  CheckResult r;
  r.module.time = options.time;
  r.module.frame = options.frame;
  {
    check::Context c(sources, diags, opts, r.module);
    c.name_uses = &r.name_uses;
    c.declared_names = &r.declared_names;
    c.item_marks = &r.item_marks;
    c.main_file = file;
    c.only_items = &check_items;
    std::unique_ptr<ast::Ast> base;
    check::check_parsed(c, r, std::span<ast::Ast>(&a, 1), path, base, false);
  }
  if (r.cancelled) return give_up("cancelled");
  if (!r.incremental_ok) return give_up("the new version is one that is checked in full");
  if (r.dialect != b.dialect) return give_up("the edit changed the dialect");

  // What was assumed: the changed items define what they did, or what changed is re-checked;
  // they read only checked items; every use resolved to a checked item.
  std::vector<std::vector<Decl>> now_decls;
  if (!decls_by_item(r.declared_names, spans, file, now_decls)) return give_up("a definition outside every statement");
  std::vector<int32_t> actual;
  for (int32_t k : changed_list) {
    const size_t ks = static_cast<size_t>(k);
    reads_of(b, now_text, spans[ks], k, now_decls[ks], actual);
    for (int32_t j : actual) {
      if (!check_items[static_cast<size_t>(j)]) return give_up("a changed statement reads an unchecked one");
    }
    auto names = [](const std::vector<Decl>& v) {
      std::vector<std::pair<std::string, bool>> s;
      for (const Decl& d : v) s.emplace_back(d.name, d.top_scope);
      std::sort(s.begin(), s.end());
      return s;
    };
    const auto before = names(b.decls[ks]), after = names(now_decls[ks]);
    if (before != after) {
      std::vector<std::pair<std::string, bool>> diff;
      std::set_symmetric_difference(before.begin(), before.end(), after.begin(), after.end(), std::back_inserter(diff));
      std::vector<uint8_t> m(n, 0);
      for (const auto& [name, top] : diff) mentions(now_text, spans, name, m, nested_definition);
      with_problems(m);
      for (size_t i = 0; i < n; ++i) {
        if (m[i] && !recheck[i]) return give_up("a renamed definition is mentioned by an unchecked statement");
      }
    }
  }
  for (const NameUse& u : r.name_uses) {
    if (u.use.file != file || !u.def.is_valid()) continue;
    const int32_t user = item_at(spans, u.use.begin, u.use.end);
    if (user < 0 || !recheck[static_cast<size_t>(user)]) continue;
    const SourceRange d = r.module.node(u.def).range;
    if (d.file != file) continue;
    const int32_t def = item_at(spans, d.begin, d.begin);
    if (def >= 0 && !check_items[static_cast<size_t>(def)]) return give_up("a use resolved to an unchecked statement");
  }

  // The diagnostics: the parse's and the whole-file phases' as made now, then per item the
  // new ones of re-checked items and the basis's, moved, of the others.
  std::vector<Diagnostic> made = diags.take();
  std::vector<Diagnostic> all(std::make_move_iterator(made.begin()),
                              std::make_move_iterator(made.begin() + static_cast<std::ptrdiff_t>(r.first_statement_diagnostic)));
  std::vector<std::vector<Diagnostic>> during, after;
  if (!split_by_item(std::move(made), r.first_statement_diagnostic, r.item_marks, spans, file, during, after)) {
    return give_up("a statement reported a problem outside its text");
  }
  for (size_t i = 0; i < n; ++i) {
    if (!check_items[i] && !after[i].empty()) return give_up("a problem was found in an unchecked statement");
  }
  auto moved = [&](const std::vector<Diagnostic>& kept, std::vector<Diagnostic>& into) {
    for (Diagnostic d : kept) {
      bool ok = move_range(d.range);
      for (DiagNote& note : d.notes) ok = ok && move_range(note.range);
      for (FixIt& f : d.fixits) ok = ok && move_range(f.range);
      if (!ok) return false;
      into.push_back(std::move(d));
    }
    return true;
  };
  for (auto* part : {&during, &after}) {
    const auto& kept = part == &during ? b.during : b.after;
    for (size_t i = 0; i < n; ++i) {
      if (recheck[i]) {
        std::move((*part)[i].begin(), (*part)[i].end(), std::back_inserter(all));
      } else if (!moved(kept[i], all)) {
        return give_up("a kept diagnostic points into the edit");
      }
    }
  }
  for (Diagnostic& d : all) diags.push(std::move(d));
  out.done = true;
  return out;
}

}  // namespace nomec
