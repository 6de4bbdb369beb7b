// textDocument/semanticTokens/full: the index's tokens (keywords, numbers, parameters,
// functions, names, comments, strings, operators; definitions marked) in LSP's relative
// encoding, with UTF-16 columns; tokens spanning lines are split per line.
#include "lsp/handler.h"

namespace nomec::lsp {

namespace {

// In index::TokenType order.
const char* const kTypes[] = {"keyword", "number", "parameter", "function", "variable", "comment", "string", "operator"};

json semantic_tokens(Context& ctx) {
  std::shared_ptr<const Analysis> a = ctx.analysis();
  json data = json::array();
  if (!a->index) return {{"data", data}};
  std::string_view text = a->text();
  uint32_t prev_line = 0, prev_char = 0;
  auto emit = [&](uint32_t begin, uint32_t end, uint32_t type, uint32_t mods) {
    if (end <= begin) return;
    Position p = a->lines.position(begin);
    uint32_t length = LineIndex::utf16_length(text.substr(begin, end - begin));
    if (length == 0) return;
    data.push_back(p.line - prev_line);
    data.push_back(p.line == prev_line ? p.character - prev_char : p.character);
    data.push_back(length);
    data.push_back(type);
    data.push_back(mods);
    prev_line = p.line;
    prev_char = p.character;
  };
  size_t n = 0;
  for (const index::SemanticToken& t : a->index->semantic_tokens(a->file)) {
    if ((++n & 1023) == 0) ctx.check_cancelled();
    if (t.range.file != a->file) continue;
    uint32_t end = std::min<uint32_t>(t.range.end, static_cast<uint32_t>(text.size()));
    uint32_t type = static_cast<uint32_t>(t.type);
    uint32_t mods = t.is_definition ? 1 : 0;
    // One piece per line.
    for (uint32_t b = t.range.begin; b < end;) {
      Position p = a->lines.position(b);
      uint32_t line_end = std::min(end, a->lines.line_content_end(p.line));
      emit(b, line_end, type, mods);
      if (p.line + 1 >= a->lines.line_count()) break;
      b = a->lines.line_start(p.line + 1);
    }
  }
  return {{"data", std::move(data)}};
}

}  // namespace

void register_semantic_tokens(Registry& r) {
  json types = json::array();
  for (const char* t : kTypes) types.push_back(t);
  r.capabilities()["semanticTokensProvider"] = {{"legend", {{"tokenTypes", types}, {"tokenModifiers", {"declaration"}}}},
                                                {"full", true}};
  r.request("textDocument/semanticTokens/full", semantic_tokens);
}

}  // namespace nomec::lsp
