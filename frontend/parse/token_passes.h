// Internal to frontend/parse: the passes between the lexer and the parser. They report stray
// characters and unclosed constructs, retype tokens (generator keywords to K_GEN/E_GEN,
// list signs to SPLUS/SMINUS, NOME2's block `instance` names to IDENT) and insert the
// tokens a repair needs (a missing `(`, the end of a single-line statement, the `*` of an
// implicit product in a function text). Offsets are bytes of the text parsed; `base` is
// that text's offset in its file (non-zero for a function text inside a file).
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "frontend/ast/ast.h"
#include "frontend/diagnostics/diagnostic.h"
#include "frontend/parse/tokens.h"

namespace nomec::parse_detail {

/// The block an opening keyword's token type opens, or none (K_GEN opens a generator).
std::optional<ast::BlockKind> open_kind(size_t type);
/// The column of byte `byte` of `text`: the bytes after the newline before it.
size_t column_of(std::string_view text, size_t byte);
/// The end keyword's token type of an opening keyword's (E_GEN for K_GEN), or 0.
size_t end_type_of(size_t open_type);
/// The text of a keyword token type (`mesh`, `endmesh`), or "" (K_GEN, E_GEN, others).
/// Views a table that lives as long as the program.
std::string_view keyword_literal(size_t type);
/// True for an end keyword's token type (E_GEN included).
bool is_end_token(size_t type);
inline bool is_open_type(size_t type) { return open_kind(type).has_value(); }
/// An arithmetic operator or sign token.
bool is_operator(size_t type);

/// Diagnostics for stray characters and unclosed constructs, generator keywords, the
/// list-sign rule and NOME2's block instance names. Returns the tokens the parser should see
/// (default-channel ones only: the passes after this one and the parser skip the others). `stopped` is set when a limit made the pass stop reading; `what`
/// names the text in messages (`file`, or `function` for a function text).
std::vector<Tok> prepare_tokens(std::vector<Tok> tokens, std::string_view text, uint32_t base, FileId file,
                                DiagnosticEngine& diags, bool& stopped, std::string_view what = "file");

/// How many statements, lists and expressions the syntax tree of `tokens` (the parser's
/// tokens, after prepare_tokens) has at most: a statement per opening keyword, a list per
/// `(`, at most an expression per value, name or operator token.
struct AstSizes {
  size_t stmts = 0, lists = 0, exprs = 0;
};
AstSizes ast_sizes(const std::vector<Tok>& tokens);
/// Reserves the arrays of `out` for `sizes`. Grown by doubling instead, a 1 MiB scene's
/// arrays leave behind copies as large as themselves, which the allocator keeps. The
/// parse reserves them once its tokens are freed, so that they can take their place.
void reserve_ast(const AstSizes& sizes, ast::Ast& out);

/// exprtk's implicit products in function texts (`5x`, `(u+1)v`): a `*` between the pairs
/// that are never valid otherwise.
void insert_implicit_multiplication(std::vector<Tok>& tokens);

/// `point p 0 0 0) endpoint`: one error with its fix-it, and the missing `(` inserted.
void insert_missing_open_parens(std::vector<Tok>& tokens, uint32_t base, FileId file, DiagnosticEngine& diags);

/// Where end_line_statements ended a single-line statement: by the start (byte offset in the
/// text) of the end token, those inserted (zero width) and those retyped.
struct LineEndRepairs {
  std::unordered_set<uint32_t> inserted, replaced;
  /// Keywords recover_structure read as another (`faec` as `face`, `endbnak` as `endbank`):
  /// by the token's start, the keyword meant (a view that lives as long as the program).
  std::unordered_map<uint32_t, std::string_view> respelled;
  /// A statement's scan for its end ran to the end of the text: what follows the text could
  /// have changed where it ends (a piece of a file parsed alone is not the same inside it).
  bool scanned_to_end = false;
};

/// NOME 2016's single-line statements (`point`, `face`, `polyline`, `instance`, `funnel`,
/// `tunnel`) end at the end of their line when not closed there (compat.md §B2).
void end_line_statements(std::vector<Tok>& tokens, std::string_view text, LineEndRepairs& repairs);

}  // namespace nomec::parse_detail
