// ParseCache: incremental parsing for the language server. Splits a document into runs of
// top-level statements ("pieces"), parses each distinct piece text once with `parse_piece`,
// and assembles the file's AST from the pieces, shifting ids and ranges. The result is
// identical to `parse_file` on the whole text; piece.h states the conditions under which a
// piece parsed alone is provably the same as inside the file, and pieces that do not meet
// them are parsed together with the pieces after them.
#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "frontend/parse/parse.h"
#include "frontend/parse/piece.h"

namespace nomec {

namespace {

bool is_id_start(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == '.';
}
bool is_id_part(char c) { return is_id_start(c) || (c >= '0' && c <= '9'); }

struct KeywordIndex {
  std::unordered_map<std::string_view, ast::BlockKind> open;
  std::unordered_map<std::string_view, ast::BlockKind> close;
};

const KeywordIndex& keywords() {
  static const KeywordIndex index = [] {
    KeywordIndex k;
    for (int i = 0; i < ast::kBlockKindCount; ++i) {
      auto kind = static_cast<ast::BlockKind>(i);
      k.open.emplace(ast::open_keyword(kind), kind);
      k.close.emplace(ast::close_keyword(kind), kind);
    }
    return k;
  }();
  return index;
}

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

// Cut points: just after a newline that follows the end keyword of a top-level block, with
// only spaces and comments in between, outside any bracket, string or comment. Returns the
// end offset of every piece; the last one is the text size.
std::vector<uint32_t> piece_ends(std::string_view t) {
  std::vector<uint32_t> ends;
  std::vector<ast::BlockKind> open;
  int comment = 0, paren = 0, brace = 0, bracket = 0;
  bool pending = false;
  const KeywordIndex& kw = keywords();
  size_t n = t.size();
  for (size_t i = 0; i < n; ++i) {
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
        ends.push_back(static_cast<uint32_t>(i + 1));
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
        while (i + 1 < n && is_id_part(t[i + 1])) ++i;
        continue;
      default:
        break;
    }
    if (!is_id_start(c)) {
      while (i + 1 < n && is_id_part(t[i + 1])) ++i;  // a number, or one other character
      continue;
    }
    size_t b = i;
    while (i + 1 < n && is_id_part(t[i + 1])) ++i;
    if (paren != 0 || brace != 0 || bracket != 0) continue;
    std::string_view word = t.substr(b, i + 1 - b);
    if (auto it = kw.open.find(word); it != kw.open.end()) {
      if (open.empty() || may_nest(open.back(), it->second)) open.push_back(it->second);
    } else if (kw.close.contains(word) && !open.empty()) {
      open.pop_back();
      pending = open.empty();
    }
  }
  if (ends.empty() || ends.back() != n) ends.push_back(static_cast<uint32_t>(n));
  return ends;
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
  std::unordered_map<std::string, Piece, TextHash, std::equal_to<>> pieces;
  uint64_t generation = 0;
  Stats stats;

  // The cached piece for `text`, parsing it if it is new. Returns the key and the piece.
  std::pair<std::string_view, Piece*> get(std::string_view text) {
    auto it = pieces.find(text);
    if (it == pieces.end()) {
      it = pieces.emplace(std::string(text), Piece{}).first;
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

ParseCache::ParseCache() : impl_(std::make_unique<Impl>()) {}
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
      c.lhs = expr(e.lhs);
      c.rhs = expr(e.rhs);
      for (ast::ExprId& a : c.args) a = expr(a);
    }
    for (int32_t k : info.unanchored_exprs) out_.exprs[e0_ + k].range = SourceRange{file_, 0, 0};
    for (const ast::ParenList& l : piece.lists) {
      ast::ParenList& c = out_.lists.emplace_back(l);
      c.range = range(l.range);
      for (ast::ExprId& e : c.elems) e = expr(e);
      for (SourceRange& r : c.commas) r = range(r);
    }
    for (const ast::Stmt& s : piece.stmts) {
      ast::Stmt& c = out_.stmts.emplace_back(s);
      c.range = range(s.range);
      c.open_kw = range(s.open_kw);
      c.close_kw = range(s.close_kw);
      c.close_text = view(s.close_text);
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
    if (v.data() == nullptr || v.data() < key_.data() || v.data() > key_.data() + key_.size()) {
      return v;
    }
    return full_.substr(at_ + static_cast<size_t>(v.data() - key_.data()), v.size());
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

ast::Ast ParseCache::parse(const SourceManager& sources, FileId file, DiagnosticEngine& diags) {
  Impl& m = *impl_;
  ++m.generation;
  m.stats = Stats{};
  std::string_view text = sources.text(file);
  std::vector<uint32_t> ends = piece_ends(text);

  struct Use {
    std::string_view key;
    Impl::Piece* piece;
    uint32_t at;
    size_t first, last;  // the chunks it covers
  };
  std::vector<Use> uses;
  size_t n = ends.size();
  size_t min_last = 0;  // a run starting at `i` must reach at least this chunk
  for (size_t i = 0; i < n;) {
    uint32_t begin = i == 0 ? 0 : ends[i - 1];
    for (size_t span = std::max<size_t>(1, min_last + 1 - std::min(min_last + 1, i));;
         span *= 2) {
      size_t j = std::min(n - 1, i + span - 1);
      auto [key, piece] = m.get(text.substr(begin, ends[j] - begin));
      if (i > 0 && !piece->info.starts_cleanly) {
        // This run cannot start here: extend the previous run over it instead.
        Use prev = uses.back();
        uses.pop_back();
        min_last = j;
        i = prev.first;
        break;
      }
      if (piece->info.self_contained || j == n - 1) {
        uses.push_back({key, piece, begin, i, j});
        min_last = 0;
        i = j + 1;
        break;
      }
    }
  }

  ast::Ast out;
  out.file = file;
  size_t exprs = 0, lists = 0, stmts = 0, top = 0;
  for (const Use& u : uses) {
    exprs += u.piece->ast.exprs.size();
    lists += u.piece->ast.lists.size();
    stmts += u.piece->ast.stmts.size();
    top += u.piece->ast.top.size();
  }
  out.exprs.reserve(exprs);
  out.lists.reserve(lists);
  out.stmts.reserve(stmts);
  out.top.reserve(top);
  Assembler assembler(out, text, file);
  for (const Use& u : uses) assembler.append(u.piece->ast, u.piece->info, u.key, u.at);
  for (const Use& u : uses) assembler.append_diags(u.piece->comments, u.key, u.at, diags);
  for (const Use& u : uses) assembler.append_diags(u.piece->tokens, u.key, u.at, diags);
  for (const Use& u : uses) assembler.append_diags(u.piece->syntax, u.key, u.at, diags);
  m.stats.pieces = uses.size();

  // Keep what this version and the one before used (an undo finds its pieces again).
  std::erase_if(m.pieces, [&](const auto& kv) { return kv.second.used + 1 < m.generation; });
  return out;
}

}  // namespace nomec
