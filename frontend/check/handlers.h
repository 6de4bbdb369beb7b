// The checker's concerns, one file each, as free functions over the Context: what each
// file owns is written above its declarations. check.cpp runs them in the order of a scene
// (dialect, banks, declarations, statements, dependencies).
#pragma once

#include <fmt/format.h>
#include <functional>
#include <span>
#include <string>
#include <string_view>

#include "frontend/check/context.h"
#include "frontend/check/options.h"

namespace nomec::check {

// ---- check.cpp: the phases of a parsed main file ----
/// Dialect, banks, declarations, then each statement (all, or `c.only_items`), then what
/// resolves at the end; loads the base scene of saved work into `base_ast`. `main` is the
/// main file's syntax tree: one, or the pieces of `parse_file_in_pieces` in order (then not
/// saved work, and not SLIDE). With `free_checked`, each piece's tree is freed, and the
/// allocator's free pages given back, as soon as its statements are checked.
void check_parsed(Context& c, CheckResult& result, std::span<ast::Ast> main, const std::string& path,
                  std::unique_ptr<ast::Ast>& base_ast, bool free_checked);

// ---- dialect.cpp: which dialect a file is written in, and the names its Tcl code makes ----
/// `trees`: the file's syntax tree, or its pieces in order.
std::string choose_dialect(Context& c, std::span<const ast::Ast> trees, const std::string& path);
void collect_tcl(Context& c, const ast::Ast& a);

// ---- tcl.cpp: SLIDE's Tcl: `tclinit`/`tclupdate` blocks, sliders, `{expr …}` values ----
/// Runs the file's Tcl blocks in the scene's interpreter and makes its sliders parameters
/// (SLIDE files only; before the banks, so `-D` reaches the sliders).
void run_tcl(Context& c, std::span<const ast::Ast> trees, const std::string& path);
/// The scene's interpreter, made on first use (a SLIDE file without Tcl blocks makes one
/// only when a value needs Tcl); nullptr outside SLIDE files.
tcl::Interp* scene_tcl(Context& c);
struct TclValue {
  bool ok = false;
  double value = 0;
  std::vector<ir::NodeId> sliders;  // the sliders the script read
  std::vector<std::string> reads;   // every watched variable it read (sliders, what `tclupdate` sets)
};
/// A SLIDE value evaluated by Tcl (`expr …` or any script), with the sliders it read; its
/// problems are reported at `where`. Nullopt without an interpreter (not a SLIDE file).
std::optional<TclValue> tcl_value(Context& c, std::string_view script, SourceRange where);
/// `slide create instance I G N` whose group G the scene never defines.
void report_unplaced_tcl_instances(Context& c);
/// A Tcl global's numeric value (`par_x`, `oOffset(height)`), if it has one.
std::optional<double> tcl_number(Context& c, std::string_view name, SourceRange where);

// ---- tcl_live.cpp: SLIDE values Tcl re-evaluates when their sliders move ----
/// Records what a `tclupdate` block (its text, its outcome from `run_tracking_writes`) sets
/// and which sliders it reads.
void note_tcl_update(Context& c, const tcl::Outcome& o, std::string_view text);
/// Does the value read (or name) a variable a `tclupdate` block sets? Then nomec's own
/// reading of it (`$r` as the number `tclupdate` left) would not follow the sliders.
bool reads_tcl_update(const Context& c, std::string_view script, const TclValue& v);
/// Tcl's value `v` of `script` (at `where`), which nomec's own expressions cannot repeat: an
/// `External` expression that follows the sliders it depends on, a constant when it depends
/// on none, or a constant with `TclValueFixed` when re-running the script changes its value.
ir::ExprId live_tcl_value(Context& c, std::string script, const TclValue& v, SourceRange where);

// ---- banks.cpp: banks and sliders, saved values, `-D` overrides, `list` entries ----
void collect_banks(Context& c, const ast::Ast& a);
void apply_saved(Context& c, const ast::Ast& a);
void apply_overrides(Context& c);
void check_pending_lists(Context& c);
/// The slider a reference names: `bank.param`, or `bank_param` with the longest declared
/// bank prefix. Memoized (a scene refers to the same sliders over and over).
ir::NodeId lookup_param_text(Context& c, std::string_view text);

// ---- names.cpp: definitions and scopes, and resolving names to nodes ----
/// NOME3 `$name` where a name is expected (compat.md B3): in a `nome3` file, a `$x` that
/// reads no slider becomes the name `x`, as an item (`torusknot $k (…)`, `instance i $k`)
/// and as a list element (`face f ($a $b $c)`). Runs after the banks are collected.
void normalize_dollar_names(Context& c, ast::Ast& a);
/// Declares the named top-level definitions of a syntax tree, or of a file's pieces in
/// order, numbering its top-level items from `order_base` + 1.
void declare(Context& c, std::span<const ast::Ast> trees, int order_base);
inline void declare(Context& c, const ast::Ast& a, int order_base) { declare(c, std::span<const ast::Ast>(&a, 1), order_base); }
/// `mesh consolidatedmesh … endmesh` in a `nome`/`nome2` file: blocks that accumulate
/// (compat.md §E5).
bool is_consolidated_mesh(const Context& c, const ast::Stmt& s);
void define(Context& c, Ns ns, std::string_view name, Symbol sym);
ir::NodeId lookup(Context& c, Ns ns, std::string_view name, SourceRange use, bool report_order);
ir::NodeId resolve(Context& c, Ns ns, std::string_view name, SourceRange use, std::string_view wanted);
ir::NodeId resolve_any(Context& c, std::string_view name, SourceRange use);
ir::NodeId resolve_point_like(Context& c, std::string_view name, SourceRange use);
ir::NodeId resolve_target(Context& c, std::string_view name, SourceRange use);
ir::NodeId report_unknown(Context& c, Ns ns, std::string_view name, SourceRange use, std::string_view wanted);
std::vector<std::string_view> names_in(const Context& c, Ns ns);

// ---- vertex_refs.cpp: vertex references and deleted faces through instance paths ----
/// A vertex of a face or polyline: a point of `mesh`, a global point, or a path through
/// instances (`inst.v`, `.inst.sub.v`, 2016 `inst_sub_v`).
/// With `unresolved` given, a name that resolves to nothing is not reported: `*unresolved`
/// is set instead (saved work drops such vertices, compat.md §G2).
ir::VertexRef resolve_vertex(Context& c, std::string_view text, SourceRange use, ir::NodeId mesh,
                             bool* unresolved = nullptr);
/// A face named in a `delete` block (`cube1_c4`, `fun2_5`, `cf.fun2.5`).
ir::DeletedFace resolve_deleted_face(Context& c, const std::string& text, SourceRange use);
/// A face named by a high-genus block (`handle h faces (c.f1 c.f2)`, `rind r punch (c.f3)`):
/// a path from one of the block's own instances; reported as `UnknownBlockFace` with the
/// closest `instance.face` as a fix-it. `scope` of the result is the block.
ir::DeletedFace resolve_block_face(Context& c, const std::string& text, SourceRange use, ir::NodeId block);
/// A vertex named by `handle h corners (c.v1 c.v5)`: a path from one of the block's instances.
ir::VertexRef resolve_block_vertex(Context& c, const std::string& text, SourceRange use, ir::NodeId block);

// ---- expressions.cpp: lowering expressions into the IR, with their checks ----
/// Lowers a syntax expression and evaluates it once (a domain problem such as a division
/// by zero is reported here). `constant`: slider values may not refer to sliders.
ir::ExprId lower_expr(Context& c, const ast::Ast& a, ast::ExprId id, bool constant);
/// One value item (`0.5`, `{expr …}`, `(0.5)`, a bare `bank.param` word) as an expression.
ir::ExprId scalar_of_item(Context& c, const ast::Ast& a, const ast::Item& it, bool constant);
ir::ExprId error_expr(Context& c, SourceRange r);
/// The text of a function surface's `[ … ]` (`[cos(u)*v]`) as an expression of the
/// variables `vars`; errors (unknown names and functions, syntax) are reported at their
/// place inside the brackets.
/// Where a function text comes from, for what NOME3 accepted in it: `generator` is the
/// generator's keyword in a NOME3 file (empty elsewhere), `has_pi` whether NOME3 defined `pi`
/// there (only genimplicitsurf did).
struct FunctionOrigin {
  std::string_view generator;
  bool has_pi = true;
};
ir::ExprId lower_function(Context& c, const ast::Ast& a, ast::ExprId raw, std::span<const std::string_view> vars,
                          FunctionOrigin origin = {});

// ---- statements.cpp: top-level statements, dispatch by kind, includes ----
/// Checks the top-level items of a syntax tree (or of one piece of the main file: then
/// `order_base` counts the items of the pieces before it), numbering them from
/// `order_base` + 1. A run of stray items is reported at its first item; `in_stray_run`,
/// when given, carries whether the items before `a` ended in such a run (the pieces of one
/// file share it, so a run across a cut is reported once, as in the whole tree).
void process(Context& c, const ast::Ast& a, int order_base, bool* in_stray_run = nullptr);
ir::NodeId handle_stmt(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
/// The file an `include` names, read through CheckOptions::read_file within the check's
/// input limits: `text`, or nullopt with `problem` (the reader's reason, maybe "") for the
/// caller to report; or `is_stopped` when a limit (depth, count, bytes) refused it — then one
/// `IncludeLimit` error is reported at the first such `include` and later ones are skipped.
struct IncludeRead {
  std::optional<std::string> text;
  std::string problem;
  bool is_stopped = false;
};
IncludeRead read_include(Context& c, const std::string& path, const std::string& rel, const ast::Item& it);

// ---- meshes.cpp: points, faces, polylines, objects, meshes, sharps, deletes, saved work ----
ir::NodeId handle_surface(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_point(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_vertex(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_controlpoint(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_polyline(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_face(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_object(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_mesh(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_sharp(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_delete(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
/// Resolves the faces named in `delete` blocks (once every instance is known).
void resolve_pending_deletes(Context& c);
/// Reads the vertex list `list_item` of a face, polyline or crease into the module.
ir::Slice<ir::VertexRef> read_vertices(Context& c, const ast::Ast& a, const ast::Item& list_item, ir::NodeId owner,
                                       ir::NodeId mesh);
/// Reads a list of names (`(f1 f2)`, `(p1 p2)`) into the module, adding edges to `owner`.
ir::Slice<ir::NodeId> read_names(Context& c, const ast::Ast& a, const ast::Item& list_item, ir::NodeId owner, Ns ns);

// ---- flat_meshes.cpp: `.sif`, `.obj`, `.stl` files as meshes (frontend/flat reads them) ----
/// Reads the flat file `file` and defines the mesh named after its stem; `name_range` is
/// where a diagnostic about the name points (the `include`), if anywhere.
ir::NodeId add_flat_mesh(Context& c, FileId file, ir::FlatFormat format, SourceRange name_range,
                         std::string name = {});
/// The scene of a flat file given alone (or as saved work's base): its mesh, instanced once.
void add_flat_scene(Context& c, FileId file, ir::FlatFormat format);
/// `include "hull.stl"` of a flat file at `path` (written `rel`): defines its mesh. False
/// when `path` is no flat file (the caller includes it as a scene file).
bool include_flat(Context& c, const std::string& path, const std::string& rel, const ast::Item& it);
/// In a flat file's scene, a bare `v<k>` names vertex k of its mesh (NOME 2016 names); an
/// unresolved reference (no instances) otherwise.
ir::VertexRef flat_scene_vertex(Context& c, std::string_view text, SourceRange use);

// ---- saved_work.cpp: the base scene of `.anom` saved work ----
/// Finds and reads the base scene of the saved work `saved` at `path`: a scene's syntax tree
/// to check first, or null (a flat mesh base is added to the scene directly; without a base
/// `MissingBaseFile` warns).
std::unique_ptr<ast::Ast> load_base(Context& c, const std::string& path, const ast::Ast& saved, CheckResult& result);

// ---- instances.cpp: instances, groups, transforms ----
ir::NodeId handle_instance(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_group(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_transform(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);

// ---- generators.cpp: generator statements, driven by the catalogue ----
ir::NodeId handle_generator(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);

// ---- symbols of option values (`sd_type NOME_SD_CC_sharp`, `projection SLF_PERSPECTIVE`) ----
template <typename E>
struct SymbolEntry {
  std::string_view word;
  E value;
};
/// The value of `v.symbol` in `table`; reports UnknownSymbol (with the closest word and the
/// known ones) otherwise.
template <typename E, size_t N>
std::optional<E> resolve_symbol(Context& c, const SymbolEntry<E> (&table)[N], const OptionValue& v, std::string_view what) {
  for (const SymbolEntry<E>& e : table) {
    if (e.word == v.symbol) return e.value;
  }
  std::vector<std::string> words;
  for (const SymbolEntry<E>& e : table) words.emplace_back(e.word);
  std::string hint = closest_match(v.symbol, words);
  auto d = c.diags().emit(DiagKind::UnknownSymbol, v.value_range,
                          fmt::format("unknown {} `{}`{}", what, v.symbol, hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
  if (!hint.empty()) d.fixit(v.value_range, hint, fmt::format("replace with `{}`", hint));
  std::vector<std::string> shown;
  for (const std::string& w : words) shown.push_back(fmt::format("`{}`", w));
  d.note(SourceRange{}, fmt::format("known values: {}", fmt::join(shown, ", ")));
  return std::nullopt;
}

// ---- blocks.cpp: pipeline blocks, sweeps, zippers ----
ir::NodeId handle_block(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
/// Gives NOME2's `merge epsilon E endmerge` every top-level instance of the scene.
void finish_scene_merges(Context& c);
ir::NodeId handle_sweep(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_sweep_part(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_zipper(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);

// ---- viewing.cpp: cameras, lights, windows, viewports, `render`, `lookat`; NOME2's display colours ----
ir::NodeId handle_scene(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
/// What a viewing statement is (set when it is declared, so a `render` above a `viewport`
/// sees its kind).
ir::SceneKind scene_kind_for(BlockKind kind);
/// Resolves the camera and light paths of every `render` (once every instance is known).
void resolve_render_paths(Context& c);

// ---- highgenus.cpp: `handle`, `rind`, `sierpinski` and `menger` ----
/// The face and vertex paths of a high-genus block, as written; resolved once the block's
/// instances are read.
struct BlockPaths {
  std::vector<std::pair<std::string, SourceRange>> faces, corners, punch, peel;
  SourceRange faces_range, corners_range;
  bool has_faces = false, has_corners = false;
};
/// Takes a `Paths` option of a high-genus block into `p`.
void note_block_paths(BlockPaths& p, const OptionValue& v);
/// Resolves the paths of block `id` into its payload and checks its required options
/// (`MissingArgument`), list lengths (`ListArity`) and levels (`LevelTooHigh`).
void finish_highgenus(Context& c, const ast::Stmt& s, ir::NodeId id, const BlockPaths& p);

// ---- colors.cpp: JIPCAD's viewer colours and back-face colours ----
ir::NodeId handle_scene_color(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_backface(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);

// ---- morphs.cpp: JIPCAD's sweepmorph and morphvisualizer ----
ir::NodeId handle_sweepmorph(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);
ir::NodeId handle_morphvisualizer(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx);

// ---- dependencies.cpp: the finished graph ----
/// Finalizes the dependency graph and reports a cycle in it.
void finish_dependencies(Context& c);

}  // namespace nomec::check
