// Checking a new version of a document from the full check of an earlier one, re-checking
// only the top-level statements an edit changed, the statements that read them, and what
// those read (issue 18: the editor's keystroke → diagnostics). Every other statement's
// diagnostics are the earlier check's, moved with the text.
//
// Which statements a statement may read is over-approximated from its words: a word names
// what a statement defines (top-level definitions, banks, instances at any depth) when the
// word or a part of it ending before an `_` or `.` is that name, the ways the checker looks
// names up (`$b0_r`, `fb0_hc0`, `g.box.v1`, 2016 paths that leave out outer instances).
// The check verifies what it assumed afterwards (the names the changed statements define,
// the definitions its uses resolved to, where each diagnostic lies) and gives up, leaving
// the version to a full check, whenever something falls outside; files that read other
// files or Tcl, or whose statements depend on the whole scene, are always checked in full
// (CheckResult::incremental_ok).
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "frontend/check/check.h"

namespace nomec {

class ParseCache;

/// What a full check of one version leaves for checking its next versions incrementally:
/// the text, its top-level statements, what each reported and which statements each may
/// read. Immutable once made, so threads may share it.
class IncrementalBasis;

/// Made from a full check with `record_names` of a file in `sources` (kept: the basis reads
/// its text); `diagnostics` are the engine's as that check left them, in the order they came
/// (before sorting). Null when the file is one that is always checked in full, or a
/// statement reported a problem outside its own text.
std::shared_ptr<const IncrementalBasis> make_incremental_basis(std::shared_ptr<const SourceManager> sources,
                                                               const CheckResult& result,
                                                               std::vector<Diagnostic> diagnostics);

struct IncrementalOutcome {
  bool done = false;     // `diags` holds the new version's diagnostics
  std::string why;       // when not done: why the version needs a full check
  size_t changed = 0;    // top-level statements whose text changed
  size_t rechecked = 0;  // statements whose diagnostics were made anew: the changed ones and their readers
  size_t checked = 0;    // statements checked: those and what they read
  double parse_ms = 0;   // thread CPU time of the parse
};

/// Checks `text`, a new version of the basis's file `path`. When `done`, `diags` holds,
/// once sorted and deduplicated, exactly what `check_source` reports for `text` with the
/// same options (tests/check/incremental_test.cpp compares the two on every corpus file);
/// otherwise its content is meaningless and the version needs a full check. Never throws.
IncrementalOutcome check_incrementally(const IncrementalBasis& basis, SourceManager& sources, const std::string& path,
                                       std::string text, const CheckOptions& options, DiagnosticEngine& diags,
                                       ParseCache* cache);

}  // namespace nomec
