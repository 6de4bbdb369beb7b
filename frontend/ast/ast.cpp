// Tables derived from block_kinds.def.
#include "frontend/ast/ast.h"

namespace nomec::ast {

namespace {
struct BlockInfo {
  std::string_view open;
  std::string_view close;
  BlockCategory category;
};
constexpr BlockInfo kBlocks[] = {
#define NOMEC_BLOCK(Kind, Open, Close, Category) {Open, Close, BlockCategory::Category},
#include "frontend/ast/block_kinds.def"
#undef NOMEC_BLOCK
};
}  // namespace

std::string_view open_keyword(BlockKind kind) { return kBlocks[static_cast<int>(kind)].open; }
std::string_view close_keyword(BlockKind kind) { return kBlocks[static_cast<int>(kind)].close; }
BlockCategory category(BlockKind kind) { return kBlocks[static_cast<int>(kind)].category; }

const std::vector<std::string_view>& all_open_keywords() {
  static const std::vector<std::string_view> words = [] {
    std::vector<std::string_view> w;
    for (const BlockInfo& b : kBlocks) {
      w.push_back(b.open);
    }
    return w;
  }();
  return words;
}

}  // namespace nomec::ast
