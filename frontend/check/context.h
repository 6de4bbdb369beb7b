// The checker's context: the state one check of a scene shares between its concerns (the
// module being written, the diagnostics, the dialect, the scopes of names and parameters,
// where each statement's node is) and the small services every concern uses (creating
// nodes and operands, reading a statement's name, common messages). The concerns themselves
// are free functions in their own files (handlers.h lists them), in the manner of Carbon's
// check::Context and Handle* functions.
#pragma once

#include <algorithm>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "frontend/ast/ast.h"
#include "frontend/check/check.h"
#include "frontend/check/tcl_live.h"
#include "frontend/diagnostics/diagnostic.h"
#include "frontend/tcl/interp.h"
#include "ir/ir.h"

namespace nomec::check {

using ast::BlockKind;
using ast::ItemKind;

// Namespaces. NOME files share one namespace for shapes; SLIDE keeps surfaces, points and
// faces apart from shapes (`surface Y` and `point Y` coexist in real SLIDE files), and we do
// the same for every dialect because no valid NOME file depends on the difference.
enum class Ns : uint8_t { Surface, Point, Face, Shape, Scene, Count };

/// Tables keyed by names: looked up with a `std::string_view` into the source text without
/// making a `std::string` for each lookup (most of a check's lookups).
struct NameHash {
  using is_transparent = void;
  /// Names are short (`v0`, `b0_r`, `fb0_hc0`): hashed inline, eight bytes at a step, rather
  /// than by a call into the library's byte hash for each of a check's lookups.
  size_t operator()(std::string_view s) const {
    uint64_t h = (s.size() + 1) * 0x9E3779B97F4A7C15ull;
    const char* p = s.data();
    size_t n = s.size();
    for (; n >= 8; p += 8, n -= 8) {
      uint64_t w;
      std::memcpy(&w, p, 8);
      h = (h ^ w) * 0xBF58476D1CE4E5B9ull;
      h ^= h >> 31;
    }
    if (n > 0) {
      uint64_t w = 0;
      for (size_t i = 0; i < n; ++i) w |= static_cast<uint64_t>(static_cast<unsigned char>(p[i])) << (8 * i);
      h = (h ^ w) * 0x94D049BB133111EBull;
      h ^= h >> 29;
    }
    return static_cast<size_t>(h ^ (h >> 32));
  }
};
template <typename V>
using NameTable = std::unordered_map<std::string, V, NameHash, std::equal_to<>>;

/// A table's names in name order: the candidates of a "did you mean" hint, which prefers the
/// first best match, so a hint does not depend on the table's hash order.
template <typename V>
std::vector<std::string_view> sorted_names(const NameTable<V>& table) {
  std::vector<std::string_view> out;
  out.reserve(table.size());
  for (const auto& [k, v] : table) out.push_back(k);
  std::sort(out.begin(), out.end());
  return out;
}

/// A definition in a namespace: its node, where its name is, and where it was declared.
struct Symbol {
  ir::NodeId node;
  SourceRange range;
  int order = 0;  // top-level statement index of the definition
  std::string_view keyword;  // of the defining statement, e.g. `funnel` (for messages)
};

/// Where a statement is being checked: its enclosing node (a mesh, group, block …).
struct Ctx {
  ir::NodeId parent;                        // enclosing mesh/group/pipeline node
  BlockKind parent_kind = BlockKind::Bank;  // Bank = top level
  std::string_view parent_keyword;          // as written, e.g. `mesh` (empty at the top level)
  bool top = true;
};

/// A `list (…)` entry to check once every bank is known.
struct PendingList {
  std::string bank, name;
  SourceRange range;
};

/// The IR node kind a statement lowers to (Bank and Savedparameter make none: Value).
ir::NodeKind node_kind_for(BlockKind kind);

/// The generator a statement is, if it is one (`funnel`, `bsplinecurve` …).
inline std::optional<ir::GenKind> generator_of(const ast::Stmt& s) { return statement_generator(s); }

/// A face named in a `delete` block, resolved once every instance is known.
struct PendingDelete {
  ir::NodeId owner;  // the delete node
  std::string text;
  SourceRange range;
};

class Context {
 public:
  Context(SourceManager& sources, DiagnosticEngine& diags, const CheckOptions& options, ir::Module& module)
      : sources_(sources), diags_(diags), options_(options), m_(module) {}

  SourceManager& sources() { return sources_; }
  DiagnosticEngine& diags() { return diags_; }
  const CheckOptions& options() const { return options_; }
  ir::Module& module() { return m_; }
  Dialect dialect() const { return dialect_; }
  void set_dialect(Dialect d) { dialect_ = d; }

  // ---- nodes ----
  /// Reserves room for the statements of syntax trees (a file's, or its pieces) and
  /// remembers their statements, so each can be given its node before it is checked.
  void reserve_for(std::span<const ast::Ast> trees);
  /// Forgets the statements of a tree about to be freed (a checked piece of the main file):
  /// a later tree may be allocated at its statements' addresses.
  void forget(const ast::Ast& a);
  /// The node declared for `s` (see `declare`), or null for a statement of no declared tree.
  ir::NodeId* declared_slot(const ast::Stmt& s);
  /// Creates (or reuses the declared) node for a statement.
  ir::NodeId node_for(const ast::Stmt& s, std::string name, const Ctx& ctx);
  /// `parent.name` for a nested definition, `name` at the top level.
  std::string qualify(const Ctx& ctx, const std::string& name) const;
  /// Adds `child` to `parent`'s children and the edge child → parent.
  void adopt(ir::NodeId parent, ir::NodeId child);

  // ---- operands ----
  /// Adds an operand to node `owner` (listed in its `operands`, in written order), with a
  /// Value node and its edges when its expressions read parameters.
  ir::OperandId add_operand(ir::NodeId owner, std::string_view name, SmallVec<ir::ExprId, 4> exprs, SourceRange range);

  // ---- names of the statement ----
  /// Reads the name that follows the keyword; reports MissingName if absent.
  std::optional<std::string> read_name(const ast::Stmt& s, size_t& pos, std::string_view example);
  void misplaced(const ast::Stmt& s, const Ctx& ctx);

  // ---- text helpers for messages ----
  static std::string clip(std::string_view t);
  /// "; the list was read as: `a` | `b`" for arity messages.
  std::string split_text(const ast::Ast& a, const ast::ParenList& list) const;
  /// Warns once per list about commas (NOME lists are separated by spaces).
  void check_commas(const ast::Ast& a, ast::ListId list);

  // ---- scopes (state used by names.cpp and the statement handlers) ----
  NameTable<Symbol> scopes[static_cast<int>(Ns::Count)];  // first definitions
  /// NOME3 redefinitions of a name, in file order (compat.md E1; `lookup` binds by position).
  NameTable<std::vector<Symbol>> redefinitions[static_cast<int>(Ns::Count)];
  NameTable<ir::NodeId> params;  // "bank.param" (unordered: sort what is listed from it)
  mutable NameTable<ir::NodeId> param_text_memo;  // see lookup_param_text
  NameTable<SourceRange> banks;
  std::unordered_map<int32_t, NameTable<ir::NodeId>> mesh_points;  // per mesh (unordered: sort what is listed)
  // Instance scopes keyed by owner node index + 1 (0 = top level).
  std::map<int32_t, NameTable<ir::NodeId>> instance_scopes;  // (unordered within a scope: sort what is listed)
  std::vector<PendingList> pending_lists;
  std::vector<PendingDelete> pending_deletes;
  std::vector<ir::NodeId> scene_merges;  // NOME2's `merge epsilon E endmerge` blocks
  std::vector<ir::NodeId> renders;       // `render` statements, whose paths resolve at the end
  /// The transform chain of the instance being read, for a `lookat` inside it.
  std::vector<ir::TransformOp>* lookat_chain = nullptr;

  // ---- SLIDE's Tcl ----
  std::set<std::string> tcl_vars;
  std::set<std::string> tcl_suffixes;
  std::set<std::string> tcl_reported;
  bool has_tcl = false;
  std::unique_ptr<tcl::Interp> tcl;              // the scene's interpreter, once made (scene_tcl, tcl.cpp)
  std::shared_ptr<tcl::Budget> tcl_budget;       // the wall time of the whole file's Tcl (scene_tcl)
  bool tcl_stop_reported = false;                // the problem that stopped the scene's Tcl is reported
  bool tcl_available = false;                    // a SLIDE file: scene_tcl makes the interpreter on first use
  std::string tcl_dir;                           // the scene's folder, for `source`
  std::vector<SourceRange> tcl_blocks;           // the text inside each `tclinit`/`tclupdate` block's braces
  std::map<std::string, ir::NodeId> tcl_sliders;  // Tcl variable bound to a `scale` → its parameter
  // For the values that follow their sliders (tcl_live.cpp): what the scene's Tcl read, its
  // blocks' texts, the globals its `tclupdate` blocks set and the sliders they read, and the
  // evaluator (also the module's `external`), made for the first such value.
  std::shared_ptr<TclFiles> tcl_files = std::make_shared<TclFiles>();
  std::vector<std::string> tcl_init_texts, tcl_update_texts;
  std::set<std::string> tcl_update_writes;
  std::vector<ir::NodeId> tcl_update_sliders;
  std::shared_ptr<TclEvaluator> tcl_live;
  const ast::Ast* tcl_ast = nullptr;               // the statements `slide create` made (in owned_asts)
  /// `slide create instance I G N` into a group G the file defines: a `group G … endgroup`
  /// of `tcl_ast` (not processed itself) whose instances handle_group adds to G.
  std::map<std::string, std::pair<const ast::Ast*, const ast::Stmt*>> tcl_group_additions;
  /// Names only Tcl defines are reported once per name (real SLIDE files use them hundreds
  /// of times); later uses stay quiet.
  /// Whether `name` (a Tcl-made value) is reported now: once per name, and never when the
  /// file's Tcl was not run on purpose (`--no-tcl` says so once, in its own error).
  bool first_tcl_report(const std::string& name) {
    if (!options().run_tcl) return false;
    return tcl_reported.insert(name).second;
  }

  // ---- progress ----
  int order = 0;  // index of the top-level statement being checked
  int include_depth = 0;
  /// What the check has read (CheckOptions::max_input_bytes): bytes of the main file, its
  /// includes and base scene; `include`s read (repeats counted); the files being included,
  /// outermost first, for messages; whether a limit stopped an include (later ones are
  /// skipped without another error).
  int64_t input_bytes = 0;
  int64_t mesh_bytes = 0;  // of flat mesh files (CheckOptions::max_mesh_bytes)
  int include_count = 0;
  std::vector<std::string> include_chain;
  bool is_include_limit_reached = false;
  bool reported_deep_expr = false;
  bool is_saved_work = false;
  bool is_jipcad = false;  // a NOME3 file with JIPCAD-only syntax (read in JIPCAD's tunnel order)
  bool base_loaded = false;
  ir::NodeId flat_scene;
  int dropped_saved_vertices = 0;  // saved-work vertices the scene lacks (meshes.cpp)  // the instance of a flat file's scene (see flat_meshes.cpp)
  std::vector<NameUse>* name_uses = nullptr;  // CheckOptions::record_names
  std::vector<std::unique_ptr<ast::Ast>> owned_asts;  // included files

  // ---- for incremental checks (incremental.cpp) ----
  FileId main_file;  // the file being checked (its top-level statements are "items")
  /// When set: only the main file's top-level items whose flag is non-zero are processed
  /// (the others are declared, not checked).
  const std::vector<uint8_t>* only_items = nullptr;
  /// When set: every name a definition makes that another statement may look up (top-level
  /// definitions, banks, instances at any depth), with where its name is written.
  std::vector<DeclaredName>* declared_names = nullptr;
  /// When set: for each processed top-level item of the main file, its index and the number
  /// of diagnostics once it was processed (the diagnostics it made come after the previous mark).
  std::vector<std::pair<int32_t, uint32_t>>* item_marks = nullptr;
  bool cancelled = false;  // CheckOptions::cancelled said so: the check stopped early
  bool checking_statements = false;  // the statements are being checked (after every declaration)
  /// Records a definition for incremental checks; `symbol`: a name of a namespace (Ns), which
  /// every "did you mean" hint of that kind lists.
  void note_declared(std::string_view name, SourceRange range, bool top_scope, bool symbol = false) {
    if (declared_names != nullptr && range.file == main_file) {
      declared_names->push_back({std::string(name), range, top_scope, symbol && checking_statements});
    }
  }
  /// A hint listed every top-level instance (NOME2's `instance X` in a block): an incremental
  /// check, which knows only the instances it checked, cannot repeat it.
  bool listed_all_instances = false;

 private:
  // The node declared for each statement, by statement index, per syntax tree (the main
  // file, its base scene, its includes: each is declared before it is processed).
  struct Declared {
    const ast::Ast* ast;
    std::vector<ir::NodeId> ids;
  };

  SourceManager& sources_;
  DiagnosticEngine& diags_;
  const CheckOptions& options_;
  ir::Module& m_;
  Dialect dialect_ = Dialect::Nome;
  std::vector<Declared> declared_;
  size_t last_declared_ = 0;  // where declared_slot last found a statement
  std::vector<int32_t> params_scratch_;  // add_operand: the parameters an operand reads
};

}  // namespace nomec::check
