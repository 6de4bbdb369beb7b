// Parse layer: NOME/NOME3/SLIDE text -> AST. The only code that includes ANTLR headers;
// every lexical and syntax problem becomes a nomec diagnostic (never an exception or a
// console print), and the parser recovers so one file reports all its problems.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "frontend/ast/ast.h"
#include "frontend/diagnostics/diagnostic.h"

namespace nomec {

/// Whether a parse may use a second thread. A large text is cut in two at the end of a
/// top-level statement near its middle and the halves are parsed at once, on two threads
/// (`parse_file`; `ParseCache` parses a new document's pieces so); the result is the same
/// as on one thread (the halves are used only when each parses as it does inside the whole
/// text, see piece.h). Automatic: texts of at least `kTwoThreadParseBytes`, on a machine
/// that runs two threads at once.
enum class ParseThreads : uint8_t { Automatic, One, Two };
inline constexpr size_t kTwoThreadParseBytes = 128 * 1024;

/// Parses one file. Always returns an AST (possibly partial); problems go to `diags`.
ast::Ast parse_file(const SourceManager& sources, FileId file, DiagnosticEngine& diags,
                    ParseThreads threads = ParseThreads::Automatic);

/// Parses one file in pieces of about `piece_bytes` each, for a check that lowers each
/// piece and then frees its syntax tree (the command line's `--check` and `--emit`,
/// `CheckOptions::piece_bytes`). Each piece is a run of whole top-level statements with ids
/// of its own; its ranges are the file's and its texts view the file's text. Taken in order,
/// the pieces hold exactly the top-level items, statements, expressions and lists of
/// `parse_file`'s AST (each piece's ids counted from the previous pieces' totals give its
/// ids), and the diagnostics are `parse_file`'s in the same order. The pieces are cut where
/// `ParseCache` cuts and used only when each parses as it does inside the whole text
/// (piece.h); otherwise, and for a text shorter than two pieces, the result is one piece,
/// `parse_file`'s AST. On two threads, each parses every other piece.
/// The pieces' size for the command line's check: large enough that a piece's set-up is a
/// small part of its parse, small enough that two pieces' parser memory is a small part of
/// the peak (bench/frontend/README.md).
inline constexpr size_t kCheckPieceBytes = 64 * 1024;
std::vector<ast::Ast> parse_file_in_pieces(const SourceManager& sources, FileId file, DiagnosticEngine& diags,
                                           size_t piece_bytes, ParseThreads threads = ParseThreads::Automatic);

/// Parses the expression inside a raw `[ … ]` item of `file` (a function surface's
/// `funcX [cos(u)*v]`; `raw` is the item's range in the file) with the grammar's `expr`
/// rule, appending its expressions to `out`; ranges are offsets in the file. A syntax error
/// is reported at its place and gives an error expression. Returns the root expression.
ast::ExprId parse_function_text(std::string_view file_text, FileId file, SourceRange raw, ast::Ast& out,
                                DiagnosticEngine& diags);

/// Incremental parsing for an editor: keeps the pieces of the previous versions of one
/// document and re-parses with ANTLR only the pieces whose text changed. `parse` returns
/// exactly what `parse_file` returns for the same text (the same AST, ids, ranges and
/// diagnostics in the same order).
///
/// How: a cheap scan splits the text at newlines after a top-level block's end keyword
/// (outside comments, strings and brackets). Each piece is parsed on its own, once per
/// distinct text; unchanged pieces are reused wherever they moved. A piece is only used
/// alone when its parse is provably independent of the text around it (see
/// `parse_piece` in piece.h); otherwise it is parsed together with the following pieces,
/// doubling the run until the run is independent or reaches the end of the file. Pieces
/// that neither of the last two versions used are dropped once the cache holds about
/// twice the document's pieces or three times its bytes, so memory stays proportional to
/// the document. Only the text around an edit (found by comparing with the previous version)
/// is scanned for cuts and looked up; the cuts and runs before and after it are reused,
/// shifted. Assembling the result still copies the whole AST. The first version of a large
/// document (no previous version to reuse) has its pieces parsed on two threads
/// (`ParseThreads`), half of the text's bytes each.
class ParseCache {
 public:
  explicit ParseCache(ParseThreads threads = ParseThreads::Automatic);
  ~ParseCache();
  ParseCache(ParseCache&&) noexcept;
  ParseCache& operator=(ParseCache&&) noexcept;

  /// Same contract as `parse_file`.
  ast::Ast parse(const SourceManager& sources, FileId file, DiagnosticEngine& diags);

  /// What the last `parse` did, for benchmarks and tests.
  struct Stats {
    size_t pieces = 0;        // pieces (runs of statements) in the assembled result
    size_t chunks = 0;        // pieces the text was cut into before joining them into runs
    size_t parsed = 0;        // pieces parsed by ANTLR in this call (the rest were reused)
    size_t parsed_bytes = 0;  // bytes given to ANTLR in this call
    size_t scanned_bytes = 0;    // bytes the cut scanner read (only around the edit)
    size_t looked_up_bytes = 0;  // bytes of piece text hashed to find cached pieces
    size_t cached_pieces = 0;    // pieces kept for the next versions after this call
    size_t cached_bytes = 0;     // their text
    int threads = 1;             // threads that parsed pieces (two for a large new document)
  };
  const Stats& last_stats() const;

 private:
  struct Impl;
  struct Steps;
  std::unique_ptr<Impl> impl_;
};

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

/// Lexes `text` with the same lexer as `parse_file`, keeping comments as tokens: the one
/// NOME lexer of the formatter and the editor features (semantic tokens, folding,
/// completion). Never fails, and forgives what an editor buffer often holds: an unclosed
/// `(*` comment or `[` function runs to the end of the text and an unclosed string to the
/// end of its line, as they would once closed. Problems are reported by `parse_file`.
std::vector<LexToken> lex_file(std::string_view text);

inline bool is_comment(LexKind k) { return k == LexKind::LineComment || k == LexKind::BlockComment; }
/// Strings, raw texts (`[ … ]`, `%{ … }%`) and whole `tclinit { … }` blocks.
inline bool is_text_literal(LexKind k) { return k == LexKind::String || k == LexKind::Raw || k == LexKind::TclInit; }
/// The characters of names (grammar/Nome.g4's ID_START and ID_PART).
inline bool is_name_start(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == '.'; }
inline bool is_name_part(char c) { return is_name_start(c) || (c >= '0' && c <= '9'); }

}  // namespace nomec
