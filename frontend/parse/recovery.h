// Internal to frontend/parse: recovery of a file's block structure before it is parsed, so
// that one typo is one error. The pass reads the tokens as the grammar nests its blocks
// (`keyword … endkeyword`, each block holding the blocks grammar/Nome.g4 lets it hold) and,
// where they do not nest, finds the one change that makes them nest, reports it once with
// its fix-it and makes it in the tokens, so the parser reads the rest as written:
//  * a word close to the keyword the structure needs (`faec … endface`, `endbnak` in a
//    bank) is read as that keyword;
//  * a block whose end keyword is missing is closed where the next statement starts;
//  * an end keyword that closes nothing is dropped, one that closes the wrong block is read
//    as the right one;
//  * an unclosed `(` or `{` is closed before the end keyword (or statement) that shows it.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "frontend/diagnostics/diagnostic.h"
#include "frontend/parse/token_passes.h"
#include "frontend/parse/tokens.h"

namespace nomec::parse_detail {

/// What the structure pass saw that ties a text's parse to what is around it (a piece of a
/// file parsed alone equals the same text inside the file only when this is all false).
struct StructureOutcome {
  /// A block or bracket was still open at the end, a decision looked at the end of the
  /// text, or a top-level word that a later end keyword could make a keyword was left.
  bool depends_on_what_follows = false;
};

/// The structure pass over the parser's tokens (after prepare_tokens and the line-end
/// repairs): reports each repair into `diags`, in the order the pass met them (ranges are
/// `base` + byte offsets), and makes it in `tokens`; keywords read as others are recorded
/// in `repairs.respelled`.
void recover_structure(std::vector<Tok>& tokens, std::string_view text, uint32_t base, FileId file,
                       DiagnosticEngine& diags, LineEndRepairs& repairs, StructureOutcome& outcome);

/// The bracket pass, before the line-end repairs (which read the brackets): an unclosed `(`
/// or `{` is closed where it ends, a `)` or `}` that closes nothing gets its opening or is
/// dropped, and a misspelt `expr` first in braces is read as `expr`; one error each.
void recover_brackets(std::vector<Tok>& tokens, std::string_view text, uint32_t base, FileId file,
                      DiagnosticEngine& diags, LineEndRepairs& repairs, StructureOutcome& outcome);

/// Whether the grammar lets a block opened by token type `parent` (0: the file's top level)
/// hold a block opened by `child` (TCLINIT only at the top level).
bool block_holds(size_t parent, size_t child);

}  // namespace nomec::parse_detail
