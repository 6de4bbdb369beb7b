// Language index: the protocol-free knowledge an editor needs about one checked scene —
// symbols (banks, parameters, points, meshes, instances, generators, …), every definition
// and use of them with exact ranges, outline, completion, signature help, semantic tokens,
// folding ranges, rename and hover text. Built in one linear pass from the checker's result
// (its IR, its syntax trees and the name resolutions it recorded); the language server in
// lsp/ turns these answers into LSP messages. Offsets are byte offsets in a FileId.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "frontend/check/check.h"
#include "frontend/diagnostics/diagnostic.h"
#include "frontend/source/source_manager.h"
#include "ir/ir.h"

namespace nomec::index {

enum class SymbolKind : uint8_t {
  Bank, Parameter, Point, Polyline, Face, Mesh, Object, Group, Instance, Generator, Surface,
  Block, Other
};
std::string_view symbol_kind_name(SymbolKind kind);

using SymbolId = int32_t;

/// A named definition, e.g. the slider `n` of bank `fp` (name `n`, detail `fp.n = 8`).
struct Symbol {
  SymbolId id = -1;
  std::string name;    // as written at the definition, e.g. `fun1`
  std::string detail;  // one line for outlines, e.g. `funnel (n ro ratio h)` or `instance of cf`
  SymbolKind kind = SymbolKind::Other;
  SourceRange name_range;  // the defining word
  SourceRange full_range;  // the whole statement (`set` line for a parameter)
  SymbolId parent = -1;    // enclosing bank / mesh / group / block, -1 at the top level
  ir::NodeId node;         // the IR node, if the symbol has one
};

/// A definition or a use of a symbol. Uses inside `$bank.param` and 2016 `_`-joined vertex
/// names cover only their part: in `$fp.n`, `fp` is a use of the bank and `n` of the slider.
struct Occurrence {
  SourceRange range;
  SymbolId symbol = -1;
  bool is_definition = false;
};

struct CompletionItem {
  std::string label;
  SymbolKind kind = SymbolKind::Other;
  bool is_keyword = false;
  std::string detail;
  std::string insert_text;  // text that replaces the word being typed (may be a snippet-free template)
};

struct SignatureHelp {
  std::string label;                                        // e.g. `funnel NAME (n ro ratio h)`
  std::vector<std::pair<uint32_t, uint32_t>> parameters;    // [begin, end) byte offsets inside label
  std::vector<std::string> parameter_docs;
  int active_parameter = 0;
};

enum class TokenType : uint8_t { Keyword, Number, Parameter, Function, Name, Comment, String, Operator };

struct SemanticToken {
  SourceRange range;
  TokenType type = TokenType::Name;
  bool is_definition = false;
};

struct FoldingRange {
  SourceRange range;
  bool is_comment = false;
};

struct TextEdit {
  SourceRange range;
  std::string new_text;
};

struct Hover {
  std::string markdown;
  SourceRange range;
  SymbolId symbol = -1;
};

struct Analysis;
struct Checked;

class Index {
 public:
  const std::vector<Symbol>& symbols() const { return symbols_; }
  /// The definition or use under the cursor (`offset` may sit just after the word).
  std::optional<Occurrence> occurrence_at(FileId file, uint32_t offset) const;
  /// Every occurrence of `s` in source order (by file, then offset).
  std::vector<Occurrence> references(SymbolId s, bool include_declaration) const;
  /// Top-level symbols of `file` in source order; their children via Symbol::parent.
  std::vector<SymbolId> outline(FileId file) const;
  /// Keywords valid here, names in scope, `$bank.param`, generator names. Works on
  /// incomplete text: it reads the token before the cursor, not only the syntax tree.
  std::vector<CompletionItem> complete(FileId file, uint32_t offset) const;
  /// Inside a generator's or a statement's argument list: its signature.
  std::optional<SignatureHelp> signature_help(FileId file, uint32_t offset) const;
  /// Source order, non-overlapping.
  std::vector<SemanticToken> semantic_tokens(FileId file) const;
  /// Blocks spanning several lines (mesh…endmesh, group, bank, …) and multi-line `(* *)` comments.
  std::vector<FoldingRange> folding_ranges(FileId file) const;
  std::optional<SourceRange> prepare_rename(FileId file, uint32_t offset) const;
  /// Edits renaming the symbol under the cursor everywhere, or a message saying why not.
  std::variant<std::vector<TextEdit>, std::string> rename(FileId file, uint32_t offset,
                                                          std::string_view new_name) const;
  std::optional<Hover> hover(FileId file, uint32_t offset) const;

  /// The symbol of an IR node, or -1.
  SymbolId symbol_of(ir::NodeId node) const;
  const SourceManager& sources() const { return *sources_; }
  const CheckResult& check() const { return *check_; }

 private:
  friend class Builder;
  friend std::shared_ptr<const Index> build(std::shared_ptr<const SourceManager>, std::shared_ptr<const CheckResult>,
                                            std::optional<CheckOptions>);
  friend std::shared_ptr<const Index> build(const Checked&);
  SymbolId symbol_at(FileId file, uint32_t offset, SourceRange* range) const;
  std::string hover_symbol(const Symbol& s) const;
  std::string rename_problem(const Symbol& s, std::string_view new_name) const;

  std::shared_ptr<const SourceManager> sources_;
  std::shared_ptr<const CheckResult> check_;
  std::optional<CheckOptions> options_;  // set by `analyze`: lets rename re-check its edits
  std::string main_path_;
  int error_count_ = -1;                 // errors of the check, -1 if unknown (rename's re-check)
  std::vector<Symbol> symbols_;
  std::vector<Occurrence> occurrences_;  // sorted by (file, begin), non-overlapping
  std::vector<uint32_t> ref_begin_;      // CSR: occurrences of symbol s are
  std::vector<uint32_t> ref_items_;      //   occurrences_[ref_items_[ref_begin_[s] .. ref_begin_[s+1])]
  std::vector<SymbolId> node_symbol_;    // by ir::NodeId index
};

/// Builds the index of a checked scene. `check` must come from `check_source` with
/// `CheckOptions::record_names` set (otherwise only definitions are known). Pass the options
/// the scene was checked with as `recheck` to let `rename` verify its edits by re-checking.
/// The index keeps both pointers alive; an owner holding both by value can hand out
/// aliasing pointers, e.g. `std::shared_ptr<const SourceManager>(owner, &owner->sources)`.
std::shared_ptr<const Index> build(std::shared_ptr<const SourceManager> sources,
                                   std::shared_ptr<const CheckResult> check,
                                   std::optional<CheckOptions> recheck = std::nullopt);

/// One analysis of a document: its own SourceManager (the file and everything it includes),
/// the check result, and the index over both. Everything is immutable and can be shared
/// between threads.
struct Analysis {
  std::shared_ptr<const SourceManager> sources;
  FileId file;
  std::shared_ptr<const CheckResult> check;
  std::shared_ptr<const Index> index;
};

/// The check half of `analyze`: the file parsed and checked with name resolutions recorded,
/// and what `build(const Checked&)` needs to index it later. The language server publishes
/// diagnostics from this and builds the index afterwards, off the keystroke's path.
struct Checked {
  std::shared_ptr<const SourceManager> sources;
  FileId file;
  std::shared_ptr<const CheckResult> check;
  CheckOptions options;  // as checked; lets rename re-check its edits
  std::string path;
  int error_count = 0;  // errors the check reported
};

/// Parses and checks `path` with text `text` (through `cache` if not null, see below).
/// Diagnostics go to `diags`. Never throws.
Checked check_document(const std::string& path, std::string text, CheckOptions options,
                       DiagnosticEngine& diags, ParseCache* cache);

/// The index of a checked document; `analyze` is `check_document` followed by this.
std::shared_ptr<const Index> build(const Checked& checked);

/// Parses, checks (recording name resolutions) and indexes the file `path` with text `text`.
/// Diagnostics go to `diags`. Never throws.
Analysis analyze(const std::string& path, std::string text, CheckOptions options,
                 DiagnosticEngine& diags);

/// The same for an editor re-analysing one document after each change: the main file is
/// parsed through `cache` (one per document, kept between calls; see ParseCache), so only
/// its changed statements are re-parsed. Equal to the overload above; `cache` may be null.
Analysis analyze(const std::string& path, std::string text, CheckOptions options,
                 DiagnosticEngine& diags, ParseCache* cache);

}  // namespace nomec::index
