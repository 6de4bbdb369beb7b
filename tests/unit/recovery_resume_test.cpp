// Differential tests of how much of a text the recovering parse reads (frontend/parse/
// parse.cpp). When the fast parse fails in a top-level statement, the statements before it
// are kept as it built them, the recovering parse starts at that statement and stops at the
// first statement after its errors where a parse of the whole text would be clean again,
// and the fast parse reads on from there; the reference parses the whole text again with
// recovery from its start (`parse_detail::resume_recovery(false)`). Every corpus file,
// example and golden input, damaged once and three times in many ways, and a generated
// scene damaged at its end and in its middle (also parsed on two threads), must give the
// same AST (every node, id, range, text and number) and the same diagnostics in the same
// order both ways.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "bench/common/generated_scene.h"
#include "frontend/parse/parse.h"
#include "frontend/parse/piece.h"
#include "tests/common/ast_dump.h"
#include "tests/common/corpus_inputs.h"
#include "tests/common/parse_switches.h"

namespace {

struct Counts {
  size_t texts = 0;
  size_t recovering = 0;  // texts whose fast parse failed
  size_t resumed = 0;     // of those, texts whose recovering passes did not read the whole text
};

void compare(const std::string& name, const std::string& text, Counts& counts,
             nomec::ParseThreads threads = nomec::ParseThreads::One) {
  ++counts.texts;
  const nomec::parse_detail::RecoveryCounts before = nomec::parse_detail::recovery_counts();
  const std::string resumed = nomec::testing_dump::parse_dump(text, threads);
  const nomec::parse_detail::RecoveryCounts after = nomec::parse_detail::recovery_counts();
  counts.recovering += after.recovering > before.recovering ? 1 : 0;
  counts.resumed += after.resumed > before.resumed ? 1 : 0;
  std::string from_start;
  {
    nomec::testing_switches::ScopedParseSwitch reference(
        &nomec::parse_detail::ParseSwitches::resumed_recovery, false);
    from_start = nomec::testing_dump::parse_dump(text, threads);
  }
  ASSERT_EQ(resumed, from_start) << name << "\n--- text ---\n" << text;
}

// Damage that makes the fast parse fail: a block left open, an end keyword alone, an
// unbalanced bracket or brace, a half-written statement, a deleted end keyword, a cut. (The
// structure pass repairs most blocks and brackets before the parser sees them, so the
// operators and commas that only the parser's recovery handles are inserted too.)
std::string damage(const std::string& text, std::mt19937& rng) {
  static const char* const kInserts[] = {"bank\n",  "mesh m\n",       "endmesh\n", ")\n",    "(\n",
                                         "{\n",     "}\n",            "point p (1 2\n", "group g instance i\n",
                                         "funnel\n", "face f (a b c) endmesh\n", "instance i m endgroup\n",
                                         "endendend\n", "set x\n", "* 2\n", ", ,\n",
                                         "point q (1 + ) endpoint\n", "instance i m rotate (1 *) endinstance\n"};
  std::string out = text;
  const auto pick = [&](size_t n) { return n == 0 ? size_t{0} : static_cast<size_t>(rng() % n); };
  switch (pick(3)) {
    case 0: {  // an insert at the start of a line
      size_t at = pick(out.size() + 1);
      at = at == 0 ? 0 : out.rfind('\n', at - 1);
      at = at == std::string::npos ? 0 : at + (at == 0 && out[0] != '\n' ? 0 : 1);
      out.insert(std::min(at, out.size()), kInserts[pick(std::size(kInserts))]);
      break;
    }
    case 1: {  // an end keyword deleted
      std::vector<size_t> ends;
      for (size_t p = out.find("end"); p != std::string::npos; p = out.find("end", p + 3)) ends.push_back(p);
      if (ends.empty()) return out + "\nbank";
      const size_t p = ends[pick(ends.size())];
      size_t e = p;
      while (e < out.size() && std::isalnum(static_cast<unsigned char>(out[e])) != 0) ++e;
      out.erase(p, e - p);
      break;
    }
    default: {  // a few characters cut
      if (out.empty()) return "bank";
      out.erase(pick(out.size()), 1 + pick(4));
      break;
    }
  }
  return out;
}

TEST(RecoveryResume, DamagedCorpusExamplesAndGoldenInputs) {
  Counts counts;
  std::mt19937 rng(20261203);
  std::vector<std::string> paths = nomec::testing_inputs::corpus_and_examples();
  for (const std::string& p : nomec::testing_inputs::golden_inputs()) paths.push_back(p);
  for (const std::string& path : paths) {
    const std::optional<std::string> text = nomec::testing_inputs::read_file(path);
    ASSERT_TRUE(text.has_value()) << path;
    compare(path, *text, counts);
    for (int k = 0; k < 6; ++k) {
      compare(path + " (damaged)", damage(*text, rng), counts);
      if (::testing::Test::HasFatalFailure()) return;
    }
    // Several errors apart: the recovering pass stops after one and the fast pass fails again.
    for (int k = 0; k < 2; ++k) {
      compare(path + " (damaged thrice)", damage(damage(damage(*text, rng), rng), rng), counts);
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
  EXPECT_GT(counts.texts, 3000u);
  EXPECT_GT(counts.recovering, 400u) << counts.recovering << " of " << counts.texts;
  // Many golden inputs are one statement, which a recovering pass reads to its end anyway.
  EXPECT_GT(counts.resumed * 2, counts.recovering) << counts.resumed << " of " << counts.recovering;
}

TEST(RecoveryResume, GeneratedSceneDamagedAtItsEndAndMiddle) {
  const std::string scene = nomec::bench::generate_scene(256 * 1024);
  const size_t middle = scene.find('\n', scene.size() / 2) + 1;
  const std::string texts[] = {
      scene + "point p (1 + ) endpoint\n",                                  // an operand missing at the end
      scene + "mesh m point p (1 2 *) endpoint endmesh\n",                  // the same, nested
      scene.substr(0, middle) + "* 2\n" + scene.substr(middle),             // operators alone
      scene.substr(0, middle) + ", ,\n" + scene.substr(middle),             // stray commas
      scene.substr(0, middle) + "* 2\n" + scene.substr(middle) + ", \n",   // two errors apart
  };
  for (nomec::ParseThreads threads : {nomec::ParseThreads::One, nomec::ParseThreads::Two}) {
    for (const std::string& text : texts) {
      Counts counts;
      compare("generated scene", text, counts, threads);
      if (::testing::Test::HasFatalFailure()) return;
      EXPECT_EQ(counts.recovering, 1u);
      EXPECT_EQ(counts.resumed, 1u);
    }
  }
}

}  // namespace
