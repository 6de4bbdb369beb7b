// The structure pass (recovery.h): one typo, one error.
#include "frontend/parse/recovery.h"

#include <algorithm>
#include <array>
#include <fmt/format.h>
#include <functional>
#include <mutex>
#include <set>
#include <string>
#include <unordered_map>

#include "frontend/parse/generated.h"
#include "ir/generator_catalogue.h"

namespace nomec::parse_detail {

using L = nomec_antlr::NomeParser;

bool block_holds(size_t parent, size_t child) {
  if (child == L::TCLINIT) return parent == 0;
  switch (parent) {
    case 0:
    case L::K_MERGE: case L::K_SUBDIVISION: case L::K_OFFSET: case L::K_HANDLE: case L::K_RIND:
    case L::K_SIERPINSKI: case L::K_MENGER: case L::K_MIRROR:
      return is_open_type(child);
    case L::K_FACE: case L::K_CONSOLIDATEFACE: return child == L::K_VERTEX;
    case L::K_MESH:
      return child == L::K_POINT || child == L::K_FACE || child == L::K_SHARP || child == L::K_VERTEX ||
             child == L::K_FACET;
    case L::K_GROUP: return child == L::K_INSTANCE;
    case L::K_INSTANCE: return child == L::K_LOOKAT;
    case L::K_SWEEP: return child == L::K_CROSSSECTION || child == L::K_PATH;
    case L::K_SWEEPMORPH: return child == L::K_PATH;
    case L::K_CROSSSECTION: return child == L::K_TRANSFORM;
    case L::K_DELETE: case L::K_SAVEDWORKINGMESH: return child == L::K_FACE;
    case L::K_CONSOLIDATE: return child == L::K_CONSOLIDATEFACE;
    default: return false;
  }
}

namespace {

// A keyword meant, kept for the program's life (the AST views it).
std::string_view interned(std::string_view s) {
  static std::mutex mutex;
  static std::set<std::string, std::less<>> words;
  std::lock_guard<std::mutex> lock(mutex);
  auto it = words.find(s);
  if (it == words.end()) it = words.emplace(s).first;
  return *it;
}

// The opening keyword type whose end keyword is `end_type` (K_GEN for E_GEN), or 0.
size_t open_type_of_end(size_t end_type) {
  static const std::vector<uint16_t> table = [] {
    std::vector<uint16_t> t;
    for (size_t type = 1; type < 1024; ++type) {
      const size_t e = end_type_of(type);
      if (e == 0) continue;
      if (t.size() <= e) t.resize(e + 1);
      t[e] = static_cast<uint16_t>(type);
    }
    return t;
  }();
  return end_type < table.size() ? table[end_type] : 0;
}

constexpr uint32_t kNone = UINT32_MAX;

// The blocks (opening types, generators aside) that `outer` holds and that hold `inner`.
std::vector<size_t> middle_blocks(size_t outer, size_t inner) {
  std::vector<size_t> out;
  for (size_t z = 1; z < 1024; ++z) {
    if (z == L::K_GEN || end_type_of(z) == 0) continue;
    if (block_holds(outer, z) && block_holds(z, inner)) out.push_back(z);
  }
  return out;
}
// How many words and blocks of a body an end keyword that closes nothing looks back over
// for its opening.
constexpr size_t kLookBack = 256;

struct Entry {
  uint32_t r;     // the token (its index among the real tokens)
  uint16_t type;  // a word's token type (IDENT, or a keyword read as a word); a child's opening type
  bool line_start;
};

struct Frame {
  uint32_t open = 0;
  uint16_t type = 0;      // 0: the top level
  std::string_view word;  // its keyword as meant (`mesh`, `funnel`)
  std::string end;        // a generator's end keyword (`endfunnel`); others use the table's
  std::vector<Entry> words;     // IDENTs and keywords read as words, outside brackets
  std::vector<Entry> children;  // the blocks it holds, closed
};

class Structure {
 public:
  Structure(std::vector<Tok>& tokens, std::string_view text, uint32_t base, FileId file, LineEndRepairs& repairs,
            bool brackets_pass)
      : tokens_(tokens), text_(text), base_(base), file_(file), repairs_(repairs), brackets_pass_(brackets_pass) {
    // The parser's tokens are all real but the end token: the index is needed only when a
    // hidden one is left.
    size_t real = 0;
    for (const Tok& t : tokens) real += !t.hidden && t.type != kEof ? 1 : 0;
    identity_ = real == tokens.size() || (real + 1 == tokens.size() && tokens.back().type == kEof);
    if (!identity_) {
      real_.reserve(real);
      for (size_t i = 0; i < tokens.size(); ++i) {
        if (!tokens[i].hidden && tokens[i].type != kEof) real_.push_back(static_cast<uint32_t>(i));
      }
    }
    n_ = static_cast<uint32_t>(real);
    budget_ = 8 * static_cast<size_t>(n_) + 256;
  }

  void run(DiagnosticEngine& diags, StructureOutcome& outcome) {
    stack_.push_back(Frame{});
    uint32_t r = 0;
    while (true) {
      if (r >= n_) {
        if (!brackets_.empty() && brackets_pass_) {
          depends_ = true;
          close_brackets(n_);
        }
        if (stack_.size() == 1 || brackets_pass_) break;
        depends_ = true;
        const uint32_t p = close_at_end();
        if (p != kNone) r = p;
        continue;
      }
      ++steps_;
      if (deleted(r)) {
        ++r;
        continue;
      }
      const uint32_t next = step(r);
      r = next;
    }
    finish(diags, outcome);
  }

 private:
  // A decision's scan position: 2r + 1 while token r is read, 2p for a block closed before
  // token p. Scanning again from p undoes the decisions from 2p + 1 on.
  struct Edit {
    uint32_t at;  // the scan position that made it
    enum Kind : uint8_t { Retype, Delete, Insert } kind;
    uint32_t r;          // the token (Insert: the token it goes before; n_: the end)
    uint16_t old_type;   // Retype: what it was
    uint16_t new_type;   // Retype, Insert
  };
  struct Report {
    uint32_t at;
    std::function<void(DiagnosticEngine&)> emit;
  };

  Tok& tok(uint32_t r) { return tokens_[index(r)]; }
  size_t index(uint32_t r) const { return identity_ ? r : real_[r]; }
  bool deleted(uint32_t r) const { return !deleted_.empty() && deleted_.contains(r); }
  std::string_view meant(uint32_t r) const {
    if (meant_.empty()) return {};
    auto it = meant_.find(r);
    return it == meant_.end() ? std::string_view() : it->second;
  }
  std::string_view text_of(uint32_t r) {
    const Tok& t = tok(r);
    return text_.substr(t.begin, t.end - t.begin);
  }
  // The word as meant: its respelling, if it has one.
  std::string_view word(uint32_t r) {
    const std::string_view m = meant(r);
    return m.empty() ? text_of(r) : m;
  }
  bool line_start(uint32_t r) { return r == 0 || tok(r - 1).line != tok(r).line; }
  bool line_end(uint32_t r) {
    if (r + 1 >= n_) {
      depends_ = true;
      return true;
    }
    return tok(r + 1).line != tok(r).line;
  }
  SourceRange range(uint32_t r) { return SourceRange{file_, base_ + tok(r).begin, base_ + tok(r).end}; }
  SourceRange at(uint32_t byte) { return SourceRange{file_, base_ + byte, base_ + byte}; }
  uint32_t end_byte() { return n_ == 0 ? 0 : tok(n_ - 1).end; }

  // The keyword a frame's block is closed by.
  std::string_view end_word(const Frame& f) {
    if (f.type == L::K_GEN) return f.end;
    return keyword_literal(end_type_of(f.type));
  }
  // Whether end keyword token r closes frame f.
  bool closes(const Frame& f, uint32_t r) { return f.type != 0 && tok(r).type == end_type_of(f.type); }

  // Emitted in scan order; the caller puts them in position order with the other passes'.
  void report(std::function<void(DiagnosticEngine&)> emit) {
    reports_.push_back(Report{scan_, std::move(emit)});
  }
  void retype(uint32_t r, uint16_t type, std::string_view meant) {
    edits_.push_back(Edit{scan_, Edit::Retype, r, tok(r).type, type});
    tok(r).type = type;
    meant_[r] = meant;  // (a map: respellings are few)
  }
  void remove(uint32_t r) {
    edits_.push_back(Edit{scan_, Edit::Delete, r, 0, 0});
    deleted_.insert(r);
  }
  void insert(uint32_t before, uint16_t type) { edits_.push_back(Edit{scan_, Edit::Insert, before, 0, type}); }

  // Undoes what was decided from token `p` on (the blocks closed before it stay closed),
  // before the scan goes on from there.
  void rewind_to(uint32_t p) {
    const uint32_t from = 2 * p + 1;
    while (!edits_.empty() && edits_.back().at >= from) {
      const Edit& e = edits_.back();
      if (e.kind == Edit::Retype) {
        tok(e.r).type = e.old_type;
        meant_.erase(e.r);
      } else if (e.kind == Edit::Delete) {
        deleted_.erase(e.r);
      }
      edits_.pop_back();
    }
    while (!reports_.empty() && reports_.back().at >= from) reports_.pop_back();
    brackets_.clear();  // a statement starts outside brackets
    scan_ = 2 * p;
  }
  bool may_rewind() const { return steps_ < budget_; }

  // Pops the top frame, closed, into its parent's children. Its lists are kept for the
  // next frame (no allocation per block).
  void pop_closed() {
    Frame f = std::move(stack_.back());
    stack_.pop_back();
    stack_.back().children.push_back(Entry{f.open, f.type, false});
    f.words.clear();
    f.children.clear();
    spare_.push_back(std::move(f));
  }

  size_t column(uint32_t r) { return column_of(text_, tok(r).begin); }

  // Where in frame `f`'s body, at or before `limit`, the block should have ended: the
  // earliest keyword read as a word at the start of a line that the frame's parent
  // (`holder`) holds, or the earliest block it holds that starts a line no further right
  // than the frame's own keyword (its body is indented, what follows it is not), after the
  // last block `f` holds that `holder` would not. kNone if none.
  uint32_t close_point(const Frame& f, size_t holder, uint32_t limit) {
    uint32_t after = f.open;
    for (const Entry& c : f.children) {
      if (!block_holds(holder, c.type)) after = std::max(after, c.r);
    }
    uint32_t best = kNone;
    for (const Entry& w : f.words) {
      if (w.r > after && w.r <= limit && w.line_start && w.type != L::IDENT && block_holds(holder, w.type)) {
        best = w.r;
        break;
      }
    }
    if (!line_start(f.open)) return best;
    const size_t col = column(f.open);
    for (const Entry& c : f.children) {
      if (c.r > after && c.r <= limit && c.r < best && line_start(c.r) && block_holds(holder, c.type) && column(c.r) <= col) {
        best = c.r;
        break;
      }
    }
    return best;
  }

  // Reports frame `f` as not closed, its end inserted before token `p` (n_: at the end).
  void report_missing_end(const Frame& f, uint32_t p) {
    const std::string end(end_word(f));
    const std::string_view kw = f.word;
    const SourceRange open = range(f.open);
    if (p >= n_) {
      // Nothing follows to show where it ends: the error is at its keyword.
      const bool newline = !text_.empty() && text_.back() == '\n';
      const uint32_t size = static_cast<uint32_t>(text_.size());
      report([=, this](DiagnosticEngine& d) {
        d.emit(DiagKind::MissingEndKeyword, open,
               fmt::format("`{}` is never closed: expected `{}` before the end of the file", kw, end))
            .fixit(at(size), (newline ? "" : "\n") + end + "\n", fmt::format("insert `{}`", end));
      });
      return;
    }
    const SourceRange where = range(p);
    const std::string_view next = text_of(p);
    std::string insert_text = end + " ";
    if (line_start(p)) {
      size_t line_begin = tok(p).begin;
      while (line_begin > 0 && (text_[line_begin - 1] == ' ' || text_[line_begin - 1] == '\t')) --line_begin;
      insert_text = end + "\n" + std::string(text_.substr(line_begin, tok(p).begin - line_begin));
    }
    report([=](DiagnosticEngine& d) {
      d.emit(DiagKind::MissingEndKeyword, where,
             fmt::format("`{}` is not closed: `{}` is missing before this `{}`", kw, end, next))
          .note(open, fmt::format("`{}` opened here", kw))
          .fixit(SourceRange{where.file, where.begin, where.begin}, insert_text, fmt::format("insert `{}`", end));
    });
  }

  // The top frame is not closed: its end goes before `p` (n_: at the end).
  void close_top_before(uint32_t p) {
    report_missing_end(stack_.back(), p);
    insert(p, static_cast<uint16_t>(end_type_of(stack_.back().type)));
    pop_closed();
  }

  // At the end of the text, the innermost open block: closed where its parent's next
  // statement starts (and the scan goes on from there), or at the end.
  uint32_t close_at_end() {
    const Frame& f = stack_.back();
    const uint32_t p = may_rewind() ? close_point(f, stack_[stack_.size() - 2].type, n_) : kNone;
    if (p != kNone) {
      rewind_to(p);
    } else {
      scan_ = 2 * n_;
    }
    close_top_before(p == kNone ? n_ : p);
    return p;
  }

  static bool ends_operand(uint16_t t) {
    return t == L::NUMBER || t == L::DOLLAR_REF || t == L::IDENT || t == L::TCL_ARRAY_REF || t == L::RPAREN ||
           t == L::RBRACE || t == L::STRING || t == L::BRACKET_RAW || t == L::PCT_RAW;
  }
  static bool starts_operand(uint16_t t) {
    return t == L::NUMBER || t == L::DOLLAR_REF || t == L::IDENT || t == L::TCL_ARRAY_REF || t == L::LPAREN ||
           t == L::LBRACE || t == L::STRING || t == L::BRACKET_RAW || t == L::PCT_RAW || t == L::SPLUS ||
           t == L::SMINUS;
  }

  // Where the expression of an unclosed `{expr …` opened at token `open` ends, before
  // `limit`: where two operands meet with no operator between them (the next list element
  // starts), outside brackets; `limit` if nowhere.
  uint32_t expr_end(uint32_t open, uint32_t limit) {
    int depth = 0;
    for (uint32_t k = open + 2; k < limit; ++k) {
      const uint16_t t = tok(k).type;
      if (depth == 0 && k > open + 2 && ends_operand(tok(k - 1).type) && starts_operand(t) &&
          !(tok(k - 1).type == L::IDENT && t == L::LPAREN)) {
        return k;
      }
      if (t == L::LPAREN || t == L::LBRACE) ++depth;
      if ((t == L::RPAREN || t == L::RBRACE) && depth > 0) --depth;
    }
    return limit;
  }

  // The open brackets above `keep` (an index into brackets_) are closed before token `r`
  // (n_: at the end), one error each; an unclosed `{expr …` where its expression ends.
  void close_brackets(uint32_t r, size_t keep = 0) {
    while (brackets_.size() > keep) {
      const Entry b = brackets_.back();
      brackets_.pop_back();
      const bool paren = tok(b.r).type == L::LPAREN;
      const char* close = paren ? ")" : "}";
      uint32_t before = r;
      if (!paren && b.r + 1 < n_ && tok(b.r + 1).type == L::K_EXPR) before = expr_end(b.r, r);
      if (paren) {
        // `(90 translate (-1 0 1) endinstance`: the list ended before a word that opens a
        // list of its own after a space (an option, not a call).
        int depth = 0;
        for (uint32_t k = b.r + 1; k + 1 < r; ++k) {
          const uint16_t t = tok(k).type;
          if (t == L::LPAREN || t == L::LBRACE) ++depth;
          if ((t == L::RPAREN || t == L::RBRACE) && depth > 0) --depth;
          if (depth == 0 && t == L::IDENT && tok(k + 1).type == L::LPAREN && tok(k).end < tok(k + 1).begin) {
            before = k;
            break;
          }
          // `(0 0 1 (90) …`: a list that starts after an element, past a space.
          if (depth == 1 && t == L::LPAREN && k > b.r + 1 && ends_operand(tok(k - 1).type) &&
              tok(k - 1).end < tok(k).begin) {
            before = k;
            break;
          }
        }
      }
      const uint32_t byte = before < n_ ? (before > 0 ? tok(before - 1).end : tok(before).begin) : end_byte();
      const std::string where = before < n_ ? fmt::format("before `{}`", text_of(before)) : "at the end of the file";
      const SourceRange open = range(b.r);
      report([=, this](DiagnosticEngine& d) {
        d.emit(DiagKind::SyntaxError, open,
               fmt::format("`{}` is never closed: `{}` is missing {}", paren ? "(" : "{", close, where))
            .fixit(at(byte), close, fmt::format("insert `{}`", close));
      });
      insert(before, static_cast<uint16_t>(paren ? L::RPAREN : L::RBRACE));
    }
  }

  // The `)` at r closes nothing: its `(` goes before token `start`. One error, at the `)`.
  void open_paren_before(uint32_t start, uint32_t r) {
    const SourceRange where = range(r), first = range(start);
    const std::string first_text(text_of(start));
    report([=, this](DiagnosticEngine& d) {
      d.emit(DiagKind::SyntaxError, where, fmt::format("`)` closes nothing: its `(` is missing before `{}`", first_text))
          .fixit(at(first.begin - base_), "(", "insert `(`");
    });
    insert(start, L::LPAREN);
  }

  // Whether a `}` follows `)` at r on its line before any other `)` or statement keyword:
  // the `)` is inside the braces (`{expr a - b) * c}`), not after them.
  bool brace_goes_on(uint32_t r) {
    for (uint32_t k = r + 1; k < n_ && tok(k).line == tok(r).line; ++k) {
      const uint16_t t = tok(k).type;
      if (t == L::RBRACE) return true;
      if (t == L::RPAREN || t == L::LBRACE || t == L::LPAREN || is_end_token(t) || is_open_type(t)) return false;
    }
    return false;
  }

  // A `)` or `}` that closes no open bracket: a `}` after `expr …` is missing its `{`
  // before the `expr`; any other is dropped. One error.
  void stray_closer(uint32_t r) {
    const uint16_t type = tok(r).type;
    const SourceRange where = range(r);
    const char c = type == L::RPAREN ? ')' : '}';
    if (type == L::RBRACE) {
      int depth = 0;
      for (uint32_t k = r; k-- > 0 && r - k <= 64;) {
        const uint16_t t = tok(k).type;
        if (t == L::RPAREN) {
          ++depth;
          continue;
        }
        if (t == L::LPAREN && depth > 0) {
          --depth;
          continue;
        }
        if (t == L::K_EXPR && depth == 0) {
          const SourceRange e = range(k);
          report([=, this](DiagnosticEngine& d) {
            d.emit(DiagKind::SyntaxError, where, "`}` closes nothing: its `{` is missing before `expr`")
                .fixit(at(e.begin - base_), "{", "insert `{`");
          });
          insert(k, L::LBRACE);
          return;
        }
        if (t == L::LBRACE || t == L::RBRACE || t == L::LPAREN || is_end_token(t) || is_open_type(t)) break;
      }
    }
    if (type == L::RPAREN) {
      // `list n ro)`, `rotate (0 0 1) 90)`: the values (or names) before it on its line,
      // after the line's first word or the last bracket, are the list it closes.
      uint32_t start = r;
      for (uint32_t k = r; k-- > 0;) {
        const uint16_t t = tok(k).type;
        if (tok(k).line != tok(r).line || deleted(k)) break;
        const bool value = t == L::NUMBER || t == L::DOLLAR_REF || t == L::IDENT || t == L::TCL_ARRAY_REF ||
                           t == L::STRING || t == L::SPLUS || t == L::SMINUS || t == L::PLUS || t == L::MINUS ||
                           t == L::STAR || t == L::SLASH || t == L::CARET;
        if (!value || (line_start(k) && t == L::IDENT)) break;
        start = k;
      }
      if (start < r) {
        open_paren_before(start, r);
        return;
      }
    }
    report([=](DiagnosticEngine& d) {
      d.emit(DiagKind::SyntaxError, where, fmt::format("`{}` closes nothing: no `{}` is open here", c, c == ')' ? '(' : '{'))
          .fixit(where, "", fmt::format("remove `{}`", c));
    });
    remove(r);
  }

  // One token; returns the next to scan.
  uint32_t step(uint32_t r) {
    scan_ = 2 * r + 1;
    const uint16_t type = tok(r).type;
    if (!brackets_pass_) {
      // The bracket pass balanced them: only the depth is followed here.
      if (type == L::LPAREN || type == L::LBRACE) {
        brackets_.push_back(Entry{r, type, false});
        return r + 1;
      }
      if (type == L::RPAREN || type == L::RBRACE) {
        if (!brackets_.empty()) brackets_.pop_back();
        return r + 1;
      }
      if (!brackets_.empty()) {
        if (!is_end_token(type) && type != L::TCLINIT) return r + 1;
        brackets_.clear();
      }
      if (is_end_token(type)) return on_end(r);
      if (type == L::TCLINIT) return on_tclinit(r);
      if (is_open_type(type)) return on_open(r);
      if (type == L::IDENT) return on_word(r);
      return r + 1;
    }
    if (type == L::LPAREN || type == L::LBRACE) {
      // `{exrp $a}`: a misspelt `expr` first in braces.
      if (type == L::LBRACE && r + 2 < n_ && tok(r + 1).type == L::IDENT && tok(r + 2).type != L::RBRACE &&
          tok(r + 2).type != L::LPAREN && is_typo_of(text_of(r + 1), "expr")) {
        respell(r + 1, L::K_EXPR, "expr");
      }
      brackets_.push_back(Entry{r, type, false});
      return r + 1;
    }
    if (type == L::RPAREN || type == L::RBRACE) {
      const uint16_t opener = type == L::RPAREN ? L::LPAREN : L::LBRACE;
      if (type == L::RPAREN && !brackets_.empty() && tok(brackets_.back().r).type == L::LBRACE && brace_goes_on(r)) {
        // `{expr a - b) * c}`: the `(` of this `)` is missing inside the braces, after `expr`.
        const uint32_t b = brackets_.back().r;
        const uint32_t start = b + 1 < n_ && tok(b + 1).type == L::K_EXPR ? b + 2 : b + 1;
        if (start < r) {
          open_paren_before(start, r);
          return r + 1;
        }
      }
      for (size_t k = brackets_.size(); k-- > 0;) {
        if (tok(brackets_[k].r).type != opener) continue;
        close_brackets(r, k + 1);  // the brackets opened inside it were not closed
        brackets_.pop_back();
        return r + 1;
      }
      stray_closer(r);
      return r + 1;
    }
    // Inside brackets keywords are names; an end keyword or a `tclinit` shows the brackets
    // were not closed.
    if (!brackets_.empty() && (is_end_token(type) || type == L::TCLINIT)) close_brackets(r);
    return r + 1;
  }

  uint32_t on_open(uint32_t r) {
    const uint16_t type = tok(r).type;
    Frame& top = stack_.back();
    if (block_holds(top.type, type)) {
      Frame f;
      if (!spare_.empty()) {
        f = std::move(spare_.back());
        spare_.pop_back();
      }
      f.open = r;
      f.type = type;
      const std::string_view m = meant(r);
      f.word = type == L::K_GEN ? word(r) : (m.empty() ? keyword_literal(type) : m);
      f.end = type == L::K_GEN ? "end" + std::string(f.word) : std::string();
      stack_.push_back(std::move(f));
      return r + 1;
    }
    top.words.push_back(Entry{r, type, line_start(r)});
    return r + 1;
  }

  // `tclinit` stands only at the top level: every block open before it was not closed.
  uint32_t on_tclinit(uint32_t r) {
    if (stack_.size() == 1) return r + 1;
    const uint32_t p = may_rewind() ? close_point(stack_.back(), stack_[stack_.size() - 2].type, r) : kNone;
    if (p != kNone) rewind_to(p);
    close_top_before(p == kNone ? r : p);
    return p == kNone ? r : p;  // the next frame out, if any, is closed before it too
  }

  uint32_t on_word(uint32_t r) {
    Frame& top = stack_.back();
    if (stack_.size() > 1) {
      const std::string_view w = text_of(r);
      // The open block's end keyword, misspelt where an end keyword stands (first or last
      // on its line), or an enclosing block's one when the word starts with `end`.
      if (line_start(r) || line_end(r)) {
        for (size_t k = stack_.size() - 1; k >= 1; --k) {
          const std::string_view e = end_word(stack_[k]);
          if (k != stack_.size() - 1 && !w.starts_with("end")) break;
          if (is_typo_of(w, e)) {
            respell(r, static_cast<uint16_t>(end_type_of(stack_[k].type)), e);
            return on_end(r);
          }
        }
      }
    }
    top.words.push_back(Entry{r, L::IDENT, line_start(r)});
    return r + 1;
  }

  // Reads word r as keyword `meant` (token type `type`), with its error and fix-it.
  void respell(uint32_t r, uint16_t type, std::string_view meant) {
    const std::string_view kept = interned(meant);
    const SourceRange where = range(r);
    const std::string written(text_of(r));
    report([=](DiagnosticEngine& d) {
      d.emit(DiagKind::MisspelledKeyword, where, fmt::format("unknown `{}`; did you mean `{}`?", written, kept))
          .fixit(where, std::string(kept), fmt::format("replace with `{}`", kept));
    });
    retype(r, type, kept);
  }

  uint32_t on_end(uint32_t r) {
    const uint16_t type = tok(r).type;
    if (closes(stack_.back(), r)) {
      // A keyword of the block's own kind at the start of one of its lines, read as a word:
      // the block ended before it (`sharp (a b)` ⏎ `sharp (c d) endsharp`).
      const Frame& f = stack_.back();
      if (may_rewind()) {
        for (const Entry& w : f.words) {
          if (w.line_start && w.type == f.type && (f.type != L::K_GEN || word(w.r) == f.word) &&
              block_holds(stack_[stack_.size() - 2].type, w.type)) {
            const uint32_t p = w.r;
            rewind_to(p);
            close_top_before(p);
            return p;
          }
        }
      }
      pop_closed();
      return r + 1;
    }
    // An enclosing block's end: the blocks inside it were not closed.
    for (size_t k = stack_.size() - 1; k-- > 1;) {
      if (!closes(stack_[k], r)) continue;
      const uint32_t p = may_rewind() ? close_point(stack_.back(), stack_[stack_.size() - 2].type, r) : kNone;
      if (p != kNone) {
        rewind_to(p);
        close_top_before(p);
        return p;
      }
      while (stack_.size() - 1 > k) close_top_before(r);
      pop_closed();
      return r + 1;
    }
    // It closes nothing open: its block's keyword may be in the open block's body, misspelt
    // or not held there.
    const size_t open = open_type_of_end(type);
    const std::string_view closed_word =
        type == L::E_GEN ? word(r).substr(std::min<size_t>(3, word(r).size())) : keyword_literal(open);
    if (uint32_t p = reopen(r, open, closed_word); p != kNone) return p;
    // The open block may be a keyword read as a block that is a word of the block around it
    // (`background` in a misspelt `window`): read it as a word, and look again there.
    if (stack_.size() > 1 && demotable(stack_.back()) && has_typo_of(stack_[stack_.size() - 2], closed_word)) {
      demote();
      if (uint32_t p = reopen(r, open, closed_word); p != kNone) return p;
    }
    Frame& top = stack_.back();
    if (top.type != 0 && next_ends_block(r)) {
      const std::string e(end_word(top));
      const std::string_view meant = interned(e);
      const SourceRange where = range(r), opened = range(top.open);
      const std::string written(text_of(r));
      const std::string_view kw = top.word;
      report([=](DiagnosticEngine& d) {
        d.emit(DiagKind::MismatchedEndKeyword, where,
               fmt::format("`{}` does not close the open `{}`; expected `{}`", written, kw, meant))
            .note(opened, fmt::format("`{}` opened here", kw))
            .fixit(where, std::string(meant), fmt::format("replace with `{}`", meant));
      });
      retype(r, static_cast<uint16_t>(end_type_of(top.type)), meant);
      pop_closed();
      return r + 1;
    }
    const SourceRange where = range(r);
    const std::string written(text_of(r));
    const std::string opener(closed_word);
    report([=](DiagnosticEngine& d) {
      d.emit(DiagKind::UnmatchedEndKeyword, where,
             fmt::format("`{}` closes nothing: no `{}` statement is open here", written, opener))
          .fixit(where, "", fmt::format("remove `{}`", written));
    });
    remove(r);
    return r + 1;
  }

  // Whether a frame's keyword can be read as a word of its parent: the blocks it holds are
  // ones its parent holds too.
  bool demotable(const Frame& f) {
    const size_t parent = stack_[stack_.size() - 2].type;
    return std::all_of(f.children.begin(), f.children.end(), [&](const Entry& c) { return block_holds(parent, c.type); });
  }
  // Whether frame f's body has a word within its look back that misspells `keyword`.
  bool has_typo_of(const Frame& f, std::string_view keyword) {
    size_t seen = 0;
    for (size_t k = f.words.size(); k-- > 0 && seen < kLookBack; ++seen) {
      if (f.words[k].type == L::IDENT && is_typo_of(text_of(f.words[k].r), keyword)) return true;
    }
    return false;
  }
  // The top frame's keyword becomes a word of its parent, with its body.
  void demote() {
    Frame f = std::move(stack_.back());
    stack_.pop_back();
    Frame& parent = stack_.back();
    parent.words.push_back(Entry{f.open, f.type, line_start(f.open)});
    parent.words.insert(parent.words.end(), f.words.begin(), f.words.end());
    parent.children.insert(parent.children.end(), f.children.begin(), f.children.end());
    f.words.clear();
    f.children.clear();
    spare_.push_back(std::move(f));
  }

  // Whether what follows end keyword r shows that the open block ends here.
  bool next_ends_block(uint32_t r) {
    uint32_t k = r + 1;
    while (k < n_ && deleted(k)) ++k;
    if (k >= n_) {
      depends_ = true;
      return true;
    }
    const uint16_t t = tok(k).type;
    if (t == L::TCLINIT) return true;
    if (is_end_token(t)) {
      for (size_t f = stack_.size() - 1; f-- > 1;) {
        if (closes(stack_[f], k)) return true;
      }
      return false;
    }
    return is_open_type(t) && line_start(k) && !block_holds(stack_.back().type, t);
  }

  // End keyword r closes a block of type `open` (`word`) that is not open: find its opening
  // in the open block's body, a misspelt word or a keyword the block could not hold, and
  // read the text as if it were there. Returns where to scan on, or kNone.
  uint32_t reopen(uint32_t r, size_t open, std::string_view keyword) {
    if (open == 0 || keyword.empty()) return kNone;
    Frame& top = stack_.back();
    // A frame out from the top that holds the block.
    auto holder_of = [&](size_t from) -> size_t {
      for (size_t k = from + 1; k-- > 0;) {
        if (block_holds(stack_[k].type, open)) return k;
      }
      return SIZE_MAX;
    };
    uint32_t typo = kNone, as_word = kNone;
    bool best_line = false;
    // The keywords this end keyword closes: its own, and for a generator's every keyword that
    // closes with it (2016's `tunnel … endfunnel`).
    std::vector<std::string_view> spellings{keyword};
    if (open == L::K_GEN) {
      const std::string end = "end" + std::string(keyword);
      for (const ir::GeneratorInfo& g : ir::generators()) {
        for (std::string_view k : g.keywords) {
          if (k != keyword && g.closes_with(k, end)) spellings.push_back(k);
        }
      }
    }
    std::string_view meant = keyword;
    size_t i = top.words.size(), j = top.children.size();
    // The look back is bounded (kLookBack entries), so many stray end keywords stay linear.
    for (size_t seen = 0; (i > 0 || j > 0) && seen < kLookBack; ++seen) {
      const bool child = j > 0 && (i == 0 || top.children[j - 1].r > top.words[i - 1].r);
      if (child) {
        if (!block_holds(open, top.children[--j].type)) break;
        continue;
      }
      const Entry& w = top.words[--i];
      if (w.type == open && (open != L::K_GEN || word(w.r) == keyword)) {
        as_word = w.r;
        break;
      }
      if (w.type == L::IDENT) {
        const std::string_view text = text_of(w.r);
        for (std::string_view k : spellings) {
          if (!is_typo_of(text, k)) continue;
          // The statement's keyword comes first: the earliest word that starts a line, else
          // the earliest (the look back goes backwards).
          if (w.line_start >= best_line) {
            best_line = w.line_start;
            typo = w.r;
            meant = k;
          }
        }
      }
    }
    const size_t holder = holder_of(stack_.size() - 1);
    if (holder == SIZE_MAX) return kNone;
    if (typo != kNone) {
      if (holder == stack_.size() - 1) {
        respell(typo, static_cast<uint16_t>(open), meant);
        // The block's children after the word are now the misspelt block's.
        auto later = [&](const Entry& e) { return e.r > typo; };
        top.children.erase(std::remove_if(top.children.begin(), top.children.end(), later), top.children.end());
        top.words.erase(std::remove_if(top.words.begin(), top.words.end(),
                                       [&](const Entry& e) { return e.r >= typo; }),
                        top.words.end());
        top.children.push_back(Entry{typo, static_cast<uint16_t>(open), false});
        return r + 1;
      }
      // Not held here: the open block ended before it.
      if (!may_rewind()) return kNone;
      const uint32_t p = typo;
      rewind_to(p);
      close_top_before(p);
      respell(p, static_cast<uint16_t>(open), meant);
      return p;
    }
    if (as_word != kNone && may_rewind()) {
      // A misspelt block that the open one holds and that holds this one, before it
      // (`fface` ⏎ `vertex v endvertex` in a saved working mesh): read as that block.
      std::vector<size_t> between;
      for (size_t z : middle_blocks(top.type, open)) between.push_back(z);
      if (!between.empty()) {
        size_t seen = 0;
        for (size_t k = top.words.size(); k-- > 0 && seen < kLookBack; ++seen) {
          const Entry& w = top.words[k];
          if (w.r >= as_word || w.type != L::IDENT) continue;
          for (size_t z : between) {
            if (!is_typo_of(text_of(w.r), keyword_literal(z))) continue;
            const uint32_t p = w.r;
            rewind_to(p);
            auto from_p = [p](const Entry& e) { return e.r >= p; };
            top.words.erase(std::remove_if(top.words.begin(), top.words.end(), from_p), top.words.end());
            top.children.erase(std::remove_if(top.children.begin(), top.children.end(), from_p), top.children.end());
            respell(p, static_cast<uint16_t>(z), keyword_literal(z));
            return p;
          }
        }
      }
    }
    if (as_word != kNone && holder != stack_.size() - 1 && may_rewind()) {
      const uint32_t p = std::min(as_word, close_point(top, stack_[stack_.size() - 2].type, as_word));
      rewind_to(p);
      close_top_before(p);
      return p;
    }
    return kNone;
  }

  void finish(DiagnosticEngine& diags, StructureOutcome& outcome) {
    // A top-level word a later end keyword could read as a keyword (within its look back).
    const Frame& top = stack_.front();
    const uint32_t window_start = [&] {
      size_t i = top.words.size(), j = top.children.size();
      uint32_t from = 0;
      for (size_t seen = 0; (i > 0 || j > 0) && seen < kLookBack; ++seen) {
        const bool child = j > 0 && (i == 0 || top.children[j - 1].r > top.words[i - 1].r);
        from = child ? top.children[--j].r : top.words[--i].r;
      }
      return from;
    }();
    for (const Entry& w : top.words) {
      if (w.type != L::IDENT || w.r < window_start) continue;
      const std::string_view text = text_of(w.r);
      for (std::string_view k : ast::all_open_keywords()) {
        if (is_typo_of(text, k)) {
          depends_ = true;
          break;
        }
      }
      if (depends_) break;
    }
    outcome.depends_on_what_follows = depends_;
    for (const Report& rep : reports_) rep.emit(diags);
    for (const auto& [r, m] : meant_) repairs_.respelled[tok(r).begin] = m;
    bool changes = false;
    for (const Edit& e : edits_) changes = changes || e.kind != Edit::Retype;
    if (!changes) return;
    // Deletions and insertions, in token order (an insertion before token r goes before it;
    // several before one token in the order they were decided).
    std::vector<std::pair<uint32_t, uint16_t>> inserts;
    for (const Edit& e : edits_) {
      if (e.kind == Edit::Insert) inserts.emplace_back(e.r, e.new_type);
    }
    std::stable_sort(inserts.begin(), inserts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<bool> drop(tokens_.size(), false);
    for (uint32_t r : deleted_) drop[index(r)] = true;
    std::vector<Tok> out;
    out.reserve(tokens_.size() + inserts.size());
    size_t next = 0;
    uint32_t r = 0;
    auto conjure = [&](uint16_t type, const Tok& near, uint32_t byte) {
      out.push_back(Tok{byte, byte, near.line, type, false});
    };
    for (size_t i = 0; i < tokens_.size(); ++i) {
      const bool is_real = r < n_ && index(r) == i;
      if (is_real) {
        while (next < inserts.size() && inserts[next].first == r) {
          conjure(inserts[next].second, tokens_[i], tokens_[i].begin);
          ++next;
        }
        ++r;
      } else if (tokens_[i].type == kEof) {
        while (next < inserts.size()) {
          conjure(inserts[next].second, tokens_[i], tokens_[i].begin);
          ++next;
        }
      }
      if (!drop[i]) out.push_back(tokens_[i]);
    }
    while (next < inserts.size()) {  // no end token: after the last one
      const Tok near = out.empty() ? Tok{} : out.back();
      conjure(inserts[next].second, near, near.end);
      ++next;
    }
    tokens_ = std::move(out);
  }

  std::vector<Tok>& tokens_;
  std::string_view text_;
  uint32_t base_;
  FileId file_;
  LineEndRepairs& repairs_;
  std::vector<uint32_t> real_;  // token r's index in tokens_, unless identity_
  bool identity_ = false;
  uint32_t n_ = 0;
  std::set<uint32_t> deleted_;
  std::unordered_map<uint32_t, std::string_view> meant_;
  std::vector<Frame> stack_;
  std::vector<Frame> spare_;
  std::vector<Entry> brackets_;
  std::vector<Edit> edits_;
  std::vector<Report> reports_;
  uint32_t scan_ = 0;
  size_t steps_ = 0, budget_ = 0;
  bool depends_ = false;
  bool brackets_pass_ = false;
};

}  // namespace

namespace {

// Whether the blocks need the structure pass: one look at the token types, as the pass
// nests blocks (most files' end keywords each close the block open before them). A word
// that could be read as a keyword is looked at only where the nesting fails.
bool structure_needs_repair(const std::vector<Tok>& tokens, std::string_view text) {
  std::vector<uint16_t> open;
  std::vector<std::string_view> open_words;  // a generator's keyword (its end keyword is `end` + it)
  int depth = 0;  // brackets (balanced by the bracket pass)
  const size_t n = tokens.size();
  for (size_t i = 0; i < n; ++i) {
    const Tok& t = tokens[i];
    if (t.hidden || t.type == kEof) continue;
    const uint16_t type = t.type;
    const bool line_start = i == 0 || tokens[i - 1].line != t.line;
    const bool line_end = i + 1 >= n || tokens[i + 1].type == kEof || tokens[i + 1].line != t.line;
    if (type == L::LPAREN || type == L::LBRACE) {
      ++depth;
      continue;
    }
    if (type == L::RPAREN || type == L::RBRACE) {
      if (depth > 0) --depth;
      continue;
    }
    if (depth > 0) continue;
    if (type == L::TCLINIT) {
      if (!open.empty()) return true;
    } else if (is_end_token(type)) {
      if (open.empty() || end_type_of(open.back()) != type) return true;
      open.pop_back();
      open_words.pop_back();
    } else if (is_open_type(type)) {
      if (block_holds(open.empty() ? 0 : open.back(), type)) {
        open.push_back(type);
        open_words.push_back(text.substr(t.begin, t.end - t.begin));
        continue;
      }
      // A statement keyword starting a line of a block that cannot hold it.
      if (line_start) return true;
    } else if (type == L::IDENT && open.empty()) {
      // A top-level word that a later end keyword could read as a keyword.
      const std::string_view w = text.substr(t.begin, t.end - t.begin);
      for (std::string_view k : ast::all_open_keywords()) {
        if (is_typo_of(w, k)) return true;
      }
    } else if (type == L::IDENT && !open.empty() && (line_start || line_end)) {
      // A word where an end keyword stands, close to the open block's.
      const std::string_view w = text.substr(t.begin, t.end - t.begin);
      const std::string end = open.back() == L::K_GEN ? "end" + std::string(open_words.back())
                                                       : std::string(keyword_literal(end_type_of(open.back())));
      if (is_typo_of(w, end) || (w.starts_with("end") && w.size() > 3)) return true;
    }
  }
  return !open.empty();
}

}  // namespace

void recover_structure(std::vector<Tok>& tokens, std::string_view text, uint32_t base, FileId file,
                       DiagnosticEngine& diags, LineEndRepairs& repairs, StructureOutcome& outcome) {
  if (!structure_needs_repair(tokens, text)) return;
  Structure(tokens, text, base, file, repairs, false).run(diags, outcome);
}

namespace {

// Whether the bracket pass has anything to do: one look at the token types (most files'
// brackets nest and close before every end keyword).
bool brackets_need_repair(const std::vector<Tok>& tokens, std::string_view text) {
  std::vector<uint16_t> open;
  for (size_t i = 0; i < tokens.size(); ++i) {
    const Tok& t = tokens[i];
    if (t.hidden || t.type == kEof) continue;
    switch (t.type) {
      case L::LPAREN: open.push_back(L::LPAREN); break;
      case L::LBRACE:
        open.push_back(L::LBRACE);
        if (i + 2 < tokens.size() && tokens[i + 1].type == L::IDENT) {
          const Tok& w = tokens[i + 1];
          if (is_typo_of(text.substr(w.begin, w.end - w.begin), "expr")) return true;
        }
        break;
      case L::RPAREN:
      case L::RBRACE:
        if (open.empty() || open.back() != (t.type == L::RPAREN ? L::LPAREN : L::LBRACE)) return true;
        open.pop_back();
        break;
      default:
        if (!open.empty() && (t.type == L::TCLINIT || is_end_token(t.type))) return true;
    }
  }
  return !open.empty();
}

}  // namespace

void recover_brackets(std::vector<Tok>& tokens, std::string_view text, uint32_t base, FileId file,
                      DiagnosticEngine& diags, LineEndRepairs& repairs, StructureOutcome& outcome) {
  if (!brackets_need_repair(tokens, text)) return;
  StructureOutcome brackets;
  Structure(tokens, text, base, file, repairs, true).run(diags, brackets);
  outcome.depends_on_what_follows = outcome.depends_on_what_follows || brackets.depends_on_what_follows;
}

}  // namespace nomec::parse_detail
