// Forgiving NOME scanner for the index (see lex.h).
#include "frontend/index/lex.h"

namespace nomec::index {

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

// End of a `(* … *)` comment starting at `i` (nested; unclosed runs to the end).
size_t block_comment_end(std::string_view t, size_t i) {
  int depth = 0;
  while (i < t.size()) {
    if (t[i] == '(' && i + 1 < t.size() && t[i + 1] == '*') {
      ++depth;
      i += 2;
    } else if (t[i] == '*' && i + 1 < t.size() && t[i + 1] == ')') {
      i += 2;
      if (--depth == 0) return i;
    } else {
      ++i;
    }
  }
  return t.size();
}

// End of a balanced bracket run `[ … ]` or `{ … }` starting at `i`.
size_t balanced_end(std::string_view t, size_t i, char open, char close) {
  int depth = 0;
  while (i < t.size()) {
    char c = t[i];
    if (c == '\\' && open == '{' && i + 1 < t.size()) {
      i += 2;
      continue;
    }
    if (c == open) ++depth;
    if (c == close && --depth == 0) return i + 1;
    ++i;
  }
  return t.size();
}

size_t number_end(std::string_view t, size_t i) {
  while (i < t.size() && is_digit(t[i])) ++i;
  if (i < t.size() && t[i] == '.') {
    ++i;
    while (i < t.size() && is_digit(t[i])) ++i;
  }
  if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
    size_t j = i + 1;
    if (j < t.size() && (t[j] == '+' || t[j] == '-')) ++j;
    if (j < t.size() && is_digit(t[j])) {
      i = j;
      while (i < t.size() && is_digit(t[i])) ++i;
    }
  }
  return i;
}

}  // namespace

std::vector<Token> lex(std::string_view t) {
  std::vector<Token> out;
  out.reserve(t.size() / 4);
  size_t i = 0;
  auto push = [&](Tok k, size_t b, size_t e) { out.push_back({k, static_cast<uint32_t>(b), static_cast<uint32_t>(e)}); };
  while (i < t.size()) {
    char c = t[i];
    if (is_space(c)) {
      ++i;
      continue;
    }
    size_t b = i;
    if (c == '#') {
      while (i < t.size() && t[i] != '\n' && t[i] != '\r') ++i;
      push(Tok::Comment, b, i);
    } else if (c == '(' && i + 1 < t.size() && t[i + 1] == '*') {
      i = block_comment_end(t, i);
      push(Tok::Comment, b, i);
    } else if (c == '"') {
      ++i;
      while (i < t.size() && t[i] != '"' && t[i] != '\n') i += (t[i] == '\\' && i + 1 < t.size()) ? 2 : 1;
      if (i < t.size() && t[i] == '"') ++i;
      push(Tok::String, b, i);
    } else if (c == '[') {
      i = balanced_end(t, i, '[', ']');
      push(Tok::String, b, i);
    } else if (c == '%' && i + 1 < t.size() && t[i + 1] == '{') {
      size_t e = t.find("}%", i + 2);
      i = e == std::string_view::npos ? t.size() : e + 2;
      push(Tok::String, b, i);
    } else if (is_digit(c) || (c == '.' && i + 1 < t.size() && is_digit(t[i + 1]))) {
      i = number_end(t, i);
      push(Tok::Number, b, i);
    } else if (c == '$' && i + 1 < t.size() && is_id_start(t[i + 1])) {
      ++i;
      while (i < t.size() && is_id_part(t[i])) ++i;
      if (i < t.size() && t[i] == '(') {  // `$oSubdivision(type)`
        size_t j = i + 1;
        while (j < t.size() && is_id_part(t[j]) && t[j] != '.') ++j;
        if (j < t.size() && t[j] == ')') i = j + 1;
      }
      push(Tok::Dollar, b, i);
    } else if (is_id_start(c)) {
      while (i < t.size() && is_id_part(t[i])) ++i;
      std::string_view w = t.substr(b, i - b);
      if (w == "tclinit") {
        size_t j = i;
        while (j < t.size() && is_space(t[j])) ++j;
        if (j < t.size() && t[j] == '{') {
          push(Tok::Word, b, i);
          size_t e = balanced_end(t, j, '{', '}');
          push(Tok::String, j, e);
          i = e;
          continue;
        }
      }
      push(Tok::Word, b, i);
    } else if (c == '/' && i + 1 < t.size() && t[i + 1] == '/') {
      i += 2;
      push(Tok::Op, b, i);
    } else if (c == '+' || c == '-' || c == '*' || c == '/' || c == '^' || c == '%') {
      ++i;
      push(Tok::Op, b, i);
    } else if (c == '(') {
      ++i;
      push(Tok::Open, b, i);
    } else if (c == ')') {
      ++i;
      push(Tok::Close, b, i);
    } else if (c == '{') {
      ++i;
      push(Tok::LBrace, b, i);
    } else if (c == '}') {
      ++i;
      push(Tok::RBrace, b, i);
    } else {
      // One UTF-8 sequence or stray byte.
      ++i;
      while (i < t.size() && (static_cast<unsigned char>(t[i]) & 0xC0) == 0x80) ++i;
      push(Tok::Other, b, i);
    }
  }
  return out;
}

}  // namespace nomec::index
