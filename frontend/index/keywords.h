// Keyword knowledge for the index: which words are keywords (block open/close keywords,
// `set`, `list`, `include`, option words), a one-line description of each for hover and
// completion, and the built-in functions of expressions.
#pragma once

#include <string_view>
#include <vector>

#include "frontend/ast/ast.h"

namespace nomec::index {

/// A short description of a keyword, e.g. `mesh` → "a mesh built from points and faces: …".
/// Empty if `word` is not a keyword.
std::string_view keyword_doc(std::string_view word);
/// True for block keywords, end keywords, `set`, `list`, `include`, `expr`, `tclinit` and
/// every option word of any block (`translate`, `surface`, `sd_level`, …).
bool is_keyword(std::string_view word);
/// The block kind opened by `word`, if it is an opening keyword.
bool block_by_open(std::string_view word, ast::BlockKind* kind);
/// The block kind closed by `word`, if it is an end keyword.
bool block_by_close(std::string_view word, ast::BlockKind* kind);
/// True when end keyword `close` closes a statement opened by `open` (`endfunnel` closes
/// `funnel`, and 2016's `tunnel`).
bool closes(std::string_view open, std::string_view close);
/// Statement keywords that may appear inside a block of `parent` (e.g. `point`, `face`,
/// `sharp` in a mesh), in a sensible order.
std::vector<ast::BlockKind> child_blocks(ast::BlockKind parent);
/// Built-in expression functions, e.g. `sin`, with a one-line description.
struct FunctionDoc {
  std::string_view name, signature, doc;
};
const std::vector<FunctionDoc>& functions();

}  // namespace nomec::index
