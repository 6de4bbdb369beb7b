// The `nomec` command line read by CLI11 (see cli.h): option definitions, the checks
// between options, and the check options they amount to.
#include "tools/cli.h"

#include <cmath>
#include <CLI/CLI.hpp>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fmt/format.h>
#include <iostream>

#include "base/file_io.h"
#include "base/read_beneath.h"
#include "tools/allocator.h"

namespace nomec::tools {

std::optional<double> parse_finite_number(const std::string& text) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

namespace {

// CLI11 reads `nan`, `inf` and `1e999999` (as infinity) into a double option; this check,
// run on the option's text before that, refuses them (a usage error, exit 2).
const CLI::Validator kFiniteNumber(
    [](const std::string& text) -> std::string {
      return parse_finite_number(text) ? std::string() : fmt::format("`{}` is not a finite number", text);
    },
    "FINITE");

void add_fmt_command(CLI::App& app, Cli& cli, CLI::App*& fmt_app) {
  fmt_app = app.add_subcommand("fmt", "Format files: print (one file), --check or -i");
  fmt_app->add_option("files", cli.fmt.files, "Files to format (`-` = standard input)")->required();
  fmt_app->add_flag("-i,--in-place", cli.fmt.in_place, "Rewrite changed files in place (atomically)");
  fmt_app->add_flag("--check", cli.fmt.check, "List files that would change; exit 1 if any");
  fmt_app->add_option("--indent", cli.fmt.indent_width, "Spaces per indentation level (default 4)")
      ->check(CLI::Range(0, 16));
  fmt_app->add_flag("--tabs", cli.fmt.use_tabs, "Indent with tabs");
  fmt_app->add_option("--max-file-size", cli.fmt.max_file_bytes, "Largest file read, e.g. 16M (default 2M)")
      ->transform(CLI::AsSizeValue(false))
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 40));
}

void add_view_command(CLI::App& app, Cli& cli, CLI::App*& view_app) {
  view_app = app.add_subcommand("view", "Live 3D preview in the browser, served on 127.0.0.1; reloads on save");
  view_app->add_option("file", cli.view.file, "The scene to show")->required();
  view_app->add_option("--port", cli.view.port, "Port on 127.0.0.1 (default 8642; 0 = any free port)")
      ->check(CLI::Range(0, 65535));
  view_app->add_flag("--open", cli.view.open, "Open the page in the default browser (xdg-open)");
  view_app->add_option("--app-dir", cli.view.app_dir, "Folder of the built preview app (index.html, app.js)");
}

void add_emit_options(CLI::App& app, Cli& cli) {
  app.add_option("--emit", cli.emit,
                 "Emit `ir` (readable typed IR), `deps` (DOT graph), a mesh (`stl`, `obj`, `ply`) "
                 "`summary` (JSON topology per output mesh) or `nome` (the scene saved with its "
                 "current slider values)")
      ->check(CLI::IsMember({"ir", "deps", "stl", "obj", "ply", "summary", "nome"}));
  app.add_option("-o", cli.output, "Output file (`-` = standard output); default: the input's "
                                   "basename with the format's extension (summary: standard output)");
  app.add_flag("--stl-ascii", cli.stl_ascii, "Write ASCII STL instead of binary");
  app.add_flag("--merge", cli.pipeline.is_merge, "Merge coinciding boundary edges of the whole scene");
  app.add_option("--merge-tolerance", cli.pipeline.merge_tolerance,
                 "Merge tolerance (default 1e-4 x bounding-box diagonal)")
      ->check(kFiniteNumber)
      ->check(CLI::NonNegativeNumber);
  app.add_option("--subdivide", cli.pipeline.subdivide_levels, "Catmull-Clark levels after merging")
      ->check(CLI::Range(0, 12));
  app.add_option("--rule", cli.rule, "Smooth-vertex rule: catmull-clark or derose")
      ->check(CLI::IsMember({"catmull-clark", "derose"}));
  app.add_option("--offset", cli.pipeline.offset_height,
                 "Offset the (merged, subdivided) scene into a slab of this half-thickness")
      ->check(kFiniteNumber)
      ->check(CLI::PositiveNumber);
  app.add_option("--subdivide-after", cli.pipeline.subdivide_after_levels, "Catmull-Clark levels after the offset")
      ->check(CLI::Range(0, 12));
  app.add_flag("--time-report", cli.time_report, "Print the time of each stage to stderr");
  app.add_option("--max-vertices", cli.pipeline.max_vertices,
                 "Most vertices evaluation may build (placed geometry and subdivisions); default 1000000")
      ->check(CLI::Range(int64_t{1}, int64_t{2'000'000'000}));
  app.add_option("--what-if", cli.what_if,
                 "Move one slider (bank.param=value) after a full build and print, as JSON, what "
                 "the incremental update re-evaluated and its time next to the full build's");
}

void add_check_options(CLI::App& app, Cli& cli) {
  app.add_option("files", cli.files, "Input files (.nome, .nom, .slf, .anom; flat meshes .sif, .obj, .stl)");
  app.add_flag("--check", cli.check_only, "Check the files and report diagnostics (default)");
  app.add_option("--dialect", cli.dialect, "Force the dialect instead of detecting it")
      ->check(CLI::IsMember({"nome", "nome2", "nome3", "slide"}));
  app.add_option("-D", cli.defines, "Override a slider: -D bank.param=value (repeatable)")
      ->allow_extra_args(false);  // one value per -D: the files that follow stay files
  app.add_flag("--werror", cli.werror, "Treat warnings as errors");
  app.add_flag("--allow-out-of-range", cli.allow_out_of_range, "Accept -D values outside the slider range");
  app.add_option("--diagnostics-format", cli.format, "Diagnostics as `text` or `json`")
      ->check(CLI::IsMember({"text", "json"}));
  app.add_option("--base", cli.base, "Base scene for a saved-work .anom file");
  app.add_flag("--sif-quads", cli.sif_quads,
               "Read .sif triangles in consecutive pairs that share an edge as quads (NOME 2016 had this off)");
  app.add_option("--color", cli.color, "Colour diagnostics: auto, always, never")
      ->check(CLI::IsMember({"auto", "always", "never"}));
  app.add_option("--time", cli.time, "Value of `$time` in expressions (default 0)")->check(kFiniteNumber);
  app.add_option("--frame", cli.frame, "Value of `$frame` in expressions (default 0)")->check(kFiniteNumber);
  app.add_option("--tcl-seconds", cli.tcl_seconds,
                 "Wall time in seconds a SLIDE file's Tcl may take in all (default 10)")
      ->check(CLI::Range(0.001, 86400.0));
  app.add_flag("--no-tcl", cli.no_tcl, "Do not run SLIDE files' Tcl (check a file from a stranger without running its code)");
  app.add_flag("-v,--verbose", cli.verbose, "Report the dialect used and summary counts");
  app.add_option("--max-file-size", cli.max_file_bytes,
                 "Most bytes read for one scene: a file, and a file with all it includes (each time) and its base "
                 "scene; e.g. 16M (default 2M)")
      ->transform(CLI::AsSizeValue(false))
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 40));
  app.add_option("--max-mesh-size", cli.max_mesh_bytes,
                 "The same for flat mesh files (.stl, .obj, .sif) a scene is or reads; e.g. 256M (default 64M)")
      ->transform(CLI::AsSizeValue(false))
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 40));
}

// The rules between options CLI11 cannot express; "" or the usage error.
std::string combination_problem(const Cli& cli) {
  if (cli.files.empty()) return "no input files (see nomec --help)";
  if (!cli.what_if.empty() && (!cli.emit.empty() || cli.files.size() != 1)) {
    return "--what-if takes exactly one input file and no --emit";
  }
  if (!cli.emits_mesh() && ((cli.pipeline.any() && cli.what_if.empty()) ||
                            (!cli.output.empty() && cli.emit != "nome") || cli.stl_ascii || cli.time_report)) {
    return "-o, --stl-ascii, --time-report, --merge, --subdivide, --offset and --subdivide-after need "
           "--emit stl|obj|ply|summary";
  }
  if (!cli.emit.empty() && cli.files.size() != 1) return "--emit takes exactly one input file";
  return {};
}

}  // namespace

int parse_command_line(int argc, char** argv, Cli& cli) {
  CLI::App app{"nomec: compiler for NOME, NOME3 and SLIDE scene files"};
  app.set_version_flag("--version", fmt::format("nomec {} (allocator: {})", NOMEC_VERSION, allocator_name()));
  CLI::App* fmt_app = nullptr;
  add_fmt_command(app, cli, fmt_app);
  CLI::App* view_app = nullptr;
  add_view_command(app, cli, view_app);
  add_check_options(app, cli);
  add_emit_options(app, cli);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return e.get_exit_code() == 0 ? code : 2;
  }
  cli.is_fmt = fmt_app->parsed();
  if (cli.is_fmt) return -1;
  cli.is_view = view_app->parsed();
  if (cli.is_view) return -1;
  cli.pipeline.rule = cli.rule == "derose" ? kernel::VertexRule::DeRose : kernel::VertexRule::CatmullClark;
  if (std::string problem = combination_problem(cli); !problem.empty()) {
    std::cerr << "nomec: " << problem << "\n";
    return 2;
  }
  return -1;
}

std::string check_options(const Cli& cli, CheckOptions& options) {
  if (!cli.dialect.empty()) options.dialect = dialect_by_name(cli.dialect);
  options.allow_out_of_range = cli.allow_out_of_range;
  options.sif_quads = cli.sif_quads;
  options.time = cli.time;
  options.frame = cli.frame;
  options.tcl_milliseconds = static_cast<int>(std::lround(cli.tcl_seconds * 1000));
  options.run_tcl = !cli.no_tcl;
  if (!cli.base.empty()) options.base_file = cli.base;
  InputReader reader = input_reader(cli.max_file_bytes, cli.max_mesh_bytes);
  options.read_file = std::move(reader.read);
  options.read_problem = std::move(reader.problem);
  options.max_input_bytes = cli.max_file_bytes;
  options.max_mesh_bytes = cli.max_mesh_bytes;
  options.read_beneath = [max = static_cast<size_t>(cli.max_file_bytes)](const std::string& folder, const std::string& name) {
    return read_file_beneath(folder, name, max);
  };
  options.list_folder = list_folder;
  for (const std::string& d : cli.defines) {
    const auto eq = d.find('=');
    if (eq == std::string::npos || eq == 0) return fmt::format("-D expects bank.param=value, got `{}`", d);
    const std::string value = d.substr(eq + 1);
    const std::optional<double> v = parse_finite_number(value);
    if (!v) return fmt::format("-D {}: `{}` is not a finite number", d.substr(0, eq), value);
    options.overrides.emplace_back(d.substr(0, eq), *v);
  }
  return {};
}

std::string output_is_input(const std::string& target, const std::vector<std::string>& inputs) {
  if (target == "-") return {};
  for (const std::string& input : inputs) {
    if (is_same_file(target, input)) {
      return target == input
                 ? fmt::format("refusing to overwrite the input `{}`; nothing written (name another output with -o)", input)
                 : fmt::format("refusing to overwrite the input `{}` with the output `{}` (the same file); nothing "
                               "written (name another output with -o)",
                               input, target);
    }
  }
  return {};
}

}  // namespace nomec::tools
