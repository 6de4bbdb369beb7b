// Test inputs shared by the corpus sweeps (robustness, index): every file under the
// corpus's nome1/, nome3/ and slide/ folders and every example, sorted, plus a binary-safe
// file reader. The including target defines NOMEC_CORPUS_DIR and NOMEC_SOURCE_DIR; the
// `corpus_present` test fails when the corpus folder is missing, so these sweeps never pass
// over an empty list unnoticed.
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace nomec::testing_inputs {

inline std::optional<std::string> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

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
