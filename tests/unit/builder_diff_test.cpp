// Differential tests of the AST builder that reads the generated parser's events (what
// every error-free parse uses, frontend/parse/parse.cpp: StreamBuilder) against the builder
// that converts each statement's ANTLR parse tree (AstBuilder, kept as its reference and for
// texts with syntax errors): on every corpus file, example, golden test input, fuzzer
// corpus input (when a fuzzing build has one), the benchmark's generated scene and
// thousands of seeded generated programs, the two must give the same AST (every node, id,
// range, text and number) and the same diagnostics in the same order.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "bench/common/generated_scene.h"
#include "frontend/parse/parse.h"
#include "frontend/parse/piece.h"
#include "tests/common/ast_dump.h"
#include "tests/common/corpus_inputs.h"
#include "tests/common/parse_switches.h"

namespace fs = std::filesystem;

namespace {

struct Counts {
  size_t texts = 0;
  size_t clean = 0;  // texts whose parse reported no error: the event-driven builder built them
};

void compare(const std::string& name, const std::string& text, Counts& counts) {
  ++counts.texts;
  bool clean = false;
  const std::string from_events = nomec::testing_dump::parse_dump(text, nomec::ParseThreads::Automatic, &clean);
  std::string from_tree;
  {
    nomec::testing_switches::ScopedParseSwitch tree(
        &nomec::parse_detail::ParseSwitches::tree_builder, true);
    from_tree = nomec::testing_dump::parse_dump(text);
  }
  if (clean) ++counts.clean;
  ASSERT_EQ(from_events, from_tree) << name;
}

TEST(BuilderDiff, CorpusAndExamples) {
  Counts counts;
  for (const std::string& path : nomec::testing_inputs::corpus_and_examples()) {
    const std::optional<std::string> text = nomec::testing_inputs::read_file(path);
    ASSERT_TRUE(text.has_value()) << path;
    compare(path, *text, counts);
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(counts.texts, 50u);
  EXPECT_GT(counts.clean * 2, counts.texts) << "most corpus files parse without syntax errors";
}

// Every golden test input (parse, check and IR goldens), and the fuzzer's working corpus
// when a fuzzing build beside the sources has one (or the folder NOMEC_FUZZ_CORPUS names).
TEST(BuilderDiff, GoldenAndFuzzInputs) {
  Counts counts;
  for (const std::string& path : nomec::testing_inputs::golden_inputs()) {
    const std::optional<std::string> text = nomec::testing_inputs::read_file(path);
    ASSERT_TRUE(text.has_value()) << path;
    compare(path, *text, counts);
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(counts.texts, 200u);
  EXPECT_GT(counts.clean, 50u);
  const char* env = std::getenv("NOMEC_FUZZ_CORPUS");
  const fs::path dir = env != nullptr ? fs::path(env) : fs::path(NOMEC_SOURCE_DIR) / "build-sanitize/fuzz-corpus/frontend_fuzzer";
  for (const std::string& path : nomec::testing_inputs::files_under(dir)) {
    const std::optional<std::string> text = nomec::testing_inputs::read_file(path);
    ASSERT_TRUE(text.has_value()) << path;
    compare(path, *text, counts);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

TEST(BuilderDiff, GeneratedScene) {
  Counts counts;
  compare("generated scene", nomec::bench::generate_scene(64 * 1024), counts);
  EXPECT_EQ(counts.clean, 1u);
}

// Random programs that mostly parse: every kind of statement, nested blocks, every
// expression form (signs, all operators, `^` chains, calls, parentheses, braces, Tcl
// braces, raw text, strings, `$` references), lists with commas, keywords used as names,
// single-line statements without their end keyword and misspelt ones (the line-end
// repairs), generators closed by another generator's end keyword, Tcl blocks, includes and
// stray items; and a few damaged ones (both builders then see the recovering parse).
class ProgramGenerator {
 public:
  explicit ProgramGenerator(uint32_t seed) : rng_(seed) {}

  std::string program() {
    std::string out;
    const int stmts = 1 + pick(8);
    for (int i = 0; i < stmts; ++i) {
      top(out);
      out += pick(4) == 0 ? " " : "\n";
    }
    if (pick(12) == 0 && !out.empty()) out.erase(pick(static_cast<int>(out.size())), 1 + pick(3));  // damage
    return out;
  }

 private:
  int pick(int n) { return static_cast<int>(rng_() % static_cast<uint32_t>(n)); }
  template <size_t N>
  const char* one(const char* const (&options)[N]) {
    return options[pick(static_cast<int>(N))];
  }

  void top(std::string& out) {
    switch (pick(14)) {
      case 0: out += one({"tclinit { set a 1 }", "tclupdate {x {y} z}", "tclinit {}"}); return;
      case 1: out += one({"include \"viewing.slf\"", "include \"\"", "include \"a b.slf\""}); return;
      case 2: item(out, 0); return;  // a stray item
      case 3:  // a single-line statement left open, or closed by a wrong end keyword
        out += one({"point p (1 2 3)\n", "instance i m translate (0 0 1)\n", "face f (a b c)\n",
                    "instance i m endinstnace\n", "point q (1 2 3) endpont\n", "funnel f (4 1 0.5 1)\n"});
        return;
      default: block(out, 0); return;
    }
  }

  void block(std::string& out, int depth) {
    static const char* const kFlat[] = {"bank", "point", "polyline", "facet", "vertex", "object", "surface", "path",
                                        "transform", "lookat", "sharp", "camera", "light", "window", "viewport",
                                        "render", "foreground", "background", "frontcolor", "backcolor",
                                        "backgroundcolor", "backface", "zipper", "controlpoint", "savedparameter"};
    static const char* const kGen[] = {"funnel", "tunnel", "torus", "circle", "sphere", "cylinder", "genparametricsurf"};
    const int what = depth > 3 ? 0 : pick(10);
    if (what <= 3) {
      const char* kw = one(kFlat);
      out += kw;
      body_items(out, depth, true);
      out += fmt::format(" end{}", kw);
    } else if (what == 4) {
      const char* kw = one(kGen);
      out += kw;
      body_items(out, depth, false);
      // Mostly its own end keyword; sometimes another generator's (a diagnostic, or 2016's
      // `tunnel … endfunnel`).
      out += fmt::format(" end{}", pick(5) == 0 ? one(kGen) : kw);
    } else {
      static const char* const kNested[] = {"mesh", "group", "instance", "face", "sweep", "merge", "subdivision",
                                            "offset", "delete", "crosssection", "consolidate", "mirror"};
      const char* kw = one(kNested);
      out += kw;
      const int n = pick(5);
      for (int i = 0; i < n; ++i) {
        out += pick(3) == 0 ? "\n  " : " ";
        if (pick(3) == 0) {
          const std::string k = kw;
          if (k == "mesh") {
            out += one({"point v (0 0 0) endpoint", "face f (a b c) endface", "sharp (a b) endsharp", "vertex v (1 1 1) endvertex"});
          } else if (k == "group") {
            out += "instance a m translate (0 0 1) endinstance";
          } else if (k == "instance") {
            out += "lookat (0 0 1) endlookat";
          } else if (k == "face") {
            out += "vertex w (1 2 3) endvertex";
          } else if (k == "sweep") {
            out += one({"crosssection c (1 2) endcrosssection", "path (0 0 0) endpath"});
          } else if (k == "delete") {
            out += "face f endface";
          } else if (k == "crosssection") {
            out += "transform (1 0 0) endtransform";
          } else if (k == "consolidate") {
            out += "consolidateface vertex v endvertex endconsolidateface";
          } else {
            block(out, depth + 1);  // pipeline blocks nest any block
          }
        } else {
          item(out, depth);
        }
      }
      out += fmt::format(" end{}", kw);
    }
  }

  void body_items(std::string& out, int depth, bool keywords_as_words) {
    const int n = pick(6);
    for (int i = 0; i < n; ++i) {
      out += pick(4) == 0 ? "\n\t" : " ";
      if (keywords_as_words && pick(8) == 0) {
        out += one({"point", "mesh", "expr", "include", "face", "funnel", "instance"});
      } else {
        item(out, depth);
      }
    }
  }

  void item(std::string& out, int depth) {
    switch (pick(6)) {
      case 0: out += one({"set", "n", "fp.x", "_a1", "translate", "rotate", "scale", "type", "NOME_SD_CC"}); return;
      case 1:
      case 2: list(out, depth); return;
      default: item_value(out, depth); return;
    }
  }

  void list(std::string& out, int depth) {
    out += pick(5) == 0 ? "( " : "(";
    const int n = pick(5);
    for (int i = 0; i < n; ++i) {
      if (i > 0) out += pick(6) == 0 ? ", " : " ";
      expr(out, depth + 1, /*in_list=*/true);
    }
    out += pick(5) == 0 ? " )" : ")";
  }

  // A value in a block body: never a bare word or `(` first.
  void item_value(std::string& out, int depth) {
    switch (pick(4)) {
      case 0: out += one({"-", "+", "--", "-+"}); operand(out, depth); break;
      case 1: number(out); break;
      default: item_atom(out, depth); break;
    }
    tail(out, depth, true);
  }

  void item_atom(std::string& out, int depth) {
    switch (pick(7)) {
      case 0: out += one({"$b.x", "$fp_n", "$time"}); return;
      case 1: out += one({"$oSub(type)", "$a(b_1)", "$x()"}); return;
      case 2: out += one({"[cos(u)*v]", "[a [b] c]", "[]"}); return;
      case 3: out += one({"\"s\"", "\"a\\\"b\"", "\"\""}); return;
      case 4: out += one({"%{ raw }%", "%{}%"}); return;
      default: brace(out, depth); return;
    }
  }

  void brace(std::string& out, int depth) {
    switch (pick(4)) {
      case 0: out += one({"{if {$n >= 2} {expr 1} else {expr 0}}", "{a b {c}}", "{}", "{x {y {z}} ;}"}); return;
      case 1: out += "{"; expr(out, depth + 1, false); out += "}"; return;
      default: out += pick(3) == 0 ? "{expr " : "{ expr "; expr(out, depth + 1, false); out += "}"; return;
    }
  }

  void number(std::string& out) { out += one({"0", "1", "2.5", ".5", "1.", "1e3", "1.5e-2", "3E+1", "0.1", "10", "1e999", "1e-310", "1e-999", "007.50",
                      "0.30000000000000004", "123456789012345678901234567890"}); }

  void operand(std::string& out, int depth) {
    const int kinds = depth > 4 ? 3 : 9;
    switch (pick(kinds)) {
      case 0: number(out); return;
      case 1: out += one({"$b.x", "$fp_n", "$a(b)"}); return;
      case 2: out += one({"pi", "x", "point", "expr", "mesh", "v.1"}); return;  // names, keywords included
      case 3:
        out += one({"sin", "cos", "f", "point"});
        out += "(";
        for (int i = 0, n = pick(3); i < n; ++i) {
          if (i > 0) out += pick(2) == 0 ? ", " : ",";
          expr(out, depth + 1, false);
        }
        out += ")";
        return;
      case 4: out += "("; expr(out, depth + 1, false); out += ")"; return;
      case 5: brace(out, depth); return;
      case 6: out += one({"\"t\"", "[u]", "%{p}%"}); return;
      default: number(out); return;
    }
  }

  // `(op sign* operand)*` after the first operand. In a list (or a block body) an
  // operator is spaced or written close on both sides, so `a -b` (a new element) is rare.
  void tail(std::string& out, int depth, bool list_like) {
    const int n = pick(4);
    for (int i = 0; i < n; ++i) {
      const char* op = one({"+", "-", "*", "/", "//", "%", "^"});
      const bool spaced = pick(2) == 0;
      if (spaced) out += " ";
      out += op;
      if (spaced || (!list_like && pick(3) == 0)) out += " ";
      if (pick(4) == 0) out += one({"-", "+", "-+"});
      operand(out, depth + 1);
    }
  }

  void expr(std::string& out, int depth, bool in_list) {
    if (pick(4) == 0) out += one({"-", "+", "--"});
    operand(out, depth);
    tail(out, depth, in_list);
  }

  std::mt19937 rng_;
};

TEST(BuilderDiff, GeneratedPrograms) {
  ProgramGenerator gen(18);
  Counts counts;
  for (int n = 0; n < 4000; ++n) {
    const std::string text = gen.program();
    compare(fmt::format("generated #{}:\n{}", n, text), text, counts);
    if (::testing::Test::HasFatalFailure()) return;
  }
  // Most programs parse, so the event-driven builder is what is compared.
  EXPECT_GT(counts.clean, 2000u);
}

}  // namespace
