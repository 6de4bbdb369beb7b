// Banks and sliders (see handlers.h): `bank fp set n 8 3 10 1 … list (n) endbank`, the
// values saved work sets (`savedparameter`), `-D bank.param=value` overrides, the `list`
// entries checked once all banks are known, and finding the slider a reference names.
#include <algorithm>
#include <cmath>
#include <map>
#include <fmt/format.h>

#include "frontend/check/handlers.h"

namespace nomec::check {

namespace {

void handle_set(Context& c, const ast::Ast& a, const ast::Stmt& bank, const std::string& bank_name,
                const ast::Item& set_kw, size_t& pos) {
  if (pos >= bank.items.size() || bank.items[pos].kind != ItemKind::Word || bank.items[pos].text == "set" ||
      bank.items[pos].text == "list") {
    c.diags().emit(DiagKind::MissingName, set_kw.range, "`set` needs a slider name: `set NAME value min max step`");
    while (pos < bank.items.size() && bank.items[pos].kind != ItemKind::Word) ++pos;  // its values
    return;
  }
  const ast::Item& name_item = bank.items[pos++];
  std::string pname(name_item.text);
  c.note_declared(pname, name_item.range, false);  // a slider: "did you mean" hints list them all
  std::vector<const ast::Item*> vals;
  while (pos < bank.items.size() && bank.items[pos].kind != ItemKind::Word) vals.push_back(&bank.items[pos++]);
  double v[4] = {0, 0, 0, 1};
  bool ok = true;
  if (vals.size() != 4) {
    SourceRange r = vals.empty() ? name_item.range
                                 : SourceRange{name_item.range.file, vals.front()->range.begin, vals.back()->range.end};
    std::vector<std::string> shown;
    for (auto* it : vals) shown.push_back(fmt::format("`{}`", c.sources().text(it->range)));
    c.diags().emit(DiagKind::ListArity, r,
                   fmt::format("`set {}` needs 4 numbers (value min max step), got {}{}", pname, vals.size(),
                               shown.empty() ? "" : fmt::format(": {}", fmt::join(shown, " | "))));
    ok = false;
  }
  for (size_t i = 0; i < vals.size() && i < 4; ++i) {
    ir::ExprId e = scalar_of_item(c, a, *vals[i], /*constant=*/true);
    ir::EvalResult r = ir::evaluate(c.module(), e);
    if (!r.ok) {
      ok = false;
      continue;
    }
    v[i] = r.value;
  }
  std::string key = bank_name + "." + pname;
  if (auto it = c.params.find(key); it != c.params.end()) {
    c.diags()
        .emit(DiagKind::DuplicateDefinition, name_item.range,
              fmt::format("slider `{}` is already defined in bank `{}`", pname, bank_name))
        .note(c.module().node(it->second).range, "previous definition is here");
    return;
  }
  ir::NodeId id = c.module().add_node(ir::NodeKind::Param, "set", key, name_item.range);
  ir::ParamData& p = c.module().param(id);
  p.bank = bank_name;
  p.value = v[0];
  p.min = v[1];
  p.max = v[2];
  p.step = v[3];
  c.params[key] = id;
  c.param_text_memo.clear();  // a new slider may change how `bank_param` resolves
  if (!ok || vals.size() != 4) return;
  if (v[1] > v[2]) {
    c.diags()
        .emit(DiagKind::BankRange, vals[1]->range, fmt::format("slider `{}`: min {} is greater than max {}", key, v[1], v[2]))
        .note(vals[2]->range, "max is here");
  } else if (v[3] <= 0) {
    c.diags().emit(DiagKind::BankRange, vals[3]->range, fmt::format("slider `{}`: step {} must be positive", key, v[3]));
  } else if (v[0] < v[1] || v[0] > v[2]) {
    c.diags().emit(DiagKind::ValueOutOfRange, vals[0]->range,
                   fmt::format("slider `{}`: value {} is outside its range [{}, {}]", key, v[0], v[1], v[2]));
  }
}

// `list (n ro)`: the sliders to show, in order (checked when every bank is known).
void handle_list(Context& c, const ast::Ast& a, const ast::Stmt& s, const std::string& bank, const ast::Item& kw,
                 size_t& pos) {
  if (pos < s.items.size() && s.items[pos].kind == ItemKind::List) {
    for (ast::ExprId e : a.list(s.items[pos].list).elems) {
      const ast::Expr& ex = a.expr(e);
      if (ex.kind != ast::ExprKind::Name) {
        c.diags().emit(DiagKind::ExpectedNameList, ex.range, "`list` names the sliders to show; expected a parameter name");
      } else {  // resolved once every bank is known: an error or the slider's list position
        c.pending_lists.push_back({bank, std::string(ex.text), ex.range});
      }
    }
    c.check_commas(a, s.items[pos].list);
    ++pos;
  } else if (pos < s.items.size() && s.items[pos].kind == ItemKind::Word && s.items[pos].text == "set") {
    // `list` with no names (NOME3 allowed an empty `list` line).
  } else if (pos < s.items.size()) {
    c.diags().emit(DiagKind::MissingArgument, kw.range, "`list` needs a parenthesised list of slider names, e.g. `list (n ro)`");
  }
}

void handle_bank(Context& c, const ast::Ast& a, const ast::Stmt& s) {
  size_t pos = 0;
  auto name = c.read_name(s, pos, "bank b set n 8 3 10 1 endbank");
  if (!name) return;
  c.note_declared(*name, s.items[0].range, true);
  c.param_text_memo.clear();  // a new bank may change how `bank_param` resolves
  if (auto [it, ok] = c.banks.emplace(*name, s.items[0].range); !ok) {
    c.diags()
        .emit(DiagKind::DuplicateDefinition, s.items[0].range, fmt::format("bank `{}` is already defined", *name))
        .note(it->second, "previous definition is here");
  }
  while (pos < s.items.size()) {
    const ast::Item& it = s.items[pos];
    if (it.kind == ItemKind::Word && it.text == "set") {
      ++pos;
      handle_set(c, a, s, *name, it, pos);
    } else if (it.kind == ItemKind::Word && it.text == "list") {
      ++pos;
      handle_list(c, a, s, *name, it, pos);
    } else if (it.kind == ItemKind::Word && (is_typo_of(it.text, "set") || is_typo_of(it.text, "list"))) {
      // `ste n 1 0 2 1`: one error, and the line is read as the `set` (or `list`) it means.
      const bool is_set = is_typo_of(it.text, "set");
      const char* meant = is_set ? "set" : "list";
      c.diags()
          .emit(DiagKind::UnknownArgument, it.range,
                fmt::format("unexpected `{}` in bank `{}`; did you mean `{}`?", it.text, *name, meant))
          .fixit(it.range, meant, fmt::format("replace with `{}`", meant));
      ++pos;
      if (is_set) {
        handle_set(c, a, s, *name, it, pos);
      } else {
        handle_list(c, a, s, *name, it, pos);
      }
    } else {
      std::string what = it.kind == ItemKind::Word ? fmt::format("`{}`", it.text)
                                                   : fmt::format("value `{}`", Context::clip(c.sources().text(it.range)));
      auto d = c.diags().emit(DiagKind::UnknownArgument, it.range,
                              fmt::format("unexpected {} in bank `{}`; a bank holds `set NAME value min max step` lines and "
                                          "an optional `list (…)`",
                                          what, *name));
      if (it.kind == ItemKind::Word) {
        std::string hint = closest_match(it.text, {"set", "list"});
        if (!hint.empty()) d.fixit(it.range, hint, fmt::format("replace with `{}`", hint));
      }
      // One error per stray run: `sett n 1 0 2 1` is one mistake, not six.
      ++pos;
      while (pos < s.items.size() &&
             !(s.items[pos].kind == ItemKind::Word && (s.items[pos].text == "set" || s.items[pos].text == "list"))) {
        ++pos;
      }
    }
  }
}

void handle_savedparameter(Context& c, const ast::Ast& a, const ast::Stmt& s) {
  for (size_t i = 0; i < s.items.size(); ++i) {
    const ast::Item& it = s.items[i];
    if (it.kind != ItemKind::Word) {
      c.diags().emit(DiagKind::UnexpectedItem, it.range, "expected `bank_param value` pairs in `savedparameter`");
      continue;
    }
    if (i + 1 >= s.items.size() || s.items[i + 1].kind != ItemKind::Value) {
      c.diags().emit(DiagKind::MissingArgument, it.range, fmt::format("saved parameter `{}` has no value", it.text));
      continue;
    }
    ir::ExprId e = scalar_of_item(c, a, s.items[++i], true);
    ir::EvalResult r = ir::evaluate(c.module(), e);
    std::string key(it.text);
    ir::NodeId p = lookup_param_text(c, key);
    if (!p.is_valid()) {
      // Saved work may name sliders the scene no longer has (real files do): warn. Without
      // its base scene every slider is unknown, and nothing is said (compat.md §G2).
      if (c.is_saved_work && !c.base_loaded) continue;
      c.diags().emit(DiagKind::StaleSavedParameter, it.range,
                     fmt::format("saved value for `{}`, but the scene has no such slider; the value is ignored", key));
      continue;
    }
    if (r.ok) c.module().param(p).value = r.value;
  }
}

}  // namespace

void collect_banks(Context& c, const ast::Ast& a) {
  for (const ast::Item& it : a.top) {
    if (it.kind == ItemKind::Block && a.stmt(it.block).kind == BlockKind::Bank) handle_bank(c, a, a.stmt(it.block));
  }
}

void apply_saved(Context& c, const ast::Ast& a) {
  for (const ast::Item& it : a.top) {
    if (it.kind == ItemKind::Block && a.stmt(it.block).kind == BlockKind::Savedparameter) {
      handle_savedparameter(c, a, a.stmt(it.block));
    }
  }
}

void apply_overrides(Context& c) {
  for (const auto& [name, value] : c.options().overrides) {
    ir::NodeId p = lookup_param_text(c, name);
    if (!p.is_valid()) {
      std::string hint = closest_match(name, sorted_names(c.params));
      c.diags().emit(DiagKind::OverrideUnknown, SourceRange{},
                     fmt::format("`-D {}={}`: no parameter `{}` in this file{}", name, value, name,
                                 hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
      continue;
    }
    const ir::Node& n = c.module().node(p);
    ir::ParamData& d = c.module().param(p);
    // A value that is not finite (`nan` is in no range, `inf` past every one) is refused even
    // with --allow-out-of-range: nothing could be built from it.
    if (!std::isfinite(value) || ((value < d.min || value > d.max) && !c.options().allow_out_of_range)) {
      c.diags().emit(DiagKind::OverrideOutOfRange, n.range,
                     std::isfinite(value)
                         ? fmt::format("`-D {}={}` is outside the slider range [{}, {}] of `{}`; pass "
                                       "--allow-out-of-range to use it anyway",
                                       name, value, d.min, d.max, n.name)
                         : fmt::format("`-D {}={}` is not a finite number; `{}` keeps {}", name, value, n.name, d.value));
      continue;
    }
    d.value = value;
  }
}

void check_pending_lists(Context& c) {
  std::map<std::string, int32_t> listed;  // per bank, how many names its lists gave so far
  for (const PendingList& pl : c.pending_lists) {
    if (auto it = c.params.find(pl.bank + "." + pl.name); it != c.params.end()) {
      ir::ParamData& d = c.module().param(it->second);
      if (d.list_index < 0) d.list_index = listed[pl.bank]++;
      continue;
    }
    std::vector<std::string> cands;
    for (const auto& [k, v] : c.params) {
      if (k.rfind(pl.bank + ".", 0) == 0) cands.push_back(k.substr(pl.bank.size() + 1));
    }
    std::sort(cands.begin(), cands.end());  // "did you mean" prefers the first best match
    std::string hint = closest_match(pl.name, cands);
    c.diags().emit(DiagKind::UnknownParameter, pl.range,
                   fmt::format("`list` names `{}`, which bank `{}` does not define{}", pl.name, pl.bank,
                               hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
  }
}

ir::NodeId lookup_param_text(Context& c, std::string_view text) {
  if (auto it = c.param_text_memo.find(text); it != c.param_text_memo.end()) return it->second;
  ir::NodeId found = ir::NodeId::None();
  if (auto it = c.params.find(text); it != c.params.end()) {
    found = it->second;
  } else {
    // `bank_param`: the longest declared bank prefix.
    std::string dotted;
    for (size_t u = text.rfind('_'); u != std::string_view::npos && u > 0; u = text.rfind('_', u - 1)) {
      const std::string_view bank = text.substr(0, u);
      if (c.banks.contains(bank)) {
        dotted.assign(bank);
        dotted += '.';
        dotted += text.substr(u + 1);
        if (auto p = c.params.find(dotted); p != c.params.end()) {
          found = p->second;
          break;
        }
      }
    }
  }
  c.param_text_memo.emplace(std::string(text), found);
  return found;
}

}  // namespace nomec::check
