// The checker's entry point (see check.h). Order of work for one scene:
//   0. a flat mesh file (`.sif`, `.obj`, `.stl`) is read as a scene of that one mesh;
//   1. parse the file (and, for `.anom` saved work, its base scene first: saved_work.cpp);
//   2. choose the dialect (dialect.cpp);
//   3. collect banks, then saved parameter values, then `-D` overrides (banks.cpp);
//   4. declare every named top-level definition (names.cpp), so uses above a definition
//      get a precise "used before its definition" in NOME and are legal in SLIDE;
//   5. check each statement in order with the handler of its kind, lowering into the IR
//      (statements.cpp and the files it dispatches to); the command line parses a large
//      file in pieces and frees each piece's tree once its statements are checked
//      (CheckOptions::piece_bytes), the passes of 2–4 reading the pieces in order;
//   6. resolve `delete` entries and `render` paths, then finish the dependency graph
//      (dependencies.cpp).
#include "base/input_limits.h"
#include "frontend/check/check.h"

#include <fmt/format.h>
#include <time.h>

#include <algorithm>

#include "base/free_memory.h"
#include "frontend/check/handlers.h"
#include "frontend/flat/flat.h"
#include "frontend/parse/parse.h"
#include "frontend/source/file_kinds.h"

namespace nomec {

double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) / 1e6;
}

std::optional<ir::GenKind> statement_generator(const ast::Stmt& s) {
  if (s.kind != ast::BlockKind::Generator) return std::nullopt;
  return ir::generator_by_keyword(s.keyword);
}

namespace check {

void check_parsed(Context& c, CheckResult& result, std::span<ast::Ast> main, const std::string& path,
                  std::unique_ptr<ast::Ast>& base_ast, bool free_checked) {
  DiagnosticEngine& diags = c.diags();
  const std::span<const ast::Ast> trees(main.data(), main.size());
  // Saved work (`.anom`) is checked on top of its base scene (and is never in pieces).
  if (is_saved_work_path(path) && main.size() == 1) base_ast = check::load_base(c, path, main[0], result);

  result.dialect_reason = check::choose_dialect(c, base_ast ? std::span<const ast::Ast>(base_ast.get(), 1) : trees,
                                                base_ast ? result.base_file : path);
  result.dialect = c.dialect();
  result.module.dialect = c.dialect();

  if (base_ast) {
    check::collect_tcl(c, *base_ast);
    check::collect_banks(c, *base_ast);
    check::apply_saved(c, *base_ast);
  }
  // The whole-file passes read the pieces in order, as they would read the one tree.
  for (const ast::Ast& a : trees) check::collect_tcl(c, a);
  check::run_tcl(c, trees, path);
  for (const ast::Ast& a : trees) check::collect_banks(c, a);
  for (const ast::Ast& a : trees) check::apply_saved(c, a);
  check::apply_overrides(c);
  for (ast::Ast& a : main) check::normalize_dollar_names(c, a);
  if (base_ast) {
    // The base scene is checked with a scratch engine: its problems belong to its own check,
    // and only the saved work is reported here.
    check::declare(c, *base_ast, -(1 << 21));
    DiagnosticEngine scratch;
    std::swap(scratch, diags);
    check::process(c, *base_ast, -(1 << 21));
    check::resolve_pending_deletes(c);
    std::swap(scratch, diags);
  }
  if (c.options().is_cancelled()) {
    result.cancelled = true;
    return;
  }
  check::declare(c, trees, 0);
  if (c.tcl_ast != nullptr) check::declare(c, *c.tcl_ast, 1 << 20);  // what `slide create` made
  result.first_statement_diagnostic = diags.diagnostics().size();
  c.checking_statements = true;
  // What an incremental check (incremental.cpp) leaves to a full one: statements that read
  // other files or Tcl (noted before a piece is freed).
  bool reads_beyond = false;
  int order_base = 0;
  bool in_stray_run = false;  // across the pieces
  for (ast::Ast& a : main) {
    reads_beyond = reads_beyond || std::any_of(a.top.begin(), a.top.end(), [](const ast::Item& it) {
                     return it.kind == ast::ItemKind::Include || it.kind == ast::ItemKind::Tcl;
                   });
    check::process(c, a, order_base, &in_stray_run);
    if (c.cancelled) {
      result.cancelled = true;
      return;
    }
    order_base += static_cast<int>(a.top.size());
    if (free_checked) {
      // Nothing reads a piece's tree once its statements are checked: the IR holds what
      // they made, and its texts view the file's text, not the tree.
      c.forget(a);
      a = ast::Ast{};
      give_back_free_memory();
    }
  }
  if (c.tcl_ast != nullptr) check::process(c, *c.tcl_ast, 1 << 20);
  check::report_unplaced_tcl_instances(c);
  check::finish_scene_merges(c);
  check::resolve_pending_deletes(c);
  check::resolve_render_paths(c);
  check::finish_dependencies(c);
  if (c.tcl_live) c.tcl_live->end_check();  // slider moves now have budgets of their own
  // Nor does it repeat statements that depend on the whole scene (NOME2's scene merges).
  result.incremental_ok = c.options().record_names && !is_saved_work_path(path) && !base_ast && c.tcl_ast == nullptr &&
                          !c.has_tcl && c.tcl_blocks.empty() && c.dialect() != Dialect::Slide && c.scene_merges.empty() &&
                          !c.reported_deep_expr && !c.listed_all_instances && c.owned_asts.empty() && !reads_beyond;
}

}  // namespace check

CheckResult check_source(SourceManager& sources, const std::string& path, std::string text,
                         const CheckOptions& options, DiagnosticEngine& diags) {
  return check_source(sources, path, std::move(text), options, diags, nullptr);
}

CheckResult check_source(SourceManager& sources, const std::string& path, std::string text,
                         const CheckOptions& options, DiagnosticEngine& diags, ParseCache* cache) {
  CheckResult result;
  result.module.time = options.time;
  result.module.frame = options.frame;
  check::Context c(sources, diags, options, result.module);
  if (options.record_names) {
    c.name_uses = &result.name_uses;
    c.declared_names = &result.declared_names;
    c.item_marks = &result.item_marks;
  }
  FileId file = sources.add_file(path, std::move(text));
  c.main_file = file;
  // Against CheckOptions::max_input_bytes, or max_mesh_bytes for a flat mesh file.
  (is_mesh_file_path(path) ? c.mesh_bytes : c.input_bytes) = static_cast<int64_t>(sources.text(file).size());
  if (std::optional<ir::FlatFormat> format = flat::format_of_path(path)) {
    // A flat mesh file is a scene of that one mesh, instanced once (language.md §8).
    if (options.parsed) options.parsed();
    c.set_dialect(options.dialect.value_or(Dialect::Nome));
    result.dialect = c.dialect();
    result.module.dialect = c.dialect();
    result.dialect_reason = fmt::format("a flat `.{}` mesh file: one mesh, instanced once", ir::flat_format_name(*format));
    check::add_flat_scene(c, file, *format);
    check::apply_overrides(c);  // a flat mesh has no sliders: every `-D` is reported
    check::finish_dependencies(c);
    return result;
  }
  if (options.is_cancelled()) {  // overtaken before it began
    result.cancelled = true;
    return result;
  }
  const double parse_start = thread_cpu_ms();
  // In pieces, each freed once checked (CheckOptions::piece_bytes), where nothing reads the
  // tree afterwards or reads it whole: not for the editor, saved work or SLIDE's Tcl.
  const std::string_view ext = path_extension(path);
  const bool in_pieces = options.piece_bytes > 0 && cache == nullptr && !options.record_names &&
                         !is_saved_work_path(path) && ext != ".slf" && options.dialect.value_or(Dialect::Nome) != Dialect::Slide;
  std::vector<ast::Ast> main;
  if (in_pieces) {
    main = parse_file_in_pieces(sources, file, diags, options.piece_bytes);
  } else {
    main.push_back(cache != nullptr ? cache->parse(sources, file, diags) : parse_file(sources, file, diags));
  }
  result.parse_ms = thread_cpu_ms() - parse_start;
  if (options.parsed) options.parsed();

  std::unique_ptr<ast::Ast> base_ast;
  check::check_parsed(c, result, main, path, base_ast, in_pieces);
  if (result.cancelled) return result;
  if (options.record_names) {
    result.asts.push_back(std::make_shared<ast::Ast>(std::move(main.front())));
    if (base_ast) result.asts.push_back(std::move(base_ast));
    for (auto& inc : c.owned_asts) result.asts.push_back(std::move(inc));
  }
  return result;
}

}  // namespace nomec
