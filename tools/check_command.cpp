// `nomec FILE…`: checks each file and shows its diagnostics, then does what `--emit` or
// `--what-if` asks for on a file without errors (see cli.h). Exit codes: 0 clean, 1 errors,
// 2 usage or unreadable input (not a regular file or standard input, or past --max-file-size).
#include <chrono>
#include <fmt/format.h>
#include <iostream>
#include <unistd.h>

#include "base/file_io.h"
#include "frontend/parse/parse.h"
#include "tools/allocator.h"
#include "tools/cli.h"
#include "tools/emit.h"
#include "tools/what_if.h"

namespace nomec::tools {

namespace {

// What follows the check of one file; returns the errors it adds.
int after_check(const Cli& cli, const std::string& path, const SourceManager& sources, CheckResult& result,
                const CheckOptions& options, const std::vector<std::string>& inputs, double check_ms,
                DiagnosticOutput& out, const WhatIf& what_if) {
  if (cli.emit == "ir") {
    std::cout << ir::dump_ir(result.module, sources);
    return 0;
  }
  if (cli.emit == "deps") {
    std::cout << ir::dump_deps_dot(result.module);
    return 0;
  }
  if (cli.emit == "nome") return emit_nome(cli, path, sources, result, options, inputs);
  if (cli.emits_mesh()) return emit_meshes(cli, path, sources, result.module, inputs, check_ms, out);
  if (cli.what_if.empty()) return 0;
  DiagnosticEngine geo;
  int errors = run_what_if(path, std::move(result.module), what_if, cli.pipeline, cli.allow_out_of_range, geo, std::cout);
  geo.sort_and_dedupe();
  out.show(sources, geo);
  return errors + geo.error_count();
}

}  // namespace

int run_check_command(const Cli& cli) {
  CheckOptions options;
  WhatIf what_if;
  std::string problem = check_options(cli, options);
  // Nothing after the check reads the syntax tree: a large file is checked in pieces, each
  // tree freed once lowered (peak memory, bench/frontend/README.md).
  options.piece_bytes = kCheckPieceBytes;
  if (problem.empty() && !cli.what_if.empty()) problem = parse_what_if(cli.what_if, what_if);
  if (!problem.empty()) {
    std::cerr << "nomec: " << problem << "\n";
    return 2;
  }
  // Every file the check reads (includes, a base scene, meshes, Tcl sources) is recorded:
  // an output must not overwrite any of them (output_is_input).
  std::vector<std::string> inputs;
  const CheckOptions unrecorded = options;
  if (options.read_file) {
    options.read_file = [&inputs, read = options.read_file](const std::string& file) {
      inputs.push_back(file);
      return read(file);
    };
  }
  if (options.read_beneath) {  // what SLIDE's Tcl sources and imports next to the scene
    options.read_beneath = [&inputs, read = options.read_beneath](const std::string& folder, const std::string& name) {
      inputs.push_back(folder.empty() || folder.back() == '/' ? folder + name : folder + "/" + name);
      return read(folder, name);
    };
  }
  const bool color = cli.color == "always" || (cli.color == "auto" && isatty(STDERR_FILENO) != 0);
  DiagnosticOutput out(cli.format == "json", cli.werror, color);
  int errors = 0;
  for (const std::string& path : cli.files) {
    inputs.assign(1, path);
    // A regular file under the cap: a FIFO or device is refused without waiting on it. The
    // one stream read is standard input, named `-` or `/dev/stdin` (a pipe the user means).
    const int64_t cap = is_mesh_file_path(path) ? cli.max_mesh_bytes : cli.max_file_bytes;
    FileRead input = path == "-" || path == "/dev/stdin" ? read_input_stream(STDIN_FILENO, path, cli.max_file_bytes)
                                                         : read_input_file(path, cap);
    if (!input.ok()) {
      std::cerr << fmt::format("nomec: {}\n", input.error);
      return 2;
    }
    std::optional<std::string> text = std::move(input.bytes);
    SourceManager sources;
    DiagnosticEngine diags;
    const auto start = std::chrono::steady_clock::now();
    CheckResult result = check_source(sources, path, std::move(*text), options, diags);
    const double check_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    // The meshes built after the check want huge pages (tools/allocator.h).
    if (cli.emits_mesh() || !cli.what_if.empty()) use_huge_pages_from_now();
    diags.sort_and_dedupe();
    out.begin_file(path, dialect_name(result.dialect));
    out.show(sources, diags);
    const int file_errors = diags.error_count() + (cli.werror ? diags.warning_count() : 0);
    errors += file_errors;
    if (cli.verbose) {
      std::cerr << fmt::format("{}: dialect {} ({}){}; {} error(s), {} warning(s); {} IR nodes\n", path,
                               dialect_name(result.dialect), result.dialect_reason,
                               result.base_file.empty() ? "" : "; base " + result.base_file, diags.error_count(),
                               diags.warning_count(), result.module.nodes.size());
    }
    const bool dumps = cli.emit == "ir" || cli.emit == "deps";  // shown even for files with errors
    if (dumps || file_errors == 0) {
      errors += after_check(cli, path, sources, result, unrecorded, inputs, check_ms, out, what_if);
    }
  }
  out.finish(std::cout);
  return errors > 0 ? 1 : 0;
}

}  // namespace nomec::tools
