// ParseCache: incremental parsing for the language server. Splits a document into chunks
// at cut points after top-level blocks, joins chunks into runs of top-level statements
// ("pieces"), parses each distinct piece text once with `parse_piece`, and assembles the
// file's AST from the pieces, shifting ids and ranges. The result is identical to
// `parse_file` on the whole text; piece.h states the conditions under which a piece parsed
// alone is provably the same as inside the file, and pieces that do not meet them are
// parsed together with the pieces after them.
//
// Each call remembers its text, chunk ends and runs. The next call compares the new text
// with it (common prefix and suffix) and keeps the chunks and runs before the edit as they
// are and those after it shifted, without scanning or hashing their text again: the cut
// scanner resumes at the last cut before the edit and stops at the first cut in the
// unchanged tail that was an old cut too, and the run building resumes after the last old
// run that ends before the edit and stops once a new run ends where an old run ended in the
// unchanged tail (see `parse` for why each is exact). The assembly still copies every
// piece's AST, as the result must view the caller's new text.
#include <algorithm>
#include <cctype>
#include <cstddef>
#include <cstring>
#include <cstdint>
#include <exception>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "base/two_threads.h"
#include "frontend/parse/parse.h"
#include "frontend/parse/piece.h"

namespace nomec {

namespace {


// Which blocks the grammar lets `parent` contain (grammar/Nome.g4); any other opening
// keyword inside it is a plain word. This only guides where pieces are cut: a wrong answer
// makes a piece fail the self-containment test and be parsed with its neighbours, never a
// wrong result.
bool may_nest(ast::BlockKind parent, ast::BlockKind child) {
  using K = ast::BlockKind;
  switch (parent) {
    case K::Face:
    case K::Consolidateface:
      return child == K::Vertex;
    case K::Mesh:
      return child == K::Point || child == K::Face || child == K::Sharp || child == K::Vertex ||
             child == K::Facet;
    case K::Group:
      return child == K::Instance;
    case K::Instance:
      return child == K::Lookat;
    case K::Sweep:
      return child == K::Crosssection || child == K::Path;
    case K::Crosssection:
      return child == K::Transform;
    case K::Delete:
    case K::Savedworkingmesh:
      return child == K::Face;
    case K::Consolidate:
      return child == K::Consolidateface;
    case K::Merge:
    case K::Subdivision:
    case K::Offset:
    case K::Handle:
    case K::Rind:
    case K::Sierpinski:
    case K::Menger:
    case K::Mirror:
      return true;
    default:
      return false;
  }
}

// The word starting at `i` (after spaces), or empty.
std::string_view word_at(std::string_view t, size_t& i) {
  while (i < t.size() && (t[i] == ' ' || t[i] == '\t' || t[i] == '\r' || t[i] == '\n')) ++i;
  const size_t b = i;
  while (i < t.size() && (std::isalnum(static_cast<unsigned char>(t[i])) || t[i] == '_' || t[i] == '.')) ++i;
  return t.substr(b, i - b);
}

// NOME2's `instance X` inside a subdivision, offset or merge names an instance and opens no
// block (the token pass retypes it the same way; piece.h): `X` and then a word that
// continues the block follow the `instance` that ends just before `i`.
bool is_block_instance_name(std::string_view t, size_t i, ast::BlockKind inside) {
  if (inside != ast::BlockKind::Subdivision && inside != ast::BlockKind::Offset && inside != ast::BlockKind::Merge) {
    return false;
  }
  if (word_at(t, i).empty()) return false;
  return continues_block_after_instance_name(word_at(t, i));
}

// Cut points: just after a newline that follows the end keyword of a top-level block, with
// only spaces and comments in between, outside any bracket, string or comment. Whether
// there is a cut at `e` depends only on the text before `e` (no token reaches across a
// newline), and at a cut the scanner's state is the initial one; so scanning may start at
// any earlier cut, and from a cut on the cuts depend only on the text after it.
//
// Scans `t` from `from` (0 or a cut), appending each cut offset to `cuts`; after each one,
// `stop(cut)` may end the scan (returns true then). Returns false at the end of the text.
template <typename Stop>
bool scan_cuts(std::string_view t, size_t from, std::vector<uint32_t>& cuts, Stop&& stop) {
  std::vector<ast::BlockKind> open;
  int comment = 0, paren = 0, brace = 0, bracket = 0;
  bool pending = false;
  size_t n = t.size();
  for (size_t i = from; i < n; ++i) {
    char c = t[i];
    char next = i + 1 < n ? t[i + 1] : '\0';
    if (comment > 0) {
      if (c == '(' && next == '*') {
        ++comment;
        ++i;
      } else if (c == '*' && next == ')') {
        --comment;
        ++i;
      }
      continue;
    }
    if (c == '(' && next == '*') {
      comment = 1;
      ++i;
      continue;
    }
    if (c == '#') {
      while (i + 1 < n && t[i + 1] != '\n') ++i;
      continue;
    }
    if (c == '\n') {
      if (pending && paren == 0 && brace == 0 && bracket == 0) {
        cuts.push_back(static_cast<uint32_t>(i + 1));
        if (stop(static_cast<uint32_t>(i + 1))) return true;
      }
      pending = false;
      continue;
    }
    if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') continue;
    pending = false;
    switch (c) {
      case '"':
        while (i + 1 < n && t[i + 1] != '"' && t[i + 1] != '\n') ++i;
        if (i + 1 < n && t[i + 1] == '"') ++i;
        continue;
      case '(': ++paren; continue;
      case ')': paren = std::max(0, paren - 1); continue;
      case '{': ++brace; continue;
      case '}': brace = std::max(0, brace - 1); continue;
      case '[': ++bracket; continue;
      case ']': bracket = std::max(0, bracket - 1); continue;
      case '$':
        while (i + 1 < n && is_name_part(t[i + 1])) ++i;
        continue;
      default:
        break;
    }
    if (!is_name_start(c)) {
      while (i + 1 < n && is_name_part(t[i + 1])) ++i;  // a number, or one other character
      continue;
    }
    size_t b = i;
    while (i + 1 < n && is_name_part(t[i + 1])) ++i;
    if (paren != 0 || brace != 0 || bracket != 0) continue;
    std::string_view word = t.substr(b, i + 1 - b);
    if (word == "instance" && !open.empty() && is_block_instance_name(t, i + 1, open.back())) continue;
    if (auto kind = ast::block_of_keyword(word)) {
      if (open.empty() || may_nest(open.back(), *kind)) open.push_back(*kind);
    } else if (!open.empty() && ast::block_of_end_keyword(word)) {
      open.pop_back();
      pending = open.empty();
    }
  }
  return false;
}

// Length of the common prefix of `a` and `b`, comparing in blocks.
size_t common_prefix(std::string_view a, std::string_view b) {
  size_t n = std::min(a.size(), b.size()), i = 0;
  constexpr size_t kBlock = 256;
  while (i + kBlock <= n && std::memcmp(a.data() + i, b.data() + i, kBlock) == 0) i += kBlock;
  while (i < n && a[i] == b[i]) ++i;
  return i;
}

// Length of the common suffix of `a` and `b`, at most `limit`.
size_t common_suffix(std::string_view a, std::string_view b, size_t limit) {
  size_t i = 0;
  constexpr size_t kBlock = 256;
  const char* ea = a.data() + a.size();
  const char* eb = b.data() + b.size();
  while (i + kBlock <= limit && std::memcmp(ea - i - kBlock, eb - i - kBlock, kBlock) == 0) {
    i += kBlock;
  }
  while (i < limit && ea[-1 - static_cast<ptrdiff_t>(i)] == eb[-1 - static_cast<ptrdiff_t>(i)]) ++i;
  return i;
}

struct TextHash {
  using is_transparent = void;
  size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
};

}  // namespace

struct ParseCache::Impl {
  // One parsed piece; its AST's views point into the map key that owns its text.
  struct Piece {
    ast::Ast ast;
    DiagnosticEngine comments, tokens, syntax;
    PieceInfo info;
    uint64_t used = 0;
  };
  // One run of chunks in a version of the document and the cached piece of its text.
  struct Use {
    std::string_view key;
    Piece* piece;
    uint32_t at;           // byte offset of the run in that version's text
    uint32_t first, last;  // the chunks it covers
    bool has_diags;        // the piece reported something (most do not)
  };
  std::unordered_map<std::string, Piece, TextHash, std::equal_to<>> pieces;
  ParseThreads threads = ParseThreads::Automatic;
  uint64_t generation = 0;
  size_t cached_bytes = 0;  // the text of every cached piece
  Stats stats;

  // The previous version: its text, chunk ends (the last is the text size, whether or not
  // it is a cut) and runs. The next call keeps what lies before and after its edit.
  bool have_prev = false;
  std::string prev_text;
  std::vector<uint32_t> prev_ends;
  bool prev_last_is_cut = false;
  std::vector<Use> prev_uses;

  // The cached piece for `text`, parsing it if it is new. Returns the key and the piece.
  std::pair<std::string_view, Piece*> get(std::string_view text) {
    stats.looked_up_bytes += text.size();
    auto it = pieces.find(text);
    if (it == pieces.end()) {
      it = pieces.emplace(std::string(text), Piece{}).first;
      cached_bytes += text.size();
      Piece& p = it->second;
      p.ast = parse_piece(it->first, FileId{0}, PieceSinks{p.comments, p.tokens, p.syntax},
                          &p.info);
      ++stats.parsed;
      stats.parsed_bytes += text.size();
    }
    it->second.used = generation;
    return {it->first, &it->second};
  }
};

ParseCache::ParseCache(ParseThreads threads) : impl_(std::make_unique<Impl>()) { impl_->threads = threads; }
ParseCache::~ParseCache() = default;
ParseCache::ParseCache(ParseCache&&) noexcept = default;
ParseCache& ParseCache::operator=(ParseCache&&) noexcept = default;

const ParseCache::Stats& ParseCache::last_stats() const { return impl_->stats; }

namespace {

// Copies `piece` (parsed alone, offsets relative to its own text `key`) into `out` as the
// part of `full` that starts at byte `at`.
class Assembler {
 public:
  Assembler(ast::Ast& out, std::string_view full, FileId file)
      : out_(out), full_(full), file_(file) {}

  void append(const ast::Ast& piece, const PieceInfo& info, std::string_view key,
              uint32_t at) {
    key_ = key;
    at_ = at;
    e0_ = static_cast<int32_t>(out_.exprs.size());
    l0_ = static_cast<int32_t>(out_.lists.size());
    s0_ = static_cast<int32_t>(out_.stmts.size());
    for (const ast::Expr& e : piece.exprs) {
      ast::Expr& c = out_.exprs.emplace_back(e);
      c.range = range(e.range);
      c.text = view(e.text);
      if (e.kind == ast::ExprKind::Call) {
        c.set_args(static_cast<uint32_t>(out_.args.size()), e.args_count());
        for (ast::ExprId a : piece.args_of(e)) out_.args.push_back(expr(a));
      } else if (e.kind == ast::ExprKind::Unary || e.kind == ast::ExprKind::Binary) {
        c.set_operands(expr(e.lhs()), expr(e.rhs()));
      }
    }
    for (int32_t k : info.unanchored_exprs) out_.exprs[e0_ + k].range = SourceRange{file_, 0, 0};
    for (const ast::ParenList& l : piece.lists) {
      ast::ParenList& c = out_.lists.emplace_back(l);
      c.range = range(l.range);
      for (ast::ExprId& e : c.elems) e = expr(e);
    }
    for (const ast::ListComma& k : piece.commas) out_.commas.push_back({ast::ListId{k.list.index + l0_}, range(k.range)});
    for (const ast::Stmt& s : piece.stmts) {
      ast::Stmt& c = out_.stmts.emplace_back(s);
      c.range = range(s.range);
      c.open_kw = range(s.open_kw);
      c.close_kw = range(s.close_kw);
      c.close_text = view(s.close_text);
      c.keyword = view(s.keyword);
      for (ast::Item& i : c.items) item(i);
    }
    for (const ast::Item& i : piece.top) item(out_.top.emplace_back(i));
  }

  void append_diags(const DiagnosticEngine& from, std::string_view key, uint32_t at,
                    DiagnosticEngine& to) {
    key_ = key;
    at_ = at;
    for (const Diagnostic& d : from.diagnostics()) {
      auto b = to.emit(d.kind, range(d.range), d.message);
      for (const DiagNote& n : d.notes) b.note(range(n.range), n.message);
      for (const FixIt& f : d.fixits) b.fixit(range(f.range), f.replacement, f.description);
    }
  }

 private:
  SourceRange range(SourceRange r) const {
    if (!r.is_valid()) return r;
    return SourceRange{file_, r.begin + at_, r.end + at_};
  }
  std::string_view view(std::string_view v) const {
    // Every text of every piece passes here: compared as addresses against the key's bounds
    // (a null or static text lies outside them), and moved by the key's offset in `full_`
    // without substr's bounds check (a view inside the key fits in `full_` at `at_`).
    const auto p = reinterpret_cast<uintptr_t>(v.data());
    const auto k = reinterpret_cast<uintptr_t>(key_.data());
    if (p < k || p > k + key_.size()) return v;
    return std::string_view(full_.data() + at_ + (p - k), v.size());
  }
  ast::ExprId expr(ast::ExprId id) const {
    return id.is_valid() ? ast::ExprId{id.index + e0_} : id;
  }
  void item(ast::Item& i) const {
    i.range = range(i.range);
    i.text = view(i.text);
    i.expr = expr(i.expr);
    if (i.list.is_valid()) i.list.index += l0_;
    if (i.block.is_valid()) i.block.index += s0_;
  }

  ast::Ast& out_;
  std::string_view full_;
  FileId file_;
  std::string_view key_;
  uint32_t at_ = 0;
  int32_t e0_ = 0, l0_ = 0, s0_ = 0;
};

}  // namespace

namespace {

// Runs `part(0)` here and `part(1)` on a second thread that parses with this thread's test
// switches (piece.h).
template <typename Part>
void run_parse_parts(Part&& part) {
  const parse_detail::ParseSwitches switches = parse_detail::ParseSwitches::current();
  run_two_parts([&](int k) {
    if (k == 1) switches.apply();
    part(k);
  });
}

// One piece of a text to assemble: what parsing `key` alone gave, placed at byte `at`.
struct PieceRef {
  const ast::Ast* ast;
  const PieceInfo* info;
  const DiagnosticEngine* comments;
  const DiagnosticEngine* tokens;
  const DiagnosticEngine* syntax;
  std::string_view key;
  uint32_t at;
  bool has_diags;  // the piece reported something (most do not)
};

// The pieces' diagnostics, as one parse of the whole text orders them: every piece's
// comment problems, then every piece's token problems, then every piece's syntax errors.
void append_piece_diags(std::span<const PieceRef> pieces, Assembler& assembler, DiagnosticEngine& diags) {
  std::vector<const PieceRef*> reporting;
  for (const PieceRef& p : pieces) {
    if (p.has_diags) reporting.push_back(&p);
  }
  for (const PieceRef* p : reporting) assembler.append_diags(*p->comments, p->key, p->at, diags);
  for (const PieceRef* p : reporting) assembler.append_diags(*p->tokens, p->key, p->at, diags);
  for (const PieceRef* p : reporting) assembler.append_diags(*p->syntax, p->key, p->at, diags);
}

bool reports_something(const DiagnosticEngine& comments, const DiagnosticEngine& tokens, const DiagnosticEngine& syntax) {
  return !comments.diagnostics().empty() || !tokens.diagnostics().empty() || !syntax.diagnostics().empty();
}

// Where a version differs from the previous one: text[0, prefix) is unchanged, and so is
// text[tail, size) (it was old[tail - delta, old size)). Without a previous version nothing
// is kept and every step below is the full computation.
struct Edit {
  std::string_view text, old;
  size_t prefix = 0;
  size_t tail = 0;
  int64_t delta = 0;
};

// The chunk ends of a version (the last is the text size, cut or not) and how many of the
// old ones it kept before the edit.
struct Chunks {
  std::vector<uint32_t> ends;
  bool last_is_cut = false;
  size_t kept_cuts = 0;
};

}  // namespace

// The cached steps of `ParseCache::parse`.
struct ParseCache::Steps {
  using Use = Impl::Use;
  using Piece = Impl::Piece;
  Impl& m;

  Edit edit_since_previous(std::string_view text) const {
    Edit e;
    e.text = text;
    e.old = m.have_prev ? std::string_view(m.prev_text) : std::string_view();
    size_t suffix = 0;
    if (m.have_prev) {
      e.prefix = common_prefix(e.old, text);
      suffix = common_suffix(e.old, text, std::min(e.old.size(), text.size()) - e.prefix);
    }
    e.tail = text.size() - suffix;
    e.delta = static_cast<int64_t>(text.size()) - static_cast<int64_t>(e.old.size());
    return e;
  }

  // 1. Chunk ends. The cuts up to `prefix` are the old ones; scanning resumes at the last of
  // them and stops at the first cut in the unchanged tail that was also an old cut: from
  // there on the old cuts, shifted, are the new ones.
  Chunks chunk_ends(const Edit& edit) const {
    const std::vector<uint32_t>& old_ends = m.prev_ends;
    const std::string_view text = edit.text;
    const size_t old_cuts = m.have_prev ? old_ends.size() - (m.prev_last_is_cut ? 0 : 1) : 0;
    Chunks c;
    c.kept_cuts = static_cast<size_t>(
        std::upper_bound(old_ends.begin(), old_ends.begin() + static_cast<ptrdiff_t>(old_cuts), edit.prefix) -
        old_ends.begin());
    c.ends.reserve(old_ends.size() + 16);
    c.ends.assign(old_ends.begin(), old_ends.begin() + static_cast<ptrdiff_t>(c.kept_cuts));
    const size_t scan_from = c.ends.empty() ? 0 : c.ends.back();
    size_t scan_to = text.size();
    const bool joined = scan_cuts(text, scan_from, c.ends, [&](uint32_t e) {
      if (e < edit.tail || e >= text.size()) return false;
      const auto old_e = static_cast<uint32_t>(static_cast<int64_t>(e) - edit.delta);
      auto it = std::lower_bound(old_ends.begin() + static_cast<ptrdiff_t>(c.kept_cuts),
                                 old_ends.begin() + static_cast<ptrdiff_t>(old_cuts), old_e);
      if (it == old_ends.begin() + static_cast<ptrdiff_t>(old_cuts) || *it != old_e) return false;
      for (++it; it != old_ends.end(); ++it) c.ends.push_back(static_cast<uint32_t>(static_cast<int64_t>(*it) + edit.delta));
      scan_to = e;
      return true;
    });
    if (joined) {
      c.last_is_cut = m.prev_last_is_cut;
    } else {
      c.last_is_cut = !c.ends.empty() && c.ends.back() == text.size();
      if (!c.last_is_cut) c.ends.push_back(static_cast<uint32_t>(text.size()));
    }
    m.stats.scanned_bytes = scan_to - scan_from;
    m.stats.chunks = c.ends.size();
    return c;
  }

  // 2. Runs. Building them is a left-to-right process over the chunk texts (a run may be
  // extended backwards over the one before it, and the chunks a step looks at never go
  // back). Right after an old run was pushed, the old process had looked only at chunks up
  // to that run's last one; if those are unchanged, the new process passes the same state,
  // so it resumes after the last old run that ends before the first changed chunk (and
  // before the last chunk, which is treated differently). An old run that survived to the
  // end was never undone by the runs after it, which therefore depend only on the chunks
  // after it; so once the new process has pushed a run that ends where an old run ended,
  // at a cut in the unchanged tail, the rest are the old runs, shifted.
  std::vector<Use> runs(const Edit& edit, const Chunks& chunks) const {
    const std::vector<uint32_t>& ends = chunks.ends;
    const size_t n = ends.size();
    const size_t old_n = m.have_prev ? m.prev_ends.size() : 0;
    const size_t same_chunks = std::min({chunks.kept_cuts, old_n == 0 ? 0 : old_n - 1, n - 1});
    std::vector<Use> uses;
    uses.reserve(m.prev_uses.size() + 16);
    auto keep = std::partition_point(m.prev_uses.begin(), m.prev_uses.end(),
                                     [&](const Use& u) { return u.last < same_chunks; });
    uses.assign(m.prev_uses.begin(), keep);
    size_t min_last = 0;  // a run starting at `i` must reach at least this chunk
    for (size_t i = uses.empty() ? 0 : uses.back().last + 1; i < n;) {
      const uint32_t begin = i == 0 ? 0 : ends[i - 1];
      bool joined_old = false;
      for (size_t span = std::max<size_t>(1, min_last + 1 - std::min(min_last + 1, i));; span *= 2) {
        const size_t j = std::min(n - 1, i + span - 1);
        auto [key, piece] = m.get(edit.text.substr(begin, ends[j] - begin));
        if (i > 0 && !piece->info.starts_cleanly) {
          // This run cannot start here: extend the previous run over it instead.
          const Use prev = uses.back();
          uses.pop_back();
          min_last = j;
          i = prev.first;
          break;
        }
        if (piece->info.self_contained || j == n - 1) {
          const bool has_diags = reports_something(piece->comments, piece->tokens, piece->syntax);
          uses.push_back({key, piece, begin, static_cast<uint32_t>(i), static_cast<uint32_t>(j), has_diags});
          min_last = 0;
          i = j + 1;
          joined_old = join_old(edit, ends, i, uses);
          break;
        }
      }
      if (joined_old) break;
    }
    for (const Use& u : uses) u.piece->used = m.generation;
    return uses;
  }

  // After a run was pushed and the next starts at `i`: appends the old runs from there on
  // if the new process is now where the old one was. Returns whether it did.
  bool join_old(const Edit& edit, const std::vector<uint32_t>& ends, size_t i, std::vector<Use>& uses) const {
    const size_t n = ends.size();
    const size_t old_n = m.have_prev ? m.prev_ends.size() : 0;
    const int64_t chunk_delta = static_cast<int64_t>(n) - static_cast<int64_t>(old_n);
    if (i >= n || ends[i - 1] < edit.tail) return false;
    const int64_t old_i = static_cast<int64_t>(i) - chunk_delta;
    if (old_i < 1 || old_i >= static_cast<int64_t>(old_n)) return false;
    if (static_cast<int64_t>(m.prev_ends[static_cast<size_t>(old_i) - 1]) != static_cast<int64_t>(ends[i - 1]) - edit.delta) {
      return false;
    }
    auto it = std::partition_point(m.prev_uses.begin(), m.prev_uses.end(),
                                   [&](const Use& u) { return static_cast<int64_t>(u.first) < old_i; });
    if (it == m.prev_uses.end() || static_cast<int64_t>(it->first) != old_i) return false;
    for (; it != m.prev_uses.end(); ++it) {
      Use u = *it;
      u.at = static_cast<uint32_t>(static_cast<int64_t>(u.at) + edit.delta);
      u.first = static_cast<uint32_t>(static_cast<int64_t>(u.first) + chunk_delta);
      u.last = static_cast<uint32_t>(static_cast<int64_t>(u.last) + chunk_delta);
      uses.push_back(u);
    }
    return true;
  }

  // 3. The file's AST and diagnostics from the runs' pieces, in order.
  static ast::Ast assemble(const std::vector<Use>& uses, std::string_view text, FileId file, DiagnosticEngine& diags) {
    if (uses.size() > 1 && uses.back().piece->info.stopped) {  // see PieceInfo::stopped
      return parse_piece(text, file, PieceSinks{diags, diags, diags}, nullptr);
    }
    ast::Ast out;
    out.file = file;
    size_t exprs = 0, args = 0, lists = 0, stmts = 0, top = 0;
    for (const Use& u : uses) {
      exprs += u.piece->ast.exprs.size();
      args += u.piece->ast.args.size();
      lists += u.piece->ast.lists.size();
      stmts += u.piece->ast.stmts.size();
      top += u.piece->ast.top.size();
    }
    out.exprs.reserve(exprs);
    out.args.reserve(args);
    out.lists.reserve(lists);
    out.stmts.reserve(stmts);
    out.top.reserve(top);
    Assembler assembler(out, text, file);
    std::vector<PieceRef> refs;
    refs.reserve(uses.size());
    const bool gave_up = !uses.empty() && uses.back().piece->info.gave_up;  // see PieceInfo::gave_up
    for (const Use& u : uses) {
      if (!gave_up) assembler.append(u.piece->ast, u.piece->info, u.key, u.at);
      const Piece& p = *u.piece;
      refs.push_back({&p.ast, &p.info, &p.comments, &p.tokens, &p.syntax, u.key, u.at, u.has_diags});
    }
    append_piece_diags(refs, assembler, diags);
    return out;
  }

  // 0. A new document (nothing to reuse) of some size: its chunks, which the runs ask for
  // first, are parsed now on two threads, half of the bytes each, and cached; the runs then
  // find them (and parse on this thread only runs of several chunks, rare).
  void parse_chunks_on_two_threads(std::string_view text, const Chunks& chunks) const {
    struct Todo {
      std::string_view key;
      Piece* piece;
    };
    std::vector<Todo> todo;
    todo.reserve(chunks.ends.size());
    m.pieces.reserve(m.pieces.size() + chunks.ends.size());
    size_t bytes = 0;
    uint32_t begin = 0;
    for (const uint32_t end : chunks.ends) {
      // Map nodes do not move: the key's text and the piece stay where they are while the
      // map grows and while the threads write the pieces (the map itself is left alone).
      auto [it, inserted] = m.pieces.try_emplace(std::string(text.substr(begin, end - begin)));
      if (inserted) {
        todo.push_back({it->first, &it->second});
        bytes += end - begin;
      }
      begin = end;
    }
    size_t half = 0;
    for (size_t acc = 0; half < todo.size() && 2 * acc < bytes; ++half) acc += todo[half].key.size();
    try {
      run_parse_parts([&](int k) {
        const size_t from = k == 0 ? 0 : half, to = k == 0 ? half : todo.size();
        for (size_t i = from; i < to; ++i) {
          Piece& p = *todo[i].piece;
          p.ast = parse_piece(todo[i].key, FileId{0}, PieceSinks{p.comments, p.tokens, p.syntax}, &p.info);
        }
      });
    } catch (...) {
      for (const Todo& t : todo) m.pieces.erase(m.pieces.find(t.key));  // none is half-made in the cache
      throw;
    }
    m.cached_bytes += bytes;
    m.stats.parsed += todo.size();
    m.stats.parsed_bytes += bytes;
    m.stats.threads = 2;
  }

  // 4. Keep what this version and the one before used (an undo finds its pieces again);
  // the sweep visits every cached piece, so it runs only once the cache holds twice as many
  // pieces as this version uses or three times the text's bytes (plus some slack), keeping
  // memory proportional to the document without a full pass per keystroke.
  void sweep(size_t text_size) const {
    if (m.pieces.size() > 2 * m.prev_uses.size() + 64 || m.cached_bytes > 3 * text_size + (64u << 10)) {
      std::erase_if(m.pieces, [&](const auto& kv) {
        if (kv.second.used + 1 >= m.generation) return false;
        m.cached_bytes -= kv.first.size();
        return true;
      });
    }
    m.stats.cached_pieces = m.pieces.size();
    m.stats.cached_bytes = m.cached_bytes;
  }
};

ast::Ast ParseCache::parse(const SourceManager& sources, FileId file, DiagnosticEngine& diags) {
  Impl& m = *impl_;
  ++m.generation;
  m.stats = Stats{};
  const std::string_view text = sources.text(file);
  Steps steps{m};
  const Edit edit = steps.edit_since_previous(text);
  Chunks chunks = steps.chunk_ends(edit);
  if (!m.have_prev && parse_detail::uses_two_threads(m.threads, text.size())) steps.parse_chunks_on_two_threads(text, chunks);
  std::vector<Impl::Use> uses = steps.runs(edit, chunks);
  ast::Ast out = Steps::assemble(uses, text, file, diags);
  m.stats.pieces = uses.size();
  m.have_prev = true;
  m.prev_text.assign(text);
  m.prev_ends = std::move(chunks.ends);
  m.prev_last_is_cut = chunks.last_is_cut;
  m.prev_uses = std::move(uses);
  steps.sweep(text.size());
  return out;
}

namespace parse_detail {

bool uses_two_threads(ParseThreads threads, size_t bytes) {
  switch (threads) {
    case ParseThreads::One: return false;
    case ParseThreads::Two: return true;
    case ParseThreads::Automatic: return bytes >= kTwoThreadParseBytes && has_two_hardware_threads();
  }
  return false;
}

std::optional<ast::Ast> parse_in_two_pieces(std::string_view text, FileId file, DiagnosticEngine& diags) {
  std::vector<uint32_t> cuts;
  const size_t middle = text.size() / 2;
  scan_cuts(text, 0, cuts, [&](uint32_t cut) { return cut >= middle; });
  if (cuts.empty() || cuts.back() >= text.size()) return std::nullopt;
  const uint32_t cut = cuts.back();
  struct Half {
    ast::Ast ast;
    DiagnosticEngine comments, tokens, syntax;
    PieceInfo info;
  };
  Half halves[2];
  const std::string_view texts[2] = {text.substr(0, cut), text.substr(cut)};
  // The first half is parsed as the file itself: its ranges, views and ids are then those of
  // the assembled AST already, and only the second half is copied after it, into arrays
  // the first half reserved for the whole text (estimated from its share of the bytes, with
  // a little to spare), so that they are not copied as they grow.
  const double whole_over_first = 1.05 * double(text.size()) / double(cut);
  run_parse_parts([&](int k) {
    Half& h = halves[k];
    h.ast = parse_piece(texts[k], k == 0 ? file : FileId{0}, PieceSinks{h.comments, h.tokens, h.syntax}, &h.info,
                        k == 0 ? whole_over_first : 1.0);
  });
  if (!halves[0].info.self_contained || !halves[1].info.starts_cleanly || halves[1].info.stopped) {
    return std::nullopt;  // see PieceInfo::stopped
  }
  ast::Ast out;
  out.file = file;
  if (!halves[1].info.gave_up) out = std::move(halves[0].ast);  // see PieceInfo::gave_up
  const ast::Ast& second = halves[1].ast;
  out.exprs.reserve(out.exprs.size() + second.exprs.size());
  out.args.reserve(out.args.size() + second.args.size());
  out.lists.reserve(out.lists.size() + second.lists.size());
  out.stmts.reserve(out.stmts.size() + second.stmts.size());
  out.top.reserve(out.top.size() + second.top.size());
  Assembler assembler(out, text, file);
  if (!halves[1].info.gave_up) assembler.append(second, halves[1].info, texts[1], cut);
  PieceRef refs[2];
  for (int k = 0; k < 2; ++k) {
    const Half& h = halves[k];
    refs[k] = {&h.ast, &h.info, &h.comments, &h.tokens, &h.syntax, texts[k], k == 0 ? 0 : cut,
               reports_something(h.comments, h.tokens, h.syntax)};
  }
  append_piece_diags(refs, assembler, diags);
  return out;
}

}  // namespace parse_detail

}  // namespace nomec

namespace nomec {

namespace {

// Moves the ranges of `piece` (parsed alone as `file`, offsets relative to its own text)
// by `at`, to where the piece starts in the file. Its texts already view the file's text,
// and its ids stay its own.
void place_piece(ast::Ast& piece, const PieceInfo& info, uint32_t at) {
  auto move = [at](SourceRange& r) {
    if (r.is_valid()) {
      r.begin += at;
      r.end += at;
    }
  };
  for (ast::Expr& e : piece.exprs) move(e.range);
  for (int32_t k : info.unanchored_exprs) {  // these stay at offset 0 (PieceInfo)
    SourceRange& r = piece.exprs[static_cast<size_t>(k)].range;
    r.begin = 0;
    r.end = 0;
  }
  for (ast::ParenList& l : piece.lists) move(l.range);
  for (ast::ListComma& k : piece.commas) move(k.range);
  for (ast::Stmt& s : piece.stmts) {
    move(s.range);
    move(s.open_kw);
    move(s.close_kw);
    for (ast::Item& i : s.items) move(i.range);
  }
  for (ast::Item& i : piece.top) move(i.range);
}

}  // namespace

std::vector<ast::Ast> parse_file_in_pieces(const SourceManager& sources, FileId file, DiagnosticEngine& diags,
                                           size_t piece_bytes, ParseThreads threads) {
  const std::string_view text = sources.text(file);
  std::vector<ast::Ast> out;
  auto whole = [&] {
    out.clear();
    out.push_back(parse_file(sources, file, diags, threads));
    return std::move(out);
  };
  if (piece_bytes == 0 || text.size() < 2 * piece_bytes || text.size() > UINT32_MAX) return whole();
  // Each piece ends at the first cut at least `piece_bytes` after its start.
  std::vector<uint32_t> starts{0}, cuts;
  for (;;) {
    const size_t from = starts.back();
    cuts.clear();
    if (!scan_cuts(text, from, cuts, [&](uint32_t cut) { return cut >= from + piece_bytes; })) break;
    if (cuts.back() >= text.size()) break;
    starts.push_back(cuts.back());
  }
  const size_t n = starts.size();
  if (n < 2) return whole();
  struct Piece {
    DiagnosticEngine comments, tokens, syntax;
    PieceInfo info;
  };
  std::vector<Piece> pieces(n);
  out.resize(n);
  auto piece_text = [&](size_t k) {
    return k + 1 < n ? text.substr(starts[k], starts[k + 1] - starts[k]) : text.substr(starts[k]);
  };
  auto parse_one = [&](size_t k) {
    Piece& p = pieces[k];
    out[k] = parse_piece(piece_text(k), file, PieceSinks{p.comments, p.tokens, p.syntax}, &p.info);
  };
  // On two threads, each parses every other piece: the pieces are about the same size, so
  // neither waits long for the other, and only two pieces' parser memory is live at once.
  if (parse_detail::uses_two_threads(threads, text.size())) {
    run_parse_parts([&](int t) {
      for (size_t k = static_cast<size_t>(t); k < n; k += 2) parse_one(k);
    });
  } else {
    for (size_t k = 0; k < n; ++k) parse_one(k);
  }
  // Each piece must parse as it does inside the whole text (piece.h): every piece but the
  // last self-contained, every piece but the first starting cleanly, and none stopped or
  // given up. Otherwise the text is parsed whole (rare: syntax errors across a cut).
  for (size_t k = 0; k < n; ++k) {
    const PieceInfo& info = pieces[k].info;
    if ((k + 1 < n && !info.self_contained) || (k > 0 && !info.starts_cleanly) || info.stopped || info.gave_up) {
      return whole();
    }
  }
  std::vector<PieceRef> refs(n);
  for (size_t k = 0; k < n; ++k) {
    place_piece(out[k], pieces[k].info, starts[k]);
    const Piece& p = pieces[k];
    refs[k] = {&out[k], &p.info, &p.comments, &p.tokens, &p.syntax, piece_text(k), starts[k],
               reports_something(p.comments, p.tokens, p.syntax)};
  }
  ast::Ast unused;
  Assembler assembler(unused, text, file);
  append_piece_diags(refs, assembler, diags);
  return out;
}

}  // namespace nomec
