// Formatter tests: golden before/after pairs (golden/NAME.in.EXT -> NAME.out.EXT; rewrite
// with NOMEC_UPDATE_GOLDEN=1), and properties over every corpus file, example and test
// input: idempotence, the same IR (locations stripped), the same comments in the same
// order; files with syntax errors are refused with `line:col`.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <regex>
#include <string>
#include <vector>

#include "base/file_io.h"
#include "frontend/source/source_manager.h"
#include "frontend/check/check.h"
#include "frontend/format/format.h"
#include "frontend/parse/parse.h"
#include "ir/ir.h"
#include "tests/common/corpus_inputs.h"

namespace fs = std::filesystem;
using nomec::format_source;
using nomec::FormatOptions;

namespace {

std::string read(const fs::path& p) { return nomec::read_file_bytes(p.string()).value(); }

// Every corpus file, example and test input (including this folder's goldens).
std::vector<fs::path> all_inputs() {
  std::vector<fs::path> out;
  for (const std::string& p : nomec::testing_inputs::scene_files_under(
           {fs::path(NOMEC_CORPUS_DIR), fs::path(NOMEC_SOURCE_DIR) / "examples", fs::path(NOMEC_SOURCE_DIR) / "tests"})) {
    out.emplace_back(p);
  }
  return out;
}

// `--emit ir` without source locations (the `  # line:col` suffixes).
std::string ir_without_locations(const std::string& path, const std::string& text) {
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  nomec::CheckResult r = nomec::check_source(sources, path, text, nomec::CheckOptions{}, diags);
  static const std::regex location("  # [0-9]+:[0-9]+");
  return std::regex_replace(nomec::ir::dump_ir(r.module, sources), location, "");
}

std::vector<std::string> comments(std::string_view text) {
  std::vector<std::string> out;
  for (const nomec::LexToken& t : nomec::lex_file(text)) {
    if (t.kind == nomec::LexKind::LineComment || t.kind == nomec::LexKind::BlockComment) {
      std::string c(text.substr(t.begin, t.end - t.begin));
      while (!c.empty() && std::isspace(static_cast<unsigned char>(c.back()))) c.pop_back();
      out.push_back(c);
    }
  }
  return out;
}

TEST(FormatGolden, EveryPairMatches) {
  fs::path dir = fs::path(NOMEC_SOURCE_DIR) / "tests/format/golden";
  bool update = std::getenv("NOMEC_UPDATE_GOLDEN") != nullptr;
  int pairs = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::string name = e.path().filename().string();
    size_t at = name.find(".in.");
    if (at == std::string::npos) continue;
    ++pairs;
    fs::path expected_path = dir / (name.substr(0, at) + ".out." + name.substr(at + 4));
    nomec::FormatResult r = format_source(read(e.path()));
    ASSERT_TRUE(r.ok) << name << ": " << r.error;
    if (update) {
      std::ofstream(expected_path, std::ios::binary) << r.text;
      continue;
    }
    EXPECT_EQ(r.text, read(expected_path)) << name;
    nomec::FormatResult again = format_source(r.text);
    ASSERT_TRUE(again.ok) << name;
    EXPECT_EQ(again.text, r.text) << name << " is not idempotent";
  }
  EXPECT_GE(pairs, 12);
}

// Idempotence, meaning and comments over every real file we have.
TEST(FormatProperties, CorpusExamplesAndTestInputs) {
  std::vector<fs::path> files = all_inputs();
  ASSERT_GT(files.size(), 100u);
  int formatted = 0;
  int refused = 0;
  for (const fs::path& p : files) {
    std::string text = read(p);
    nomec::FormatResult r = format_source(text);
    if (!r.ok) {
      ++refused;
      EXPECT_TRUE(std::regex_search(r.error, std::regex("^[0-9]+:[0-9]+: "))) << p << ": " << r.error;
      EXPECT_EQ(r.error.find("meaning"), std::string::npos) << p << ": " << r.error;
      continue;
    }
    ++formatted;
    nomec::FormatResult again = format_source(r.text);
    ASSERT_TRUE(again.ok) << p << ": " << again.error;
    EXPECT_EQ(again.text, r.text) << p << " is not idempotent";
    EXPECT_EQ(ir_without_locations(p.string(), r.text), ir_without_locations(p.string(), text))
        << p << ": the IR changed";
    EXPECT_EQ(comments(r.text), comments(text)) << p << ": comments changed";
  }
  // Most files parse; the refused ones are the syntax-error test inputs.
  EXPECT_GT(formatted, 100);
  EXPECT_GT(refused, 10);
}

TEST(FormatRefuses, SyntaxErrorsWithTheirLocation) {
  struct Case {
    const char* text;
    const char* where;
  };
  for (Case c : {Case{"point p (0 0 0 endpoint\n", "1:"},
                 Case{"mesh m\n  face f (a b c) endface\n", "1:1:"},
                 Case{"point p (0 0 0) endpoint\n(* never closed\n", "2:1:"},
                 Case{"point p (0 0 0) endpoint\nendmesh\n", "2:1:"}}) {
    nomec::FormatResult r = format_source(c.text);
    EXPECT_FALSE(r.ok) << c.text;
    EXPECT_TRUE(r.text.empty());
    EXPECT_EQ(r.error.rfind(c.where, 0), 0u) << c.text << " -> " << r.error;
  }
}

TEST(FormatOptions, IndentWidthAndTabs) {
  std::string text = "group g\ninstance i m endinstance\nendgroup\n";
  FormatOptions two;
  two.indent_width = 2;
  EXPECT_EQ(format_source(text, two).text, "group g\n  instance i m endinstance\nendgroup\n");
  FormatOptions tabs;
  tabs.insert_spaces = false;
  EXPECT_EQ(format_source(text, tabs).text, "group g\n\tinstance i m endinstance\nendgroup\n");
}

TEST(FormatLineEndings, CrlfInputKeepsCrlf) {
  std::string text = "group g\r\ninstance i m endinstance  # note\r\n\r\n\r\nendgroup\r\n";
  nomec::FormatResult r = format_source(text);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.text, "group g\r\n    instance i m endinstance # note\r\n\r\nendgroup\r\n");
  EXPECT_EQ(format_source(r.text).text, r.text);
}

// A file saved with a UTF-8 byte order mark is formatted (it was a syntax error, left
// alone) and keeps its mark in front; an error's column counts from after the mark.
TEST(FormatEdges, ByteOrderMarkIsKept) {
  const std::string bom = "\xEF\xBB\xBF";
  nomec::FormatResult r = format_source(bom + "group g\ninstance i m endinstance\nendgroup\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.text, bom + "group g\n    instance i m endinstance\nendgroup\n");
  EXPECT_EQ(format_source(r.text).text, r.text);
  EXPECT_EQ(format_source(bom + "  # only a comment\n").text, bom + "# only a comment\n");
  nomec::FormatResult bad = format_source(bom + "point p (0 0 0 endpoint\n");
  EXPECT_FALSE(bad.ok);
  EXPECT_EQ(bad.error.rfind("1:", 0), 0u) << bad.error;
}

TEST(FormatEdges, EmptyAndCommentOnlyFiles) {
  EXPECT_TRUE(format_source("").ok);
  EXPECT_EQ(format_source("").text, "");
  EXPECT_EQ(format_source("\n\n  \n").text, "");
  EXPECT_EQ(format_source("  # only a comment   \n\n\n").text, "# only a comment\n");
  // No final newline in the input: one in the output.
  EXPECT_EQ(format_source("point p (0 0 0) endpoint").text, "point p (0 0 0) endpoint\n");
}

TEST(FormatEdges, SignRuleIsKept) {
  // `(1 -2)` has two elements, `(1 - 2)` and `(1-2)` one: the formatter keeps each.
  nomec::FormatResult r = format_source("point a (1 -2) endpoint\npoint b (1 - 2) endpoint\n"
                                        "point c (1-2) endpoint\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.text, "point a (1 -2) endpoint\npoint b (1 - 2) endpoint\npoint c (1-2) endpoint\n");
}

}  // namespace

namespace {

// The language server formats whatever is in the editor: damaged text must never crash the
// formatter, and whatever it accepts must be a fixed point of it.
TEST(FormatRobustness, MutatedAndTruncatedFilesNeverCrash) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(fs::path(NOMEC_SOURCE_DIR) / "tests/format/golden")) {
    if (e.path().filename().string().find(".in.") != std::string::npos) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty());
  uint32_t seed = 12345;
  auto next = [&seed] {
    seed = seed * 1664525u + 1013904223u;
    return seed >> 8;
  };
  const std::string alphabet = "(){}[]*#-+ \n\t\"$%^,01a\xc3\xa9\r";
  int accepted = 0;
  for (const fs::path& p : files) {
    std::string text = read(p);
    // NOMEC_FORMAT_FUZZ_ROUNDS raises the number of mutations per file for a longer local run.
    const char* rounds_env = std::getenv("NOMEC_FORMAT_FUZZ_ROUNDS");
    const int rounds = rounds_env != nullptr ? std::atoi(rounds_env) : 40;
    for (int k = 0; k < rounds; ++k) {
      std::string t = text;
      if (k % 4 == 0) {
        t.resize(next() % (t.size() + 1));
      } else {
        for (int m = 0; m < 1 + k % 3; ++m) {
          t[next() % t.size()] = alphabet[next() % alphabet.size()];
        }
      }
      nomec::FormatResult r = format_source(t);
      if (!r.ok) {
        EXPECT_TRUE(std::regex_search(r.error, std::regex("^[0-9]+:[0-9]+: "))) << r.error;
        EXPECT_EQ(r.error.find("meaning"), std::string::npos) << p << " mutation " << k << ":\n" << t;
        continue;
      }
      ++accepted;
      nomec::FormatResult again = format_source(r.text);
      ASSERT_TRUE(again.ok) << p << " mutation " << k;
      EXPECT_EQ(again.text, r.text) << p << " mutation " << k << " is not idempotent:\n" << t;
    }
  }
  EXPECT_GT(accepted, 50);
}

}  // namespace

namespace {

TEST(FormatEdges, LoneCarriageReturnEndsALineComment) {
  // The lexer ends `# note` at the `\r`; `is` after it is code and must stay out of the comment.
  nomec::FormatResult r = format_source("point p (0 0 0) endpoint # note\ris\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.text, "point p (0 0 0) endpoint # note\nis\n");
}

}  // namespace

namespace {

TEST(FormatEdges, SignGluedToACommentStaysGlued) {
  // `+#` is a sign (followed by a non-space): `+ #` would make it a binary `+`.
  const char* text = "bank b\nset n 8 3 10 1 +# note\nset m 8 3 10 1\nendbank\n";
  nomec::FormatResult r = format_source(text);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_NE(r.text.find("+# note"), std::string::npos) << r.text;
  EXPECT_EQ(format_source(r.text).text, r.text);
}

TEST(FormatEdges, BlockCommentAfterALoneCarriageReturn) {
  nomec::FormatResult r = format_source("point p (0 0 0) endpoint # a\r(* b *)\npoint q (1 0 0) endpoint\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.text, "point p (0 0 0) endpoint # a\n(* b *)\npoint q (1 0 0) endpoint\n");
}

}  // namespace

namespace {

TEST(FormatEdges, NeverGluesTokensIntoANewOne) {
  // `1e- 1` is the number 1, the word `e` and `-1`; `1e-1` would be one number.
  nomec::FormatResult r = format_source("point p (0 0 0) endpoint\nbank b\nset z 1 0 1e- 1\nendbank\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_NE(r.text.find("1e- 1"), std::string::npos) << r.text;
  EXPECT_EQ(format_source(r.text).text, r.text);
}

}  // namespace

namespace {

TEST(FormatEdges, SignMovedToItsOwnLineIsIdempotent) {
  // Two stray top-level items: `fac` and `- f(x)`; the second moves to its own line.
  nomec::FormatResult r = format_source("fac- f (x)\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(format_source(r.text).text, r.text);
}

}  // namespace
