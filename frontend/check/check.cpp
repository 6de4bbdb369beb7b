// The checker's entry point (see check.h). Order of work for one scene:
//   0. a flat mesh file (`.sif`, `.obj`, `.stl`) is read as a scene of that one mesh;
//   1. parse the file (and, for `.anom` saved work, its base scene first: saved_work.cpp);
//   2. choose the dialect (dialect.cpp);
//   3. collect banks, then saved parameter values, then `-D` overrides (banks.cpp);
//   4. declare every named top-level definition (names.cpp), so uses above a definition
//      get a precise "used before its definition" in NOME and are legal in SLIDE;
//   5. check each statement in order with the handler of its kind, lowering into the IR
//      (statements.cpp and the files it dispatches to);
//   6. resolve `delete` entries and `render` paths, then finish the dependency graph
//      (dependencies.cpp).
#include "frontend/check/check.h"

#include <fmt/format.h>
#include <time.h>

#include <algorithm>

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

void check_parsed(Context& c, CheckResult& result, ast::Ast& main_ast, const std::string& path,
                  std::unique_ptr<ast::Ast>& base_ast) {
  DiagnosticEngine& diags = c.diags();
  // Saved work (`.anom`) is checked on top of its base scene.
  if (is_saved_work_path(path)) base_ast = check::load_base(c, path, main_ast, result);

  result.dialect_reason = check::choose_dialect(c, base_ast ? *base_ast : main_ast, base_ast ? result.base_file : path);
  result.dialect = c.dialect();
  result.module.dialect = c.dialect();

  if (base_ast) {
    check::collect_tcl(c, *base_ast);
    check::collect_banks(c, *base_ast);
    check::apply_saved(c, *base_ast);
  }
  check::collect_tcl(c, main_ast);
  check::run_tcl(c, main_ast, path);
  check::collect_banks(c, main_ast);
  check::apply_saved(c, main_ast);
  check::apply_overrides(c);
  check::normalize_dollar_names(c, main_ast);
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
  check::declare(c, main_ast, 0);
  if (c.tcl_ast != nullptr) check::declare(c, *c.tcl_ast, 1 << 20);  // what `slide create` made
  result.first_statement_diagnostic = diags.diagnostics().size();
  c.checking_statements = true;
  check::process(c, main_ast, 0);
  if (c.cancelled) {
    result.cancelled = true;
    return;
  }
  if (c.tcl_ast != nullptr) check::process(c, *c.tcl_ast, 1 << 20);
  check::report_unplaced_tcl_instances(c);
  check::finish_scene_merges(c);
  check::resolve_pending_deletes(c);
  check::resolve_render_paths(c);
  check::finish_dependencies(c);
  // What an incremental check (incremental.cpp) leaves to a full one: statements that read
  // other files or Tcl, or that depend on the whole scene (NOME2's scene merges).
  const bool reads_beyond = std::any_of(main_ast.top.begin(), main_ast.top.end(), [](const ast::Item& it) {
    return it.kind == ast::ItemKind::Include || it.kind == ast::ItemKind::Tcl;
  });
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
  ast::Ast main_ast = cache != nullptr ? cache->parse(sources, file, diags) : parse_file(sources, file, diags);
  result.parse_ms = thread_cpu_ms() - parse_start;
  if (options.parsed) options.parsed();

  std::unique_ptr<ast::Ast> base_ast;
  check::check_parsed(c, result, main_ast, path, base_ast);
  if (result.cancelled) return result;
  if (options.record_names) {
    result.asts.push_back(std::make_shared<ast::Ast>(std::move(main_ast)));
    if (base_ast) result.asts.push_back(std::move(base_ast));
    for (auto& inc : c.owned_asts) result.asts.push_back(std::move(inc));
  }
  return result;
}

void release_thread_resources() { tcl::finish_thread(); }

}  // namespace nomec
