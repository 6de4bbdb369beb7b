// Differential test of the language server's incremental path: seeded random edit sequences
// (typing digits and names, deleting characters, ranges and lines, duplicating lines,
// inserting whole statements, undoing back to the original) are typed into every corpus file,
// every example and generated scenes, one `didChange` each, into a server that keeps the
// document open (its first version parsed in one piece, later ones through the document's
// ParseCache once the background thread filled it, or in one piece again before that). After
// every edit, its published diagnostics and the IR it checked the version into must equal
// those of a second server that opens the same text fresh (a full check); so must the first
// diagnostics published for the version, which come from an incremental check
// (frontend/check/incremental.h) when the edit allows one.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <fmt/format.h>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "lsp_client.h"
#include "tests/common/corpus_inputs.h"
#include "tests/common/text_edits.h"

namespace nomec::lsp::test {
namespace {

// A scene of `modules` repetitions of banks, points, meshes, a funnel, groups and instances
// that read each other's names, so edits change what later statements resolve to.
std::string generated_scene(int modules) {
  std::string out = "# generated\n";
  for (int k = 0; k < modules; ++k) {
    out += fmt::format(
        "bank b{0}\n  set n {1} 3 20 1\n  set r 1.{2} 0.1 5 0.1\nendbank\n"
        "point q{0} ({{expr $b{0}_r * cos(pi / 2)}} {2} -0.5) endpoint\n"
        "mesh m{0}\n  point v0 (0 0 0) endpoint\n  point v1 (1 0 0) endpoint\n"
        "  point v2 (0 1 {{expr $b{0}_r}}) endpoint\n  face f0 (v0 v1 v2) endface\nendmesh\n"
        "funnel fun{0} ($b{0}_n $b{0}_r 0.5 1) endfunnel\n"
        "group g{0}\n  instance box m{0} translate (0 0 -1) endinstance\n"
        "  instance f fun{0} endinstance\nendgroup\n"
        "instance gi{0} g{0} rotate (0 0 1) (90) endinstance\n\n",
        k, 4 + k % 8, k % 10);
  }
  return out;
}

// One edit as a sculptor makes them, at a random place.
void random_edit(std::string& text, const std::string& original, std::mt19937& rng) {
  static const std::vector<std::string> typed = {
      "0", "7", ".5", "-", " ", "\n", "x", "q1", "m0", "g1", "_", "$", "(", ")", "{", "}", "#",
      "(*", "*)", "endpoint", "endmesh", "instance", "$b0_r", "{expr $b1_n * 2}",
      "point p (1 2 3) endpoint\n", "mesh m0\n  face f (v0 v1 v2) endface\nendmesh\n",
      "instance i9 g0 endinstance\n", "group g0\nendgroup\n"};
  std::uniform_int_distribution<size_t> pos(0, text.size());
  const size_t at = pos(rng);
  switch (std::uniform_int_distribution<int>(0, 11)(rng)) {
    case 0: {  // delete a character (backspace)
      if (at > 0) text.erase(at - 1, 1);
      break;
    }
    case 1: {  // delete a short range
      text.erase(std::min(at, text.size()), std::uniform_int_distribution<size_t>(1, 12)(rng));
      break;
    }
    case 2: {  // delete a whole line
      const auto [b, e] = nomec::testing_edits::line_around(text, at);
      if (b < e) text.erase(b, e - b);
      break;
    }
    case 3: {  // duplicate a line
      const auto [b, e] = nomec::testing_edits::line_around(text, at);
      text.insert(b, text.substr(b, e - b));
      break;
    }
    case 4:
    case 5: {  // type a digit into a value
      size_t d = text.find_first_of("0123456789", at);
      if (d != std::string::npos) text.insert(d + 1, 1, static_cast<char>('0' + rng() % 10));
      break;
    }
    case 6: {  // rename: type a letter into a name
      size_t w = text.find_first_of("abcdefghijklmnopqrstuvwxyz", at);
      if (w != std::string::npos) text.insert(w + 1, 1, static_cast<char>('a' + rng() % 26));
      break;
    }
    case 7: {  // undo everything
      text = original;
      break;
    }
    default:
      text.insert(at, typed[rng() % typed.size()]);
      break;
  }
}

bool is_ascii(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) < 0x80; });
}

// The LSP position of byte `offset` of an ASCII text (UTF-16 units are bytes there).
json ascii_position(const std::string& text, size_t offset) {
  int line = 0;
  size_t line_start = 0;
  for (size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  return pos(line, static_cast<int>(offset - line_start));
}

// The change that turns `before` into `after`: one ranged replacement of what differs (an
// editor's incremental sync) when both are ASCII, the whole text otherwise.
json change_of(const std::string& before, const std::string& after) {
  if (!is_ascii(before) || !is_ascii(after)) return json::array({{{"text", after}}});
  size_t prefix = 0;
  while (prefix < before.size() && prefix < after.size() && before[prefix] == after[prefix]) ++prefix;
  size_t suffix = 0;
  while (suffix < before.size() - prefix && suffix < after.size() - prefix &&
         before[before.size() - 1 - suffix] == after[after.size() - 1 - suffix]) {
    ++suffix;
  }
  return json::array({{{"range", {{"start", ascii_position(before, prefix)},
                                  {"end", ascii_position(before, before.size() - suffix)}}},
                       {"text", after.substr(prefix, after.size() - prefix - suffix)}}});
}

void wait_background(Server& server) {
  auto deadline = std::chrono::steady_clock::now() + Client::kHungServer;
  while (server.background_busy() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// Types `edits` random edits into `text` (document `uri`) and compares every version with a
// fresh check. Some edits follow at once, others after the background work (the cache fill,
// the index) finished, so both ways a version can be parsed are compared.
// Returns how many versions were first published from an incremental check.
size_t differential(const std::string& uri, const std::string& original, int edits, uint32_t seed) {
  Client edited, fresh;
  edited.initialize();
  fresh.initialize();
  std::mt19937 rng(seed);
  std::string text = original;
  edited.open(uri, text, 1);
  json first = edited.diagnostics(uri, 1);
  fresh.open(uri, text, 1);
  EXPECT_EQ(first["diagnostics"], fresh.diagnostics(uri, 1)["diagnostics"]) << uri;
  size_t cached_versions = 0, quick_versions = 0;
  for (int k = 0; k < edits; ++k) {
    const int version = k + 2;
    if (rng() % 3 == 0) wait_background(edited.server());
    const std::string before = text;
    random_edit(text, original, rng);
    edited.change(uri, version, change_of(before, text));
    json got = edited.diagnostics(uri, version)["diagnostics"];
    fresh.notify("textDocument/didClose", {{"textDocument", {{"uri", uri}}}});
    fresh.open(uri, text, version);
    json want = fresh.diagnostics(uri, version)["diagnostics"];
    EXPECT_EQ(edited.server().document_text(uri), text) << uri << " edit " << k;
    EXPECT_EQ(got, want) << uri << " edit " << k << " (seed " << seed << "), text:\n" << text;
    EXPECT_EQ(edited.first_diagnostics(uri, version)["diagnostics"], want)
        << uri << " edit " << k << " (seed " << seed << "): first published, text:\n" << text;
    if (std::optional<AnalysisTimes> t = edited.server().analysis_times(uri); t && t->incremental_ms > 0) ++quick_versions;
    std::optional<std::pair<int64_t, std::string>> got_ir = edited.server().ir_dump(uri);
    std::optional<std::pair<int64_t, std::string>> want_ir = fresh.server().ir_dump(uri);
    if (!got_ir || !want_ir) {
      ADD_FAILURE() << uri << ": no IR";
      return quick_versions;
    }
    EXPECT_EQ(got_ir->first, version);
    EXPECT_EQ(want_ir->first, version);
    EXPECT_EQ(got_ir->second, want_ir->second) << uri << " edit " << k << " (seed " << seed << "), text:\n" << text;
    if (::testing::Test::HasFailure()) return quick_versions;
    if (std::optional<ParseStats> s = edited.server().parse_stats(uri); s && s->pieces > 1) ++cached_versions;
    edited.clear();
    fresh.clear();
  }
  // The edited document did go through its cache, so the comparison above covered the
  // incremental path and not only whole-text parses (how little a keystroke re-parses is
  // tests/incremental's concern: edits here such as an opened comment re-parse the rest).
  if (edits >= 8 && original.size() > 2000) {
    EXPECT_GT(cached_versions, 0u) << uri;
  }
  return quick_versions;
}

TEST(LspIncrementalCheck, RandomEditsInCorpusFilesMatchAFreshCheck) {
  const std::vector<std::string> files = testing_inputs::corpus_and_examples();
  ASSERT_FALSE(files.empty());
  uint32_t seed = 1;
  for (const std::string& path : files) {
    std::optional<std::string> text = testing_inputs::read_file(path);
    ASSERT_TRUE(text.has_value()) << path;
    if (text->size() > (256u << 10)) continue;  // the generated scenes cover large files
    differential("file://" + path, *text, 16, seed++);  // corpus paths need no escaping
    if (::testing::Test::HasFailure()) return;
  }
}

TEST(LspIncrementalCheck, RandomEditsInGeneratedScenesMatchAFreshCheck) {
  size_t quick = 0;
  for (int modules : {3, 40, 150}) {
    for (uint32_t seed : {11u, 12u}) {
      quick += differential(fmt::format("file:///tmp/lsp-test/generated{}.nome", modules), generated_scene(modules), 40,
                            seed * 100 + static_cast<uint32_t>(modules));
      if (::testing::Test::HasFailure()) return;
    }
  }
  // The first diagnostics of many versions came from incremental checks, so the comparison
  // above covered them.
  EXPECT_GT(quick, 20u);
}

}  // namespace
}  // namespace nomec::lsp::test
