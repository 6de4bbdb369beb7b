// textDocument/formatting: `nomec fmt` (frontend/format) on the current version — one edit
// replacing the whole text when it changes; no edits when the file does not parse.
#include "frontend/format/format.h"
#include "lsp/handler.h"

namespace nomec::lsp {

namespace {

json formatting(Context& ctx) {
  std::shared_ptr<const Analysis> a = ctx.analysis();
  FormatOptions options;
  if (auto o = ctx.params.find("options"); o != ctx.params.end() && o->is_object()) {
    if (auto t = o->find("tabSize"); t != o->end() && t->is_number_integer()) {
      options.indent_width = std::clamp(t->get<int>(), 1, 16);
    }
    if (auto s = o->find("insertSpaces"); s != o->end() && s->is_boolean()) options.insert_spaces = s->get<bool>();
  }
  FormatResult r = format_source(a->text(), options);
  if (!r.ok || r.text == a->text()) return json::array();
  return json::array({{{"range", a->range_json(SourceRange{a->file, 0, static_cast<uint32_t>(a->text().size())})},
                       {"newText", r.text}}});
}

}  // namespace

void register_formatting(Registry& r) {
  r.capabilities()["documentFormattingProvider"] = true;
  r.request("textDocument/formatting", formatting);
}

}  // namespace nomec::lsp
