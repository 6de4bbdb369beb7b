// The `nomec` command line: checks NOME/NOME3/SLIDE files and prints diagnostics (text like
// clang, or JSON), or emits the IR dump, the dependency graph, meshes (STL/OBJ/PLY through
// backend/) or a JSON topology summary of them. The first client of the
// nomec libraries; it knows only what they expose.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unistd.h>

#include "base/file_io.h"
#include "backend/evaluate.h"
#include "backend/save.h"
#include "backend/summary.h"
#include "backend/write.h"
#include "frontend/check/check.h"
#include "ir/ir.h"
#include "tools/allocator.h"
#include "tools/fmt_command.h"
#include "lsp/summary_json.h"
#include "tools/what_if.h"
#ifdef NOMEC_HAVE_LSP
#include "lsp/server.h"
#endif

NOMEC_JEMALLOC_CONFIG();

namespace {

nlohmann::json range_json(const nomec::SourceManager& sources, nomec::SourceRange r) {
  if (!r.is_valid()) {
    return nullptr;
  }
  nomec::LineCol b = sources.line_col(r.file, r.begin);
  nomec::LineCol e = sources.line_col(r.file, r.end);
  return {{"file", std::string(sources.name(r.file))},
          {"start", {{"line", b.line}, {"column", b.column}, {"offset", r.begin}}},
          {"end", {{"line", e.line}, {"column", e.column}, {"offset", r.end}}}};
}

nlohmann::json diag_json(const nomec::SourceManager& sources, const nomec::Diagnostic& d,
                         bool werror) {
  nomec::Severity sev = d.severity;
  if (werror && sev == nomec::Severity::Warning) {
    sev = nomec::Severity::Error;
  }
  nlohmann::json j = {{"code", std::string(nomec::diag_kind_name(d.kind))},
                      {"severity", std::string(nomec::severity_name(sev))},
                      {"message", d.message},
                      {"range", range_json(sources, d.range)},
                      {"notes", nlohmann::json::array()},
                      {"fixits", nlohmann::json::array()}};
  for (const auto& n : d.notes) {
    j["notes"].push_back({{"message", n.message}, {"range", range_json(sources, n.range)}});
  }
  for (const auto& f : d.fixits) {
    j["fixits"].push_back({{"description", f.description},
                           {"replacement", f.replacement},
                           {"range", range_json(sources, f.range)}});
  }
  return j;
}

// `--emit summary`: one object per output mesh (kernel::topology of the built mesh).
nlohmann::json summary_json(const std::string& path, const std::vector<nomec::backend::OutputMesh>& meshes) {
  std::vector<nomec::backend::MeshSummary> s;
  for (const auto& m : meshes) s.push_back(nomec::backend::summarize(m));
  return nomec::lsp::summary_json(path, s);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::string_view(argv[1]) == "--lsp") {
#ifdef NOMEC_HAVE_LSP
    // The language server on stdin/stdout (lsp/). Editors' clients may append `--stdio`
    // and `--clientProcessId=N` (vscode-languageclient does); both are accepted.
    for (int i = 2; i < argc; ++i) {
      std::string_view a = argv[i];
      if (a != "--stdio" && a.rfind("--clientProcessId", 0) != 0) {
        std::cerr << "nomec: --lsp takes no other arguments (got `" << a << "`)\n";
        return 2;
      }
    }
    return nomec::lsp::run_stdio();
#else
    std::cerr << "nomec: built without the language server (NOMEC_BUILD_LSP=OFF)\n";
    return 2;
#endif
  }
  CLI::App app{"nomec: compiler for NOME, NOME3 and SLIDE scene files"};
  app.set_version_flag("--version", fmt::format("nomec {} (allocator: {})", NOMEC_VERSION, nomec::allocator_name()));
  std::vector<std::string> files;
  bool check_only = false;
  std::string emit;
  std::string dialect;
  std::vector<std::string> defines;
  bool werror = false;
  bool verbose = false;
  bool allow_out_of_range = false;
  std::string format = "text";
  std::string base;
  std::string color = "auto";
  double time = 0;
  double frame = 0;
  app.add_option("files", files, "Input files (.nome, .nom, .slf, .anom)");
  nomec::tools::FmtCommand fmt_command;
  CLI::App* fmt_app = app.add_subcommand("fmt", "Format files: print (one file), --check or -i");
  fmt_app->add_option("files", fmt_command.files, "Files to format (`-` = standard input)")->required();
  fmt_app->add_flag("-i,--in-place", fmt_command.in_place, "Rewrite changed files in place (atomically)");
  fmt_app->add_flag("--check", fmt_command.check, "List files that would change; exit 1 if any");
  fmt_app->add_option("--indent", fmt_command.indent_width, "Spaces per indentation level (default 4)")
      ->check(CLI::Range(0, 16));
  fmt_app->add_flag("--tabs", fmt_command.use_tabs, "Indent with tabs");
  app.add_flag("--check", check_only, "Check the files and report diagnostics (default)");
  app.add_option("--emit", emit,
                 "Emit `ir` (readable typed IR), `deps` (DOT graph), a mesh (`stl`, `obj`, `ply`) "
                 "`summary` (JSON topology per output mesh) or `nome` (the scene saved with its "
                 "current slider values)")
      ->check(CLI::IsMember({"ir", "deps", "stl", "obj", "ply", "summary", "nome"}));
  std::string output;
  bool stl_ascii = false;
  bool time_report = false;
  nomec::backend::PipelineOptions pipeline;
  std::string rule = "catmull-clark";
  app.add_option("-o", output, "Output file (`-` = standard output); default: the input's "
                               "basename with the format's extension (summary: standard output)");
  app.add_flag("--stl-ascii", stl_ascii, "Write ASCII STL instead of binary");
  app.add_flag("--merge", pipeline.is_merge, "Merge coinciding boundary edges of the whole scene");
  app.add_option("--merge-tolerance", pipeline.merge_tolerance,
                 "Merge tolerance (default 1e-4 x bounding-box diagonal)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--subdivide", pipeline.subdivide_levels, "Catmull-Clark levels after merging")
      ->check(CLI::Range(0, 12));
  app.add_option("--rule", rule, "Smooth-vertex rule: catmull-clark or derose")
      ->check(CLI::IsMember({"catmull-clark", "derose"}));
  app.add_option("--offset", pipeline.offset_height, "Offset the (merged, subdivided) scene into a slab of this half-thickness")
      ->check(CLI::PositiveNumber);
  app.add_option("--subdivide-after", pipeline.subdivide_after_levels, "Catmull-Clark levels after the offset")
      ->check(CLI::Range(0, 12));
  app.add_flag("--time-report", time_report, "Print the time of each stage to stderr");
  app.add_option("--max-vertices", pipeline.max_vertices,
                 "Most vertices evaluation may build (placed geometry and subdivisions); default 20000000")
      ->check(CLI::Range(int64_t{1}, int64_t{2'000'000'000}));
  app.add_option("--dialect", dialect, "Force the dialect instead of detecting it")
      ->check(CLI::IsMember({"nome", "nome3", "slide"}));
  app.add_option("-D", defines, "Override a slider: -D bank.param=value (repeatable)")
      ->allow_extra_args(false);  // one value per -D: the files that follow stay files
  app.add_flag("--werror", werror, "Treat warnings as errors");
  app.add_flag("--allow-out-of-range", allow_out_of_range,
               "Accept -D values outside the slider range");
  app.add_option("--diagnostics-format", format, "Diagnostics as `text` or `json`")
      ->check(CLI::IsMember({"text", "json"}));
  app.add_option("--base", base, "Base scene for a saved-work .anom file");
  app.add_option("--color", color, "Colour diagnostics: auto, always, never")
      ->check(CLI::IsMember({"auto", "always", "never"}));
  app.add_option("--time", time, "Value of `$time` in expressions (default 0)");
  app.add_option("--frame", frame, "Value of `$frame` in expressions (default 0)");
  app.add_flag("-v,--verbose", verbose, "Report the dialect used and summary counts");
  std::string what_if_text;
  app.add_option("--what-if", what_if_text,
                 "Move one slider (bank.param=value) after a full build and print, as JSON, what "
                 "the incremental update re-evaluated and its time next to the full build's");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return e.get_exit_code() == 0 ? code : 2;
  }
  if (fmt_app->parsed()) {
    return nomec::tools::run_fmt(fmt_command);
  }
  if (files.empty()) {
    std::cerr << "nomec: no input files (see nomec --help)\n";
    return 2;
  }
  pipeline.rule = rule == "derose" ? nomec::kernel::VertexRule::DeRose : nomec::kernel::VertexRule::CatmullClark;
  const bool emit_mesh = emit == "stl" || emit == "obj" || emit == "ply" || emit == "summary";
  nomec::tools::WhatIf what_if;
  if (!what_if_text.empty()) {
    std::string problem = nomec::tools::parse_what_if(what_if_text, what_if);
    if (problem.empty() && (!emit.empty() || files.size() != 1)) {
      problem = "--what-if takes exactly one input file and no --emit";
    }
    if (!problem.empty()) {
      std::cerr << "nomec: " << problem << "\n";
      return 2;
    }
  }
  if (!emit_mesh && ((pipeline.any() && what_if_text.empty()) || (!output.empty() && emit != "nome") || stl_ascii || time_report)) {
    std::cerr << "nomec: -o, --stl-ascii, --time-report, --merge, --subdivide, --offset and "
                 "--subdivide-after need --emit stl|obj|ply|summary\n";
    return 2;
  }
  if (!emit.empty() && files.size() != 1) {
    std::cerr << "nomec: --emit takes exactly one input file\n";
    return 2;
  }

  nomec::CheckOptions options;
  if (!dialect.empty()) {
    options.dialect = nomec::dialect_by_name(dialect);
  }
  options.allow_out_of_range = allow_out_of_range;
  options.time = time;
  options.frame = frame;
  if (!base.empty()) {
    options.base_file = base;
  }
  options.read_file = nomec::read_file_bytes;
  options.list_folder = nomec::list_folder;
  for (const std::string& d : defines) {
    auto eq = d.find('=');
    if (eq == std::string::npos || eq == 0) {
      std::cerr << fmt::format("nomec: -D expects bank.param=value, got `{}`\n", d);
      return 2;
    }
    char* end = nullptr;
    std::string value = d.substr(eq + 1);
    double v = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0') {
      std::cerr << fmt::format("nomec: -D {}: `{}` is not a number\n", d.substr(0, eq), value);
      return 2;
    }
    std::string name = d.substr(0, eq);
    options.overrides.emplace_back(name, v);
  }
  bool use_color = color == "always" || (color == "auto" && isatty(STDERR_FILENO) != 0);

  int errors = 0;
  nlohmann::json json_out = nlohmann::json::array();

  // Evaluates the checked scene, runs the --merge/--subdivide/--offset pipeline and writes
  // the requested format. Returns the number of errors (diagnostics or a failed write).
  auto emit_meshes = [&](const std::string& path, const nomec::SourceManager& sources,
                         const nomec::ir::Module& module, double check_ms) -> int {
    namespace be = nomec::backend;
    const bool progress = isatty(STDERR_FILENO) != 0;
    auto say = [&](std::string_view stage) {
      if (progress) {
        std::cerr << fmt::format("\r\033[Knomec: {}: {}…", path, stage) << std::flush;
      }
    };
    be::StageTimings timings;
    nomec::DiagnosticEngine geo;
    say("evaluate");
    std::vector<be::OutputMesh> meshes = be::evaluate_scene(module, geo, &timings, pipeline.max_vertices);
    if (geo.error_count() == 0 && pipeline.any()) {
      std::string stem = std::filesystem::path(path).stem().string();
      nomec::SourceRange where;
      if (!module.scene.empty()) {
        where = module.node(module.scene.front()).range;
      }
      meshes = be::run_pipeline(std::move(meshes), pipeline, stem, where, geo, &timings, say);
    }
    if (progress) {
      std::cerr << "\r\033[K" << std::flush;
    }
    geo.sort_and_dedupe();
    for (const auto& d : geo.diagnostics()) {
      if (format == "json") {
        json_out.back()["diagnostics"].push_back(diag_json(sources, d, werror));
      } else {
        std::cerr << nomec::render_text(sources, d, werror, use_color);
      }
    }
    if (geo.error_count() > 0) {
      return geo.error_count();
    }
    auto write_start = std::chrono::steady_clock::now();
    std::string target = output;
    std::string ext = emit == "summary" ? "json" : emit;
    if (target.empty()) {
      target = emit == "summary" ? "-" : std::filesystem::path(path).stem().string() + "." + ext;
    }
    std::string content;
    std::string mtl;
    if (emit == "stl") {
      content = stl_ascii ? be::to_stl_ascii(meshes) : be::to_stl_binary(meshes);
    } else if (emit == "ply") {
      content = be::to_ply(meshes);
    } else if (emit == "summary") {
      content = summary_json(path, meshes).dump(2) + "\n";
    } else {
      bool colored = std::any_of(meshes.begin(), meshes.end(),
                                 [](const be::OutputMesh& m) { return !m.soup.face_colors.empty(); });
      std::string mtl_name;
      if (target != "-" && colored) {
        mtl_name = std::filesystem::path(target).stem().string() + ".mtl";
        mtl = be::to_mtl(meshes);
      }
      content = be::to_obj(meshes, mtl_name);
    }
    int failed = 0;
    if (target == "-") {
      std::cout.write(content.data(), static_cast<std::streamsize>(content.size()));
      std::cout.flush();
    } else {
      std::string err = nomec::write_file_atomically(target, content);
      if (err.empty() && !mtl.empty()) {
        std::filesystem::path mtl_path = std::filesystem::path(target).replace_extension(".mtl");
        err = nomec::write_file_atomically(mtl_path.string(), mtl);
      }
      if (!err.empty()) {
        std::cerr << fmt::format("nomec: {}\n", err);
        failed = 1;
      }
    }
    double write_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - write_start).count();
    if (time_report) {
      double total = check_ms + timings.evaluate_ms + timings.merge_ms + timings.subdivide_ms +
                     timings.offset_ms + write_ms;
      std::cerr << fmt::format(
          "time report for {} (ms):\n  parse+check {:10.2f}\n  evaluate    {:10.2f}\n  merge       {:10.2f}\n"
          "  subdivide   {:10.2f}\n  offset      {:10.2f}\n  write       {:10.2f}\n  total       {:10.2f}\n",
          path, check_ms, timings.evaluate_ms, timings.merge_ms, timings.subdivide_ms, timings.offset_ms,
          write_ms, total);
    }
    return failed;
  };
  for (const std::string& path : files) {
    std::optional<std::string> text = nomec::read_file_bytes(path);
    if (!text) {
      std::cerr << fmt::format("nomec: cannot read `{}`\n", path);
      return 2;
    }
    nomec::SourceManager sources;
    nomec::DiagnosticEngine diags;
    auto check_start = std::chrono::steady_clock::now();
    nomec::CheckResult result = nomec::check_source(sources, path, std::move(*text), options, diags);
    double check_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - check_start).count();
    diags.sort_and_dedupe();
    if (format == "json") {
      nlohmann::json file = {{"file", path},
                             {"dialect", std::string(nomec::dialect_name(result.dialect))},
                             {"diagnostics", nlohmann::json::array()}};
      for (const auto& d : diags.diagnostics()) {
        file["diagnostics"].push_back(diag_json(sources, d, werror));
      }
      json_out.push_back(file);
    } else {
      for (const auto& d : diags.diagnostics()) {
        std::cerr << nomec::render_text(sources, d, werror, use_color);
      }
    }
    int file_errors = diags.error_count() + (werror ? diags.warning_count() : 0);
    errors += file_errors;
    if (verbose) {
      std::cerr << fmt::format("{}: dialect {} ({}){}; {} error(s), {} warning(s); {} IR nodes\n",
                               path, nomec::dialect_name(result.dialect), result.dialect_reason,
                               result.base_file.empty() ? "" : "; base " + result.base_file,
                               diags.error_count(), diags.warning_count(),
                               result.module.nodes.size());
    }
    if (emit == "ir") {
      std::cout << nomec::ir::dump_ir(result.module, sources);
    } else if (emit == "deps") {
      std::cout << nomec::ir::dump_deps_dot(result.module);
    } else if (emit == "nome" && file_errors == 0) {
      // The seed's "save": default target `scene.saved.nome` next to the working directory.
      std::filesystem::path p(path);
      std::string ext = p.extension() == ".anom" ? ".nome" : p.extension().string();
      std::string target = output.empty() ? p.stem().string() + ".saved" + ext : output;
      std::string content = nomec::backend::to_nome(result.module, sources, path);
      if (target == "-") {
        std::cout << content << std::flush;
      } else if (std::string err = nomec::write_file_atomically(target, content); !err.empty()) {
        std::cerr << fmt::format("nomec: {}\n", err);
        errors += 1;
      }
    } else if (emit_mesh && file_errors == 0) {
      errors += emit_meshes(path, sources, result.module, check_ms);
    } else if (!what_if_text.empty() && file_errors == 0) {
      nomec::DiagnosticEngine geo;
      errors += nomec::tools::run_what_if(path, std::move(result.module), what_if, pipeline,
                                          allow_out_of_range, geo, std::cout);
      geo.sort_and_dedupe();
      for (const auto& d : geo.diagnostics()) std::cerr << nomec::render_text(sources, d, werror, use_color);
      errors += geo.error_count();
    }
  }
  if (format == "json") {
    std::cout << json_out.dump(2) << "\n";
  }
  return errors > 0 ? 1 : 0;
}
