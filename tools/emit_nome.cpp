// `nomec --emit nome`: the seed report's "save" (see emit.h).
#include <filesystem>
#include <fmt/format.h>
#include <iostream>

#include "backend/save.h"
#include "base/file_io.h"
#include "frontend/flat/flat.h"
#include "tools/emit.h"

namespace nomec::tools {

int emit_nome(const Cli& cli, const std::string& path, const SourceManager& sources, const ir::Module& module) {
  const std::filesystem::path p(path);
  // Saved work and flat mesh files are saved as NOME scenes.
  const bool as_nome = p.extension() == ".anom" || flat::format_of_path(path).has_value();
  const std::string ext = as_nome ? ".nome" : p.extension().string();
  const std::string target = cli.output.empty() ? p.stem().string() + ".saved" + ext : cli.output;
  const std::string content = backend::to_nome(module, sources, path);
  if (target == "-") {
    std::cout << content << std::flush;
    return 0;
  }
  if (std::string err = write_file_atomically(target, content); !err.empty()) {
    std::cerr << fmt::format("nomec: {}\n", err);
    return 1;
  }
  return 0;
}

}  // namespace nomec::tools
