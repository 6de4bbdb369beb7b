// The hand-written NOME lexer: one pass over the bytes of a text, producing the token list
// (tokens.h) that ANTLR's generated NomeLexer produces for it, with byte offsets and no
// per-token allocation. grammar/Nome.g4 stays the definition of the tokens; this file
// follows its lexer rules one by one (longest match, the earlier rule on a tie), and
// tests/parse/lexer_diff_test.cpp holds it to NomeLexer on every corpus file, example,
// fuzz seed and generated input. Also: the block-comment blanking both lexers read through.
#include <algorithm>
#include <array>
#include <cstring>
#include <deque>
#include <string>
#include <string_view>

#include "frontend/parse/tokens.h"

#include "frontend/parse/generated.h"
#include "frontend/parse/token_stream.h"

#include <fmt/format.h>

namespace nomec::parse_detail {

std::string_view blank_block_comments(std::string_view text, std::string& storage, FileId file,
                                      DiagnosticEngine& diags, bool& comment_open) {
  comment_open = false;
  if (text.find("(*") == std::string_view::npos) return text;
  storage.assign(text);
  std::string& s = storage;
  size_t depth = 0;
  size_t outer_open = 0;
  const size_t n = s.size();
  for (size_t i = 0; i < n; ++i) {
    const char c = s[i];
    const char next = i + 1 < n ? s[i + 1] : '\0';
    if (depth == 0) {
      if (c == '#') {
        while (i + 1 < n && s[i + 1] != '\n') ++i;
      } else if (c == '"') {
        while (i + 1 < n && s[i + 1] != '"' && s[i + 1] != '\n') ++i;
        ++i;
      } else if (c == '(' && next == '*') {
        depth = 1;
        outer_open = i;
        s[i] = s[i + 1] = ' ';
        ++i;
      }
      continue;
    }
    if (c == '(' && next == '*') {
      ++depth;
      s[i] = s[i + 1] = ' ';
      ++i;
    } else if (c == '*' && next == ')') {
      --depth;
      s[i] = s[i + 1] = ' ';
      ++i;
    } else if (c != '\n') {
      s[i] = ' ';
    }
  }
  if (depth > 0) {
    const auto at = static_cast<uint32_t>(outer_open);
    diags.emit(DiagKind::UnclosedBlockComment, SourceRange{file, at, at + 2},
               "block comment `(*` is never closed by a matching `*)`");
    comment_open = true;
  }
  return s;
}

namespace {

using L = nomec_antlr::NomeLexer;

// Keyword literals of the generated lexer (`'mesh'` -> K_MESH), read from its vocabulary so
// the two lexers cannot disagree on the keyword set.
class Keywords {
 public:
  Keywords() {
    const antlr4::dfa::Vocabulary& vocab = grammar_vocabulary();
    for (size_t type = 1; type <= vocab.getMaxTokenType(); ++type) {
      const std::string lit = vocab.getLiteralName(type);
      if (lit.size() <= 2 || lit.front() != '\'') continue;
      const std::string word = lit.substr(1, lit.size() - 2);
      const bool is_word = std::all_of(word.begin(), word.end(), [](char c) { return c >= 'a' && c <= 'z'; });
      if (!is_word) continue;
      words_.push_back(word);
      max_len_ = std::max(max_len_, word.size());
      min_len_ = std::min(min_len_, word.size());
      insert(words_.back(), static_cast<uint16_t>(type));
    }
  }
  // Every keyword is lower case, so a word that starts otherwise is a name without a lookup.
  uint16_t find(std::string_view w) const {
    if (w.size() < min_len_ || w.size() > max_len_ || w.front() < 'a' || w.front() > 'z') return 0;
    for (size_t i = slot(w);; i = (i + 1) & kMask) {
      const Slot& s = slots_[i];
      if (s.type == 0) return 0;
      if (s.word == w) return s.type;
    }
  }

 private:
  // Open addressing over a fixed table: a handful of bytes of the word decide its slot,
  // which costs less than hashing every byte (the lexer asks once per name in the file).
  static constexpr size_t kSize = 1024, kMask = kSize - 1;
  struct Slot {
    std::string_view word;
    uint16_t type = 0;
  };
  static size_t slot(std::string_view w) {
    const size_t n = w.size();
    const auto b = [&](size_t i) { return static_cast<size_t>(static_cast<unsigned char>(w[i])); };
    return (n * 131 + b(0) * 31 + b(n - 1) * 7 + b(n / 2) * 3 + b((n - 1) / 3)) & kMask;
  }
  void insert(std::string_view w, uint16_t type) {
    size_t i = slot(w);
    while (slots_[i].type != 0) i = (i + 1) & kMask;
    slots_[i] = Slot{w, type};
  }

  std::deque<std::string> words_;
  std::array<Slot, kSize> slots_{};
  size_t min_len_ = SIZE_MAX, max_len_ = 0;
};

const Keywords& keywords() {
  static const Keywords k;
  return k;
}

bool is_digit(unsigned char c) { return c >= '0' && c <= '9'; }
// Byte classes, one table lookup each (the lexer asks about every byte of every name).
constexpr uint8_t kIdStart = 1, kIdPart = 2;
constexpr std::array<uint8_t, 256> kByteClass = [] {
  std::array<uint8_t, 256> c{};
  for (int b = 0; b < 256; ++b) {
    const bool start = (b >= 'a' && b <= 'z') || (b >= 'A' && b <= 'Z') || b == '_' || b == '.';
    c[b] = static_cast<uint8_t>((start ? kIdStart | kIdPart : 0) | (b >= '0' && b <= '9' ? kIdPart : 0));
  }
  return c;
}();
bool is_id_start(unsigned char c) { return (kByteClass[c] & kIdStart) != 0; }
bool is_id_part(unsigned char c) { return (kByteClass[c] & kIdPart) != 0; }
bool is_ws(unsigned char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

// The lexer's state over one text. `at(j)` reads byte j, and notes when a rule looked past
// the end (NomeLexer reads one character past every token, and further while trying a
// longer rule).
class Scanner {
 public:
  Scanner(std::string_view s, Lexed& out) : s_(s), n_(s.size()), out_(out) {}

  bool run();

 private:
  int at(size_t j) {
    if (j >= n_) {
      out_.eof_touch_start = std::min(out_.eof_touch_start, start_);
      return -1;
    }
    return static_cast<unsigned char>(s_[j]);
  }
  // The length of the UTF-8 sequence at j as the input decoder reads it (an invalid byte is
  // one code point), and its code point.
  size_t code_point(size_t j, char32_t& cp) const;
  size_t byte_order_mark(size_t j) const;
  size_t whitespace_end(size_t j, uint32_t& newlines);
  size_t digits(size_t j) {
    while (true) {
      const int c = at(j);
      if (c < 0 || !is_digit(static_cast<unsigned char>(c))) return j;
      ++j;
    }
  }
  size_t id_run(size_t j) {
    while (true) {
      const int c = at(j);
      if (c < 0 || !is_id_part(static_cast<unsigned char>(c))) return j;
      ++j;
    }
  }
  // NUMBER from `start_`, or `start_` when none matches.
  size_t number();
  // `TCL_BRACES` from j (at a `{`): the end past its `}`, or 0 when it is not closed.
  size_t tcl_braces(size_t j);
  size_t ident_or_keyword(uint16_t& type);
  void string();
  void bracket();
  void dollar();
  void percent();
  void word_or_number(unsigned char c);
  bool no_break_spaces();
  // The token [start_, end), which holds `newlines` line breaks: only whitespace, `[…]`,
  // `%{…}%` and `tclinit {…}` may hold any (a string or a comment ends at its line's end),
  // and their rules count them (newlines_in).
  void emit(size_t end, uint16_t type, bool hidden = false, uint32_t newlines = 0) {
    out_.last = Tok{static_cast<uint32_t>(start_), static_cast<uint32_t>(end), line_, type, hidden};
    if (!hidden || type == L::NBSP || !out_.drop_whitespace) out_.tokens.push_back(out_.last);
    if (end == n_) at(end);  // NomeLexer reads past the last token
    line_ += newlines;
    start_ = end;
  }
  uint32_t newlines_in(size_t begin, size_t end) const {
    return static_cast<uint32_t>(std::count(s_.data() + begin, s_.data() + end, '\n'));
  }
  void unexpected() {
    char32_t cp = 0;
    emit(start_ + code_point(start_, cp), L::UNEXPECTED_CHAR);
  }

  std::string_view s_;
  size_t n_;
  Lexed& out_;
  size_t start_ = 0;
  uint32_t line_ = 1;
};

size_t Scanner::code_point(size_t j, char32_t& cp) const {
  const auto b = static_cast<unsigned char>(s_[j]);
  cp = 0xFFFD;
  if (b < 0x80) {
    cp = b;
    return 1;
  }
  const size_t need = (b & 0xE0) == 0xC0 ? 2 : (b & 0xF0) == 0xE0 ? 3 : (b & 0xF8) == 0xF0 ? 4 : 0;
  if (need == 0 || j + need > n_) return 1;
  char32_t v = b & (0x7F >> need);
  for (size_t k = 1; k < need; ++k) {
    const auto c = static_cast<unsigned char>(s_[j + k]);
    if ((c & 0xC0) != 0x80) return 1;
    v = (v << 6) | (c & 0x3F);
  }
  if (v > 0x10FFFF || (v >= 0xD800 && v <= 0xDFFF)) return 1;
  cp = v;
  return need;
}

size_t Scanner::number() {
  size_t j = start_;
  const int c0 = at(j);
  if (c0 >= 0 && is_digit(static_cast<unsigned char>(c0))) {
    j = digits(j);
    if (at(j) == '.') j = digits(j + 1);
  } else if (c0 == '.' && at(j + 1) >= 0 && is_digit(static_cast<unsigned char>(at(j + 1)))) {
    j = digits(j + 1);
  } else {
    return start_;
  }
  const int e = at(j);
  if (e == 'e' || e == 'E') {
    size_t k = j + 1;
    if (at(k) == '+' || at(k) == '-') ++k;
    const int d = at(k);
    if (d >= 0 && is_digit(static_cast<unsigned char>(d))) j = digits(k);
  }
  return j;
}

size_t Scanner::tcl_braces(size_t j) {
  int depth = 0;
  while (true) {
    const int c = at(j);
    if (c < 0) return 0;
    if (c == '\\') {
      if (at(j + 1) < 0) return 0;
      j += 2;  // `'\\' .`: the escaped byte, or the first byte of a code point (the rest are ~[{}\\])
      continue;
    }
    ++j;
    if (c == '{') ++depth;
    if (c == '}' && --depth == 0) return j;
  }
}

size_t Scanner::ident_or_keyword(uint16_t& type) {
  const size_t id_end = id_run(start_ + 1);
  const std::string_view word = s_.substr(start_, id_end - start_);
  type = L::IDENT;
  if (word == "tclinit" || word == "tclupdate") {
    size_t j = id_end;
    while (true) {
      const int c = at(j);
      if (c != ' ' && c != '\t' && c != '\r' && c != '\n') break;
      ++j;
    }
    if (at(j) == '{') {
      if (const size_t end = tcl_braces(j)) {
        type = L::TCLINIT;
        return end;
      }
    }
    return id_end;
  }
  if (const uint16_t kw = keywords().find(word)) type = kw;
  return id_end;
}

// STRING, or an unclosed `"` as UNEXPECTED_CHAR.
void Scanner::string() {
  size_t j = start_ + 1;
  bool closed = false;
  while (true) {
    const int d = at(j);
    if (d < 0 || d == '\r' || d == '\n') break;
    if (d == '"') {
      closed = true;
      ++j;
      break;
    }
    if (d == '\\') {
      if (at(j + 1) < 0) break;
      j += 2;
      continue;
    }
    ++j;
  }
  if (closed) {
    emit(j, L::STRING);
  } else {
    emit(start_ + 1, L::UNEXPECTED_CHAR);
  }
}

// BRACKET_RAW (balanced), or an unclosed `[` as UNEXPECTED_CHAR.
void Scanner::bracket() {
  size_t j = start_;
  int depth = 0;
  size_t end = 0;
  while (true) {
    const int d = at(j);
    if (d < 0) break;
    ++j;
    if (d == '[') ++depth;
    if (d == ']' && --depth == 0) {
      end = j;
      break;
    }
  }
  if (end != 0) {
    emit(end, L::BRACKET_RAW, false, newlines_in(start_, end));
  } else {
    emit(start_ + 1, L::UNEXPECTED_CHAR);
  }
}

// TCL_ARRAY_REF, DOLLAR_REF, or a lone `$` as UNEXPECTED_CHAR.
void Scanner::dollar() {
  const int d = at(start_ + 1);
  if (d < 0 || !is_id_start(static_cast<unsigned char>(d))) {
    emit(start_ + 1, L::UNEXPECTED_CHAR);
    return;
  }
  const size_t id_end = id_run(start_ + 2);
  if (at(id_end) == '(') {
    size_t j = id_end + 1;
    while (true) {
      const int e = at(j);
      if (e < 0 || !(is_id_part(static_cast<unsigned char>(e)) && e != '.')) break;
      ++j;
    }
    if (at(j) == ')') {
      emit(j + 1, L::TCL_ARRAY_REF);
      return;
    }
  }
  emit(id_end, L::DOLLAR_REF);
}

// PCT_RAW (`%{ … }%`), or PERCENT.
void Scanner::percent() {
  if (at(start_ + 1) == '{') {
    const size_t close = s_.find("}%", start_ + 2);
    if (close != std::string_view::npos) {
      emit(close + 2, L::PCT_RAW, false, newlines_in(start_, close + 2));
      return;
    }
    at(n_);  // searched to the end
  }
  emit(start_ + 1, L::PERCENT);
}

// NUMBER, IDENT, a keyword or TCLINIT: the longest match, NUMBER first on a tie (`.5`).
void Scanner::word_or_number(unsigned char c) {
  const size_t num_end = number();
  if (is_digit(c)) {
    emit(num_end, L::NUMBER);
    return;
  }
  uint16_t type = L::IDENT;
  const size_t id_end = ident_or_keyword(type);
  if (num_end > start_ && num_end >= id_end) {
    emit(num_end, L::NUMBER);
  } else {
    emit(id_end, type, false, type == L::TCLINIT ? newlines_in(start_, id_end) : 0);
  }
}

// The length of the code point at `j` when it is U+FEFF, the byte order mark (a zero-width
// no-break space inside a text), else 0. It is whitespace, so a file an editor saved with a
// leading mark reads as it would without.
size_t Scanner::byte_order_mark(size_t j) const {
  char32_t cp = 0;
  const size_t len = code_point(j, cp);
  return cp == 0xFEFF ? len : 0;
}

// The end of a run of whitespace (ASCII spaces, tabs, line ends, form feeds, and U+FEFF)
// that goes on at `j`, counting its line ends into `newlines`. Inlined into `run`: a 1 MiB
// scene has about 200 000 such runs, nearly all ASCII (a byte of 0x80 or more is looked at
// again only where a run ends).
[[gnu::always_inline]] inline size_t Scanner::whitespace_end(size_t j, uint32_t& newlines) {
  while (true) {
    const int d = at(j);
    if (d < 0 || !is_ws(static_cast<unsigned char>(d))) {
      if (d < 0x80) return j;
      const size_t mark = byte_order_mark(j);
      if (mark == 0) return j;
      j += mark;
      continue;
    }
    newlines += d == '\n' ? 1 : 0;
    ++j;
  }
}

// A run of no-break spaces (U+00A0, in any form the input decoder reads as one) as NBSP;
// false when the code point at the start is another one.
bool Scanner::no_break_spaces() {
  char32_t cp = 0;
  const size_t len = code_point(start_, cp);
  if (cp != 0xA0) return false;
  size_t j = start_ + len;
  while (j < n_) {
    char32_t next = 0;
    const size_t l = code_point(j, next);
    if (next != 0xA0) break;
    j += l;
  }
  at(j);
  emit(j, L::NBSP, true);
  return true;
}

bool Scanner::run() {
  out_.tokens.reserve(out_.tokens.size() + n_ / 3);
  if (n_ == 0) at(0);  // NomeLexer looks for a token at the end
  while (start_ < n_) {
    const auto c = static_cast<unsigned char>(s_[start_]);
    switch (c) {
      case ' ': case '\t': case '\r': case '\n': case '\f': case '\v': {
        uint32_t newlines = c == '\n' ? 1 : 0;
        const size_t end = whitespace_end(start_ + 1, newlines);
        emit(end, L::WS, true, newlines);
        continue;
      }
      case '#': {
        size_t j = start_ + 1;
        while (true) {
          const int d = at(j);
          if (d < 0 || d == '\r' || d == '\n') break;
          ++j;
        }
        emit(j, L::LINE_COMMENT, true);
        continue;
      }
      case '(':
        if (at(start_ + 1) == '*') return false;  // a BLOCK_COMMENT left for NomeLexer
        emit(start_ + 1, L::LPAREN);
        continue;
      case ')': emit(start_ + 1, L::RPAREN); continue;
      case '{': emit(start_ + 1, L::LBRACE); continue;
      case '}': emit(start_ + 1, L::RBRACE); continue;
      case ',': emit(start_ + 1, L::COMMA); continue;
      case '+': emit(start_ + 1, L::PLUS); continue;
      case '-': emit(start_ + 1, L::MINUS); continue;
      case '*': emit(start_ + 1, L::STAR); continue;
      case '^': emit(start_ + 1, L::CARET); continue;
      case '/': emit(start_ + (at(start_ + 1) == '/' ? 2 : 1), at(start_ + 1) == '/' ? L::DSLASH : L::SLASH); continue;
      case '%': percent(); continue;
      case '"': string(); continue;
      case '[': bracket(); continue;
      case '$': dollar(); continue;
      default: break;
    }
    if (is_digit(c) || is_id_start(c)) {
      word_or_number(c);
      continue;
    }
    if (c >= 0x80 && no_break_spaces()) continue;
    if (const size_t mark = c >= 0x80 ? byte_order_mark(start_) : 0; mark > 0) {
      uint32_t newlines = 0;
      const size_t end = whitespace_end(start_ + mark, newlines);
      emit(end, L::WS, true, newlines);
      continue;
    }
    unexpected();
  }
  return true;
}

}  // namespace

namespace {

// An overlong UTF-8 form of an ASCII character (`C1 AE` is `n` to the input decoder, which
// accepts overlong forms): NomeLexer reads it as that character.
bool has_overlong_ascii(std::string_view s) {
  for (size_t i = 0; i < s.size(); ++i) {
    // ASCII eight bytes at a time (most texts are all ASCII).
    for (uint64_t w = 0; i + 8 <= s.size(); i += 8) {
      std::memcpy(&w, s.data() + i, 8);
      if ((w & 0x8080808080808080ULL) != 0) break;
    }
    if (i >= s.size()) break;
    const auto b = static_cast<unsigned char>(s[i]);
    if (b < 0xC0) continue;
    if (b == 0xC0 || b == 0xC1) return true;
    const auto next = i + 1 < s.size() ? static_cast<unsigned char>(s[i + 1]) : 0;
    if ((b == 0xE0 && next < 0xA0) || (b == 0xF0 && next < 0x90)) return true;
  }
  return false;
}

}  // namespace

bool lex_fast(std::string_view blanked, Lexed& out) {
  if (has_overlong_ascii(blanked)) return false;  // left to NomeLexer
  Scanner scanner(blanked, out);
  return scanner.run();
}

namespace {

// ANTLR reads code points: decode as the parse layer always has (an invalid byte is one
// U+FFFD), remembering each code point's byte offset.
std::u32string decode(std::string_view text, std::vector<uint32_t>& cp_to_byte) {
  std::u32string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    const auto b = static_cast<unsigned char>(text[i]);
    char32_t cp = 0xFFFD;
    size_t len = 1;
    if (b < 0x80) {
      cp = b;
    } else {
      const size_t need = (b & 0xE0) == 0xC0 ? 2 : (b & 0xF0) == 0xE0 ? 3 : (b & 0xF8) == 0xF0 ? 4 : 0;
      if (need > 0 && i + need <= text.size()) {
        char32_t v = b & (0x7F >> need);
        bool ok = true;
        for (size_t k = 1; k < need; ++k) {
          const auto c = static_cast<unsigned char>(text[i + k]);
          if ((c & 0xC0) != 0x80) {
            ok = false;
            break;
          }
          v = (v << 6) | (c & 0x3F);
        }
        if (ok && v <= 0x10FFFF && !(v >= 0xD800 && v <= 0xDFFF)) {
          cp = v;
          len = need;
        }
      }
    }
    cp_to_byte.push_back(static_cast<uint32_t>(i));
    out.push_back(cp);
    i += len;
  }
  cp_to_byte.push_back(static_cast<uint32_t>(text.size()));
  return out;
}

// The character stream of NomeLexer; records the start of the earliest token whose lexing
// looked at the end of the input.
class WatchedInput : public antlr4::ANTLRInputStream {
 public:
  explicit WatchedInput(std::u32string data) {
    _data = std::move(data);
    p = 0;
  }
  size_t LA(ssize_t i) override {
    const size_t c = antlr4::ANTLRInputStream::LA(i);
    if (c == antlr4::IntStream::EOF && i > 0 && lexer_ != nullptr) {
      eof_touch_start_ = std::min(eof_touch_start_, lexer_->tokenStartCharIndex);
    }
    return c;
  }
  antlr4::Lexer* lexer_ = nullptr;
  size_t eof_touch_start_ = static_cast<size_t>(-1);
};

class SilentListener : public antlr4::BaseErrorListener {};

}  // namespace

void lex_antlr(std::string_view blanked, Lexed& out) {
  std::vector<uint32_t> cp_to_byte;
  WatchedInput input(decode(blanked, cp_to_byte));
  L lexer(&input);
  input.lexer_ = &lexer;
  lexer.removeErrorListeners();
  SilentListener silent;
  lexer.addErrorListener(&silent);
  std::vector<std::unique_ptr<antlr4::Token>> raw = lexer.getAllTokens();
  out.tokens.reserve(raw.size());
  for (const auto& t : raw) {
    out.tokens.push_back(Tok{cp_to_byte[t->getStartIndex()], cp_to_byte[t->getStopIndex() + 1],
                             static_cast<uint32_t>(t->getLine()), static_cast<uint16_t>(t->getType()),
                             t->getChannel() != antlr4::Token::DEFAULT_CHANNEL});
  }
  if (!out.tokens.empty()) out.last = out.tokens.back();
  if (input.eof_touch_start_ != static_cast<size_t>(-1)) {
    out.eof_touch_start = std::min(out.eof_touch_start, static_cast<size_t>(cp_to_byte[input.eof_touch_start_]));
  }
}

namespace {
thread_local bool reference_lexer = false;
}  // namespace

void use_reference_lexer(bool on) { reference_lexer = on; }
bool reference_lexer_in_use() { return reference_lexer; }

Lexed lex_text(std::string_view text, FileId file, DiagnosticEngine& comment_diags, std::string& blanked_storage,
               bool drop_whitespace) {
  Lexed out;
  out.drop_whitespace = drop_whitespace;
  const std::string_view blanked = blank_block_comments(text, blanked_storage, file, comment_diags, out.comment_open);
  if (!reference_lexer && lex_fast(blanked, out)) return out;
  const bool open = out.comment_open;
  out = Lexed{};
  out.comment_open = open;
  lex_antlr(blanked, out);  // keeps every token (rare: see lex_fast)
  return out;
}

Lexed lex_unblanked(std::string_view text) {
  Lexed out;
  if (!reference_lexer && lex_fast(text, out)) return out;
  out = Lexed{};
  lex_antlr(text, out);
  return out;
}

}  // namespace nomec::parse_detail
