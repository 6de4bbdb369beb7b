// The `nomec` command line: checks NOME/NOME3/SLIDE files and prints diagnostics (text like
// clang, or JSON), or emits the IR dump or the dependency graph. The first client of the
// nomec libraries; it knows only what they expose.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unistd.h>

#include "frontend/check/check.h"
#include "ir/ir.h"

namespace {

std::optional<std::string> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return std::nullopt;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"nomec: compiler for NOME, NOME3 and SLIDE scene files"};
  app.set_version_flag("--version", std::string("nomec ") + NOMEC_VERSION);
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
  app.add_option("files", files, "Input files (.nome, .nom, .slf, .anom)")->required();
  app.add_flag("--check", check_only, "Check the files and report diagnostics (default)");
  app.add_option("--emit", emit, "Emit `ir` (readable typed IR) or `deps` (DOT graph)")
      ->check(CLI::IsMember({"ir", "deps"}));
  app.add_option("--dialect", dialect, "Force the dialect instead of detecting it")
      ->check(CLI::IsMember({"nome", "nome3", "slide"}));
  app.add_option("-D", defines, "Override a slider: -D bank.param=value (repeatable)");
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
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return e.get_exit_code() == 0 ? code : 2;
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
  options.read_file = read_file;
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
  for (const std::string& path : files) {
    std::optional<std::string> text = read_file(path);
    if (!text) {
      std::cerr << fmt::format("nomec: cannot read `{}`\n", path);
      return 2;
    }
    nomec::SourceManager sources;
    nomec::DiagnosticEngine diags;
    nomec::CheckResult result = nomec::check_source(sources, path, std::move(*text), options, diags);
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
    }
  }
  if (format == "json") {
    std::cout << json_out.dump(2) << "\n";
  }
  return errors > 0 ? 1 : 0;
}
