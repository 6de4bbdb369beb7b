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
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "frontend/check/check.h"
#include "frontend/parse/parse.h"
#include "ir/ir.h"

namespace fs = std::filesystem;

namespace {

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
  const std::vector<fs::path> roots = {fs::path(NOMEC_CORPUS_DIR) / "nome1",
                                       fs::path(NOMEC_CORPUS_DIR) / "nome3",
                                       fs::path(NOMEC_CORPUS_DIR) / "slide",
                                       fs::path(NOMEC_SOURCE_DIR) / "examples"};
  for (const fs::path& root : roots) {
    std::error_code ec;
    for (const auto& e : fs::recursive_directory_iterator(root, ec)) {
      if (!e.is_regular_file()) continue;
      std::string ext = e.path().extension().string();
      if (ext == ".md" || ext == ".sif") continue;
      out.push_back({e.path().string(), read(e.path())});
    }
  }
  std::sort(out.begin(), out.end(), [](const Doc& a, const Doc& b) { return a.name < b.name; });
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

std::string dump_range(nomec::SourceRange r) {
  return fmt::format("{}:{}-{}", r.file.index, r.begin, r.end);
}

std::string dump_items(const std::vector<nomec::ast::Item>& items) {
  std::string s;
  for (const auto& i : items) {
    s += fmt::format(" [{} {} '{}' e{} l{} s{}]", static_cast<int>(i.kind), dump_range(i.range),
                     i.text, i.expr.index, i.list.index, i.block.index);
  }
  return s;
}

std::string dump_ast(const nomec::ast::Ast& a) {
  std::string s = fmt::format("file {}\ntop:{}\n", a.file.index, dump_items(a.top));
  for (size_t k = 0; k < a.stmts.size(); ++k) {
    const auto& st = a.stmts[k];
    s += fmt::format("s{} kind {} {} open {} close {} '{}':{}\n", k, static_cast<int>(st.kind),
                     dump_range(st.range), dump_range(st.open_kw), dump_range(st.close_kw),
                     st.close_text, dump_items(st.items));
  }
  for (size_t k = 0; k < a.exprs.size(); ++k) {
    const auto& e = a.exprs[k];
    s += fmt::format("e{} {} '{}' {} {} '{}' {} l{} r{}", k, static_cast<int>(e.kind),
                     e.op == 0 ? ' ' : e.op, e.in_braces, dump_range(e.range), e.text, e.number,
                     e.lhs.index, e.rhs.index);
    for (auto arg : e.args) s += fmt::format(" a{}", arg.index);
    s += "\n";
  }
  for (size_t k = 0; k < a.lists.size(); ++k) {
    const auto& l = a.lists[k];
    s += fmt::format("l{} {}", k, dump_range(l.range));
    for (auto e : l.elems) s += fmt::format(" e{}", e.index);
    for (auto c : l.commas) s += " ," + dump_range(c);
    s += "\n";
  }
  return s;
}

std::string dump_diags(const nomec::DiagnosticEngine& diags) {
  std::string s;
  for (const auto& d : diags.diagnostics()) {
    s += fmt::format("{} {} {}\n", nomec::diag_kind_name(d.kind), dump_range(d.range), d.message);
    for (const auto& n : d.notes) s += fmt::format("  note {} {}\n", dump_range(n.range), n.message);
    for (const auto& f : d.fixits) {
      s += fmt::format("  fixit {} '{}' {}\n", dump_range(f.range), f.replacement, f.description);
    }
  }
  return s;
}

// Both parses see the document as file 1 (file 0 is another file), so a cache that kept
// the file id its pieces were parsed with would show up.
std::string full_parse(const std::string& text) {
  nomec::SourceManager sources;
  sources.add_file("other.nome", "point p (1 2 3) endpoint\n");
  nomec::DiagnosticEngine diags;
  nomec::FileId f = sources.add_file("doc.nome", text);
  nomec::ast::Ast a = nomec::parse_file(sources, f, diags);
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
      size_t b = text.rfind('\n', at == 0 ? 0 : at - 1);
      b = b == std::string::npos ? 0 : b + 1;
      size_t e = text.find('\n', at);
      e = e == std::string::npos ? text.size() : e + 1;
      if (b < e) text.erase(b, e - b);
      break;
    }
    case 3: {  // duplicate a line
      size_t b = text.rfind('\n', at == 0 ? 0 : at - 1);
      b = b == std::string::npos ? 0 : b + 1;
      size_t e = text.find('\n', at);
      e = e == std::string::npos ? text.size() : e + 1;
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
void differential(const std::string& name, std::string text, int edits, uint32_t seed) {
  std::mt19937 rng(seed);
  nomec::ParseCache cache;
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

TEST(ParseCache, CorpusFilesUnderRandomEdits) {
  std::vector<Doc> docs = corpus_docs();
  ASSERT_FALSE(docs.empty()) << "no corpus files under " << NOMEC_CORPUS_DIR;
  uint32_t seed = 1;
  for (const Doc& d : docs) differential(d.name, d.text, 10, seed++);
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
