// Invariants of the language index over every corpus file and example: every occurrence
// names its symbol's text and resolves to a definition inside a file, references include
// the definition, semantic tokens are sorted and non-overlapping, folding ranges nest, and
// renaming symbols (same-length fresh names) re-checks with no new errors and the same IR
// dump once the name is mapped back.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "frontend/index/index.h"
#include "tests/common/corpus_inputs.h"

namespace nomec::index {
namespace {

namespace fs = std::filesystem;

using nomec::testing_inputs::read_file;
std::vector<std::string> input_files() { return nomec::testing_inputs::corpus_and_examples(); }

TEST(IndexCorpus, FoundInputs) { EXPECT_GE(input_files().size(), 50u); }

class IndexCorpus : public ::testing::TestWithParam<std::string> {};

Analysis analyze_file(const std::string& path, DiagnosticEngine& diags, std::string text) {
  CheckOptions opts;
  opts.read_file = read_file;
  opts.list_folder = list_folder;
  return analyze(path, std::move(text), opts, diags);
}

// A valid name of the same length as `old` that no symbol uses.
std::string fresh_name(const Index& ix, const std::string& old) {
  std::set<std::string> used;
  for (const Symbol& s : ix.symbols()) used.insert(s.name);
  for (char first : std::string("QWXZJK")) {
    std::string n(old.size(), 'q');
    n[0] = first;
    if (!used.contains(n)) return n;
  }
  return "";
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) s.replace(p, from.size(), to);
  return s;
}

TEST_P(IndexCorpus, Invariants) {
  const std::string path = GetParam();
  std::optional<std::string> text = read_file(path);
  ASSERT_TRUE(text);
  DiagnosticEngine diags;
  Analysis a = analyze_file(path, diags, *text);
  const Index& ix = *a.index;
  const SourceManager& sm = *a.sources;
  const auto& syms = ix.symbols();

  // Occurrences: inside their file, named like their symbol, found again by position.
  size_t occ_count = 0;
  for (const Symbol& s : syms) {
    auto all = ix.references(s.id, true);
    auto uses = ix.references(s.id, false);
    size_t defs = 0;
    for (const Occurrence& o : all) {
      ++occ_count;
      ASSERT_TRUE(o.range.file.is_valid());
      ASSERT_LT(static_cast<size_t>(o.range.file.index), sm.file_count());
      ASSERT_LE(o.range.end, sm.text(o.range.file).size());
      EXPECT_EQ(sm.text(o.range), s.name) << path << ": occurrence of `" << s.name << "`";
      EXPECT_EQ(o.symbol, s.id);
      auto again = ix.occurrence_at(o.range.file, o.range.begin);
      ASSERT_TRUE(again);
      EXPECT_EQ(again->range, o.range);
      if (o.is_definition) {
        ++defs;
        EXPECT_EQ(o.range, s.name_range);
      }
    }
    EXPECT_LE(defs, 1u);
    EXPECT_EQ(all.size(), uses.size() + defs);
    if (defs == 0) {
      // Only names without a written definition: SLIDE instances named by their target,
      // SLIDE sliders a helper made (located at the helper's call, which names their bank),
      // and `consolidatemesh`.
      const bool helper_slider = s.kind == SymbolKind::Parameter && a.check->dialect == Dialect::Slide &&
                                 sm.text(s.name_range) != s.name;
      EXPECT_TRUE((s.kind == SymbolKind::Instance && a.check->dialect == Dialect::Slide) || helper_slider ||
                  s.name == "consolidatemesh")
          << path << ": `" << s.name << "` has no definition occurrence";
    }
    ASSERT_TRUE(s.name_range.is_valid());
    ASSERT_LT(static_cast<size_t>(s.name_range.file.index), sm.file_count());
    if (s.parent >= 0) {
      EXPECT_LT(s.parent, s.id);
    }
  }
  // Flat meshes define no names, nor does saved work over one (its vertices are `v<k>`).
  auto flat = [](const std::string& p) { return p.ends_with(".sif") || p.ends_with(".obj") || p.ends_with(".stl"); };
  const bool nome_source = !flat(path) && !flat(a.check->base_file);
  if (nome_source) {
    EXPECT_GT(syms.size(), 0u) << path;
  }

  for (size_t f = 0; f < sm.file_count(); ++f) {
    FileId file{static_cast<int32_t>(f)};
    // Semantic tokens: sorted, non-overlapping, non-empty, inside the file.
    auto toks = ix.semantic_tokens(file);
    for (size_t i = 0; i < toks.size(); ++i) {
      EXPECT_LT(toks[i].range.begin, toks[i].range.end);
      EXPECT_LE(toks[i].range.end, sm.text(file).size());
      if (i > 0) {
        EXPECT_LE(toks[i - 1].range.end, toks[i].range.begin) << path;
      }
    }
    // Folding ranges: each pair nested or disjoint.
    auto folds = ix.folding_ranges(file);
    for (size_t i = 0; i < folds.size(); ++i) {
      for (size_t j = i + 1; j < folds.size(); ++j) {
        const SourceRange& x = folds[i].range;
        const SourceRange& y = folds[j].range;
        bool disjoint = x.end <= y.begin || y.end <= x.begin;
        bool nested = (x.begin <= y.begin && y.end <= x.end) || (y.begin <= x.begin && x.end <= y.end);
        EXPECT_TRUE(disjoint || nested) << path;
      }
    }
    // Outline: top-level, in source order.
    auto top = ix.outline(file);
    for (size_t i = 0; i < top.size(); ++i) {
      EXPECT_EQ(syms[top[i]].parent, -1);
      if (i > 0) {
        EXPECT_LE(syms[top[i - 1]].full_range.begin, syms[top[i]].full_range.begin);
      }
    }
  }
  // Hover on every definition works and names the symbol.
  for (const Symbol& s : syms) {
    auto h = ix.hover(s.name_range.file, s.name_range.begin);
    if (!h) continue;  // no definition occurrence (see above)
    EXPECT_NE(h->markdown.find(s.name), std::string::npos) << path << ": " << h->markdown;
  }

  // Rename: a few symbols of each kind in the main file.
  int errors = diags.error_count();
  std::string dump = ir::dump_ir(a.check->module, sm);
  // One symbol per kind, at most five per file: each rename re-checks the file twice.
  std::map<SymbolKind, int> tried;
  int renamed_count = 0;
  for (const Symbol& s : syms) {
    if (s.name_range.file != a.file || tried[s.kind] >= 1 || renamed_count >= 5) continue;
    std::string fresh = fresh_name(ix, s.name);
    if (fresh.empty()) continue;
    auto r = ix.rename(s.name_range.file, s.name_range.begin, fresh);
    if (!std::holds_alternative<std::vector<TextEdit>>(r)) continue;  // refused with a reason
    ++tried[s.kind];
    ++renamed_count;
    auto edits = std::get<std::vector<TextEdit>>(r);
    // Apply the edits to every file they touch (an included file may use the name too).
    std::map<int32_t, std::string> texts;
    for (const TextEdit& e : edits) texts.emplace(e.range.file.index, std::string(sm.text(e.range.file)));
    for (size_t i = edits.size(); i-- > 0;) {
      std::string& t = texts[edits[i].range.file.index];
      t.replace(edits[i].range.begin, edits[i].range.end - edits[i].range.begin, edits[i].new_text);
    }
    std::map<std::string, std::string> by_name;
    for (auto& [f, t] : texts) by_name[std::string(sm.name(FileId{f}))] = t;
    std::string renamed = texts.contains(a.file.index) ? texts[a.file.index] : *text;
    CheckOptions opts;
    opts.read_file = [&](const std::string& p) -> std::optional<std::string> {
      if (auto it = by_name.find(p); it != by_name.end()) return it->second;
      return read_file(p);
    };
    opts.list_folder = list_folder;
    DiagnosticEngine d2;
    Analysis b = analyze(path, renamed, opts, d2);
    EXPECT_EQ(d2.error_count(), errors) << path << ": renaming `" << s.name << "` to `" << fresh << "`";
    std::string dump2 = replace_all(ir::dump_ir(b.check->module, *b.sources), fresh, s.name);
    EXPECT_EQ(dump2, dump) << path << ": renaming `" << s.name << "` to `" << fresh << "`";
  }
  if (nome_source) {
    EXPECT_GT(occ_count, 0u);
  }
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string rel = info.param;
  for (std::string_view root : {std::string_view(NOMEC_CORPUS_DIR), std::string_view(NOMEC_SOURCE_DIR)}) {
    if (rel.starts_with(root)) rel = rel.substr(root.size());
  }
  std::string out;
  for (char c : rel) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out;
}

INSTANTIATE_TEST_SUITE_P(Files, IndexCorpus, ::testing::ValuesIn(input_files()), test_name);

}  // namespace
}  // namespace nomec::index
