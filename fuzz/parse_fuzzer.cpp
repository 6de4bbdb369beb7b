// libFuzzer target for the parser's equivalences: any bytes, as a NOME, NOME3 or SLIDE file
// (chosen by the first byte). Differential: the hand-written lexer must give exactly the
// tokens of ANTLR's NomeLexer, its reference; on a text that parses without errors the AST
// builder that reads the parser's events must give exactly the AST and diagnostics of the
// one that converts parse trees (a text with errors takes the tree-based path in both); the
// parse with the parser's remembered predictions must be exactly the parse with ANTLR's
// simulator alone (prediction_seed.h); the text cut in two and parsed on two threads must
// give exactly its parse on one (`ParseThreads`, forced below the automatic size), and its
// parse through a new parse cache too; the check in pieces, each tree freed once checked,
// must give exactly the check of the whole tree; and the text edited by one character
// (chosen by the input's last byte), when checked incrementally from the check of the text
// (frontend/check/incremental.h), must give exactly the diagnostics of a full check.
// Several parses and checks of each input: slower than frontend_fuzzer, which looks for
// crashes and broken ranges. SLIDE files' Tcl is not run (slide_fuzzer runs it).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "frontend/check/check.h"
#include "frontend/check/incremental.h"
#include "frontend/parse/parse.h"
#include "frontend/parse/piece.h"
#include "frontend/parse/prediction_seed.h"
#include "frontend/parse/tokens.h"
#include "tests/common/ast_dump.h"

namespace {


// The two lexers agree on the text (when the hand-written one does not leave it to NomeLexer).
bool lexers_agree(std::string_view text) {
  nomec::DiagnosticEngine ignored;
  std::string storage;
  bool open = false;
  const std::string_view blanked = nomec::parse_detail::blank_block_comments(text, storage, nomec::FileId{}, ignored, open);
  nomec::parse_detail::Lexed fast, reference;
  if (!nomec::parse_detail::lex_fast(blanked, fast)) return true;
  nomec::parse_detail::lex_antlr(blanked, reference);
  return fast.tokens == reference.tokens && fast.eof_touch_start == reference.eof_touch_start;
}

// The text's AST and diagnostics, parsed by `parse_file` on `threads`, or through `cache`
// when one is given (the editor's parse, which cuts the text after every top-level block and
// parses the pieces alone where that is provably the same).
std::string parse_dump(const std::string& text, bool* clean, nomec::ParseThreads threads = nomec::ParseThreads::One,
                       nomec::ParseCache* cache = nullptr) {
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  const nomec::FileId f = sources.add_file("fuzz.nome", text);
  const nomec::ast::Ast a =
      cache != nullptr ? cache->parse(sources, f, diags) : nomec::parse_file(sources, f, diags, threads);
  *clean = diags.error_count() == 0;
  return nomec::testing_dump::dump_ast(a) + nomec::testing_dump::dump_diags(diags);
}

// Prints both dumps of a disagreement, `what` (`got`) against `reference` (`want`): what a
// finding's reader needs first. Returns false, for `a == b || report(…)`.
bool report(const char* what, const std::string& got, const char* reference, const std::string& want) {
  std::fprintf(stderr, "parse_fuzzer: %s differs from %s.\n--- %s:\n%s\n--- %s:\n%s\n", what, reference, what,
               got.c_str(), reference, want.c_str());
  return false;
}

// The text's parse on one thread (`one`: the event-driven AST builder, remembered
// predictions, recovery only around the errors) agrees, errors and all, with the reference
// parse (the tree-based builder when the text has no errors, every prediction from the
// simulator, one recovering parse of the whole text) and with its parse cut
// in two and parsed on two threads (or, when its halves would not parse as inside it, in
// one piece after all), and with its parse through a new parse cache.
bool parses_agree(const std::string& text) {
  bool clean = false;
  const std::string one = parse_dump(text, &clean);
  bool ignored = false;
  // The reference parse: the tree-based builder (when the text has no errors), every
  // prediction asked of ANTLR's simulator, none of the remembered walks, and one recovering
  // parse of the whole text.
  nomec::parse_detail::use_tree_builder(clean);
  nomec::parse_detail::use_remembered_predictions(false);
  nomec::parse_detail::resume_recovery(false);
  const std::string reference = parse_dump(text, &ignored);
  nomec::parse_detail::resume_recovery(true);
  nomec::parse_detail::use_remembered_predictions(true);
  nomec::parse_detail::use_tree_builder(false);
  if (reference != one) return report("the reference parse", reference, "the parse on one thread", one);
  const std::string two = parse_dump(text, &ignored, nomec::ParseThreads::Two);
  if (two != one) return report("the parse on two threads", two, "the parse on one thread", one);
  nomec::ParseCache cache(nomec::ParseThreads::One);
  const std::string cached = parse_dump(text, &ignored, nomec::ParseThreads::One, &cache);
  return cached == one || report("the parse through a new parse cache", cached, "the parse on one thread", one);
}

std::string sorted_dump(nomec::DiagnosticEngine& diags) {
  diags.sort_and_dedupe();
  return nomec::testing_dump::dump_diags(diags);
}

// `text` edited by one character (an insertion or a deletion at a place chosen by `key`),
// checked incrementally from `basis`, gives exactly a full check's diagnostics when the
// incremental check says it is done.
bool incremental_agrees(const nomec::IncrementalBasis& basis, const char* path, const std::string& text,
                        const nomec::CheckOptions& options, uint8_t key) {
  static const char kTyped[] = "0a_ .(){}$#\nxe";
  std::string edited = text;
  const size_t at = edited.empty() ? 0 : (static_cast<size_t>(key) * 2654435761u) % edited.size();
  if ((key & 1) != 0 && !edited.empty()) {
    edited.erase(at, 1);
  } else {
    edited.insert(at, 1, kTyped[key % (sizeof kTyped - 1)]);
  }
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  const nomec::IncrementalOutcome o = nomec::check_incrementally(basis, sources, path, edited, options, diags, nullptr);
  if (!o.done) return true;
  nomec::SourceManager full_sources;
  nomec::DiagnosticEngine full;
  nomec::check_source(full_sources, path, edited, options, full);
  const std::string got = sorted_dump(diags), want = sorted_dump(full);
  return got == want || report("the incremental check", got, "the full check", want);
}

// The check in pieces of a few bytes, each piece's tree freed once checked (what the
// command line does to a large file, CheckOptions::piece_bytes), gives exactly the
// diagnostics, in emission order, and the IR of the check of the whole tree.
bool pieces_agree(const char* path, const std::string& text, const nomec::CheckOptions& options) {
  std::string dumps[2];
  for (int k = 0; k < 2; ++k) {
    nomec::CheckOptions o = options;
    o.piece_bytes = k == 0 ? 0 : 8;
    nomec::SourceManager sources;
    nomec::DiagnosticEngine diags;
    const nomec::CheckResult r = nomec::check_source(sources, path, text, o, diags);
    dumps[k] = nomec::testing_dump::dump_diags(diags) + nomec::ir::dump_ir(r.module, sources);
  }
  return dumps[1] == dumps[0] || report("the check in pieces", dumps[1], "the check of the whole tree", dumps[0]);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const char* const kPaths[] = {"fuzz.nome", "fuzz.nom", "fuzz.slf"};
  const char* path = kPaths[size > 0 ? data[0] % 3 : 0];
  std::string text(reinterpret_cast<const char*>(data), size);
  if (!lexers_agree(text)) std::abort();
  if (!parses_agree(text)) std::abort();
  auto shared_sources = std::make_shared<nomec::SourceManager>();  // an incremental basis keeps them
  nomec::DiagnosticEngine diags;
  nomec::CheckOptions options;
  options.read_file = [](const std::string&) -> std::optional<std::string> { return std::nullopt; };
  options.run_tcl = false;
  try {
    nomec::CheckOptions recording = options;
    recording.record_names = true;  // what the editor's checks record, for the incremental one
    const nomec::CheckResult r = nomec::check_source(*shared_sources, path, text, recording, diags);
    if (auto basis = nomec::make_incremental_basis(shared_sources, r, diags.diagnostics())) {
      if (!incremental_agrees(*basis, path, text, options, size > 0 ? data[size - 1] : 0)) std::abort();
    }
    if (!pieces_agree(path, text, options)) std::abort();
  } catch (...) {
    std::abort();  // "No stage throws" (ARCHITECTURE.md)
  }
  return 0;
}
