// `nomec --emit nome`: the seed report's "save" (see emit.h): the scene with its sliders'
// values written in place (backend/save.h), checked again before it is written, so a save
// never silently gives a slider another value than the one asked for.
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <optional>

#include "backend/save.h"
#include "base/file_io.h"
#include "frontend/flat/flat.h"
#include "frontend/source/file_kinds.h"
#include "tools/emit.h"

namespace nomec::tools {

namespace {

// `text` checked as the file `path` with `options` less its `-D` overrides; the result, or
// nullopt after setting `error` to its first error.
std::optional<CheckResult> check_plain(SourceManager& sources, const std::string& path, std::string text,
                                       CheckOptions options, std::string& error) {
  options.overrides.clear();
  DiagnosticEngine diags;
  CheckResult r = check_source(sources, path, std::move(text), options, diags);
  for (const Diagnostic& d : diags.diagnostics()) {
    if (d.severity == Severity::Error) {
      error = d.message;
      return std::nullopt;
    }
  }
  return r;
}

}  // namespace

int emit_nome(const Cli& cli, const std::string& path, const SourceManager& sources, const CheckResult& result,
              const CheckOptions& options, const std::vector<std::string>& inputs) {
  const std::filesystem::path p(path);
  // Saved work and flat mesh files are saved as NOME scenes.
  const bool as_nome = is_saved_work_path(path) || flat::format_of_path(path).has_value();
  const std::string ext = as_nome ? ".nome" : p.extension().string();
  const std::string target = cli.output.empty() ? p.stem().string() + ".saved" + ext : cli.output;
  if (std::string problem = output_is_input(target, inputs); !problem.empty()) {
    std::cerr << fmt::format("nomec: {}\n", problem);
    return 1;
  }
  // The file as written, to tell the moved sliders: the checked module itself without `-D`.
  SourceManager plain_sources;
  std::optional<CheckResult> plain;
  if (!options.overrides.empty()) {
    std::string main_text;
    for (size_t i = 0; i < sources.file_count(); ++i) {
      if (sources.name(FileId{static_cast<int32_t>(i)}) == path) main_text = sources.text(FileId{static_cast<int32_t>(i)});
    }
    std::string error;
    plain = check_plain(plain_sources, path, std::move(main_text), options, error);
    if (!plain) {
      std::cerr << fmt::format("nomec: `{}` does not check without its -D values: {}\n", path, error);
      return 1;
    }
  }
  const backend::SavedScene saved =
      backend::save_scene(result.module, plain ? plain->module : result.module, sources, path, result.base_file);
  // Checked again beside the original (where its includes and Tcl sources are) before it
  // is written: it must give every slider its value.
  const std::string beside = (p.parent_path() / (p.stem().string() + ".saved" + ext)).string();
  SourceManager back_sources;
  CheckOptions self_contained = options;
  self_contained.base_file.reset();  // saved work is saved with its base scene
  std::string error;
  std::optional<CheckResult> back = check_plain(back_sources, beside, saved.text, self_contained, error);
  std::vector<std::string> lost =
      back ? backend::lost_values(result.module, saved, back->module)
           : std::vector<std::string>{fmt::format("the saved text does not check: {}", error)};
  if (!lost.empty()) {
    for (const std::string& line : lost) std::cerr << fmt::format("nomec: {}\n", line);
    std::cerr << fmt::format("nomec: `{}` not saved: the saved file would not give these sliders their values\n", path);
    return 1;
  }
  if (target == "-") {
    std::cout << saved.text << std::flush;
    return 0;
  }
  if (std::string err = write_file_atomically(target, saved.text); !err.empty()) {
    std::cerr << fmt::format("nomec: {}\n", err);
    return 1;
  }
  return 0;
}

}  // namespace nomec::tools
