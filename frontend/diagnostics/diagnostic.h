// Diagnostics model: every kind registered once in kinds.def with a code and severity;
// a record carries a primary range, a message, notes with their own ranges and fix-its.
// Stages emit into a DiagnosticEngine; consumers (console text, JSON, LSP) read from it.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "frontend/source/source_manager.h"

namespace nomec {

enum class Severity : uint8_t { Note, Warning, Error };

/// Every diagnostic kind, e.g. `DiagKind::UnknownName` for `instance i nosuchmesh endinstance`.
enum class DiagKind : uint16_t {
#define NOMEC_DIAG(Name, Sev, Summary) Name,
#include "frontend/diagnostics/kinds.def"
};

/// Number of kinds in kinds.def.
inline constexpr int kDiagKindCount = 0
#define NOMEC_DIAG(Name, Sev, Summary) +1
#include "frontend/diagnostics/kinds.def"
    ;

std::string_view diag_kind_name(DiagKind kind);
Severity diag_kind_severity(DiagKind kind);
std::string_view diag_kind_summary(DiagKind kind);
std::string_view severity_name(Severity severity);

/// A secondary location explaining a diagnostic, e.g. "previous definition is here".
struct DiagNote {
  SourceRange range;  // may be invalid for a note without a location
  std::string message;
};

/// A suggested edit: replace `range` with `replacement` (empty = delete).
struct FixIt {
  SourceRange range;
  std::string replacement;
  std::string description;  // e.g. "replace with `radius`"
};

struct Diagnostic {
  DiagKind kind;
  Severity severity;
  SourceRange range;
  std::string message;
  std::vector<DiagNote> notes;
  std::vector<FixIt> fixits;
};

/// Collects diagnostics from every stage. Stages never throw; they emit and recover.
class DiagnosticEngine {
 public:
  /// Fluent handle returned by `emit`, e.g.
  /// `diags.emit(DiagKind::UnknownName, range, msg).note(def, "…").fixit(range, "radius");`
  class Builder {
   public:
    explicit Builder(Diagnostic* diag) : diag_(diag) {}
    Builder& note(SourceRange range, std::string message);
    Builder& fixit(SourceRange range, std::string replacement, std::string description);

   private:
    Diagnostic* diag_;
  };

  Builder emit(DiagKind kind, SourceRange range, std::string message);

  const std::vector<Diagnostic>& diagnostics() const { return diags_; }
  /// Sorts by file and position and removes exact duplicates (same kind, range, message).
  void sort_and_dedupe();
  int error_count() const;
  int warning_count() const;
  /// Moves every diagnostic of `other` into this engine.
  void append(DiagnosticEngine&& other);
  /// Adds a diagnostic made elsewhere (e.g. kept from an earlier check).
  void push(Diagnostic d) { diags_.push_back(std::move(d)); }
  /// Moves every diagnostic out, in the order they came, leaving the engine empty.
  std::vector<Diagnostic> take() { return std::exchange(diags_, {}); }
  /// Moves every diagnostic of `other` into this engine, both in position order (by start
  /// offset; this engine's first on ties), keeping that order.
  void merge_in_order(DiagnosticEngine&& other);
  /// Orders the diagnostics by start offset, keeping the order of those that start together.
  void sort_by_position();

 private:
  std::vector<Diagnostic> diags_;
};

/// Clang-style text: `file:line:col: error: message [Code]`, the source line, a caret
/// and underline, then notes and fix-it hints. `werror` prints warnings as errors.
std::string render_text(const SourceManager& sources, const Diagnostic& diag, bool werror,
                        bool color);

/// Finds the closest candidate to `name` by edit distance, or "" if none is close enough
/// to be a plausible misspelling.
std::string closest_match(std::string_view name, const std::vector<std::string>& candidates);
std::string closest_match(std::string_view name, std::span<const std::string_view> candidates);

/// The distance of a typo (optimal string alignment: an insertion, deletion, substitution or
/// swap of two neighbours is one edit), letters compared without case; above `bound` as soon
/// as it is sure to be.
size_t typo_distance(std::string_view a, std::string_view b, size_t bound);

/// Whether `word` is close enough to `keyword` to be read as it where the keyword is
/// expected: one edit for keywords of four letters or fewer, two for longer ones, or a
/// difference of case only.
bool is_typo_of(std::string_view word, std::string_view keyword);

}  // namespace nomec
