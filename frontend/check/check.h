// Checker: resolves names, checks every statement's shape, arity and kinds, evaluates
// expressions and parameters, and lowers the checked AST into the typed IR with its
// dependency graph. Continues after errors so one run reports every problem.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "base/folder_listing.h"
#include "base/input_limits.h"
#include "frontend/ast/ast.h"
#include "frontend/diagnostics/diagnostic.h"
#include "ir/dialect.h"
#include "ir/ir.h"

namespace nomec {

/// Reads an input file (the main file, `include`d files, `.anom` base files). Returns
/// nullopt when the file cannot be read.
using FileReader = std::function<std::optional<std::string>(const std::string& path)>;

/// Why a `FileReader` read nothing for `path`, lowercase without the path ("it is a named
/// pipe (FIFO), not a regular file"), or "" when it cannot say.
using ReadProblem = std::function<std::string(const std::string& path)>;

/// Lists a folder (its name and file names), to find the base scene of saved work next to
/// it. May be empty: then only `CheckOptions::base_file` names one.
using FolderLister = std::function<std::optional<FolderListing>(const std::string& dir)>;

struct CheckOptions {
  std::optional<Dialect> dialect;                          // --dialect
  std::vector<std::pair<std::string, double>> overrides;  // -D bank.param=value
  bool allow_out_of_range = false;                         // --allow-out-of-range
  std::optional<std::string> base_file;                    // --base for `.anom` files
  bool sif_quads = false;  // --sif-quads: `.sif` triangle pairs read as quads (frontend/flat)
  double time = 0;                                         // --time: value of `$time`
  double frame = 0;                                        // --frame: value of `$frame`
  int tcl_milliseconds = 10000;  // --tcl-seconds: wall time of a SLIDE file's Tcl in all (its blocks and values)
  int tcl_move_milliseconds = 2000;  // wall time of a SLIDE file's Tcl per slider move, once checked
  /// false (`--no-tcl`): a SLIDE file's Tcl is not run at all: one `TclUnavailable` error
  /// says so, and the values only Tcl computes are errors without more messages.
  bool run_tcl = true;
  FileReader read_file;                                    // may be empty: no includes
  /// Reads a file by its name relative to a folder without leaving the folder (no `..`, no
  /// link out of it): what SLIDE's Tcl `source`s and imports next to the scene. May be
  /// empty: then `read_file(folder + name)` (tests and fuzzers that read from memory).
  std::function<std::optional<std::string>(const std::string& folder, const std::string& name)> read_beneath;
  ReadProblem read_problem;                                // may be empty: no reasons given
  /// The most bytes one check reads (`--max-file-size`): the main file's text, every file
  /// it includes (each time it is included, so a file that includes itself spends it) and
  /// its base scene, together. Includes also stop at kMaxIncludeDepth levels and
  /// kMaxIncludes files; the `include` that crosses a limit is one `IncludeLimit` error and
  /// later ones are skipped.
  int64_t max_input_bytes = kDefaultMaxFileBytes;
  /// The same for flat mesh files (`.stl`, `.obj`, `.sif`; `--max-mesh-size`): the mesh
  /// files the check reads (the main file, includes, a base scene) count against this.
  int64_t max_mesh_bytes = kDefaultMaxMeshFileBytes;
  FolderLister list_folder;                                // may be empty: no base search
  /// May be empty; called once the file's text is parsed (a flat mesh file's: before it is
  /// read), before its check begins (the language server then starts work that must not
  /// share the cores with that parse).
  std::function<void()> parsed;
  bool record_names = false;  // fill CheckResult::name_uses and ::asts (for frontend/index)
  /// When non-zero (the command line's `--check` and `--emit`): the main file is parsed in
  /// pieces of about this many bytes (`parse_file_in_pieces`), and each piece's syntax tree
  /// is freed, and the free memory given back to the system, once its statements are
  /// checked, so the trees and the IR are not both whole at once. Ignored where the tree is
  /// kept or read whole: with `record_names` or a parse cache, for saved work and SLIDE.
  /// The result and diagnostics are the same as without.
  size_t piece_bytes = 0;
  /// May be empty; asked between statements: when it returns true the check stops early
  /// and its result says `cancelled` (an editor's check of a version already replaced).
  std::function<bool()> cancelled;
  bool is_cancelled() const { return cancelled && cancelled(); }
};

/// A name a definition makes (see CheckResult::declared_names).
struct DeclaredName {
  std::string name;
  SourceRange range;  // where the name is written
  bool top_scope = false;  // in the file's own scope, where a second one is a duplicate
  bool while_checking = false;  // made while checking statements (`consolidate`), not declared before
};

/// A resolved name: the word at `use` refers to the IR node `def` (recorded for the index).
struct NameUse {
  SourceRange use;
  ir::NodeId def;
};

struct CheckResult {
  ir::Module module;
  Dialect dialect = Dialect::Nome;
  std::string dialect_reason;  // why this dialect was chosen (for --verbose)
  std::string base_file;       // `.anom`: the base scene used, if any
  // Only with CheckOptions::record_names: every name the checker resolved to a definition,
  // and the syntax trees of every file read (main file first, then base scene, includes).
  std::vector<NameUse> name_uses;
  std::vector<std::shared_ptr<const ast::Ast>> asts;
  /// Milliseconds of the calling thread's CPU time spent parsing the main file (the rest of
  /// the call is checking); for the editor's benchmark.
  double parse_ms = 0;
  /// CheckOptions::cancelled stopped the check: the rest of the result is incomplete.
  bool cancelled = false;
  // Only with CheckOptions::record_names, for the editor's incremental checks
  // (frontend/check/incremental.h):
  /// Every name a definition of the main file makes that another statement may look up:
  /// top-level definitions, banks, and instances at any depth.
  std::vector<DeclaredName> declared_names;
  /// Where the diagnostics of checking the statements begin in the engine (before: the
  /// parse's and those of dialect, banks and declarations, which read the whole file).
  size_t first_statement_diagnostic = 0;
  /// For each checked top-level item of the main file (`ast::Ast::top`), its index and the
  /// number of diagnostics in the engine once it was checked.
  std::vector<std::pair<int32_t, uint32_t>> item_marks;
  /// Each diagnostic from there on lies within one top-level statement of the main file, and
  /// the file has none of what an incremental check leaves to a full one (includes, Tcl, a
  /// base scene, NOME2's scene merges): see incremental.h.
  bool incremental_ok = false;
};

/// The calling thread's CPU time in milliseconds (for phase timings that a loaded machine
/// does not inflate).
double thread_cpu_ms();

/// The generator of the catalogue a statement is, if it is one (`funnel`, `bsplinecurve` …).
std::optional<ir::GenKind> statement_generator(const ast::Stmt& s);

/// The option words the statement this keyword opens accepts, e.g. `translate`, `rotate`,
/// `surface` for `instance` (for completion and highlighting in frontend/index).
std::vector<std::string_view> option_words(std::string_view keyword);

/// Parses and checks the file `path` whose text is `text`. Never throws.
CheckResult check_source(SourceManager& sources, const std::string& path, std::string text,
                         const CheckOptions& options, DiagnosticEngine& diags);

class ParseCache;  // frontend/parse/parse.h

/// The same, for an editor that re-checks one document after every change: the main file
/// is parsed through `cache` (one per document, kept between calls), so only the changed
/// statements are re-parsed. The result and diagnostics equal the overload above; `cache`
/// may be null.
CheckResult check_source(SourceManager& sources, const std::string& path, std::string text,
                         const CheckOptions& options, DiagnosticEngine& diags,
                         ParseCache* cache);

}  // namespace nomec
