// The generator catalogue (ir/generators.def) against itself and against the places that
// repeat it for people: the catalogue builds without problems, each argument's declared type
// agrees with the domain rules the checker and backend apply, the VS Code grammar's keyword
// lists are the catalogue's and the block kinds', and docs/generators.md carries the
// reference generated from the catalogue. NOMEC_UPDATE_GOLDEN=1 rewrites the two files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "frontend/ast/ast.h"
#include "ir/generator_catalogue.h"

namespace nomec {
namespace {

using ir::ArgType;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

bool updating() {
  const char* u = std::getenv("NOMEC_UPDATE_GOLDEN");
  return u != nullptr && std::string(u) == "1";
}

const std::string kRoot = NOMEC_SOURCE_DIR;

TEST(Catalogue, BuildsWithoutProblems) {
  EXPECT_TRUE(ir::catalogue_problems().empty()) << ir::catalogue_problems().front();
  std::set<std::string_view> keywords;
  for (const ir::GeneratorInfo& g : ir::generators()) {
    EXPECT_FALSE(g.keywords.empty());
    EXPECT_EQ(g.keywords.front(), g.keyword);
    EXPECT_FALSE(g.summary.empty()) << g.keyword;
    for (std::string_view k : g.keywords) {
      EXPECT_TRUE(keywords.insert(k).second) << "keyword `" << k << "` is listed twice";
      EXPECT_EQ(ast::block_of_keyword(k), ast::BlockKind::Generator) << k;
      EXPECT_EQ(ir::generator_by_keyword(k), g.kind) << k;
    }
    for (const ir::ArgInfo& a : g.args) EXPECT_FALSE(a.doc.empty()) << g.keyword << " " << a.name;
    // Every dialect that has the keyword can set every argument a function or point list
    // needs; a generator without a positional list in a dialect takes options there.
    for (Dialect d : kDialects) {
      if (g.signature(d) == nullptr && g.option_words(d).empty()) {
        ADD_FAILURE() << g.keyword << " takes neither a list nor options in " << dialect_name(d);
      }
    }
  }
}

// One argument known, the others unknown: the value's domain rule alone decides.
std::optional<ir::ArgProblem> check_one(const ir::GeneratorInfo& g, ir::ArgIndex arg, double value) {
  std::vector<std::optional<double>> known(g.args.size());
  known[arg] = value;
  return ir::check_arguments(g.kind, Dialect::Nome3, known);
}

TEST(Catalogue, DomainRulesMatchDeclaredTypes) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const ir::GeneratorInfo& g : ir::generators()) {
    for (ir::ArgIndex i = 0; i < g.args.size(); ++i) {
      const ir::ArgInfo& a = g.args[i];
      const std::string what = std::string(g.keyword) + " `" + std::string(a.name) + "` (" +
                               std::string(ir::arg_type_name(a.type)) + ")";
      auto rejects = [&](double v) {
        std::optional<ir::ArgProblem> p = check_one(g, i, v);
        return p.has_value() && p->arg == i;
      };
      switch (a.type) {
        case ArgType::Count:
          EXPECT_TRUE(rejects(0)) << what << " accepts a count of 0";
          EXPECT_TRUE(rejects(ir::kMaxCount + 1.0)) << what << " accepts a count above the maximum";
          EXPECT_FALSE(rejects(8)) << what << " rejects a count of 8";
          EXPECT_TRUE(rejects(nan)) << what << " accepts NaN";
          break;
        case ArgType::Length:
          EXPECT_TRUE(rejects(0)) << what << " accepts 0";
          EXPECT_TRUE(rejects(-1)) << what << " accepts a negative length";
          EXPECT_FALSE(rejects(1.5)) << what << " rejects 1.5";
          EXPECT_TRUE(rejects(nan)) << what << " accepts NaN";
          break;
        case ArgType::Ratio:
          EXPECT_TRUE(rejects(-1)) << what << " accepts -1";
          EXPECT_FALSE(rejects(-0.5)) << what << " rejects -0.5";
          EXPECT_FALSE(rejects(2)) << what << " rejects 2";
          EXPECT_TRUE(rejects(nan)) << what << " accepts NaN";
          break;
        case ArgType::Fraction:
          EXPECT_TRUE(rejects(-0.1)) << what << " accepts -0.1";
          EXPECT_TRUE(rejects(1.5)) << what << " accepts 1.5";
          EXPECT_FALSE(rejects(0.5)) << what << " rejects 0.5";
          EXPECT_TRUE(rejects(nan)) << what << " accepts NaN";
          break;
        case ArgType::Angle:
        case ArgType::Real:
        case ArgType::Whole:
          EXPECT_TRUE(rejects(nan)) << what << " accepts NaN";
          EXPECT_TRUE(rejects(std::numeric_limits<double>::infinity())) << what << " accepts infinity";
          break;
        case ArgType::Flag:
        case ArgType::Function:
        case ArgType::Points:
        case ArgType::Path:
          // Not numbers: the checker reads them as words, texts and names; no domain rule
          // may claim them.
          EXPECT_FALSE(rejects(0)) << what << " has a numeric domain rule";
          break;
      }
    }
  }
}

// ---- The VS Code grammar's keyword lists ----

std::string alternation(std::vector<std::string_view> words) {
  std::sort(words.begin(), words.end(), [](std::string_view a, std::string_view b) {
    return a.size() != b.size() ? a.size() > b.size() : a < b;  // longest first: no prefix wins early
  });
  words.erase(std::unique(words.begin(), words.end()), words.end());
  std::string out;
  for (std::string_view w : words) {
    if (!out.empty()) out += '|';
    out += w;
  }
  return out;
}

TEST(Catalogue, EditorGrammarListsEveryKeyword) {
  std::vector<std::string_view> generators, blocks, all = ast::all_open_keywords();
  for (std::string_view k : all) {
    (ast::block_of_keyword(k) == ast::BlockKind::Generator ? generators : blocks).push_back(k);
  }
  const std::string want_all = alternation(all), want_blocks = alternation(blocks),
                    want_generators = alternation(generators);
  const std::string path = kRoot + "/editors/vscode/syntaxes/nome.tmLanguage.json";
  const std::string text = read_text(path);
  ASSERT_FALSE(text.empty()) << path;
  // Each keyword alternation in the file is one of the three lists: with generators and
  // other blocks (the end keywords), with other blocks only, with generators only.
  const std::regex group(R"(\((\?:)?([a-z]+(\|[a-z]+)+)\))");
  std::string updated;
  size_t last = 0;
  int seen = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), group); it != std::sregex_iterator(); ++it) {
    const std::string words = (*it)[2];
    const bool has_gen = ("|" + words + "|").find("|funnel|") != std::string::npos;
    const bool has_block = ("|" + words + "|").find("|mesh|") != std::string::npos;
    if (!has_gen && !has_block) continue;  // another list (option words)
    ++seen;
    const std::string& want = has_gen && has_block ? want_all : has_gen ? want_generators : want_blocks;
    const size_t at = static_cast<size_t>(it->position(2));
    updated += text.substr(last, at - last) + want;
    last = at + words.size();
    if (!updating()) {
      EXPECT_EQ(words, want) << path << " has a keyword list that is not the catalogue's (NOMEC_UPDATE_GOLDEN=1 rewrites it)";
    }
  }
  updated += text.substr(last);
  EXPECT_GE(seen, 3) << "the grammar's keyword lists were not found";
  if (updating() && updated != text) write_text(path, updated);
}

// The fuzzers' dictionary holds every opening and end keyword, so mutations can make any
// statement.
TEST(Catalogue, FuzzDictionaryListsEveryKeyword) {
  const std::string dict = read_text(kRoot + "/fuzz/nome.dict");
  ASSERT_FALSE(dict.empty());
  for (std::string_view k : ast::all_open_keywords()) {
    EXPECT_NE(dict.find("=\"" + std::string(k) + "\""), std::string::npos) << "fuzz/nome.dict lacks `" << k << "`";
    EXPECT_NE(dict.find("=\"" + ast::end_keyword(k) + "\""), std::string::npos)
        << "fuzz/nome.dict lacks `" << ast::end_keyword(k) << "`";
  }
}

// ---- docs/generators.md's reference section ----

std::string dialects_text(DialectSet set) {
  std::vector<std::string> names;
  for (Dialect d : kDialects) {
    if ((set & dialect_bit(d)) != 0) names.emplace_back(dialect_name(d));
  }
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::string reference_section() {
  std::ostringstream o;
  o << "This section is generated from `ir/generators.def`; `tests/unit/catalogue_test.cpp`\n"
       "checks it (`NOMEC_UPDATE_GOLDEN=1` rewrites it).\n";
  for (const ir::GeneratorInfo& g : ir::generators()) {
    o << "\n### `" << g.keyword << "`";
    for (size_t k = 1; k < g.keywords.size(); ++k) o << ", `" << g.keywords[k] << "`";
    std::string summary(g.summary);
    if (!summary.empty()) summary[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(summary[0])));
    o << "\n\n" << summary << " (" << (g.output == ir::GenOutput::Surface ? "faces" : "a curve") << ").\n";
    for (const ir::Signature& s : g.positional) {
      o << "\n- " << dialects_text(s.dialects) << ": `(";
      for (size_t n = 0; n < s.names.size(); ++n) {
        const bool optional = n >= s.args.size();
        o << (n > 0 ? " " : "") << (optional ? "[" : "") << s.names[n] << (optional ? "]" : "");
      }
      o << ")`";
    }
    for (const ir::Signature& s : g.orders) {
      o << "\n- another era's order in " << dialects_text(s.dialects)
        << (s.era.empty() ? std::string() : " (read first in " + std::string(s.era) + " files)") << ": `(";
      for (size_t n = 0; n < s.names.size(); ++n) o << (n > 0 ? " " : "") << s.names[n];
      o << ")`";
    }
    if (!g.digit_prefix.empty()) {
      o << "\n- also opened by `" << g.digit_prefix << "K` … `end" << g.digit_prefix << "K`, K digits setting `"
        << g.args[g.digit_arg].name << "`";
    }
    for (const ir::OptionInfo& op : g.options) {
      o << "\n- " << dialects_text(op.dialects) << ": option `" << op.word << "` sets `" << g.args[op.arg].name << "`";
    }
    if (!g.other_ends.empty()) {
      for (std::string_view e : g.other_ends) o << "\n- also closed by `" << e << "` (warned)";
    }
    o << "\n\n| argument | kind | also written | meaning |\n|---|---|---|---|\n";
    for (const ir::ArgInfo& a : g.args) {
      std::string aliases;
      for (std::string_view al : a.aliases) aliases += (aliases.empty() ? "`" : ", `") + std::string(al) + "`";
      o << "| `" << a.name << "` | " << ir::arg_type_name(a.type) << " | " << aliases << " | " << a.doc << " |\n";
    }
    if (!g.variables.empty()) {
      o << "\nFunction variables:";
      for (std::string_view v : g.variables) o << " `" << v << "`";
      o << ".\n";
    }
    if (!g.rings.empty()) {
      o << "\nVertices:";
      for (size_t r = 0; r < g.rings.size(); ++r) {
        o << (r > 0 ? "," : "") << " `" << g.rings[r].prefix << "0` … `" << g.rings[r].prefix << "{"
          << g.args[g.rings[r].count_arg].name << "−1}`";
      }
      for (const ir::VertexAlias& al : g.aliases) o << "; `" << al.alias << "{k}` = `" << al.prefix << "{k}`";
      o << ".\n";
    }
  }
  return o.str();
}

TEST(Catalogue, GeneratorDocsCarryTheReference) {
  const std::string path = kRoot + "/docs/generators.md";
  const std::string text = read_text(path);
  const std::string begin = "<!-- catalogue reference: begin -->\n", end = "<!-- catalogue reference: end -->";
  const size_t b = text.find(begin), e = text.find(end);
  ASSERT_NE(b, std::string::npos) << path << " lacks the line " << begin;
  ASSERT_NE(e, std::string::npos) << path << " lacks the line " << end;
  ASSERT_LT(b, e);
  const std::string have = text.substr(b + begin.size(), e - b - begin.size());
  const std::string want = reference_section();
  if (updating()) {
    if (have != want) write_text(path, text.substr(0, b + begin.size()) + want + text.substr(e));
    return;
  }
  EXPECT_EQ(have, want) << path << " is not the catalogue's reference (NOMEC_UPDATE_GOLDEN=1 rewrites it)";
}

}  // namespace
}  // namespace nomec
