// Internal to frontend/parse: the parser's predictions that a build step saw, remembered by
// every program before its first parse (see Predictor in grammar/NomeParserBase.h).
//
// `prediction_seed_tool` (prediction_seed_tool.cpp) parses the training texts (the examples
// and the parse and check tests' inputs) with no walks remembered, and writes the walks it
// saw as `prediction_seed()` into a source file of the build directory, which
// `nomec_frontend` compiles; the tool itself links `prediction_seed_none.cpp` (no walks).
// Without them, the first parse of every process paid for the simulator's DFA states:
// about 46 M instructions, 64 % of a cold `nomec --check` of a 19 KiB example.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace nomec::parse_detail {

/// The remembered walks: records `decision, alternative, length, token types…`.
std::span<const uint16_t> prediction_seed();

/// Remembers `prediction_seed()` once per process (every parse calls it first).
void remember_seeded_predictions();

/// The walks the parser remembers now (the seed's and those it saw since), as records;
/// and remembering `records` (false, and nothing more remembered, at a malformed record).
/// For the tests and the tool.
std::vector<uint16_t> remembered_walks();
bool remember_walks(std::span<const uint16_t> records);

/// For the differential tests: while off (on this thread), the parser asks ANTLR's
/// simulator for every prediction and remembers none.
void use_remembered_predictions(bool on);

}  // namespace nomec::parse_detail
