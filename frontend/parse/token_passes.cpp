// The token passes between the lexer and the parser (token_passes.h): diagnostics for
// stray characters and unclosed constructs, retyped tokens and the tokens repairs insert.
#include "frontend/parse/token_passes.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <fmt/format.h>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "frontend/parse/piece.h"
#include "ir/generator_catalogue.h"

#include "frontend/parse/generated.h"
#include "frontend/parse/token_stream.h"

namespace nomec::parse_detail {

namespace {

using L = nomec_antlr::NomeParser;  // every token type, those the passes assign included

// Opening and end keyword token types -> block kinds, from the lexer's literal names so the
// grammar and block_kinds.def cannot drift apart silently (a missing keyword fails a test).
// Every generator keyword is the one token type K_GEN (its end keyword E_GEN).
struct KeywordTable {
  std::vector<std::optional<ast::BlockKind>> open, close;  // by token type
  std::vector<uint16_t> end_of;                            // an opening keyword's end keyword type
  std::vector<std::string> literal;                        // a keyword token's text ("" for K_GEN)
};

const KeywordTable& keyword_table() {
  static const KeywordTable table = [] {
    KeywordTable t;
    const antlr4::dfa::Vocabulary& vocab = grammar_vocabulary();
    const size_t size = std::max<size_t>({vocab.getMaxTokenType(), L::K_GEN, L::E_GEN, L::SPLUS, L::SMINUS}) + 1;
    t.open.resize(size);
    t.close.resize(size);
    t.end_of.resize(size);
    t.literal.resize(size);
    std::unordered_map<std::string, size_t> by_word;
    for (size_t type = 1; type <= vocab.getMaxTokenType(); ++type) {
      std::string lit = vocab.getLiteralName(type);
      if (lit.size() <= 2) continue;
      std::string word = lit.substr(1, lit.size() - 2);
      if (auto kind = ast::block_of_keyword(word)) t.open[type] = *kind;
      if (auto kind = ast::block_of_end_keyword(word)) t.close[type] = *kind;
      by_word[word] = type;
      t.literal[type] = std::move(word);
    }
    for (size_t type = 1; type < size; ++type) {
      if (!t.open[type] || t.literal[type].empty()) continue;
      if (auto it = by_word.find("end" + t.literal[type]); it != by_word.end()) t.end_of[type] = static_cast<uint16_t>(it->second);
    }
    t.open[L::K_GEN] = ast::BlockKind::Generator;
    t.close[L::E_GEN] = ast::BlockKind::Generator;
    t.end_of[L::K_GEN] = L::E_GEN;
    return t;
  }();
  return table;
}

// The characters of generator keywords (and `end`, and the digits of digit-suffixed ones):
// a name with any other character is no generator keyword, and most names are told so
// without a catalogue lookup.
const std::array<bool, 256>& generator_keyword_chars() {
  static const std::array<bool, 256> chars = [] {
    std::array<bool, 256> c{};
    auto add = [&](std::string_view w) {
      for (char ch : w) c[static_cast<unsigned char>(ch)] = true;
    };
    add("end0123456789");
    for (const ir::GeneratorInfo& g : ir::generators()) {
      for (std::string_view k : g.keywords) add(k);
      add(g.digit_prefix);
    }
    return c;
  }();
  return chars;
}

// The generator token type a name takes (K_GEN, E_GEN), or 0 when it is no generator keyword.
size_t generator_token_type(std::string_view word) {
  if (word.size() < 4) return 0;  // shorter than any generator keyword
  const std::array<bool, 256>& chars = generator_keyword_chars();
  for (char ch : word) {
    if (!chars[static_cast<unsigned char>(ch)]) return 0;
  }
  if (ast::block_of_keyword(word) == ast::BlockKind::Generator) return L::K_GEN;
  if (word.starts_with("end") && ast::block_of_end_keyword(word) == ast::BlockKind::Generator) return L::E_GEN;
  return 0;
}

}  // namespace

std::optional<ast::BlockKind> open_kind(size_t type) {
  const auto& open = keyword_table().open;
  return type < open.size() ? open[type] : std::nullopt;
}

size_t column_of(std::string_view text, size_t byte) {
  size_t b = byte;
  while (b > 0 && text[b - 1] != '\n') --b;
  return byte - b;
}

size_t end_type_of(size_t open_type) {
  const auto& end_of = keyword_table().end_of;
  return open_type < end_of.size() ? end_of[open_type] : 0;
}

std::string_view keyword_literal(size_t type) {
  const auto& literal = keyword_table().literal;
  return type < literal.size() ? std::string_view(literal[type]) : std::string_view();
}

bool is_end_token(size_t type) {
  const auto& close = keyword_table().close;
  return type < close.size() && close[type].has_value();
}

bool is_operator(size_t type) {
  switch (type) {
    case L::PLUS: case L::MINUS: case L::SPLUS: case L::SMINUS:
    case L::STAR: case L::SLASH: case L::DSLASH: case L::PERCENT:
    case L::CARET: return true;
    default: return false;
  }
}

namespace {

// NOME2 (2018) names a top-level instance inside `subdivision`, `offset` and `merge` blocks
// with `instance X`, without `endinstance` (`subdivision s instance c type T subdivisions 2
// endsubdivision`). Such an `instance` becomes a name, which the block reads as its
// `instance` option (frontend/check/blocks.cpp): it is inside one of those blocks and the
// word after its name continues the block (`type`, `min`, …, another `instance`, or the
// block's end keyword), where an instance statement would have its target.
void retype_block_instance_names(std::vector<Tok>& toks, std::string_view text) {
  auto next = [&](size_t i) {
    while (++i < toks.size() && toks[i].hidden) {
    }
    return i;
  };
  int depth = 0;  // open subdivision, offset and merge blocks
  for (size_t i = 0; i < toks.size(); ++i) {
    if (toks[i].hidden) continue;
    const size_t type = toks[i].type;
    if (type == L::K_SUBDIVISION || type == L::K_OFFSET || type == L::K_MERGE) ++depth;
    if ((type == L::E_SUBDIVISION || type == L::E_OFFSET || type == L::E_MERGE) && depth > 0) --depth;
    if (type != L::K_INSTANCE || depth == 0) continue;
    const size_t name = next(i);
    const size_t after = next(name);
    if (after >= toks.size() || toks[name].type != L::IDENT) continue;
    const size_t t = toks[after].type;
    const bool is_word = t == L::IDENT || t == L::K_INSTANCE || t == L::E_SUBDIVISION ||
                         t == L::E_OFFSET || t == L::E_MERGE;
    if (!is_word || !continues_block_after_instance_name(text.substr(toks[after].begin, toks[after].end - toks[after].begin))) continue;
    toks[i].type = L::IDENT;
  }
}

}  // namespace

// Token pass: diagnostics for stray characters and unclosed constructs, and the list-sign
// rule. Returns the tokens the parser should see.
// `stopped` is set when a limit made the pass stop reading the text; `what` names the text
// in messages (`file`, or `function` for a function text parsed on its own).
std::vector<Tok> prepare_tokens(std::vector<Tok> tokens, std::string_view text, uint32_t base, FileId file,
                                DiagnosticEngine& diags, bool& stopped, std::string_view what) {
  size_t kept = 0;  // tokens[0, kept) are the output (written in place, never ahead of i)
  int brace_depth = 0;
  constexpr int kMaxNesting = 200;
  int nesting = 0;
  int sign_run = 0;
  int caret_run = 0;
  auto range = [&](const Tok& t) {
    return SourceRange{file, base + t.begin, base + t.end};
  };
  for (size_t i = 0; i < tokens.size(); ++i) {
    auto& tok = tokens[i];
    size_t type = tok.type;
    if (type == kEof) {
      tokens[kept++] = tok;
      break;
    }
    const size_t start = tok.begin;  // index into `text`
    // The parser is recursive: bound how deep brackets, signs and `^` chains nest, and stop
    // reading the file where a limit is crossed (one error, no stack overflow).
    if (type == L::LPAREN || type == L::LBRACE) {
      ++nesting;
    } else if ((type == L::RPAREN || type == L::RBRACE) && nesting > 0) {
      --nesting;
    }
    bool is_sign = type == L::PLUS || type == L::MINUS;
    sign_run = is_sign ? sign_run + 1 : 0;
    if (type == L::CARET) {
      ++caret_run;
    } else if (type != L::NUMBER && type != L::IDENT &&
               type != L::DOLLAR_REF && !is_sign) {
      caret_run = 0;
    }
    if (nesting > kMaxNesting || sign_run > kMaxNesting || caret_run > kMaxNesting) {
      diags.emit(DiagKind::NestingTooDeep, range(tok),
                 fmt::format("brackets, signs or `^` nest more than {} levels deep here; nomec "
                             "stops reading the {} at this point",
                             kMaxNesting, what));
      stopped = true;
      while (i + 1 < tokens.size() && tokens[i + 1].type != kEof) {
        ++i;
      }
      continue;
    }
    if (type == L::IDENT) {
      if (size_t gen = generator_token_type(text.substr(start, tok.end - start))) {
        tok.type = static_cast<uint16_t>(gen);
        tokens[kept++] = tok;
        continue;
      }
    }
    if (type == L::IDENT && (text.substr(start, tok.end - start) == "tclinit" || text.substr(start, tok.end - start) == "tclupdate")) {
      diags.emit(DiagKind::UnclosedTclBlock, range(tok),
                 fmt::format("`{}` block is not enclosed in balanced braces `{{ … }}`", text.substr(start, tok.end - start)));
      stopped = true;
      while (i + 1 < tokens.size() && tokens[i + 1].type != kEof) {
        ++i;
      }
      continue;
    }
    if (type == L::LBRACE) {
      ++brace_depth;
    } else if (type == L::RBRACE && brace_depth > 0) {
      --brace_depth;
    }
    if (type == L::UNEXPECTED_CHAR && brace_depth > 0 && text[start] != '"') {
      // Inside braces any character may belong to a Tcl script (`{if {$n >= 2} …}`); the
      // parser keeps such a value raw and the checker explains it.
      tokens[kept++] = tok;
      continue;
    }
    if (type == L::UNEXPECTED_CHAR) {
      char c = text[start];
      if (c == '"') {
        diags.emit(DiagKind::UnexpectedCharacter, range(tok),
                   "string is not closed: `\"` has no matching `\"` on this line");
      } else if (c == '[') {
        diags.emit(DiagKind::UnexpectedCharacter, range(tok),
                   "`[` is not closed by a matching `]`");
      } else if (c == ';') {
        diags.emit(DiagKind::UnexpectedCharacter, range(tok),
                   "unexpected `;`: NOME statements end with their `end…` keyword")
            .fixit(range(tok), "", "remove `;`");
      } else {
        unsigned char uc = static_cast<unsigned char>(c);
        std::string shown = std::isprint(uc) ? std::string(1, c) : fmt::format("\\x{:02x}", uc);
        diags.emit(DiagKind::UnexpectedCharacter, range(tok),
                   fmt::format("unexpected character `{}`", shown));
      }
      continue;
    }
    if (type == L::NBSP) {
      const SourceRange r = range(tok);
      diags
          .emit(DiagKind::NonBreakingSpace, r,
                "a no-break space (U+00A0) here is read as a space; it is invisible in most editors and other "
                "tools may read it as part of a name or number")
          .fixit(r, std::string((r.end - r.begin) / 2, ' '), "replace with a plain space");
      continue;
    }
    if ((type == L::PLUS || type == L::MINUS) &&
        tok.hidden == false) {
      // U+00A0 is C2 A0 in UTF-8 and separates like a space.
      auto nbsp_at = [&](size_t i) { return i + 1 < text.size() && text[i] == '\xC2' && text[i + 1] == '\xA0'; };
      bool before = start == 0 || std::isspace(static_cast<unsigned char>(text[start - 1])) ||
                    text[start - 1] == '(' || (start >= 2 && nbsp_at(start - 2));
      bool after = start + 1 < text.size() &&
                   !std::isspace(static_cast<unsigned char>(text[start + 1])) && !nbsp_at(start + 1);  // ASCII sign
      if (before && after) {
        tok.type = type == L::PLUS ? L::SPLUS : L::SMINUS;
      }
    }
    if (!tok.hidden) tokens[kept++] = tok;  // whitespace and comments are no use after this pass
  }
  tokens.resize(kept);
  retype_block_instance_names(tokens, text);
  return tokens;
}

AstSizes ast_sizes(const std::vector<Tok>& tokens) {
  size_t stmts = 0, lists = 0, exprs = 0;
  for (const Tok& t : tokens) {
    const size_t type = t.type;
    if (type == L::LPAREN) {
      ++lists;
    } else if (type == L::NUMBER || type == L::IDENT || type == L::DOLLAR_REF || type == L::TCL_ARRAY_REF ||
               type == L::STRING || type == L::PCT_RAW || type == L::BRACKET_RAW || type == L::LBRACE ||
               is_operator(type)) {
      ++exprs;
    } else if (type == L::K_GEN || is_open_type(type)) {
      ++stmts;
    }
  }
  return AstSizes{stmts, lists, exprs - std::min(exprs, stmts)};  // most statements' names are words, not expressions
}

void reserve_ast(const AstSizes& sizes, ast::Ast& out) {
  out.stmts.reserve(sizes.stmts);
  out.lists.reserve(sizes.lists);
  out.exprs.reserve(sizes.exprs);
}

namespace {

// A zero-width token of `type` at byte `at` (a repair the parser reads as written).
Tok conjured_token(size_t type, const Tok& near, size_t at) {
  return Tok{static_cast<uint32_t>(at), static_cast<uint32_t>(at), near.line, static_cast<uint16_t>(type), false};
}

}  // namespace

// NOME3 evaluated function texts with exprtk, which reads a product without its `*` (`5x`,
// `10(x^2+y^2)`, `(u+1)v`, `u v`; generators-original.md §11.2): between a number and a name
// or `(`, a name and a number, `)` and a number or name, and two names. The same pairs
// are never valid otherwise, so a `*` is put between them and the text is read as exprtk
// read it.
void insert_implicit_multiplication(std::vector<Tok>& tokens) {
  auto product_pair = [](size_t a, size_t b) {
    const bool number = a == L::NUMBER, name = a == L::IDENT, close = a == L::RPAREN;
    if (number) return b == L::IDENT || b == L::LPAREN;
    if (name) return b == L::NUMBER || b == L::IDENT;
    if (close) return b == L::NUMBER || b == L::IDENT;
    return false;
  };
  std::vector<Tok> out;
  out.reserve(tokens.size());
  const Tok* last = nullptr;  // the previous default-channel token
  for (Tok& t : tokens) {
    if (t.hidden == false && t.type != kEof) {
      if (last != nullptr && product_pair(last->type, t.type)) {
        out.push_back(conjured_token(L::STAR, t, t.begin));
      }
      last = &t;
    }
    out.push_back(std::move(t));
  }
  tokens = std::move(out);
}

// `point p 0 0 0) endpoint`: a `)` that closes nothing, after a run of values (or of names
// after a statement's own name) on its line, is missing its `(`. One error with the fix-it,
// and a `(` is put before the run so the statement is read as meant.
void insert_missing_open_parens(std::vector<Tok>& tokens, uint32_t base,
                                FileId file, DiagnosticEngine& diags) {
  auto real = [&](size_t i) {
    return tokens[i].hidden == false && tokens[i].type != kEof;
  };
  auto is_value = [](size_t t) {
    return t == L::NUMBER || t == L::DOLLAR_REF || t == L::TCL_ARRAY_REF || is_operator(t);
  };
  std::vector<std::pair<size_t, size_t>> inserts;  // (position in `tokens` to insert before, code point)
  // The open brackets: a `)` inside braces whose `(` is missing there (`{expr a - b) * c}`)
  // is the bracket pass's (recover_brackets), not a list's missing `(`.
  std::vector<uint16_t> open;
  for (size_t i = 0; i < tokens.size(); ++i) {
    if (!real(i)) continue;
    const size_t type = tokens[i].type;
    if (type == L::LPAREN || type == L::LBRACE) open.push_back(static_cast<uint16_t>(type));
    if (type == L::RBRACE) {
      const auto brace = std::find(open.rbegin(), open.rend(), static_cast<uint16_t>(L::LBRACE));
      if (brace != open.rend()) open.erase(std::prev(brace.base()), open.end());
      continue;
    }
    if (type != L::RPAREN) continue;
    if (!open.empty()) {
      if (open.back() == L::LPAREN) open.pop_back();
      continue;
    }
    // Walk back over the values on the `)`'s line (a `{…}` group counts as one value).
    const size_t line = tokens[i].line;
    size_t first = i;
    int braces = 0;
    for (size_t k = i; k-- > 0;) {
      if (!real(k)) continue;
      const Tok& t = tokens[k];
      if (t.line != line && braces == 0) break;
      if (t.type == L::RBRACE) ++braces;
      else if (t.type == L::LBRACE && braces > 0) --braces;
      else if (braces == 0 && !is_value(t.type)) break;
      if (braces == 0) first = k;
    }
    if (first == i) {
      // Names: `face f a b c)`; the run starts after the statement's keyword and name.
      size_t names = i, keyword = i;
      for (size_t k = i; k-- > 0;) {
        if (!real(k)) continue;
        const Tok& t = tokens[k];
        if (t.line != line) break;
        if (is_open_type(t.type)) {
          keyword = k;
          break;
        }
        if (t.type != L::IDENT) break;
        names = k;
      }
      if (keyword == i) continue;
      size_t after_name = keyword + 1;
      while (after_name < i && !real(after_name)) ++after_name;
      ++after_name;  // past the statement's own name
      while (after_name < i && !real(after_name)) ++after_name;
      if (after_name >= i || names > after_name) continue;
      first = after_name;
    }
    const size_t at = tokens[first].begin;
    const uint32_t byte = base + static_cast<uint32_t>(at);
    const uint32_t close_at = base + tokens[i].begin;
    diags
        .emit(DiagKind::SyntaxError, SourceRange{file, close_at, close_at + 1},
              fmt::format("`)` closes nothing here: the list it ends is missing its `(`"))
        .note(SourceRange{file, byte, byte}, "the list would start here")
        .fixit(SourceRange{file, byte, byte}, "(", "insert `(`");
    inserts.emplace_back(first, at);
  }
  if (inserts.empty()) return;
  std::vector<Tok> out;
  out.reserve(tokens.size() + inserts.size());
  size_t next = 0;
  for (size_t i = 0; i < tokens.size(); ++i) {
    while (next < inserts.size() && inserts[next].first == i) {
      out.push_back(conjured_token(L::LPAREN, tokens[i], inserts[next].second));
      ++next;
    }
    out.push_back(std::move(tokens[i]));
  }
  tokens = std::move(out);
}

namespace {

// NOME 2016 read `point`, `face`, `polyline`, `instance`, `funnel` and `tunnel` statements a
// line at a time: the statement ended at its end keyword or at the end of its line, and a
// wrong or misspelt end keyword there went unnoticed (compat.md §B2). So that such a file
// parses as its author saw it, a statement of these kinds that is not closed on its first
// line gets its end at the end of that line, in every dialect: a wrong end keyword
// or a misspelt one (`endinstnace`) that ends the line is taken as its end, and where none
// is there and the statement does not go on to its end keyword on later lines (the next
// line starts another statement, or ends an enclosing one), an end is inserted. The parser
// then reads the rest of the file as it is; the checker warns in `nome` files and reports
// an error in the others (ast::CloseRepair says which repair was made).


// The end token type of a single-line statement opened by `type` (with its text `word`),
// or 0 when the statement is not one of them.
size_t line_statement_end(size_t type, std::string_view word) {
  switch (type) {
    case L::K_POINT: return L::E_POINT;
    case L::K_FACE: return L::E_FACE;
    case L::K_POLYLINE: return L::E_POLYLINE;
    case L::K_INSTANCE: return L::E_INSTANCE;
    case L::K_GEN: return word == "funnel" || word == "tunnel" ? L::E_GEN : 0;
    default: return 0;
  }
}

// The block the statement may contain on later lines (`instance … lookat … endlookat …`),
// or 0.
size_t nested_block(size_t open) {
  return open == L::K_INSTANCE ? L::K_LOOKAT : open == L::K_FACE ? L::K_VERTEX : 0;
}
bool nests_in(size_t open, size_t inner) { return inner != 0 && nested_block(open) == inner; }

// A keyword that is also an option word of these statements (`surface RED`, the 2016
// instance transform `mirror (…)`), so a line it starts may continue the statement.
bool is_option_keyword(size_t type) { return type == L::K_SURFACE || type == L::K_MIRROR; }

}  // namespace

void end_line_statements(std::vector<Tok>& tokens, std::string_view text,
                         LineEndRepairs& repairs) {
  // The default-channel tokens, by position in `tokens` (reserved: a 1 MiB scene has about
  // 300 000, and growing the array by doubling touched twice its size).
  std::vector<uint32_t> real;
  real.reserve(tokens.size());
  for (size_t i = 0; i < tokens.size(); ++i) {
    if (tokens[i].hidden == false && tokens[i].type != kEof) {
      real.push_back(i);
    }
  }
  auto tok = [&](size_t r) -> Tok& { return tokens[real[r]]; };
  auto word = [&](size_t r) {
    const size_t b = tok(r).begin, e = tok(r).end;
    return text.substr(b, e - b);
  };
  auto line = [&](size_t r) { return tok(r).line; };
  auto first_on_line = [&](size_t r) { return r == 0 || line(r - 1) != line(r); };
  struct Insert {
    size_t after;  // position in `tokens` of the token the end follows
    size_t type;
  };
  std::vector<Insert> inserts;
  // Where a statement may start, judged from the tokens before it, never from line breaks
  // (the formatter moves statements onto lines of their own and must not change how they
  // are read): at the start of the text, after an end keyword (or an end inserted here),
  // after a `tclinit` block or an `include "…"`, or first in the body of a block that holds
  // statements (`group g instance …`, `mesh m face …`).
  std::unordered_set<size_t> ended;  // real positions an end was inserted after
  auto holds_statements = [](size_t t) {
    switch (t) {
      case L::K_MESH: case L::K_GROUP: case L::K_DELETE: case L::K_CONSOLIDATE:
      case L::K_CONSOLIDATEFACE: case L::K_SAVEDWORKINGMESH: case L::K_MERGE:
      case L::K_SUBDIVISION: case L::K_OFFSET: case L::K_HANDLE: case L::K_RIND:
      case L::K_SIERPINSKI: case L::K_MENGER: case L::K_MIRROR: case L::K_SWEEP:
        return true;
      default: return false;
    }
  };
  auto may_start = [&](size_t r) {
    if (r == 0) return true;
    const size_t prev = tok(r - 1).type;
    if (is_end_token(prev) || ended.contains(r - 1) || prev == L::TCLINIT || prev == L::STRING ||
        holds_statements(prev)) {
      return true;
    }
    return r >= 2 && holds_statements(tok(r - 2).type) &&
           (prev == L::IDENT || is_open_type(prev) || prev == L::K_GEN);
  };
  // Each statement looks at its own line and then jumps between the places where a scan
  // for its end could stop, so the pass stays linear in the text (a long line of
  // statements, or many unclosed ones, must not make it quadratic).
  const size_t n = real.size();
  // The last token of r's line. `r` only grows, so each line is scanned once.
  size_t line_last_cached = 0;
  bool has_line_last = false;
  auto line_last = [&](size_t r) {
    if (!has_line_last || r > line_last_cached) {
      has_line_last = true;
      line_last_cached = r;
      while (line_last_cached + 1 < n && line(line_last_cached + 1) == line(r)) ++line_last_cached;
    }
    return line_last_cached;
  };
  // The next token, from k on, outside brackets, where a scan for an end may stop: an end
  // keyword, a block nested in an instance or face, or a statement keyword opening a line.
  // Built the first time a statement is not closed on its line (files that write their end
  // keywords never need it). The repairs made before then change tokens only up to the end
  // of the current line, and every later look is past it, so building it late reads the
  // same tokens as building it first.
  std::vector<size_t> next_stop;
  // A misspelt block the statement may contain, first on its line (`vertxe v endvertex` in
  // a face): it nests as the block would.
  auto nested_typo = [&](size_t open, size_t k) {
    return tok(k).type == L::IDENT && first_on_line(k) && is_typo_of(word(k), keyword_literal(nested_block(open)));
  };
  auto build_next_stop = [&] {
    std::vector<int> depth_at(n);  // `(` and `{` open before token k
    for (size_t k = 0, d = 0; k < n; ++k) {
      depth_at[k] = static_cast<int>(d);
      const size_t t = tok(k).type;
      if (t == L::LPAREN || t == L::LBRACE) ++d;
      if ((t == L::RPAREN || t == L::RBRACE) && d > 0) --d;
    }
    next_stop.assign(n + 1, n);
    for (size_t k = n; k-- > 0;) {
      const size_t t = tok(k).type;
      const bool stop = depth_at[k] == 0 &&
                        (is_end_token(t) || t == L::K_LOOKAT || t == L::K_VERTEX ||
                         (t == L::IDENT && (first_on_line(k) || k + 1 == n || line(k + 1) != line(k))) ||
                         (first_on_line(k) && (is_open_type(t) || t == L::K_GEN) && !is_option_keyword(t)));
      next_stop[k] = stop ? k : next_stop[k + 1];
    }
  };
  constexpr size_t kMaxStops = 4096;  // beyond this many nested blocks, leave the statement as written
  size_t depth = 0;  // `(` and `{` open before token r
  for (size_t r = 0; r < n; ++r) {
    const size_t type = tok(r).type;
    const size_t depth_at_r = depth;
    if (type == L::LPAREN || type == L::LBRACE) ++depth;
    if ((type == L::RPAREN || type == L::RBRACE) && depth > 0) --depth;
    const bool at_start = depth_at_r == 0 && may_start(r);
    const size_t end_type = at_start ? line_statement_end(type, word(r)) : 0;
    if (end_type == 0) continue;
    // The rest of its line, at its own bracket depth, up to its end or an enclosing one's.
    const size_t last = line_last(r);
    bool closed = false;
    int d = 0;
    size_t foreign = 0;  // a token on the line that ends an enclosing statement
    int inner_on_line = 0;  // statements nested on the line (`instance … lookat … endlookat …`)
    for (size_t k = r + 1; k <= last; ++k) {
      const size_t t = tok(k).type;
      if (t == L::LPAREN || t == L::LBRACE) ++d;
      if ((t == L::RPAREN || t == L::RBRACE) && d > 0) --d;
      if (d != 0) continue;
      if (nests_in(type, t)) {
        ++inner_on_line;
        continue;
      }
      if (inner_on_line > 0 && is_end_token(t) && t != end_type) {
        --inner_on_line;
        continue;
      }
      if (t == end_type) {
        closed = true;
        // `funnel … endtunnel`: one token type closes every generator; the checker decides.
        if (t == L::E_GEN) {
          const std::optional<ir::GenKind> gen = ir::generator_by_keyword(word(r));
          if (gen && !ir::generator(*gen).closes_with(word(r), word(k))) repairs.replaced.insert(tok(k).begin);
        }
        break;
      }
      if (is_end_token(t)) {
        foreign = k;
        break;
      }
    }
    // Closed on its line, or a bracket left open there (another error, reported as such).
    if (closed || d != 0) continue;
    const std::string expected = ast::end_keyword(word(r));
    if (foreign != 0) {
      // A wrong end keyword of this family that ends the line is this statement's end; any
      // other (`endmesh`) closes an enclosing block, and this statement ends before it.
      const std::string_view w = word(foreign);
      const bool family = w == "endpoint" || w == "endface" || w == "endpolyline" || w == "endinstance" ||
                          tok(foreign).type == L::E_GEN;
      if (family && foreign == last) {
        tok(foreign).type = static_cast<uint16_t>(end_type);
        repairs.replaced.insert(tok(foreign).begin);
      } else {
        inserts.push_back({real[foreign - 1], end_type});
        ended.insert(foreign - 1);
      }
      continue;
    }
    if (last != r && tok(last).type == L::IDENT && is_typo_of(word(last), expected)) {
      tok(last).type = static_cast<uint16_t>(end_type);  // `endinstnace`
      repairs.replaced.insert(tok(last).begin);
      continue;
    }
    // Not closed on its line: does it go on to its end keyword before the next statement?
    bool continues = false;
    size_t inner = 0;
    size_t stops = 0;
    size_t nested_closed = SIZE_MAX;  // the end keyword of its last nested block (`endvertex`)
    size_t stop_at = n;               // where the scan stopped: an enclosing end or the next statement
    const std::string_view nested_end = keyword_literal(end_type_of(nested_block(type)));
    if (next_stop.empty()) build_next_stop();
    for (size_t k = next_stop[last + 1]; k < n; k = next_stop[k + 1]) {
      if (++stops > kMaxStops) {
        continues = true;
        break;
      }
      const size_t t = tok(k).type;
      if (t == end_type && inner == 0) {
        continues = true;
        break;
      }
      if (nests_in(type, t) || nested_typo(type, k)) {  // `face` … `vertex v endvertex` …
        ++inner;
        continue;
      }
      if (t == L::IDENT) {
        // A misspelt end keyword: of its nested block, or its own (the structure pass
        // reports it and reads it as meant).
        if (inner > 0 && is_typo_of(word(k), nested_end)) {
          if (--inner == 0) nested_closed = k;
        } else if (inner == 0 && is_typo_of(word(k), expected)) {
          continues = true;
          break;
        }
        continue;
      }
      if (is_end_token(t)) {
        if (inner == 0) {
          stop_at = k;
          break;
        }
        if (--inner == 0) nested_closed = k;
        continue;
      }
      if (first_on_line(k) && (is_open_type(t) || t == L::K_GEN) && !is_option_keyword(t)) {
        stop_at = k;
        break;
      }
    }
    if (!continues && stop_at == n) repairs.scanned_to_end = true;
    if (!continues) {
      // Its end goes at the end of its line; or, when its later lines are its body (they
      // hold its nested blocks, or are indented deeper than its keyword), after them.
      size_t after = last;
      if (nested_closed != SIZE_MAX) {
        after = nested_closed;
      } else if (stop_at > last + 1 && stop_at - last < 4096) {
        const size_t col = column_of(text, tok(r).begin);
        bool deeper = true;
        for (size_t k = last + 1; k < stop_at && deeper; ++k) {
          if (first_on_line(k)) deeper = column_of(text, tok(k).begin) > col;
        }
        if (deeper) after = stop_at - 1;
      }
      inserts.push_back({real[after], end_type});
      ended.insert(after);
    }
  }
  std::stable_sort(inserts.begin(), inserts.end(), [](const Insert& a, const Insert& b) { return a.after < b.after; });
  if (inserts.empty()) return;
  std::vector<Tok> out;
  out.reserve(tokens.size() + inserts.size());
  size_t next = 0;
  for (size_t i = 0; i < tokens.size(); ++i) {
    out.push_back(std::move(tokens[i]));
    while (next < inserts.size() && inserts[next].after == i) {
      const Tok before = out.back();
      // A zero-width token right after the last token of the line.
      const size_t at = before.end;
      repairs.inserted.insert(static_cast<uint32_t>(at));
      out.push_back(conjured_token(inserts[next].type, before, at));
      ++next;
    }
  }
  tokens = std::move(out);
}


}  // namespace nomec::parse_detail
