// Differential tests of the hand-written lexer (frontend/parse/lexer.cpp) against ANTLR's
// generated NomeLexer, its reference: on every corpus file, example, golden test input,
// fuzzer corpus input (when a fuzzing build has one) and thousands of seeded generated
// inputs, the two must give exactly the same tokens (type, byte range, line, channel), the
// same end-of-text lookahead, and through the whole parse layer the same AST (every node,
// id, range and text), the same diagnostics in the same order and the same `lex_file`
// tokens; on corpus files and examples also the same `check_source` diagnostics and IR
// (function texts included).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "frontend/check/check.h"
#include "frontend/parse/parse.h"
#include "frontend/parse/tokens.h"
#include "ir/ir.h"
#include "tests/common/ast_dump.h"
#include "tests/common/corpus_inputs.h"
#include "tests/common/parse_switches.h"

namespace fs = std::filesystem;
using nomec::parse_detail::Lexed;

namespace {

struct Counts {
  size_t texts = 0;
  size_t fast = 0;  // texts the hand-written lexer lexed (the rest it leaves to NomeLexer)
};

std::string dump_tokens(const Lexed& l) {
  std::string s;
  for (const auto& t : l.tokens) s += fmt::format("{} {}-{} L{}{}\n", t.type, t.begin, t.end, t.line, t.hidden ? " h" : "");
  return s;
}

std::string parse_dump(const std::string& text) {
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  const nomec::FileId f = sources.add_file("doc.nome", text);
  const nomec::ast::Ast a = nomec::parse_file(sources, f, diags);
  std::string s = nomec::testing_dump::dump_ast(a) + "--\n" + nomec::testing_dump::dump_diags(diags) + "--\n";
  for (const nomec::LexToken& t : nomec::lex_file(text)) s += fmt::format("{} {}-{}\n", static_cast<int>(t.kind), t.begin, t.end);
  return s;
}

std::string check_dump(const std::string& path, const std::string& text) {
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  nomec::CheckOptions options;
  options.read_file = [](const std::string&) -> std::optional<std::string> { return std::nullopt; };
  const nomec::CheckResult r = nomec::check_source(sources, path, text, options, diags);
  return nomec::testing_dump::dump_diags(diags) + "--\n" + nomec::ir::dump_ir(r.module, sources);
}

// Compares the two lexers on `text`, then the parse layer through each.
void compare(const std::string& name, const std::string& text, Counts& counts, bool check = false) {
  ++counts.texts;
  nomec::DiagnosticEngine ignored;
  std::string storage;
  bool open = false;
  const std::string_view blanked = nomec::parse_detail::blank_block_comments(text, storage, nomec::FileId{}, ignored, open);
  Lexed fast, reference;
  const bool lexed = nomec::parse_detail::lex_fast(blanked, fast);
  nomec::parse_detail::lex_antlr(blanked, reference);
  if (lexed) {
    ++counts.fast;
    ASSERT_EQ(dump_tokens(fast), dump_tokens(reference)) << name;
    ASSERT_EQ(fast.eof_touch_start, reference.eof_touch_start) << name;
  }
  const std::string with_fast = parse_dump(text);
  std::string with_reference;
  {
    nomec::testing_switches::ScopedParseSwitch ref(
        &nomec::parse_detail::ParseSwitches::reference_lexer, true);
    with_reference = parse_dump(text);
  }
  ASSERT_EQ(with_fast, with_reference) << name;
  if (check) {
    const std::string checked_fast = check_dump(name, text);
    nomec::testing_switches::ScopedParseSwitch ref(
        &nomec::parse_detail::ParseSwitches::reference_lexer, true);
    ASSERT_EQ(checked_fast, check_dump(name, text)) << name;
  }
}

TEST(LexerDiff, CorpusAndExamples) {
  Counts counts;
  for (const std::string& path : nomec::testing_inputs::corpus_and_examples()) {
    const std::optional<std::string> text = nomec::testing_inputs::read_file(path);
    ASSERT_TRUE(text.has_value()) << path;
    compare(path, *text, counts, /*check=*/true);
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(counts.texts, 50u);
  EXPECT_GE(counts.fast * 100, counts.texts * 95) << "the hand-written lexer left too many files to NomeLexer";
}

// Every golden test input (parse, check and IR goldens: most hold an error on purpose).
TEST(LexerDiff, GoldenInputs) {
  Counts counts;
  for (const std::string& path : nomec::testing_inputs::golden_inputs()) {
    const std::optional<std::string> text = nomec::testing_inputs::read_file(path);
    ASSERT_TRUE(text.has_value()) << path;
    compare(path, *text, counts);
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(counts.texts, 200u);
  EXPECT_GE(counts.fast * 100, counts.texts * 95);
}

// Hand-picked corners of the lexer rules.
TEST(LexerDiff, Corners) {
  const std::vector<std::string> texts = {
      "", " ", "a", "1", ".", "..", ".5", ".5.", ".5e3", ".5e3x", ".5e+3", "1.", "1.x", "1.5.3", "1e", "1e+", "1e+5",
      "1E-2x", "a.b", "x.5", "endmesh", "mesh", "meshx", "expr", "include \"a.slf\"", "$", "$a", "$a.b", "$a(", "$a(b",
      "$a(b)", "$a(b.c)", "$a(b c)", "$1", "\"", "\"abc", "\"a\\\"b\"", "\"a\\", "\"a\nb\"", "\"a\rb\"", "[", "[a", "[a]",
      "[[a]", "[[a]]", "[a]]", "%", "%{", "%{a", "%{a}%", "%{}%", "%{a}", "/", "//", "///", "tclinit", "tclinit {",
      "tclinit {a}", "tclinit{a}b", "tclinit \n\t{a {b} \\} c}", "tclinit {\\", "tclupdate {x}", "tclinitx {a}",
      "tclinit\f{a}", "#", "# a\nb", "# a\rb", "(*", "(* a *)", "(* a (* b *) c *)", "# x\r(* y *)", "\"a\\\"(*\" *)",
      "(*)", "*)", "\xC2\xA0", "a\xC2\xA0\xC2\xA0" "b", "\xC2", "\xC2\xA0\xC2", "\xE0\x82\xA0", "\xFF", "\xE2\x82\xAC",
      "\xF0\x9F\x98\x80", "\xED\xA0\x80", "\xF4\x90\x80\x80", "\xC0\x80", ";", "a;b", "{a}", "{expr $a*2}", "{if {$n} {x}}",
      "-1 +2", "a -1", "(1 -2)", "f(x, y)", "\t\v\f\r\n", "\n\n\nx", std::string("a\0b", 3), "point p (1 2 3) endpoint",
      "funnel f (4 1 0.5 1) endtunnel", "instance i m endinstnace\npoint q (0 0 0) endpoint",
  };
  Counts counts;
  for (const std::string& t : texts) {
    compare(t, t, counts);
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(counts.fast, texts.size() / 2);
}

// Seeded generated inputs: random runs of language fragments, bytes and whitespace; and the
// fuzzer's corpus where there is one.
TEST(LexerDiff, GeneratedInputs) {
  static const std::vector<std::string> kPieces = {
      "mesh", "endmesh", "point", "endpoint", "face", "endface", "instance", "endinstance", "group", "endgroup",
      "bank", "endbank", "set", "funnel", "endfunnel", "tunnel", "endtunnel", "surface", "subdivision",
      "endsubdivision", "torus", "endtorus", "genparametricsurf", "funcX", "expr", "include", "tclinit", "tclupdate",
      "(", ")", "{", "}", "[", "]", ",", "+", "-", "*", "/", "//", "%", "^", "$", "$b.x", "$a(b)", "\"", "\"s\"",
      "\\", "#", "(*", "*)", "%{", "}%", ".", "..", ".5", "1", "2.5", "1e3", "1e-", "e", "x", "a_b", "q.r", ";",
      " ", " ", " ", "  ", "\n", "\n", "\r", "\r\n", "\t", "\f", "\v", "\xC2\xA0", "\xC2", "\xA0", "\xE2\x82\xAC",
      "\xFF", "\xE0\x82\xA0", "\x01", "@", "'", "`", "!", "~", "=", "<", ">", "|", "&", "?", ":"};
  std::mt19937 rng(18);
  Counts counts;
  for (int n = 0; n < 6000; ++n) {
    std::string text;
    const int pieces = 1 + static_cast<int>(rng() % 40);
    for (int k = 0; k < pieces; ++k) {
      if (rng() % 10 == 0) {
        text += static_cast<char>(rng() % 256);
      } else {
        text += kPieces[rng() % kPieces.size()];
      }
    }
    compare(fmt::format("generated #{}: {}", n, text), text, counts);
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(counts.fast, 3000u);
  // Also the fuzzer's working corpus, when a fuzzing build beside the sources has one (or
  // the folder NOMEC_FUZZ_CORPUS names).
  const char* env = std::getenv("NOMEC_FUZZ_CORPUS");
  const fs::path dir = env != nullptr ? fs::path(env) : fs::path(NOMEC_SOURCE_DIR) / "build-sanitize/fuzz-corpus/frontend_fuzzer";
  for (const std::string& path : nomec::testing_inputs::files_under(dir)) {
    const std::optional<std::string> text = nomec::testing_inputs::read_file(path);
    ASSERT_TRUE(text.has_value()) << path;
    compare(path, *text, counts);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

}  // namespace
