// Differential tests of incremental checks (frontend/check/incremental.h) against full
// ones: every corpus file, every example and generated scenes are edited the way a sculptor
// types (digits into values, letters into names and keywords, deleted characters, pasted
// and removed words and lines), and whenever `check_incrementally` says it is done, its
// diagnostics (sorted and deduplicated, with notes and fix-its) must be exactly those of
// `check_source` on the same text. The scenes a sculptor edits most (values, point and
// instance names in a scene of banks, meshes, funnels, groups and instances) must be
// checked incrementally, and only the statements near the edit re-checked.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "bench/common/generated_scene.h"
#include "frontend/check/check.h"
#include "frontend/check/incremental.h"
#include "frontend/parse/parse.h"
#include "tests/common/ast_dump.h"
#include "tests/common/corpus_inputs.h"

namespace {

using nomec::testing_dump::dump_diags;

nomec::CheckOptions options_for() {
  nomec::CheckOptions o;
  o.read_file = nomec::testing_inputs::read_file;
  return o;
}

struct Full {
  std::string dump;  // sorted, deduplicated diagnostics
  std::shared_ptr<const nomec::IncrementalBasis> basis;
};

// A full check as the editor makes it (names recorded), and the basis it leaves.
Full full_check(const std::string& path, const std::string& text) {
  auto sources = std::make_shared<nomec::SourceManager>();
  nomec::DiagnosticEngine diags;
  nomec::CheckOptions o = options_for();
  o.record_names = true;
  nomec::CheckResult r = nomec::check_source(*sources, path, text, o, diags);
  Full f;
  f.basis = nomec::make_incremental_basis(sources, r, diags.diagnostics());
  diags.sort_and_dedupe();
  f.dump = dump_diags(diags);
  return f;
}

struct Incremental {
  nomec::IncrementalOutcome outcome;
  std::string dump;
};

Incremental incremental_check(const nomec::IncrementalBasis& basis, const std::string& path, const std::string& text,
                              nomec::ParseCache* cache) {
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  Incremental i;
  i.outcome = nomec::check_incrementally(basis, sources, path, text, options_for(), diags, cache);
  diags.sort_and_dedupe();
  i.dump = dump_diags(diags);
  return i;
}

bool word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '.'; }

// One edit a sculptor makes while typing, within 40 bytes of `near`.
void typing_edit(std::string& text, size_t near, std::mt19937& rng) {
  if (text.empty()) {
    text = "p";
    return;
  }
  const size_t lo = near > 40 ? near - 40 : 0;
  std::uniform_int_distribution<size_t> pos(std::min(lo, text.size() - 1), std::min(near + 40, text.size() - 1));
  size_t at = pos(rng);
  switch (std::uniform_int_distribution<int>(0, 7)(rng)) {
    case 0: {  // a digit typed after a digit (a value)
      size_t d = text.find_first_of("0123456789", at);
      if (d != std::string::npos) text.insert(d + 1, 1, static_cast<char>('0' + rng() % 10));
      break;
    }
    case 1:
    case 2: {  // a letter typed into a word (a name or a keyword)
      while (at < text.size() && !word_char(text[at])) ++at;
      if (at < text.size()) text.insert(at + 1, 1, static_cast<char>('a' + rng() % 26));
      break;
    }
    case 3: {  // a character deleted
      text.erase(at, 1);
      break;
    }
    case 4: {  // a digit replaced
      size_t d = text.find_first_of("0123456789", at);
      if (d != std::string::npos) text[d] = static_cast<char>('0' + rng() % 10);
      break;
    }
    case 5: {  // a word or a line pasted
      static const char* kWords[] = {" v0", " m0", " b0_r", " $b0_n", " fb0_hc0", " box", " x", " (0 0 0)", " )", " endmesh",
                                     "\n  set k 1 0 2 0.1\n", "\n  point v9 (0 0 {expr $b0_r}) endpoint\n",
                                     "\n  instance box m0 endinstance\n", "\n  face f9 (v0 v1 v9) endface\n"};
      text.insert(at, kWords[rng() % std::size(kWords)]);
      break;
    }
    case 6: {  // a word deleted
      size_t b = at;
      while (b < text.size() && !word_char(text[b])) ++b;
      size_t e = b;
      while (e < text.size() && word_char(text[e])) ++e;
      text.erase(b, e - b);
      break;
    }
    default: {  // a comment typed
      text.insert(at, " # note\n");
      break;
    }
  }
}

struct Tally {
  int versions = 0, done = 0;
};

// Types `edits` versions, each one to three typing edits in one place away from the version last
// checked in full (the editor's basis while its full checks are overtaken by typing); every
// version the incremental check finishes must report what a full check reports.
void differential(const std::string& path, const std::string& original, int edits, uint32_t seed, Tally& tally) {
  std::mt19937 rng(seed);
  Full base = full_check(path, original);
  if (!base.basis) return;  // a file always checked in full
  nomec::ParseCache cache;
  std::string basis_text = original;
  for (int k = 0; k < edits; ++k) {
    std::string text = basis_text;
    const int n = 1 + static_cast<int>(rng() % 3);
    const size_t near = text.empty() ? 0 : rng() % text.size();
    for (int e = 0; e < n; ++e) typing_edit(text, near, rng);
    Incremental inc = incremental_check(*base.basis, path, text, &cache);
    ++tally.versions;
    if (std::getenv("NOMEC_INCREMENTAL_WHY") != nullptr) {
      std::fprintf(stderr, "%s: %s\n", path.c_str(), inc.outcome.done ? "done" : inc.outcome.why.c_str());
    }
    if (inc.outcome.done) {
      ++tally.done;
      const Full want = full_check(path, text);
      if (inc.dump != want.dump && std::getenv("NOMEC_DBG_DIR") != nullptr) {  // keep the case for debugging
        std::ofstream(std::string(std::getenv("NOMEC_DBG_DIR")) + "/incremental_fail.txt", std::ios::binary) << text;
        std::ofstream(std::string(std::getenv("NOMEC_DBG_DIR")) + "/incremental_basis.txt", std::ios::binary) << basis_text;
      }
      ASSERT_EQ(inc.dump, want.dump) << path << " (seed " << seed << ", version " << k << ", " << inc.outcome.rechecked
                                     << " re-checked)\n--- text ---\n"
                                     << text;
    }
    if (k % 4 == 3) {  // a full check catches up
      basis_text = text;
      base = full_check(path, basis_text);
      if (!base.basis) return;
    }
  }
}

TEST(IncrementalCheck, CorpusFilesAndExamplesUnderTyping) {
  const std::vector<std::string> files = nomec::testing_inputs::corpus_and_examples();
  ASSERT_FALSE(files.empty());
  Tally tally;
  // NOMEC_INCREMENTAL_SEED and NOMEC_INCREMENTAL_EDITS widen the sweep by hand.
  uint32_t seed = std::getenv("NOMEC_INCREMENTAL_SEED") ? static_cast<uint32_t>(std::atoi(std::getenv("NOMEC_INCREMENTAL_SEED"))) : 1;
  const int edits = std::getenv("NOMEC_INCREMENTAL_EDITS") ? std::atoi(std::getenv("NOMEC_INCREMENTAL_EDITS")) : 24;
  for (const std::string& path : files) {
    differential(path, nomec::testing_inputs::read_file(path).value(), edits, seed++, tally);
    if (HasFatalFailure()) return;
  }
  // Most corpus files can be checked incrementally; the sweep must exercise the path.
  EXPECT_GT(tally.done, tally.versions / 4) << tally.done << " of " << tally.versions << " versions";
  std::printf("%d of %d versions checked incrementally\n", tally.done, tally.versions);
}

TEST(IncrementalCheck, GeneratedScenesUnderTyping) {
  for (int modules : {40, 120}) {
    Tally tally;
    differential("scene.nome", nomec::bench::generate_scene(static_cast<size_t>(modules) * 1500), 80, 100 + static_cast<uint32_t>(modules),
                 tally);
    if (HasFatalFailure()) return;
    EXPECT_GT(tally.done, tally.versions / 3) << modules << " modules: " << tally.done << " of " << tally.versions;
  }
}

// The editor's typing session of bench_lsp on a large scene: each keystroke is checked
// incrementally, re-checking a handful of statements, with the full check's diagnostics.
TEST(IncrementalCheck, KeystrokesInALargeSceneRecheckLittle) {
  const std::string original = nomec::bench::generate_scene(300 * 1500);
  const Full base = full_check("scene.nome", original);
  ASSERT_TRUE(base.basis);
  // Digits typed after a value in a bank, a point's coordinate and a funnel's argument;
  // letters typed into a point's, a mesh's and an instance's name; an unknown name typed.
  struct Edit {
    std::string anchor;  // the edit goes right after the first occurrence of this text
    std::string insert;
  };
  const std::vector<Edit> edits = {
      {"set r 1.5", "7"},  {"point q200_2 ({expr $b200_r * cos(2", "1"}, {"funnel fun200 ($b200_n $b200_r 0.5", "2"},
      {"point q", "x"},    {"mesh m", "y"},                                  {"instance gi", "z"},
      {"face j200 (fb200_hc0", "9"}, {"face t200 (q200_0 q", "w"},  {"  instance box", "q"},
  };
  nomec::ParseCache cache;
  for (const Edit& e : edits) {
    std::string text = original;
    const size_t at = text.find(e.anchor, text.size() / 2);
    ASSERT_NE(at, std::string::npos) << e.anchor;
    text.insert(at + e.anchor.size(), e.insert);
    const Incremental inc = incremental_check(*base.basis, "scene.nome", text, &cache);
    ASSERT_TRUE(inc.outcome.done) << e.anchor << "+" << e.insert << ": " << inc.outcome.why;
    EXPECT_LE(inc.outcome.checked, 40u) << e.anchor;
    EXPECT_EQ(inc.dump, full_check("scene.nome", text).dump) << e.anchor << "+" << e.insert;
  }
}

}  // namespace
