// Test inputs shared by the corpus sweeps (robustness, index, parse cache, formatter):
// every scene file (chosen by extension with `nomec::is_scene_path`: not the `.tcl` helpers
// SLIDE files `source`, nor `.sif` meshes) under the corpus's nome1/, nome3/ and slide/
// folders and the examples, sorted, plus a binary-safe file reader. The including target defines NOMEC_CORPUS_DIR and NOMEC_SOURCE_DIR; the
// `corpus_present` test fails when the corpus folder is missing, so these sweeps never pass
// over an empty list unnoticed.
#pragma once

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "base/file_io.h"
#include "frontend/source/file_kinds.h"
#include "frontend/source/source_manager.h"

namespace nomec::testing_inputs {

inline std::optional<std::string> read_file(const std::string& path) { return read_file_bytes(path); }

/// Every file under `root` (recursively), scene or not, sorted: golden inputs, fuzz corpora.
inline std::vector<std::string> files_under(const std::filesystem::path& root) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : std::filesystem::recursive_directory_iterator(root, ec)) {
    if (e.is_regular_file()) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// Every scene file under `roots` (recursively), sorted.
inline std::vector<std::string> scene_files_under(const std::vector<std::filesystem::path>& roots) {
  std::vector<std::string> out;
  for (const std::filesystem::path& root : roots) {
    std::error_code ec;
    for (const auto& e : std::filesystem::recursive_directory_iterator(root, ec)) {
      if (e.is_regular_file() && is_scene_path(e.path().string())) out.push_back(e.path().string());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// The corpus's scene files (nome1/, nome3/, slide/), sorted.
inline std::vector<std::string> corpus_scenes() {
  namespace fs = std::filesystem;
  return scene_files_under({fs::path(NOMEC_CORPUS_DIR) / "nome1", fs::path(NOMEC_CORPUS_DIR) / "nome3",
                            fs::path(NOMEC_CORPUS_DIR) / "slide"});
}

/// The corpus's scene files and the examples, sorted.
inline std::vector<std::string> corpus_and_examples() {
  namespace fs = std::filesystem;
  return scene_files_under({fs::path(NOMEC_CORPUS_DIR) / "nome1", fs::path(NOMEC_CORPUS_DIR) / "nome3",
                            fs::path(NOMEC_CORPUS_DIR) / "slide", fs::path(NOMEC_SOURCE_DIR) / "examples"});
}

/// Every golden test input (the parse, check and IR goldens' folders in that order, each
/// sorted), whatever its extension.
inline std::vector<std::string> golden_inputs() {
  std::vector<std::string> out;
  for (const char* folder : {"tests/parse", "tests/check", "tests/ir"}) {
    std::vector<std::string> files = files_under(std::filesystem::path(NOMEC_SOURCE_DIR) / folder);
    out.insert(out.end(), files.begin(), files.end());
  }
  return out;
}

}  // namespace nomec::testing_inputs
