// Tables derived from block_kinds.def and, for generators, the generator catalogue.
#include "frontend/ast/ast.h"

#include <deque>
#include <unordered_map>

#include "ir/generator_catalogue.h"

namespace nomec::ast {

namespace {
struct BlockInfo {
  std::string_view open;
  BlockCategory category;
};
constexpr BlockInfo kBlocks[] = {
#define NOMEC_BLOCK(Kind, Open, Category) {Open, BlockCategory::Category},
#include "frontend/ast/block_kinds.def"
#undef NOMEC_BLOCK
};

struct KeywordMaps {
  std::deque<std::string> end_words;  // storage the `close` keys view (stable addresses)
  std::unordered_map<std::string_view, BlockKind> open;
  std::unordered_map<std::string_view, BlockKind> close;
  std::vector<std::string_view> words;
  // The generators with a digit keyword (NOME2's `bspline3`): the only ones a word ending in
  // a digit is compared with (the cache's cut scanner asks about every word it meets).
  std::vector<const ir::GeneratorInfo*> digit_generators;
  void add(std::string_view keyword, BlockKind kind) {
    open.emplace(keyword, kind);
    close.emplace(end_words.emplace_back(end_keyword(keyword)), kind);
    words.push_back(keyword);
  }
};

const KeywordMaps& keyword_maps() {
  static const KeywordMaps maps = [] {
    KeywordMaps m;
    for (int k = 0; k < kBlockKindCount; ++k) {
      auto kind = static_cast<BlockKind>(k);
      if (kind != BlockKind::Generator) m.add(kBlocks[k].open, kind);
    }
    for (const ir::GeneratorInfo& g : ir::generators()) {
      for (std::string_view kw : g.keywords) m.add(kw, BlockKind::Generator);
      if (!g.digit_prefix.empty()) m.digit_generators.push_back(&g);
    }
    return m;
  }();
  return maps;
}
}  // namespace

std::string_view open_keyword(BlockKind kind) {
  return kind == BlockKind::Generator ? std::string_view("generator") : kBlocks[static_cast<int>(kind)].open;
}
BlockCategory category(BlockKind kind) { return kBlocks[static_cast<int>(kind)].category; }

std::string end_keyword(std::string_view keyword) { return "end" + std::string(keyword); }

namespace {
// A generator keyword made of a prefix and digits (NOME2's `bspline3`), which no table lists.
bool is_digit_keyword(std::string_view word) {
  if (word.empty() || word.back() < '0' || word.back() > '9') return false;
  for (const ir::GeneratorInfo* g : keyword_maps().digit_generators) {
    if (g->keyword_digits(word)) return true;
  }
  return false;
}
}  // namespace

std::optional<BlockKind> block_of_keyword(std::string_view word) {
  const auto& open = keyword_maps().open;
  if (auto it = open.find(word); it != open.end()) return it->second;
  if (is_digit_keyword(word)) return BlockKind::Generator;
  return std::nullopt;
}

std::optional<BlockKind> block_of_end_keyword(std::string_view word) {
  const auto& close = keyword_maps().close;
  if (auto it = close.find(word); it != close.end()) return it->second;
  if (word.starts_with("end") && is_digit_keyword(word.substr(3))) return BlockKind::Generator;
  return std::nullopt;
}

const std::vector<std::string_view>& all_open_keywords() { return keyword_maps().words; }

}  // namespace nomec::ast
