// The checker's entry point (see check.h). Order of work for one scene:
//   1. parse the file (and, for `.anom` saved work, its base scene first);
//   2. choose the dialect (dialect.cpp);
//   3. collect banks, then saved parameter values, then `-D` overrides (banks.cpp);
//   4. declare every named top-level definition (names.cpp), so uses above a definition
//      get a precise "used before its definition" in NOME and are legal in SLIDE;
//   5. check each statement in order with the handler of its kind, lowering into the IR
//      (statements.cpp and the files it dispatches to);
//   6. resolve `delete` entries, then finish the dependency graph (dependencies.cpp).
#include "frontend/check/check.h"

#include "frontend/check/handlers.h"
#include "frontend/parse/parse.h"
#include "frontend/source/file_kinds.h"

namespace nomec {

namespace {

// The base scene of a saved-work file: `--base`, else the `.nom`/`.nome` named like its
// folder, else the only one in the folder (listed through `options.list_folder`).
std::optional<std::string> find_base(const std::string& path, const CheckOptions& options) {
  if (options.base_file) return options.base_file;
  if (!options.list_folder) return std::nullopt;
  const size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash == 0 ? 1 : slash);
  std::optional<FolderListing> listing = options.list_folder(dir);
  if (!listing) return std::nullopt;
  std::vector<std::string> candidates;
  for (const std::string& f : listing->files) {
    if (is_base_scene_path(f)) candidates.push_back(f);
  }
  auto full = [&](const std::string& name) { return (dir.empty() ? std::string(".") : dir) + "/" + name; };
  for (const std::string& c : candidates) {
    if (c.substr(0, c.size() - path_extension(c).size()) == listing->name) return full(c);
  }
  if (candidates.size() == 1) return full(candidates[0]);
  return std::nullopt;
}

// Reads the base scene of saved work into `base_ast`; warns when there is none.
std::unique_ptr<ast::Ast> load_base(check::Context& c, const std::string& path, FileId file, CheckResult& result) {
  c.is_saved_work = true;
  std::optional<std::string> base = find_base(path, c.options());
  std::optional<std::string> base_text;
  if (base && c.options().read_file) base_text = c.options().read_file(*base);
  if (!base_text) {
    c.diags().emit(DiagKind::MissingBaseFile, SourceRange{file, 0, 0},
                   "saved-work file without its base scene: its instance vertices cannot be resolved; pass `--base SCENE.nom`");
    return nullptr;
  }
  FileId bf = c.sources().add_file(*base, std::move(*base_text));
  DiagnosticEngine base_diags;  // the base file is checked on its own; only its scope is reused
  auto base_ast = std::make_unique<ast::Ast>(parse_file(c.sources(), bf, base_diags));
  result.base_file = *base;
  c.base_loaded = true;
  return base_ast;
}

}  // namespace

std::optional<ir::GenKind> statement_generator(const ast::Stmt& s) {
  if (s.kind != ast::BlockKind::Generator) return std::nullopt;
  return ir::generator_by_keyword(s.keyword);
}

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
  if (options.record_names) c.name_uses = &result.name_uses;
  FileId file = sources.add_file(path, std::move(text));
  ast::Ast main_ast = cache != nullptr ? cache->parse(sources, file, diags) : parse_file(sources, file, diags);

  // Saved work (`.anom`) is checked on top of its base scene.
  std::unique_ptr<ast::Ast> base_ast;
  if (is_saved_work_path(path)) base_ast = load_base(c, path, file, result);

  result.dialect_reason = check::choose_dialect(c, base_ast ? *base_ast : main_ast, base_ast ? result.base_file : path);
  result.dialect = c.dialect();
  result.module.dialect = c.dialect();

  if (base_ast) {
    check::collect_tcl(c, *base_ast);
    check::collect_banks(c, *base_ast);
    check::apply_saved(c, *base_ast);
  }
  check::collect_tcl(c, main_ast);
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
  check::declare(c, main_ast, 0);
  check::process(c, main_ast, 0);
  check::finish_scene_merges(c);
  check::resolve_pending_deletes(c);
  check::finish_dependencies(c);
  if (options.record_names) {
    result.asts.push_back(std::make_shared<ast::Ast>(std::move(main_ast)));
    if (base_ast) result.asts.push_back(std::move(base_ast));
    for (auto& inc : c.owned_asts) result.asts.push_back(std::move(inc));
  }
  return result;
}

}  // namespace nomec
