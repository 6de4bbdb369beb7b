// A small, forgiving scanner for the index: splits NOME text into comments, strings, numbers,
// words, `$` references, operators and brackets with byte ranges. It never fails (unclosed
// comments and strings run to the end), so semantic tokens, folding and completion work on
// text that does not parse. Mirrors the token rules of grammar/Nome.g4.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace nomec::index {

enum class Tok : uint8_t {
  Comment,  // `# …` or `(* … *)` (nested)
  String,   // `"…"`, `[…]` raw functions, `%{ … }%`, `tclinit { … }`
  Number,   // `0.5`, `1e-3`
  Word,     // `fun1`, `cf.fun1`, `.inst.v`, `endmesh`
  Dollar,   // `$fp.n`, `$fp_n`, `$oSubdivision(type)`
  Op,       // + - * / // ^ %
  Open,     // (
  Close,    // )
  LBrace,   // {
  RBrace,   // }
  Other,    // , and anything unexpected
};

struct Token {
  Tok kind;
  uint32_t begin;
  uint32_t end;
};

/// Scans `text`; offsets are relative to `text`.
std::vector<Token> lex(std::string_view text);

inline bool is_id_start(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == '.';
}
inline bool is_id_part(char c) { return is_id_start(c) || (c >= '0' && c <= '9'); }

}  // namespace nomec::index
