// Differential tests of nomec::ParseCache against nomec::parse_file. Each document (corpus
// files, examples, a generated scene) goes through a seeded sequence of random edits with
// one cache kept across versions; every version's full AST dump (all nodes, ids, ranges and
// texts) and diagnostics (in emission order, with notes and fix-its) must equal a fresh
// parse_file of the same text. Also: check_source through a cache equals check_source
// without one (diagnostics and IR dump), and small edits re-parse only a small piece.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "frontend/check/check.h"
#include "base/two_threads.h"
#include "frontend/parse/parse.h"
#include "frontend/parse/piece.h"
#include "ir/ir.h"
#include "tests/common/ast_dump.h"
#include "tests/common/corpus_inputs.h"
#include "tests/common/text_edits.h"

namespace fs = std::filesystem;

namespace {

using nomec::testing_dump::dump_ast;
using nomec::testing_dump::dump_diags;
using nomec::testing_dump::dump_range;

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Doc {
  std::string name;
  std::string text;
};

std::vector<Doc> corpus_docs() {
  std::vector<Doc> out;
  for (const std::string& path : nomec::testing_inputs::corpus_and_examples()) out.push_back({path, read(path)});
  return out;
}

// A scene of `modules` repetitions of banks, points, a mesh, a funnel, groups and instances.
std::string generated_scene(int modules) {
  std::string out = "# generated\n";
  for (int k = 0; k < modules; ++k) {
    out += fmt::format(
        "bank b{0}\n  set n {1} 3 20 1\n  set r 1.{2} 0.1 5 0.1\nendbank\n"
        "point q{0} ({{expr $b{0}_r * cos(pi / 2)}} {2} -0.5) endpoint\n"
        "mesh m{0}\n  point v0 (0 0 0) endpoint\n  point v1 (1 0 0) endpoint\n"
        "  point v2 (0 1 {{expr $b{0}_r}}) endpoint\n  face f0 (v0 v1 v2) endface\nendmesh\n"
        "funnel fun{0} ($b{0}_n $b{0}_r 0.5 1) endfunnel\n"
        "group g{0}\n  instance box m{0} translate (0 0 -1) endinstance\nendgroup\n"
        "(* a (* nested *) comment *)\n"
        "instance gi{0} g{0} rotate (0 0 1) (90) endinstance  # trailing\n\n",
        k, 4 + k % 8, k % 10);
  }
  return out;
}

// Both parses see the document as file 1 (file 0 is another file), so a cache that kept
// the file id its pieces were parsed with would show up. The reference is the parse on one
// thread, in one piece.
std::string full_parse(const std::string& text, nomec::ParseThreads threads = nomec::ParseThreads::One) {
  nomec::SourceManager sources;
  sources.add_file("other.nome", "point p (1 2 3) endpoint\n");
  nomec::DiagnosticEngine diags;
  nomec::FileId f = sources.add_file("doc.nome", text);
  nomec::ast::Ast a = nomec::parse_file(sources, f, diags, threads);
  return dump_ast(a) + "--\n" + dump_diags(diags);
}

std::string cached_parse(nomec::ParseCache& cache, const std::string& text) {
  nomec::SourceManager sources;
  sources.add_file("other.nome", "point p (1 2 3) endpoint\n");
  nomec::DiagnosticEngine diags;
  nomec::FileId f = sources.add_file("doc.nome", text);
  nomec::ast::Ast a = cache.parse(sources, f, diags);
  return dump_ast(a) + "--\n" + dump_diags(diags);
}

// Empty when `got` equals `want`; otherwise the first differing line of each, so that a
// failure on a large document stays readable.
std::string first_difference(const std::string& got, const std::string& want) {
  if (got == want) return "";
  size_t i = 0;
  while (i < got.size() && i < want.size() && got[i] == want[i]) ++i;
  size_t b = want.rfind('\n', i == 0 ? 0 : i - 1);
  b = b == std::string::npos ? 0 : b + 1;
  size_t bg = std::min(b, got.size());
  return fmt::format("first difference near\n  want: {}\n  got:  {}",
                     want.substr(b, want.find('\n', i) - b),
                     got.substr(bg, got.find('\n', i) - bg));
}

// The cached parse of `text` through `cache`, which must also have split the text into the
// same chunks and runs as a fresh cache does (cuts are only hints, so a wrong cut could
// still give the right AST; the counts show it).
std::string cached_parse_same_runs(nomec::ParseCache& cache, const std::string& text) {
  std::string got = cached_parse(cache, text);
  nomec::ParseCache fresh;
  cached_parse(fresh, text);
  if (cache.last_stats().pieces != fresh.last_stats().pieces ||
      cache.last_stats().chunks != fresh.last_stats().chunks) {
    return fmt::format("{} runs of {} chunks instead of {} of {}", cache.last_stats().pieces,
                       cache.last_stats().chunks, fresh.last_stats().pieces,
                       fresh.last_stats().chunks);
  }
  return got;
}

// One random edit at a random place: the alphabet favours what changes structure.
void random_edit(std::string& text, std::mt19937& rng) {
  static const std::vector<std::string> fragments = {
      "0", "7", ".5", "-", "+", " ", "\n", "x", "p1", "_", "$", "(", ")", "{", "}", "[", "]",
      "(*", "*)", "#", "\"", ",", "^", "*", "endpoint", "point", "mesh", "endmesh", "face",
      "endface", "group", "endgroup", "instance", "endinstance", "bank", "endbank", "set ",
      "tclinit {", "{expr ", "%{", "}%", "include \"a\"", "point p (1 2 3) endpoint\n",
      "mesh m\n  face f (a b c) endface\nendmesh\n", "\xff", "\xc3\xa9"};
  std::uniform_int_distribution<size_t> pos(0, text.size());
  size_t at = pos(rng);
  switch (std::uniform_int_distribution<int>(0, 9)(rng)) {
    case 0:
    case 1: {  // delete a short range
      size_t len = std::uniform_int_distribution<size_t>(1, 12)(rng);
      text.erase(std::min(at, text.size()), len);
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
    case 4: {  // replace a digit (typing in a value)
      size_t d = text.find_first_of("0123456789", at);
      if (d != std::string::npos) text[d] = static_cast<char>('0' + rng() % 10);
      break;
    }
    default: {
      const std::string& f = fragments[rng() % fragments.size()];
      text.insert(at, f);
      break;
    }
  }
}

// Runs `edits` random edits over `text` with one cache; every version must match.
void differential(const std::string& name, std::string text, int edits, uint32_t seed,
                  nomec::ParseThreads threads = nomec::ParseThreads::Automatic) {
  std::mt19937 rng(seed);
  nomec::ParseCache cache(threads);
  ASSERT_EQ(cached_parse(cache, text), full_parse(text)) << name << " (unedited)";
  std::string original = text;
  for (int k = 0; k < edits; ++k) {
    if (k % 16 == 15) text = original;  // an undo back to the first version
    random_edit(text, rng);
    std::string want = full_parse(text);
    std::string got = cached_parse(cache, text);
    if (got != want) {
      // Show the first differing line to make a failure readable.
      size_t i = 0;
      while (i < got.size() && i < want.size() && got[i] == want[i]) ++i;
      size_t b = want.rfind('\n', i == 0 ? 0 : i - 1);
      b = b == std::string::npos ? 0 : b + 1;
      if (const char* dir = std::getenv("NOMEC_DBG_DIR")) {  // keep the case for debugging
        std::ofstream(fmt::format("{}/fail_{}.txt", dir, seed), std::ios::binary) << text;
        std::ofstream(fmt::format("{}/fail_{}.want", dir, seed), std::ios::binary) << want;
        std::ofstream(fmt::format("{}/fail_{}.got", dir, seed), std::ios::binary) << got;
      }
      FAIL() << name << " after edit " << k << " (seed " << seed << "): first difference near\n"
             << "  want: " << want.substr(b, want.find('\n', i) - b) << "\n"
             << "  got:  " << got.substr(b, got.find('\n', i) - b) << "\n--- text ---\n"
             << text;
    }
  }
}

// Every corpus file and example in `versions` versions: as it is, then after each of
// `versions - 1` random edits (seeded per file from `seed` on). `check(doc, text, k)` runs on
// version k; the walk stops at the first fatal failure.
template <typename Check>
void for_each_edited_corpus_version(uint32_t seed, int versions, Check&& check) {
  const std::vector<Doc> docs = corpus_docs();
  ASSERT_FALSE(docs.empty()) << "no corpus files under " << NOMEC_CORPUS_DIR;
  for (const Doc& d : docs) {
    std::mt19937 rng(seed++);
    std::string text = d.text;
    for (int k = 0; k < versions; ++k) {
      if (k > 0) random_edit(text, rng);
      check(d, text, k);
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
}

TEST(ParseCache, CorpusFilesUnderRandomEdits) {
  std::vector<Doc> docs = corpus_docs();
  ASSERT_FALSE(docs.empty()) << "no corpus files under " << NOMEC_CORPUS_DIR;
  uint32_t seed = 1;
  for (const Doc& d : docs) differential(d.name, d.text, 10, seed++);
}

// NOME2's blocks name top-level instances with `instance X` and no `endinstance`: the
// cache must not take such an `instance` for an open block, or its cuts fall inside the
// statements below and they are parsed together; it still equals a whole-file parse, under
// edits too.
TEST(ParseCache, Nome2BlockInstanceNames) {
  const std::string text =
      "point a (0 0 0) endpoint\npoint b (1 0 0) endpoint\npoint c (0 1 0) endpoint\n"
      "mesh m\n  face f (a b c) endface\nendmesh\n"
      "instance i m endinstance\n"
      "subdivision s instance i type NOME_SD_CC subdivisions 1 endsubdivision\n"
      "mesh n\n  face g (a c b) endface\nendmesh\n"
      "offset o instance i type NOME_OFFSET_DEFAULT min 0.1 max 0.5 step 0.1 endoffset\n"
      "mesh q\n  face h (a b c) endface\nendmesh\n";
  nomec::ParseCache cache;
  EXPECT_EQ(cached_parse(cache, text), full_parse(text));
  EXPECT_EQ(full_parse(text).find("error"), std::string::npos) << full_parse(text);
  // One piece per top-level statement, each parsed alone.
  EXPECT_EQ(cache.last_stats().pieces, 9u);
  EXPECT_EQ(cache.last_stats().parsed, 9u);
  for (uint32_t seed = 200; seed < 204; ++seed) differential("nome2 blocks", text, 40, seed);
}

TEST(ParseCache, GeneratedSceneUnderRandomEdits) {
  std::string scene = generated_scene(16);
  for (uint32_t seed = 100; seed < 103; ++seed) differential("generated", scene, 80, seed);
}

TEST(ParseCache, SmallEditsReparseSmallPieces) {
  std::string scene = generated_scene(240);
  nomec::ParseCache cache;
  ASSERT_EQ(cached_parse(cache, scene), full_parse(scene));
  EXPECT_EQ(cache.last_stats().parsed, cache.last_stats().pieces);
  EXPECT_GT(cache.last_stats().pieces, 240u);
  // Typing a digit into a value in the middle of the file.
  size_t at = scene.find("set r 1.", scene.size() / 2) + 8;
  scene.insert(at, "5");
  ASSERT_EQ(cached_parse(cache, scene), full_parse(scene));
  EXPECT_EQ(cache.last_stats().parsed, 1u);
  EXPECT_LT(cache.last_stats().parsed_bytes, 200u);
  // Opening a block that is closed only by the next statement's end keyword: the piece is
  // parsed together with its neighbours, not alone.
  size_t mesh = scene.find("mesh m120");
  scene.insert(mesh, "point z (1 2 3)\n");
  ASSERT_EQ(cached_parse(cache, scene), full_parse(scene));
  EXPECT_GE(cache.last_stats().parsed, 2u);
  EXPECT_LT(cache.last_stats().parsed_bytes, 2000u);
  // An unclosed comment swallows the rest of the file.
  scene.insert(scene.size() / 2, "(* ");
  ASSERT_EQ(cached_parse(cache, scene), full_parse(scene));
  EXPECT_GT(cache.last_stats().parsed_bytes, scene.size() / 3);
}

// Scripted edits that each hit one path of the edit-local update (cuts and runs kept before
// the edit, re-derived around it, and taken over shifted after it): every version must
// equal a fresh parse.
TEST(ParseCache, EditsAtEveryPlaceAndOfEveryStructure) {
  const std::string scene = generated_scene(16);
  struct Edit {
    const char* what;
    std::function<void(std::string&)> apply;
  };
  auto at_mid = [](const std::string& t, const char* needle) { return t.find(needle, t.size() / 2); };
  const std::vector<Edit> edits = {
      {"insert at the start", [](std::string& t) { t.insert(0, "point s (1 2 3) endpoint\n"); }},
      {"delete the first character", [](std::string& t) { t.erase(0, 1); }},
      {"delete the first line", [](std::string& t) { t.erase(0, t.find('\n') + 1); }},
      {"type a digit in the middle", [&](std::string& t) { t.insert(at_mid(t, "set r 1.") + 8, "7"); }},
      {"type a name character", [&](std::string& t) { t.insert(at_mid(t, "mesh m") + 6, "x"); }},
      // Two edits whose lengths cancel: between them, the new cuts sit where old cuts were,
      // but the text after them changed, so nothing there may be taken over.
      {"two same-length edits far apart",
       [](std::string& t) {
         size_t a = t.find("set n ", t.size() / 5) + 6;
         t[a] = t[a] == '9' ? '8' : '9';
         size_t b = t.find("set n ", t.size() * 4 / 5) + 6;
         t[b] = t[b] == '9' ? '8' : '9';
       }},
      {"same-length edits far apart, breaking end keywords",
       [](std::string& t) {
         t[t.find("endpoint", t.size() / 5)] = 'x';
         t[t.find("endmesh", t.size() * 4 / 5) + 6] = 'x';
       }},
      {"and mending them the same way",
       [](std::string& t) {
         t[t.find("xndpoint", t.size() / 5)] = 'e';
         t[t.find("endmesx", t.size() * 4 / 5) + 6] = 'h';
       }},
      {"insert and delete far apart",
       [](std::string& t) {
         t.insert(t.find('\n', t.size() / 5) + 1, "#");
         t.erase(t.find("endmesh", t.size() * 4 / 5), 1);
       }},
      // The last run is accepted because it is last, not because it is self-contained: text
      // typed after it must be parsed with it.
      {"end with a block closed by the wrong keyword",
       [](std::string& t) { t += "mesh m\n  point a (1 2 3) endpoint\nendpoint\n"; }},
      {"type a statement and its end keyword after it",
       [](std::string& t) { t += "point z (1 2 3) endpoint\nendmesh\n"; }},
      {"and another statement", [](std::string& t) { t += "point z (1 2 3) endpoint\n"; }},
      {"append at the end", [](std::string& t) { t += "point e (0 0 1) endpoint\n"; }},
      {"append without a newline", [](std::string& t) { t += "point f (0 0 1) endpoint"; }},
      {"type after the last character", [](std::string& t) { t += "  "; }},
      {"drop the final newline", [](std::string& t) { t.pop_back(); t.pop_back(); t.pop_back(); }},
      {"truncate the last statement", [](std::string& t) { t.erase(t.rfind("endpoint")); }},
      {"open a comment in the middle", [&](std::string& t) { t.insert(at_mid(t, "mesh m"), "(* "); }},
      {"close it further down", [&](std::string& t) { t.insert(t.find("endgroup", t.size() * 3 / 4), "*) "); }},
      {"open a nested comment inside it", [&](std::string& t) { t.insert(at_mid(t, "point v1"), "(* "); }},
      {"close the nested comment", [&](std::string& t) { t.insert(t.find("endgroup", t.size() * 3 / 4), "*) "); }},
      {"remove an end keyword", [&](std::string& t) { t.erase(at_mid(t, "endmesh"), 7); }},
      {"put it back", [&](std::string& t) { t.insert(at_mid(t, "\nfunnel fun"), "endmesh"); }},
      {"unbalanced open bracket", [&](std::string& t) { t.insert(at_mid(t, "instance box"), "("); }},
      {"unbalanced close bracket", [&](std::string& t) { t.insert(at_mid(t, "group g"), ")"); }},
      {"open a brace", [&](std::string& t) { t.insert(at_mid(t, "bank b"), "{ "); }},
      {"open a string", [&](std::string& t) { t.insert(at_mid(t, "set n"), "\""); }},
      {"an end keyword with nothing open", [&](std::string& t) { t.insert(at_mid(t, "\nbank b") + 1, "endbank\n"); }},
      {"a token that cannot start a statement", [&](std::string& t) { t.insert(at_mid(t, "\npoint q") + 1, ") , "); }},
      {"two edits far apart", [](std::string& t) { t.insert(t.size() / 5, "9"); t.insert(t.size() * 4 / 5, "(* x *)"); }},
      {"replace everything", [](std::string& t) { t = generated_scene(3); }},
      {"empty the document", [](std::string& t) { t.clear(); }},
      {"type into the empty document", [](std::string& t) { t = "p"; }},
      {"paste a scene", [&](std::string& t) { t = scene; }},
      {"the same text again", [](std::string&) {}},
  };
  nomec::ParseCache cache;
  std::string text = scene;
  ASSERT_EQ(first_difference(cached_parse_same_runs(cache, text), full_parse(text)), "");
  std::vector<std::string> versions = {text};
  for (const Edit& e : edits) {
    e.apply(text);
    ASSERT_EQ(first_difference(cached_parse_same_runs(cache, text), full_parse(text)), "")
        << e.what;
    versions.push_back(text);
  }
  // Undo every step back to the start, then redo them.
  for (size_t k = versions.size(); k-- > 0;) {
    ASSERT_EQ(first_difference(cached_parse_same_runs(cache, versions[k]), full_parse(versions[k])), "")
        << "undo to " << k;
  }
  for (size_t k = 0; k < versions.size(); ++k) {
    ASSERT_EQ(first_difference(cached_parse_same_runs(cache, versions[k]), full_parse(versions[k])), "")
        << "redo to " << k;
  }
}

// A typing session: edits cluster around a moving cursor (as in an editor), sometimes
// several at once (a multi-cursor edit or a formatter), and sometimes jump back several
// versions (undo); every version must equal a fresh parse.
TEST(ParseCache, TypingSessionsWithUndo) {
  const std::string scene = generated_scene(10);
  static const std::vector<std::string> typed = {
      "1", "0", ".", " ", "\n", "e", "n", "d", "(", ")", "(*", "*)", "#", "\"", "{", "}",
      "endmesh", "endpoint", "mesh ", "point ", "face ", "endface", "set ", "\n\n"};
  for (uint32_t seed = 300; seed < 304; ++seed) {
    std::mt19937 rng(seed);
    nomec::ParseCache cache;
    std::string text = scene;
    std::vector<std::string> history = {text};
    size_t cursor = std::uniform_int_distribution<size_t>(0, text.size())(rng);
    ASSERT_EQ(first_difference(cached_parse_same_runs(cache, text), full_parse(text)), "");
    for (int k = 0; k < 40; ++k) {
      int action = std::uniform_int_distribution<int>(0, 19)(rng);
      if (action == 0 && history.size() > 1) {  // undo a few versions
        size_t back = std::min<size_t>(history.size() - 1, 1 + rng() % 4);
        history.resize(history.size() - back);
        text = history.back();
      } else if (action == 1) {  // edits at several places at once
        for (int c = 0; c < 3; ++c) random_edit(text, rng);
      } else if (action == 2) {  // move the cursor
        cursor = std::uniform_int_distribution<size_t>(0, text.size())(rng);
      } else if (action <= 5 && cursor > 0) {  // backspace
        text.erase(--cursor, 1);
      } else {  // type
        const std::string& f = typed[rng() % typed.size()];
        cursor = std::min(cursor, text.size());
        text.insert(cursor, f);
        cursor += f.size();
      }
      cursor = std::min(cursor, text.size());
      history.push_back(text);
      std::string want = full_parse(text);
      ASSERT_EQ(first_difference(cached_parse_same_runs(cache, text), want), "")
          << "seed " << seed << " step " << k;
    }
  }
}

// The work of a keystroke is proportional to the edit: the cut scanner reads and the piece
// lookup hashes only the text around it, not the whole file.
TEST(ParseCache, KeystrokeWorkIsLocal) {
  std::string scene = generated_scene(240);
  nomec::ParseCache cache;
  ASSERT_EQ(first_difference(cached_parse(cache, scene), full_parse(scene)), "");
  EXPECT_EQ(cache.last_stats().scanned_bytes, scene.size());
  EXPECT_GE(cache.last_stats().looked_up_bytes, scene.size());
  for (size_t place : {scene.size() / 10, scene.size() / 2, scene.size() - 40}) {
    size_t at = scene.find_first_of("0123456789", place);
    ASSERT_NE(at, std::string::npos);
    scene.insert(at, "3");
    ASSERT_EQ(first_difference(cached_parse(cache, scene), full_parse(scene)), "") << "at " << at;
    EXPECT_LT(cache.last_stats().scanned_bytes, 2000u) << "at " << at;
    EXPECT_LT(cache.last_stats().looked_up_bytes, 2000u) << "at " << at;
    EXPECT_EQ(cache.last_stats().parsed, 1u) << "at " << at;
    EXPECT_GT(cache.last_stats().pieces, 240u);
  }
  // The same text again: nothing is parsed, and almost nothing scanned.
  ASSERT_EQ(first_difference(cached_parse(cache, scene), full_parse(scene)), "");
  EXPECT_EQ(cache.last_stats().parsed, 0u);
  EXPECT_LT(cache.last_stats().scanned_bytes, 2000u);
  // Removing an end keyword joins the block with what follows up to the next cut that
  // lines up with an old one; the scan goes no further than that.
  size_t end = scene.find("endmesh", scene.size() / 2);
  scene.erase(end, 7);
  ASSERT_EQ(first_difference(cached_parse(cache, scene), full_parse(scene)), "");
  EXPECT_LT(cache.last_stats().scanned_bytes, 4000u);
  // An unclosed comment hides every later cut: the scan runs to the end of the file.
  size_t open_at = scene.size() / 3;
  scene.insert(open_at, "(* ");
  ASSERT_EQ(first_difference(cached_parse(cache, scene), full_parse(scene)), "");
  EXPECT_GE(cache.last_stats().scanned_bytes, scene.size() - open_at - 2000);
  // Closing it again: the cuts after it are found again (scan to the first old cut after
  // the edit, which is the end, since the previous version had none).
  scene.insert(open_at + 3, "*) ");
  ASSERT_EQ(first_difference(cached_parse(cache, scene), full_parse(scene)), "");
}

// Memory stays proportional to the document: typing where every keystroke makes a new
// piece of most of the file (inside an unclosed comment), and typing new statements that
// each add pieces, never lets the cache grow past a few times the document.
TEST(ParseCache, CacheStaysProportionalToTheDocument) {
  std::string scene = generated_scene(60);
  nomec::ParseCache cache;
  cached_parse(cache, scene);
  scene.insert(scene.size() / 3, "(* ");
  size_t at = scene.size() / 2;
  for (int k = 0; k < 40; ++k) {
    scene.insert(at++, 1, static_cast<char>('a' + k % 26));
    cached_parse(cache, scene);
    EXPECT_LE(cache.last_stats().cached_bytes, 3 * scene.size() + (64u << 10)) << k;
  }
  ASSERT_EQ(first_difference(cached_parse(cache, scene), full_parse(scene)), "");
  scene.erase(scene.size() / 3, 3);
  for (int k = 0; k < 200; ++k) {
    scene.insert(scene.find('\n', scene.size() / 2) + 1,
                 fmt::format("point t{} ({} 0 0) endpoint\n", k, k));
    cached_parse(cache, scene);
    EXPECT_LE(cache.last_stats().cached_pieces, 2 * cache.last_stats().pieces + 64) << k;
  }
  ASSERT_EQ(first_difference(cached_parse(cache, scene), full_parse(scene)), "");
}

std::string check_dump(const std::string& text, nomec::ParseCache* cache) {
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  nomec::CheckResult r =
      nomec::check_source(sources, "doc.nome", text, nomec::CheckOptions{}, diags, cache);
  return dump_diags(diags) + "--\n" + nomec::ir::dump_ir(r.module, sources);
}

TEST(ParseCache, CheckThroughCacheEqualsCheck) {
  std::string text = generated_scene(12);
  std::mt19937 rng(7);
  nomec::ParseCache cache;
  for (int k = 0; k < 40; ++k) {
    ASSERT_EQ(check_dump(text, &cache), check_dump(text, nullptr)) << "after edit " << k;
    random_edit(text, rng);
  }
}

}  // namespace

// A large text parsed on two threads (`parse_file`: two halves parsed alone at once and
// assembled; a new document's cache: its pieces, half of the bytes on each thread) must be
// exactly the parse on one thread. Every corpus file and example is cut in two (forced
// below the automatic size), also after random edits, which often leave a half that does
// not parse as it does inside the whole text: then the text is parsed in one piece.
TEST(ParseTwoThreads, EqualsOneThreadOnCorpusFilesUnderRandomEdits) {
  int versions = 0, halved = 0;
  ASSERT_NO_FATAL_FAILURE(for_each_edited_corpus_version(500, 6, [&](const Doc& d, const std::string& text, int k) {
    const std::string want = full_parse(text);
    ASSERT_EQ(first_difference(full_parse(text, nomec::ParseThreads::Two), want), "")
        << d.name << " after " << k << " edits, parse_file on two threads";
    nomec::ParseCache cache(nomec::ParseThreads::Two);
    ASSERT_EQ(first_difference(cached_parse(cache, text), want), "")
        << d.name << " after " << k << " edits, a new cache on two threads";
    EXPECT_EQ(cache.last_stats().threads, 2);
    nomec::DiagnosticEngine scratch;
    halved += nomec::parse_detail::parse_in_two_pieces(text, nomec::FileId{1}, scratch).has_value() ? 1 : 0;
    ++versions;
  }));
  // Most versions were really parsed as two halves, not in one piece after all.
  EXPECT_GT(halved, versions / 2) << halved << " of " << versions;
}

// With the parse layer's test switches set (the reference lexer and the tree-based
// builder), a parse on two threads still equals the one-thread parse; `ParseSwitches`
// carries the switches to the thread that parses the second half.
TEST(ParseTwoThreads, UnderTheReferenceSwitchesEqualsOneThread) {
  const std::string text = generated_scene(40);
  const std::string want = full_parse(text);
  nomec::parse_detail::ParseSwitches{true, true}.apply();
  const std::string got = full_parse(text, nomec::ParseThreads::Two);
  nomec::ParseCache cache(nomec::ParseThreads::Two);
  const std::string cached = cached_parse(cache, text);
  nomec::parse_detail::ParseSwitches{}.apply();
  EXPECT_EQ(first_difference(got, want), "");
  EXPECT_EQ(first_difference(cached, want), "");
  nomec::parse_detail::ParseSwitches seen;
  std::thread([&] {
    nomec::parse_detail::ParseSwitches{true, false}.apply();
    seen = nomec::parse_detail::ParseSwitches::current();
  }).join();
  EXPECT_TRUE(seen.reference_lexer);
  EXPECT_FALSE(seen.tree_builder);
  EXPECT_FALSE(nomec::parse_detail::ParseSwitches::current().reference_lexer);  // this thread's own
}

// Above `kTwoThreadParseBytes` both parse on two threads by themselves (on a machine with
// two hardware threads), and a cache filled so keeps matching under edits.
TEST(ParseTwoThreads, LargeSceneAutomaticallyOnTwoThreads) {
  const std::string scene = generated_scene(400);
  ASSERT_GE(scene.size(), nomec::kTwoThreadParseBytes);
  const std::string want = full_parse(scene);
  EXPECT_EQ(first_difference(full_parse(scene, nomec::ParseThreads::Automatic), want), "");
  nomec::ParseCache cache;
  EXPECT_EQ(first_difference(cached_parse(cache, scene), want), "");
  EXPECT_EQ(cache.last_stats().threads, nomec::has_two_hardware_threads() ? 2 : 1);
  EXPECT_EQ(cache.last_stats().parsed, cache.last_stats().pieces);
  differential("large generated", scene, 12, 700);
}

// The cut after the middle may be followed by a token that cannot start a statement (a
// stray `,`; a stray `)` is dropped by the bracket pass the same way in a piece and in the
// whole text): a piece starting there recovers differently from the whole text (piece.h),
// so the text is parsed in one piece, with the same result.
TEST(ParseTwoThreads, SecondHalfThatCannotStartAStatementIsNotUsed) {
  const int m = 20;
  std::string text;
  for (int k = 0; k < 2 * m; ++k) {
    if (k == m + 1) text += ", ";
    text += fmt::format("point p{:02} (1 2 3) endpoint\n", k);
  }
  nomec::DiagnosticEngine scratch;
  EXPECT_FALSE(nomec::parse_detail::parse_in_two_pieces(text, nomec::FileId{1}, scratch).has_value());
  EXPECT_TRUE(scratch.diagnostics().empty());  // nothing reported when the halves are not used
  EXPECT_EQ(first_difference(full_parse(text, nomec::ParseThreads::Two), full_parse(text)), "");
  // Without the stray `,` the same text is parsed as two halves.
  std::string clean = text;
  clean.erase(clean.find(", "), 2);
  EXPECT_TRUE(nomec::parse_detail::parse_in_two_pieces(clean, nomec::FileId{1}, scratch).has_value());
  EXPECT_EQ(first_difference(full_parse(clean, nomec::ParseThreads::Two), full_parse(clean)), "");
}

// Inputs on which the front-end fuzzer found the two-thread parse differing from the
// one-thread parse (fuzz/frontend_fuzzer.cpp compares them on every input). The first: the
// whole text's error recovery gives up in its second statement and keeps no AST, while its
// first statement parsed alone was kept (the cache did the same: PieceInfo::gave_up). The
// next two: the error recovery's diagnostics and the AST builder's came in another order
// when the text was cut in two (a recovery error after the cut, a wrong `end` word before
// it); the parse now reports them in position order. The fourth: an unclosed `tclupdate`
// in the second half stops the whole text's token pass, which then makes no repairs
// anywhere, while the first half parsed alone put a missing `(` before `0 2 1)`; a text
// whose last piece stopped is now parsed in one piece.
TEST(ParseTwoThreads, FuzzFindings) {
  const std::vector<std::string> texts = {
      std::string("point pnt p1 (0 2 1) endpoint\npoint ") + std::string(39, '\xff') +
          "\x91\x8b`)\xb1) endpt\npoint  (   1      -0 pr\x01\x86rus1 (",
      std::string("q\0n bspline  1  endtorus\ninst    0.1sav ) endtorus\ninstanc\ne c   ", 65),
      "point p1 (0- 1) endp\xff\xffot\xffn\xf2i\nciircle (20 1) endcircle\ntorus - 1) endp\xff\xffot\xffn"
      "\xf2i\nciircle (20 1) endcircle\ntorutor0s0 (",
      std::string("point W\0\0\0" "0 2 1)", 16) + std::string(38, '\xc7') + " endpoint\npoi) 1tclupdate) endpuo",
  };
  for (const std::string& text : texts) {
    EXPECT_EQ(first_difference(full_parse(text, nomec::ParseThreads::Two), full_parse(text)), "") << text;
    nomec::ParseCache cache(nomec::ParseThreads::One);
    EXPECT_EQ(first_difference(cached_parse(cache, text), full_parse(text)), "") << "cache";
  }
}

// ---- A file parsed in pieces, each checked and freed (`parse_file_in_pieces`) ----

namespace {

// The pieces joined into one AST, each piece's ids moved by the totals of the pieces
// before it: this must be exactly `parse_file`'s AST.
nomec::ast::Ast joined(const std::vector<nomec::ast::Ast>& pieces) {
  namespace ast = nomec::ast;
  ast::Ast out;
  if (!pieces.empty()) out.file = pieces.front().file;
  for (const ast::Ast& p : pieces) {
    EXPECT_EQ(p.file.index, out.file.index);
    const int32_t e0 = static_cast<int32_t>(out.exprs.size()), l0 = static_cast<int32_t>(out.lists.size()),
                  s0 = static_cast<int32_t>(out.stmts.size());
    auto expr = [&](ast::ExprId id) { return id.is_valid() ? ast::ExprId{id.index + e0} : id; };
    auto item = [&](ast::Item i) {
      i.expr = expr(i.expr);
      if (i.list.is_valid()) i.list.index += l0;
      if (i.block.is_valid()) i.block.index += s0;
      return i;
    };
    for (const ast::Expr& e : p.exprs) {
      ast::Expr& c = out.exprs.emplace_back(e);
      if (e.kind == ast::ExprKind::Call) {
        c.set_args(static_cast<uint32_t>(out.args.size()), e.args_count());
        for (ast::ExprId a : p.args_of(e)) out.args.push_back(expr(a));
      } else if (e.kind == ast::ExprKind::Unary || e.kind == ast::ExprKind::Binary) {
        c.set_operands(expr(e.lhs()), expr(e.rhs()));
      }
    }
    for (const ast::ParenList& l : p.lists) {
      ast::ParenList& c = out.lists.emplace_back(l);
      for (ast::ExprId& e : c.elems) e = expr(e);
    }
    for (const ast::ListComma& k : p.commas) out.commas.push_back({ast::ListId{k.list.index + l0}, k.range});
    for (const ast::Stmt& s : p.stmts) {
      ast::Stmt& c = out.stmts.emplace_back(s);
      for (ast::Item& i : c.items) i = item(i);
    }
    for (const ast::Item& i : p.top) out.top.push_back(item(i));
  }
  return out;
}

// `text` parsed in pieces of about `bytes` (as file 1, like full_parse): the joined AST's
// dump and the diagnostics; `count` gets the number of pieces.
std::string pieces_parse(const std::string& text, size_t bytes, nomec::ParseThreads threads, size_t* count = nullptr) {
  nomec::SourceManager sources;
  sources.add_file("other.nome", "point p (1 2 3) endpoint\n");
  nomec::DiagnosticEngine diags;
  const nomec::FileId f = sources.add_file("doc.nome", text);
  const std::vector<nomec::ast::Ast> pieces = nomec::parse_file_in_pieces(sources, f, diags, bytes, threads);
  if (count != nullptr) *count = pieces.size();
  // Runs of whole top-level items in the text's order (a piece of only comments has none).
  uint32_t end = 0;
  for (size_t k = 0; k < pieces.size(); ++k) {
    if (pieces[k].top.empty()) continue;
    EXPECT_LE(end, pieces[k].top.front().range.begin) << "piece " << k;
    end = pieces[k].top.back().range.end;
  }
  return dump_ast(joined(pieces)) + "--\n" + dump_diags(diags);
}

// A check's diagnostics (in emission order) and IR dump; `piece_bytes` as in CheckOptions.
std::string check_dump_named(const std::string& path, const std::string& text, size_t piece_bytes) {
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  nomec::CheckOptions options;
  options.piece_bytes = piece_bytes;
  nomec::CheckResult r = nomec::check_source(sources, path, text, options, diags);
  return dump_diags(diags) + "--\n" + nomec::ir::dump_ir(r.module, sources) + "--\n" + r.dialect_reason;
}

}  // namespace

// Every corpus file and example, also after random edits (which often leave a piece that
// does not parse as it does inside the whole text: then the text is one piece), in pieces
// of one byte (a piece per top-level statement), of 97 bytes and of 1 KiB, on one and two
// threads: joined, exactly `parse_file`'s AST and diagnostics.
TEST(ParseInPieces, EqualsParseFileOnCorpusFilesUnderRandomEdits) {
  int versions = 0, pieced = 0;
  ASSERT_NO_FATAL_FAILURE(for_each_edited_corpus_version(900, 4, [&](const Doc& d, const std::string& text, int k) {
    const std::string want = full_parse(text);
    for (size_t bytes : {size_t{1}, size_t{97}, size_t{1024}}) {
      const auto threads = bytes == 97 ? nomec::ParseThreads::Two : nomec::ParseThreads::One;
      size_t count = 0;
      ASSERT_EQ(first_difference(pieces_parse(text, bytes, threads, &count), want), "")
          << d.name << " after " << k << " edits, pieces of " << bytes << " bytes";
      if (bytes == 1) {
        ++versions;
        pieced += count > 1 ? 1 : 0;
      }
    }
  }));
  // Most versions really were parsed in pieces, not as one piece after all.
  EXPECT_GT(pieced, versions / 2) << pieced << " of " << versions;
}

// The generated scene in the command line's pieces (64 KiB), on two threads: several
// pieces, the same AST; under edits too.
TEST(ParseInPieces, LargeSceneInCheckPieces) {
  std::string scene = generated_scene(1200);
  ASSERT_GE(scene.size(), 4 * nomec::kCheckPieceBytes);
  std::mt19937 rng(31);
  for (int k = 0; k < 6; ++k) {
    if (k > 0) random_edit(scene, rng);
    size_t count = 0;
    EXPECT_EQ(first_difference(pieces_parse(scene, nomec::kCheckPieceBytes, nomec::ParseThreads::Automatic, &count),
                               full_parse(scene)),
              "")
        << "after " << k << " edits";
    if (k == 0) {
      EXPECT_GE(count, 4u);
    }
  }
}

// A piece after which the next cannot start a statement (a stray `,`), an unclosed comment
// running over the cuts, and the fuzzer's findings for the two-thread parse: one piece, or
// pieces that still join to the same AST.
TEST(ParseInPieces, PiecesThatCannotStandAlone) {
  std::string stray, comment;
  for (int k = 0; k < 40; ++k) {
    stray += fmt::format("{}point p{:02} (1 2 3) endpoint\n", k == 21 ? ", " : "", k);
    comment += fmt::format("point p{:02} (1 2 3) endpoint\n", k);
  }
  size_t count = 0;
  EXPECT_EQ(first_difference(pieces_parse(stray, 64, nomec::ParseThreads::One, &count), full_parse(stray)), "");
  EXPECT_EQ(count, 1u);  // the piece before the `)` is not self-contained
  EXPECT_EQ(first_difference(pieces_parse(comment, 64, nomec::ParseThreads::One, &count), full_parse(comment)), "");
  EXPECT_GT(count, 10u);  // the clean text is in pieces
  comment.insert(comment.size() / 3, "(* not closed\n");
  EXPECT_EQ(first_difference(pieces_parse(comment, 64, nomec::ParseThreads::Two, &count), full_parse(comment)), "");
  EXPECT_LT(count, 6u);  // only the statements before the comment can be pieces of their own
  const std::vector<std::string> fuzz = {
      std::string("q\0n bspline  1  endtorus\ninst    0.1sav ) endtorus\ninstanc\ne c   ", 65),
      std::string("point W\0\0\0" "0 2 1)", 16) + std::string(38, '\xc7') + " endpoint\npoi) 1tclupdate) endpuo",
  };
  for (const std::string& text : fuzz) {
    for (size_t bytes : {size_t{1}, size_t{8}}) {
      EXPECT_EQ(first_difference(pieces_parse(text, bytes, nomec::ParseThreads::Two), full_parse(text)), "") << text;
    }
  }
}

// A check in pieces, each tree freed once checked, gives exactly the diagnostics (in
// emission order), IR and dialect of the check of the whole tree: every corpus file and
// example under its own name (the extension chooses dialects and SLIDE, which is never in
// pieces), also after random edits, and the generated scene. Under the address sanitizer
// this also shows that nothing reads a freed piece.
TEST(CheckInPieces, EqualsCheckOfTheWholeTree) {
  ASSERT_NO_FATAL_FAILURE(for_each_edited_corpus_version(1300, 3, [&](const Doc& d, const std::string& text, int k) {
    const std::string name = fs::path(d.name).filename().string();
    const std::string want = check_dump_named(name, text, 0);
    for (size_t bytes : {size_t{1}, size_t{200}}) {
      ASSERT_EQ(first_difference(check_dump_named(name, text, bytes), want), "")
          << d.name << " after " << k << " edits, pieces of " << bytes << " bytes";
    }
  }));
  std::string scene = generated_scene(300);
  std::mt19937 rng(77);
  for (int k = 0; k < 4; ++k) {
    if (k > 0) random_edit(scene, rng);
    ASSERT_EQ(first_difference(check_dump_named("scene.nome", scene, 4096), check_dump_named("scene.nome", scene, 0)),
              "")
        << "generated scene after " << k << " edits";
  }
  // A run of stray items is reported at its first item only; the front-end fuzzer found a
  // run cut between two pieces reported again at the cut.
  const std::vector<std::string> stray_runs = {
      "jank param\r\n\" set sharpness 2 0 10 0.5\r\n  list (sharpness)\r\nendbank\r\n\r\n\r\n"
      "point p1 (1 1 1) endpoint ### direc\rn)tses\nen sharpness",
      "point p (1 2 3) endpoint\nfoo bar baz qux quux (1 2) corge grault\npoint q (0 0 0) endpoint\n",
  };
  for (const std::string& text : stray_runs) {
    const std::string want = check_dump_named("fuzz.nom", text, 0);
    for (size_t bytes : {size_t{1}, size_t{8}, size_t{13}}) {
      ASSERT_EQ(first_difference(check_dump_named("fuzz.nom", text, bytes), want), "") << text << "\npieces of " << bytes;
    }
  }
}
