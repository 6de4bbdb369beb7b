// Internal to frontend/parse: parsing one piece of a file on its own, shared by `parse_file`
// (the piece is the whole file) and `ParseCache` (the piece is a run of top-level
// statements). Not part of the public API.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "frontend/ast/ast.h"
#include "frontend/diagnostics/diagnostic.h"
#include "frontend/parse/parse.h"

namespace nomec {

/// Where a piece's diagnostics go, by stage. A whole-file parse emits all comment
/// diagnostics, then all token diagnostics, then all syntax errors; ParseCache keeps that
/// order across pieces by collecting the stages apart.
struct PieceSinks {
  DiagnosticEngine& comments;
  DiagnosticEngine& tokens;
  DiagnosticEngine& syntax;
};

/// What ParseCache needs to know about a piece besides its AST.
struct PieceInfo {
  bool self_contained = false;
  /// The first token can start a top-level statement (or there is none). A piece that does
  /// not start cleanly can only be used at the start of the file.
  bool starts_cleanly = false;
  /// Error expressions the parser could not place (range `{file, 0, 0}` in any parse): they
  /// keep offset 0 wherever the piece lands.
  std::vector<int32_t> unanchored_exprs;
  /// Error recovery gave up (the parser threw): the piece's AST is empty. A piece that gave
  /// up is never self-contained, so it can only be the last of a text; the whole text's
  /// parse then gives up at the same place and keeps no AST either, so the assembled AST
  /// must be empty too (its diagnostics are still every piece's).
  bool gave_up = false;
  /// A limit stopped the token pass (brackets nested too deep, an unclosed `tclinit` or
  /// `tclupdate`: prepare_tokens). The parse of a text whose token pass stopped makes no
  /// repairs anywhere in it (a missing `(`, a single-line statement's end), so the pieces
  /// before a stopped piece, parsed with their repairs, may differ from the same text inside
  /// the whole: a text whose last piece stopped is parsed in one piece. (A stopped piece is
  /// never self-contained, so it can only be the last.)
  bool stopped = false;
};

/// Parses `text` as if it were the whole of `file`: ranges are byte offsets into `text` and
/// string views point into it. When `info` is given, `self_contained` says whether the
/// result is provably what the same text gives inside a longer file when it starts where a
/// top-level statement may start and ends with a newline: no comment is left open, no limit
/// stopped the reading, the lexer looked past the end only for trailing whitespace, and the
/// parser saw the end only at the top level with every token consumed and no error
/// recovery under way (in both the SLL and the LL pass, whichever ran).
/// `reserve_scale`: the AST's arrays are reserved for that many times what the piece
/// needs, for a piece that the rest of a longer text will be appended to (the first of
/// `parse_in_two_pieces`), so that appending does not move them.
ast::Ast parse_piece(std::string_view text, FileId file, const PieceSinks& sinks,
                     PieceInfo* info, double reserve_scale = 1.0);

/// NOME2 (2018) names a top-level instance inside `subdivision`, `offset` and `merge`
/// blocks with `instance X` and no `endinstance`: the word after `X` then continues the
/// block. True for those words (the token pass and the cache's scanner agree on them).
inline bool continues_block_after_instance_name(std::string_view word) {
  return word == "type" || word == "subdivisions" || word == "min" || word == "max" || word == "step" ||
         word == "epsilon" || word == "instance" || word == "endsubdivision" || word == "endoffset" || word == "endmerge";
}

namespace parse_detail {
/// For the differential tests: while set (on this thread), the parse of an error-free text
/// builds each statement's ANTLR parse tree and converts it (the tree-based builder, which
/// a text with syntax errors always uses), instead of building the AST from the parser's
/// events.
void use_tree_builder(bool on);

/// For the differential tests: while cleared (on this thread), a text whose fast parse
/// fails is parsed again with error recovery from its start to its end, instead of only
/// from the top-level statement where the fast parse failed (the statements before it kept
/// as that parse built them) to the first statement after the errors where a recovering
/// parse of the whole text would be clean again. Both give the same AST and diagnostics.
void resume_recovery(bool on);
/// How many parses in this process ran the recovering pass, and how many of them recovered
/// only part of their text (for the tests, which check that their damaged texts reach that
/// path).
struct RecoveryCounts {
  size_t recovering = 0;
  size_t resumed = 0;
};
RecoveryCounts recovery_counts();

/// The parse switches of the tests (`use_reference_lexer`, `use_tree_builder`,
/// `use_remembered_predictions`, `resume_recovery`) that are set on the calling thread; a
/// thread that parses pieces for it sets the same (`apply`), so a parse split over two
/// threads takes the same paths as one on a single thread.
struct ParseSwitches {
  bool reference_lexer = false;
  bool tree_builder = false;
  bool remembered_predictions = true;  // prediction_seed.h
  bool resumed_recovery = true;        // resume_recovery
  static ParseSwitches current();
  void apply() const;
};

/// Whether a parse of `bytes` bytes with `threads` uses two threads.
bool uses_two_threads(ParseThreads threads, size_t bytes);

/// `parse_file` of `text` as two pieces parsed at once on two threads: the text is cut at
/// the first cut point (see ParseCache) after its middle, or the last one before it, and the pieces' ASTs and
/// diagnostics are assembled as ParseCache assembles its runs. Returns nothing (and reports
/// nothing) when the text has no such cut or the pieces do not parse as they would inside
/// the text (the first must be self-contained, the second must start cleanly): the caller
/// then parses it in one piece.
std::optional<ast::Ast> parse_in_two_pieces(std::string_view text, FileId file, DiagnosticEngine& diags);
}  // namespace parse_detail

}  // namespace nomec
