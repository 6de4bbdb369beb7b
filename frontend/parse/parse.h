// Parse layer: NOME/NOME3/SLIDE text -> AST. The only code that includes ANTLR headers;
// every lexical and syntax problem becomes a nomec diagnostic (never an exception or a
// console print), and the parser recovers so one file reports all its problems.
#pragma once

#include "frontend/ast/ast.h"
#include "frontend/diagnostics/diagnostic.h"

namespace nomec {

/// Parses one file. Always returns an AST (possibly partial); problems go to `diags`.
ast::Ast parse_file(const SourceManager& sources, FileId file, DiagnosticEngine& diags);

}  // namespace nomec

namespace nomec {

/// Token classes of `lex_file`, for tools that work on the text itself (the formatter).
enum class LexKind : uint8_t {
  Word,          // identifiers and keywords: `mesh`, `endmesh`, `fp.n`
  Number,        // `0.5`, `1e-3`
  DollarRef,     // `$fp.n`, `$oSubdivision(type)`
  String,        // `"viewing.slf"`
  Raw,           // `[ … ]`, `%{ … }%`
  TclInit,       // a whole `tclinit { … }`
  LParen, RParen, LBrace, RBrace, Comma,
  Operator,      // `+ - * / // % ^`
  LineComment,   // `# …` (up to, not including, the line break)
  BlockComment,  // a whole nested `(* … *)`
  Other,         // a character the grammar does not know
};

/// One token with its byte range in the text. Whitespace is not a token; comments are.
struct LexToken {
  LexKind kind = LexKind::Other;
  uint32_t begin = 0;
  uint32_t end = 0;
};

/// Lexes `text` with the same lexer as `parse_file`, keeping comments as tokens. Never
/// fails: problems are reported by `parse_file`, not here.
std::vector<LexToken> lex_file(std::string_view text);

}  // namespace nomec
