// The parser's remembered walks (frontend/parse/prediction_seed.h): the build's seed is
// remembered before the first parse, malformed records are refused, and a parse that uses
// the remembered walks gives exactly the AST and diagnostics of one that asks ANTLR's
// simulator for every prediction, on every corpus file, example, golden input, the
// benchmark's generated scene and random edits of them.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <string>
#include <vector>

#include "bench/common/generated_scene.h"
#include "frontend/parse/parse.h"
#include "frontend/parse/prediction_seed.h"
#include "tests/common/ast_dump.h"
#include "tests/common/corpus_inputs.h"
#include "tests/common/parse_switches.h"

namespace {

using Record = std::vector<uint16_t>;

std::set<Record> records_of(std::span<const uint16_t> walks) {
  std::set<Record> out;
  for (size_t i = 0; i + 3 <= walks.size();) {
    const size_t end = i + 3 + walks[i + 2];
    out.insert(Record(walks.begin() + static_cast<std::ptrdiff_t>(i), walks.begin() + static_cast<std::ptrdiff_t>(end)));
    i = end;
  }
  return out;
}

// Parses `text` with the remembered walks and with the simulator alone.
void compare(const std::string& name, const std::string& text) {
  const std::string remembered = nomec::testing_dump::parse_dump(text, nomec::ParseThreads::One);
  std::string simulated;
  {
    nomec::testing_switches::ScopedParseSwitch simulator(
        &nomec::parse_detail::ParseSwitches::remembered_predictions, false);
    simulated = nomec::testing_dump::parse_dump(text, nomec::ParseThreads::One);
  }
  ASSERT_EQ(remembered, simulated) << name;
}

TEST(PredictionSeed, TheBuildsWalksAreRememberedBeforeTheFirstParse) {
  const std::span<const uint16_t> seed = nomec::parse_detail::prediction_seed();
  const std::set<Record> seeded = records_of(seed);
  EXPECT_GT(seeded.size(), 100u) << "the build step saw the training texts' walks";
  nomec::testing_dump::parse_dump("point p (0 0 0) endpoint\n", nomec::ParseThreads::One);
  const std::vector<uint16_t> now = nomec::parse_detail::remembered_walks();
  const std::set<Record> remembered = records_of(now);
  for (const Record& r : seeded) EXPECT_TRUE(remembered.contains(r));
}

TEST(PredictionSeed, MalformedRecordsAreRefused) {
  const std::vector<uint16_t> before = nomec::parse_detail::remembered_walks();
  EXPECT_FALSE(nomec::parse_detail::remember_walks(std::vector<uint16_t>{36, 1}));          // cut short
  EXPECT_FALSE(nomec::parse_detail::remember_walks(std::vector<uint16_t>{600, 1, 1, 12}));  // no such decision
  EXPECT_FALSE(nomec::parse_detail::remember_walks(std::vector<uint16_t>{36, 1, 5, 12, 107}));  // longer than given
  EXPECT_FALSE(nomec::parse_detail::remember_walks(std::vector<uint16_t>{36, 1, 0}));  // empty walk
  EXPECT_EQ(nomec::parse_detail::remembered_walks(), before);
}

TEST(PredictionSeed, RememberedWalksParseAsTheSimulator) {
  std::vector<std::string> paths = nomec::testing_inputs::corpus_and_examples();
  for (const std::string& p : nomec::testing_inputs::golden_inputs()) paths.push_back(p);
  std::mt19937 rng(18);
  const std::string alphabet = "{}()$_.+-*/^ \n0123456789abcxyz";
  size_t texts = 0;
  for (const std::string& path : paths) {
    const std::optional<std::string> text = nomec::testing_inputs::read_file(path);
    ASSERT_TRUE(text.has_value()) << path;
    compare(path, *text);
    ++texts;
    // Edits make walks no training text had.
    std::string edited = *text;
    for (int k = 0; k < 3 && !edited.empty(); ++k) {
      const size_t at = std::uniform_int_distribution<size_t>(0, edited.size() - 1)(rng);
      edited.insert(at, 1, alphabet[std::uniform_int_distribution<size_t>(0, alphabet.size() - 1)(rng)]);
    }
    compare(path + " (edited)", edited);
    if (::testing::Test::HasFatalFailure()) return;
  }
  compare("generated scene", nomec::bench::generate_scene(256 * 1024));
  EXPECT_GT(texts, 200u);
}

}  // namespace
