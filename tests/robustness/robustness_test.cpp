// Robustness: the front end must survive any bytes. For every corpus file (nome1, nome3,
// slide, and examples/, plus flat mesh files) the test checks the file cut at ~25 evenly spaced points and with
// ~25 deterministic random edits (fixed seed: insertions, deletions, random bytes including
// 0x00 and invalid UTF-8, and fragments that open or close constructs), calling
// `nomec::check_source` directly. Each run must return without throwing, and every
// diagnostic, note and fix-it range must lie inside a file the SourceManager holds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "frontend/check/check.h"
#include "tests/common/corpus_inputs.h"

namespace fs = std::filesystem;

namespace {

using nomec::testing_inputs::read_file;
// The corpus, the examples, and flat mesh files: the corpus' `.sif` meshes and the inputs of
// the flat readers' tests (`.sif`, `.obj`, binary and ASCII `.stl`).
std::vector<std::string> input_files() {
  std::vector<std::string> files = nomec::testing_inputs::corpus_and_examples();
  for (const fs::path& root : {fs::path(NOMEC_CORPUS_DIR) / "nome1", fs::path(NOMEC_SOURCE_DIR) / "tests/check/inputs/flat"}) {
    std::error_code ec;
    for (const auto& e : fs::recursive_directory_iterator(root, ec)) {
      const std::string ext = e.path().extension().string();
      if (e.is_regular_file() && (ext == ".sif" || ext == ".obj" || ext == ".stl")) files.push_back(e.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Checks one text as if it were the file at `path`; returns a failure description or "".
std::string check_one(const std::string& path, std::string text) {
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  nomec::CheckOptions options;
  options.read_file = read_file;
  options.list_folder = nomec::list_folder;
  try {
    nomec::check_source(sources, path, std::move(text), options, diags);
    diags.sort_and_dedupe();
  } catch (const std::exception& e) {
    return std::string("check_source threw: ") + e.what();
  } catch (...) {
    return "check_source threw a non-standard exception";
  }
  auto inside = [&](const nomec::SourceRange& r) {
    if (!r.is_valid()) return true;  // diagnostics without a location (e.g. `-D`) are fine
    if (static_cast<size_t>(r.file.index) >= sources.file_count()) return false;
    return r.begin <= r.end && r.end <= sources.text(r.file).size();
  };
  auto show = [&](const nomec::SourceRange& r) {
    return "[" + std::to_string(r.file.index) + ": " + std::to_string(r.begin) + ", " + std::to_string(r.end) + ")";
  };
  for (const nomec::Diagnostic& d : diags.diagnostics()) {
    std::string kind(nomec::diag_kind_name(d.kind));
    if (!inside(d.range)) return kind + " range " + show(d.range) + " is outside its file: " + d.message;
    for (const auto& n : d.notes) {
      if (!inside(n.range)) return kind + " note range " + show(n.range) + " is outside its file: " + n.message;
    }
    for (const auto& f : d.fixits) {
      if (!inside(f.range)) return kind + " fix-it range " + show(f.range) + " is outside its file";
    }
  }
  return "";
}

// Deterministic edits. std::mt19937 is fully specified; only the distribution helpers
// vary between standard libraries, so bytes are derived from raw engine output.
std::string mutate(const std::string& text, uint32_t seed) {
  static const std::vector<std::string> fragments = {
      "(*", "*)", "{", "}", "(", ")", "[", "]", "\"", "$", "tclinit {", "endmesh", "mesh",
      "instance", "endinstance", "{expr", "-", "^", "/0", "\xC3", "\xE2\x82", "\xFF\xFE", std::string(1, '\0'),
      "\r\n", "#", ",", ";", ".", "..", "_", "1e999", "-0.5*$b.w"};
  std::mt19937 rng(seed);
  std::string out = text;
  int edits = 1 + static_cast<int>(rng() % 4);
  for (int e = 0; e < edits; ++e) {
    size_t at = out.empty() ? 0 : rng() % (out.size() + 1);
    switch (rng() % 5) {
      case 0:  // insert a random byte (any value, including 0x00 and 0x80-0xFF)
        out.insert(at, 1, static_cast<char>(rng() & 0xFF));
        break;
      case 1: {  // delete a short range
        size_t len = 1 + rng() % 16;
        if (at < out.size()) out.erase(at, std::min(len, out.size() - at));
        break;
      }
      case 2:  // overwrite a byte
        if (at < out.size()) out[at] = static_cast<char>(rng() & 0xFF);
        break;
      case 3:  // insert a fragment that opens or closes a construct
        out.insert(at, fragments[rng() % fragments.size()]);
        break;
      default: {  // duplicate a slice somewhere else
        if (out.empty()) break;
        size_t from = rng() % out.size();
        size_t len = std::min<size_t>(1 + rng() % 64, out.size() - from);
        out.insert(at, out.substr(from, len));
        break;
      }
    }
  }
  return out;
}

class Robustness : public ::testing::TestWithParam<std::string> {};

constexpr int kCuts = 25;
// NOMEC_ROBUSTNESS_MUTATIONS=N raises the number of mutations per file for a longer local
// hunt; ctest runs the default.
int mutation_count() {
  const char* env = std::getenv("NOMEC_ROBUSTNESS_MUTATIONS");
  int n = env != nullptr ? std::atoi(env) : 0;
  return n > 0 ? n : 25;
}

TEST_P(Robustness, TruncatedFile) {
  const std::string& path = GetParam();
  std::optional<std::string> text = read_file(path);
  ASSERT_TRUE(text.has_value()) << path;
  for (int i = 0; i <= kCuts; ++i) {
    size_t cut = text->size() * i / kCuts;
    std::string failure = check_one(path, text->substr(0, cut));
    EXPECT_EQ(failure, "") << path << " cut at byte " << cut;
  }
}

TEST_P(Robustness, MutatedFile) {
  const std::string& path = GetParam();
  std::optional<std::string> text = read_file(path);
  ASSERT_TRUE(text.has_value()) << path;
  for (int i = 0, n = mutation_count(); i < n; ++i) {
    uint32_t seed = 0x5EED0000u + static_cast<uint32_t>(i);
    std::string failure = check_one(path, mutate(*text, seed));
    EXPECT_EQ(failure, "") << path << " mutated with seed " << std::hex << seed;
  }
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string rel = fs::relative(info.param, fs::path(info.param).parent_path().parent_path()).string();
  std::string out;
  for (char c : rel) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out + "_" + std::to_string(info.index);
}

INSTANTIATE_TEST_SUITE_P(Corpus, Robustness, ::testing::ValuesIn(input_files()), test_name);

// Token soup: random sequences of keywords, end keywords, names, numbers and punctuation
// (fixed seed), which reach parser recovery paths that edits of real files rarely do.
TEST(Robustness, TokenSoup) {
  static const std::vector<std::string> tokens = {
      "mesh", "endmesh", "point", "endpoint", "face", "endface", "group", "endgroup",
      "instance", "endinstance", "bank", "endbank", "set", "list", "funnel", "endfunnel",
      "tunnel", "endtunnel", "surface", "endsurface", "subdivision", "endsubdivision",
      "sweep", "endsweep", "crosssection", "endcrosssection", "path", "endpath", "sharp",
      "endsharp", "delete", "enddelete", "consolidate", "endconsolidate", "consolidateface",
      "endconsolidateface", "vertex", "endvertex", "savedparameter", "endsavedparameter",
      "camera", "endcamera", "include", "tclinit {", "}", "{", "{expr", "(", ")", "[", "]",
      "(*", "*)", "#", "\n", "\"s\"", "$b.w", "$b_n", "$o(t)", "b", "n", "p", "m", "x.y.hc1",
      "fun_hc1", "1", "-1", "0.5", ".5", "1e3", "-0.5*$b.w", "+", "-", "*", "/", "//", "%",
      "^", ",", ";", "translate", "rotate", "scale", "color", "sd_type", "isloop", "id",
      "\xC3", std::string(1, '\0')};
  std::mt19937 rng(0x70CE5u);
  const char* env = std::getenv("NOMEC_ROBUSTNESS_SOUP");  // more rounds for a local hunt
  int rounds = env != nullptr && std::atoi(env) > 0 ? std::atoi(env) : 400;
  for (int round = 0; round < rounds; ++round) {
    std::string text;
    int n = 1 + static_cast<int>(rng() % 60);
    for (int i = 0; i < n; ++i) {
      const std::string& t = tokens[rng() % tokens.size()];
      text += t;
      text += (rng() % 4 == 0) ? "" : " ";
    }
    for (const char* path : {"soup.nome", "soup.nom", "soup.slf"}) {
      std::string failure = check_one(path, text);
      EXPECT_EQ(failure, "") << path << " round " << round << ":\n" << text;
    }
  }
}

TEST(Robustness, FoundInputs) { EXPECT_GE(input_files().size(), 50u); }

}  // namespace
