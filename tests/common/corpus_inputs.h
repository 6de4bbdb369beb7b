// Test inputs shared by the corpus sweeps (robustness, index): every file under the
// corpus's nome1/, nome3/ and slide/ folders and every example, sorted, plus a binary-safe
// file reader. The including target defines NOMEC_CORPUS_DIR and NOMEC_SOURCE_DIR; the
// `corpus_present` test fails when the corpus folder is missing, so these sweeps never pass
// over an empty list unnoticed.
#pragma once

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "frontend/source/source_manager.h"

namespace nomec::testing_inputs {

inline std::optional<std::string> read_file(const std::string& path) { return read_file_bytes(path); }

inline std::vector<std::string> corpus_and_examples() {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  const std::vector<fs::path> roots = {fs::path(NOMEC_CORPUS_DIR) / "nome1", fs::path(NOMEC_CORPUS_DIR) / "nome3",
                                       fs::path(NOMEC_CORPUS_DIR) / "slide", fs::path(NOMEC_SOURCE_DIR) / "examples"};
  for (const fs::path& root : roots) {
    std::error_code ec;
    for (const auto& e : fs::recursive_directory_iterator(root, ec)) {
      if (!e.is_regular_file() || e.path().extension() == ".md") continue;
      out.push_back(e.path().string());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace nomec::testing_inputs
