// Completion, signature help and hover. Completion and signature help read the text before
// the cursor with the forgiving scanner (lex.h) and a stack of open statements, so they work
// while a statement is still being typed; names come from the index's symbols. Hover text
// for parameters shows value, range, bank and the instances the slider controls (from the
// IR dependency graph); for generators, the arguments with their values and meanings.
#include <algorithm>
#include <fmt/format.h>

#include "ir/generator_catalogue.h"
#include "frontend/index/index.h"
#include "frontend/index/keywords.h"
#include "frontend/parse/parse.h"

namespace nomec::index {

using ast::BlockKind;

namespace {

// What surrounds the cursor, from the text alone.
struct Context {
  std::string_view prefix;          // the word being typed (may start with `$`)
  uint32_t prefix_begin = 0;
  bool in_comment_or_string = false;
  bool have_stmt = false;            // inside some statement
  BlockKind stmt = BlockKind::Bank;
  std::string_view stmt_keyword;      // its keyword as written, e.g. `funnel`
  BlockKind outer = BlockKind::Bank;  // the statement enclosing `stmt`, if any
  bool have_outer = false;
  uint32_t outer_begin = 0;          // offset of the enclosing statement's keyword
  std::vector<LexToken> items;          // tokens of the statement after its keyword, before the prefix
  int paren_depth = 0;               // unclosed `(` of this statement before the cursor
  size_t paren_open = 0;             // index in `items` of the innermost unclosed `(`
  int lists_before = 0;              // complete `( … )` lists at depth 0 before the cursor
  std::string_view prev_word;        // last word token at depth 0 before the prefix
};

// Where scanning may start for a cursor at `offset`: the keyword of the last top-level
// statement that starts before it (always outside comments and blocks), so completion costs
// the size of one statement, not of the file.
uint32_t scan_start(const CheckResult& check, FileId file, uint32_t offset) {
  for (const auto& a : check.asts) {
    if (a->file != file) continue;
    auto it = std::upper_bound(a->top.begin(), a->top.end(), offset,
                               [](uint32_t off, const ast::Item& item) { return off < item.range.begin; });
    // Only a statement's own keyword is sure to be at the top level (stray words after an
    // unfinished statement are not).
    // A statement the parser had to close itself (no end keyword) may textually enclose the
    // ones after it, so start at the earliest of such a chain.
    uint32_t start = 0;
    bool found = false;
    while (it != a->top.begin()) {
      --it;
      if (it->kind != ast::ItemKind::Block) continue;
      if (found && a->stmt(it->block).close_kw.is_valid()) break;
      start = it->range.begin;
      found = true;
    }
    return start;
  }
  return 0;
}

Context context_at(std::string_view text, uint32_t offset, uint32_t start) {
  Context c;
  offset = std::min<uint32_t>(offset, static_cast<uint32_t>(text.size()));
  uint32_t b = offset;
  while (b > 0 && is_name_part(text[b - 1])) --b;
  if (b > 0 && text[b - 1] == '$') --b;
  c.prefix = text.substr(b, offset - b);
  c.prefix_begin = b;
  start = std::min(start, b);
  std::vector<LexToken> toks = lex_file(text.substr(start, b - start));
  for (LexToken& t : toks) {
    t.begin += start;
    t.end += start;
  }
  struct Open {
    BlockKind kind;
    size_t tok;
    std::string_view keyword;
  };
  std::vector<Open> stack;
  for (size_t i = 0; i < toks.size(); ++i) {
    const LexToken& t = toks[i];
    if (t.kind != LexKind::Word) continue;
    std::string_view w = text.substr(t.begin, t.end - t.begin);
    BlockKind k;
    if (block_by_close(w, &k)) {
      for (size_t j = stack.size(); j-- > 0;) {
        if (stack[j].kind == k && closes(stack[j].keyword, w)) {
          stack.resize(j);
          break;
        }
      }
      continue;
    }
    if (block_by_open(w, &k)) {
      // Option words that are also block keywords (`surface S`, `point p`, `polyline L`)
      // stay options inside a statement that accepts them.
      if (!stack.empty()) {
        auto opts = option_words(stack.back().keyword);
        if (std::find(opts.begin(), opts.end(), w) != opts.end()) continue;
      }
      stack.push_back({k, i, w});
    }
  }
  // Unclosed comment or string at the cursor?
  if (!toks.empty()) {
    const LexToken& last = toks.back();
    if ((is_comment(last.kind) || is_text_literal(last.kind)) && last.end >= b) {
      std::string_view t = text.substr(last.begin, last.end - last.begin);
      bool closed = (t.starts_with("(*") && t.ends_with("*)") && t.size() >= 4) ||
                    (t.starts_with("\"") && t.size() >= 2 && t.ends_with("\"")) ||
                    (t.starts_with("[") && t.ends_with("]")) || (t.starts_with("{") && t.ends_with("}"));
      if (t.starts_with("#") || !closed) c.in_comment_or_string = true;
    }
  }
  if (stack.empty()) return c;
  c.have_stmt = true;
  c.stmt = stack.back().kind;
  c.stmt_keyword = stack.back().keyword;
  if (stack.size() >= 2) {
    c.have_outer = true;
    c.outer = stack[stack.size() - 2].kind;
    c.outer_begin = toks[stack[stack.size() - 2].tok].begin;
  }
  std::vector<size_t> opens;
  for (size_t i = stack.back().tok + 1; i < toks.size(); ++i) {
    const LexToken& t = toks[i];
    if (is_comment(t.kind)) continue;
    c.items.push_back(t);
    if (t.kind == LexKind::LParen) opens.push_back(c.items.size() - 1);
    if (t.kind == LexKind::RParen && !opens.empty()) {
      opens.pop_back();
      if (opens.empty()) ++c.lists_before;
    }
    if (t.kind == LexKind::Word && opens.empty()) c.prev_word = text.substr(t.begin, t.end - t.begin);
    if (t.kind != LexKind::Word && t.kind != LexKind::RParen && opens.empty()) c.prev_word = {};
  }
  c.paren_depth = static_cast<int>(opens.size());
  if (!opens.empty()) c.paren_open = opens.back();
  return c;
}

bool starts_with(std::string_view s, std::string_view p) { return s.substr(0, p.size()) == p; }

std::string fmt_num(double v) { return fmt::format("{}", v); }

}  // namespace

namespace {

// Completion items for one cursor position, by what surrounds it (see `Index::complete`).
class Completer {
 public:
  Completer(const Index& ix, const CheckResult& check, std::string_view text, FileId file, const Context& c)
      : ix_(ix), symbols_(ix.symbols()), check_(check), text_(text), file_(file), c_(c) {}

  std::vector<CompletionItem> run() {
    if (c_.in_comment_or_string) return std::move(out_);
    if (starts_with(c_.prefix, "$")) {
      add_params(true);
    } else if (!c_.have_stmt) {
      statement_keywords();
    } else if (c_.paren_depth > 0) {
      in_list();
    } else {
      in_body();
    }
    return std::move(out_);
  }

 private:
  void add(std::string label, SymbolKind kind, bool kw, std::string detail) {
    if (!starts_with(label, c_.prefix)) return;
    CompletionItem it;
    it.insert_text = label;
    it.label = std::move(label);
    it.kind = kind;
    it.is_keyword = kw;
    it.detail = std::move(detail);
    out_.push_back(std::move(it));
  }
  void add_params(bool dollar) {
    for (const Symbol& s : symbols_) {
      if (s.kind != SymbolKind::Parameter || s.parent < 0) continue;
      const std::string& bank = symbols_[s.parent].name;
      const std::string name = check_.dialect == Dialect::Nome ? bank + "_" + s.name : bank + "." + s.name;
      add((dollar ? "$" : "") + name, SymbolKind::Parameter, false, s.detail);
    }
    if (dollar) {
      add("$time", SymbolKind::Parameter, false, "built-in: the animation time (--time)");
      add("$frame", SymbolKind::Parameter, false, "built-in: the animation frame (--frame)");
    }
  }
  void add_symbols(std::initializer_list<SymbolKind> kinds, bool top_only) {
    for (const Symbol& s : symbols_) {
      if (top_only && s.parent >= 0) continue;
      if (std::find(kinds.begin(), kinds.end(), s.kind) == kinds.end()) continue;
      add(s.name, s.kind, false, s.detail);
    }
  }
  void add_keyword(std::string_view kw) { add(std::string(kw), SymbolKind::Other, true, std::string(keyword_doc(kw))); }

  // Outside any statement: the statements that may start here.
  void statement_keywords() {
    for (std::string_view kw : ast::all_open_keywords()) {
      if (ast::category(*ast::block_of_keyword(kw)) != ast::BlockCategory::Sub) add_keyword(kw);
    }
    add_keyword("include");
    add_keyword("tclinit");
    add_keyword("tclupdate");
  }

  // Inside `( … )`: faces of an object, vertices of a face-like list, or values.
  void in_list() {
    const BlockKind k = c_.stmt;
    if (k == BlockKind::Object) {
      add_symbols({SymbolKind::Face}, true);
      return;
    }
    const bool vertex_list = k == BlockKind::Face || k == BlockKind::Facet || k == BlockKind::Polyline ||
                             k == BlockKind::Sharp || k == BlockKind::Zipper || k == BlockKind::Consolidateface;
    if (vertex_list) {
      vertices();
      return;
    }
    // A value list: sliders, functions, constants.
    add_params(true);
    for (const FunctionDoc& f : functions()) add(std::string(f.name), SymbolKind::Other, false, std::string(f.signature));
    add("pi", SymbolKind::Other, false, "3.14159…");
  }

  // A vertex: a point, an instance path, or a point of the mesh being written.
  void vertices() {
    if (auto dot = c_.prefix.rfind('.'); dot != std::string_view::npos) {
      instance_path(dot);
      return;
    }
    add_symbols({SymbolKind::Point}, true);
    add_symbols({SymbolKind::Instance}, true);
    if (c_.have_outer && c_.outer == BlockKind::Mesh) points_of_enclosing_mesh();
  }

  // A path through instances: complete the part after the last `.`.
  void instance_path(size_t dot) {
    std::string_view path = c_.prefix.substr(0, dot);
    if (starts_with(path, ".")) path.remove_prefix(1);
    SymbolId cur = -1;
    size_t at = 0;
    while (true) {
      const size_t d = path.find('.', at);
      const std::string_view part = path.substr(at, d == std::string_view::npos ? std::string_view::npos : d - at);
      SymbolId next = -1;
      for (const Symbol& s : symbols_) {
        if (s.kind == SymbolKind::Instance && s.name == part && (cur < 0 ? s.parent < 0 : s.parent == cur)) {
          next = s.id;
          break;
        }
      }
      if (next < 0) return;
      // Continue inside the instance's target.
      const ir::Node& n = check_.module.node(symbols_[next].node);
      cur = n.kind == ir::NodeKind::Instance ? ix_.symbol_of(n.as<ir::InstanceData>().target) : -1;
      if (cur < 0 || d == std::string_view::npos) break;
      at = d + 1;
    }
    if (cur < 0) return;
    const std::string base(c_.prefix.substr(0, dot + 1));
    for (const Symbol& s : symbols_) {
      if (s.parent != cur || (s.kind != SymbolKind::Instance && s.kind != SymbolKind::Point)) continue;
      add(base + s.name, s.kind, false, s.detail);
    }
  }

  // Points of the mesh being written (found by where its keyword is: the mesh may be
  // unfinished, so its parsed range can end before the cursor).
  void points_of_enclosing_mesh() {
    const size_t before = out_.size();
    for (const Symbol& s : symbols_) {
      if (s.kind == SymbolKind::Point && s.parent >= 0 && s.full_range.file == file_ &&
          symbols_[s.parent].full_range.begin == c_.outer_begin) {
        add(s.name, s.kind, false, s.detail);
      }
    }
    if (out_.size() != before) return;
    // The parser could not keep this unfinished mesh's points: read them from the text.
    const std::vector<LexToken> toks = lex_file(text_.substr(c_.outer_begin, c_.prefix_begin - c_.outer_begin));
    for (size_t i = 0; i + 1 < toks.size(); ++i) {
      const std::string_view w = text_.substr(c_.outer_begin + toks[i].begin, toks[i].end - toks[i].begin);
      if (toks[i].kind == LexKind::Word && toks[i + 1].kind == LexKind::Word && (w == "point" || w == "vertex")) {
        const LexToken& n = toks[i + 1];
        add(std::string(text_.substr(c_.outer_begin + n.begin, n.end - n.begin)), SymbolKind::Point, false, "point");
      }
    }
  }

  // In a statement's body, outside brackets.
  void in_body() {
    const BlockKind k = c_.stmt;
    const Dialect dialect = check_.dialect;
    // Typing the name right after the keyword: a new name, nothing to offer — except where
    // that word refers to something (SLIDE instance targets, sweep paths).
    if (c_.items.empty()) {
      if (k == BlockKind::Instance && dialect == Dialect::Slide) {
        add_symbols({SymbolKind::Mesh, SymbolKind::Object, SymbolKind::Group, SymbolKind::Generator, SymbolKind::Block},
                    true);
      } else if (k == BlockKind::Path || (k == BlockKind::Crosssection && c_.have_outer)) {
        add_symbols({SymbolKind::Generator, SymbolKind::Polyline, SymbolKind::Other}, true);
      }
      return;
    }
    if (k == BlockKind::Instance && dialect != Dialect::Slide && c_.items.size() == 1 &&
        c_.items[0].kind == LexKind::Word) {
      add_symbols({SymbolKind::Mesh, SymbolKind::Object, SymbolKind::Group, SymbolKind::Generator, SymbolKind::Block,
                   SymbolKind::Polyline},
                  true);
      return;
    }
    if (c_.prev_word == "surface") {
      add_symbols({SymbolKind::Surface}, true);
      return;
    }
    if (c_.prev_word == "point" || c_.prev_word == "polyline" || c_.prev_word == "path" ||
        c_.prev_word == "bsplinecurve" || c_.prev_word == "beziercurve") {
      add_symbols({SymbolKind::Point, SymbolKind::Polyline, SymbolKind::Generator}, true);
      return;
    }
    if (k == BlockKind::Bank) {
      add_keyword("set");
      add_keyword("list");
    }
    for (std::string_view w : option_words(c_.stmt_keyword)) add_keyword(w);
    for (BlockKind child : child_blocks(k)) add_keyword(ast::open_keyword(child));
    add_keyword(ast::end_keyword(c_.stmt_keyword));
    // A value after an option: sliders too.
    add_params(true);
  }

  const Index& ix_;
  const std::vector<Symbol>& symbols_;
  const CheckResult& check_;
  std::string_view text_;
  FileId file_;
  const Context& c_;
  std::vector<CompletionItem> out_;
};

}  // namespace

std::vector<CompletionItem> Index::complete(FileId file, uint32_t offset) const {
  if (!file.is_valid() || file.index >= static_cast<int32_t>(sources_->file_count())) return {};
  const std::string_view text = sources_->text(file);
  const Context c = context_at(text, offset, scan_start(*check_, file, offset));
  return Completer(*this, *check_, text, file, c).run();
}

namespace {

// The element of the innermost open list the cursor is in: elements of the list before the
// cursor, counted by the sign rule (`1 -2` is two elements, `1 - 2` and `1-2` one).
int active_element(const Context& c, std::string_view text) {
  int elem = 0;
  bool have_operand = false;  // the current element has a complete operand
  int depth = 0;
  for (size_t i = c.paren_open + 1; i < c.items.size(); ++i) {
    const LexToken& t = c.items[i];
    bool opens = t.kind == LexKind::LParen || t.kind == LexKind::LBrace;
    bool closes = t.kind == LexKind::RParen || t.kind == LexKind::RBrace;
    if (depth > 0) {
      if (opens) ++depth;
      if (closes && --depth == 0) have_operand = true;
      continue;
    }
    if (t.kind == LexKind::Operator) {
      char op = text[t.begin];
      bool space_before = t.begin > 0 && (text[t.begin - 1] == ' ' || text[t.begin - 1] == '\t' || text[t.begin - 1] == '\n');
      bool space_after = t.end < text.size() && (text[t.end] == ' ' || text[t.end] == '\t' || text[t.end] == '\n');
      if ((op == '+' || op == '-') && have_operand && space_before && !space_after) {
        ++elem;
      }
      have_operand = false;
      continue;
    }
    if (opens || t.kind == LexKind::Number || t.kind == LexKind::Word || t.kind == LexKind::DollarRef || is_text_literal(t.kind)) {
      if (have_operand) ++elem;
      if (opens) {
        depth = 1;
        have_operand = false;
      } else {
        have_operand = true;
      }
    }
  }
  // After a complete element and a space, the cursor starts the next one.
  uint32_t b = c.prefix_begin;
  if (c.prefix.empty() && have_operand && b > 0 && (text[b - 1] == ' ' || text[b - 1] == '\t')) ++elem;
  return elem;
}

}  // namespace

std::optional<SignatureHelp> Index::signature_help(FileId file, uint32_t offset) const {
  if (!file.is_valid() || file.index >= static_cast<int32_t>(sources_->file_count())) return std::nullopt;
  std::string_view text = sources_->text(file);
  Context c = context_at(text, offset, scan_start(*check_, file, offset));
  if (!c.have_stmt || c.paren_depth == 0 || c.in_comment_or_string) return std::nullopt;
  SignatureHelp h;
  std::vector<std::pair<std::string, std::string>> params;  // name, doc
  std::string head;
  // Which list: the word before the `(` (an option), or the statement's positional list.
  std::string_view option;
  if (c.paren_open > 0 && c.items[c.paren_open - 1].kind == LexKind::Word) {
    const LexToken& w = c.items[c.paren_open - 1];
    option = text.substr(w.begin, w.end - w.begin);
  }
  // `rotate (x y z) (deg)`: the second list is the angle.
  bool rotate_angle = c.paren_open >= 2 && c.items[c.paren_open - 1].kind == LexKind::RParen;
  if (rotate_angle) {
    int depth = 0;
    for (size_t i = c.paren_open - 1; i-- > 0;) {
      if (c.items[i].kind == LexKind::RParen) ++depth;
      if (c.items[i].kind == LexKind::LParen && depth-- == 0) {
        rotate_angle = i > 0 && c.items[i - 1].kind == LexKind::Word &&
                       text.substr(c.items[i - 1].begin, c.items[i - 1].end - c.items[i - 1].begin) == "rotate";
        break;
      }
    }
  }
  const std::optional<ir::GenKind> gen = ir::generator_by_keyword(c.stmt_keyword);
  const ir::GeneratorInfo* info = gen ? &ir::generator(*gen) : nullptr;
  const ir::Signature* sig = info != nullptr ? info->signature(check_->dialect) : nullptr;
  // The signature's arguments with their meanings; the optional ones marked as such.
  auto add_arguments = [&](bool with_optional) {
    for (size_t i = 0; i < sig->names.size(); ++i) {
      const bool optional = i >= sig->args.size();
      if (optional && !with_optional) break;
      const ir::ArgIndex arg = optional ? sig->optional[i - sig->args.size()] : sig->args[i];
      std::string doc = arg == ir::kNoArg ? std::string() : std::string(info->args[arg].doc);
      params.push_back({std::string(sig->names[i]), optional ? "optional: " + doc : doc});
    }
  };
  if (rotate_angle) {
    head = "rotate (ax ay az) ";
    params = {{"degrees", "rotation angle in degrees"}};
  } else if (option == "translate" || option == "scale") {
    head = std::string(option) + " ";
    params = {{"x", "along x"}, {"y", "along y"}, {"z", "along z"}};
  } else if (option == "rotate") {
    head = "rotate ";
    params = {{"ax", "axis x"}, {"ay", "axis y"}, {"az", "axis z"}};
  } else if (option == "mirror") {
    head = "mirror ";
    params = {{"a", "plane normal x"}, {"b", "plane normal y"}, {"c", "plane normal z"}, {"d", "plane offset: ax+by+cz=d"}};
  } else if (option == "color") {
    head = "color ";
    params = {{"r", "red in [0, 1]"}, {"g", "green in [0, 1]"}, {"b", "blue in [0, 1]"}};
  } else if ((c.stmt == BlockKind::Point || c.stmt == BlockKind::Vertex) && c.lists_before == 0) {
    head = fmt::format("{} NAME ", c.stmt_keyword);
    params = {{"x", "x coordinate"}, {"y", "y coordinate"}, {"z", "z coordinate"}};
  } else if (sig != nullptr && c.lists_before == 0 && option.empty()) {
    head = fmt::format("{} NAME ", c.stmt_keyword);
    add_arguments(true);
  } else if (sig != nullptr && c.lists_before == 0 && (c.items.size() >= 1)) {
    // `funnel f (` where the name happens to be an option word.
    head = fmt::format("{} NAME ", c.stmt_keyword);
    add_arguments(false);
  } else {
    return std::nullopt;
  }
  h.label = head + "(";
  for (size_t i = 0; i < params.size(); ++i) {
    if (i > 0) h.label += ' ';
    uint32_t b = static_cast<uint32_t>(h.label.size());
    h.label += params[i].first;
    h.parameters.push_back({b, static_cast<uint32_t>(h.label.size())});
    std::string doc = params[i].second;
    if (info != nullptr && doc.find("count") == std::string::npos) {
      std::optional<ir::ArgIndex> arg = info->arg_named(params[i].first);
      const bool counted = arg && (info->args[*arg].type == ir::ArgType::Count || info->args[*arg].type == ir::ArgType::Whole);
      if (counted) doc += doc.empty() ? "a whole-number count" : " (count)";
    }
    h.parameter_docs.push_back(std::move(doc));
  }
  h.label += ")";
  h.active_parameter = std::min<int>(active_element(c, text), static_cast<int>(params.size()) - 1);
  return h;
}

// ---------------- hover ----------------

std::string Index::hover_symbol(const Symbol& s) const {
  const ir::Module& m = check_->module;
  std::string md;
  const ir::Node* n = s.node.is_valid() ? &m.node(s.node) : nullptr;
  auto value_of = [&](ir::ExprId e) {
    ir::EvalResult r = ir::evaluate(m, e);
    std::string t = ir::expr_text(m, e);
    if (!r.ok) return t;
    std::string v = fmt_num(r.value);
    return t == v ? t : fmt::format("{} = {}", t, v);
  };
  switch (s.kind) {
    case SymbolKind::Parameter: {
      if (n == nullptr) break;
      const ir::ParamData& pd = n->as<ir::ParamData>();
      md = fmt::format("**slider `{}`** in bank `{}`\n\n", s.name, pd.bank);
      md += "| value | min | max | step |\n|---|---|---|---|\n";
      md += fmt::format("| {} | {} | {} | {} |\n", fmt_num(pd.value), fmt_num(pd.min), fmt_num(pd.max), fmt_num(pd.step));
      std::vector<std::string> insts;
      size_t total = 0;
      for (ir::NodeId d : m.deps.affected_by(s.node)) {
        const ir::Node& dn = m.node(d);
        if (dn.kind != ir::NodeKind::Instance) continue;
        ++total;
        if (insts.size() < 12) insts.push_back(fmt::format("`{}`", dn.name.empty() ? dn.keyword : dn.name));
      }
      if (total == 0) {
        md += "\nControls no instance.";
      } else {
        md += fmt::format("\nControls {} instance{}: {}{}", total, total == 1 ? "" : "s", fmt::join(insts, ", "),
                          total > insts.size() ? fmt::format(" and {} more", total - insts.size()) : "");
      }
      size_t uses = 0;
      for (uint32_t i = ref_begin_[s.id]; i < ref_begin_[s.id + 1]; ++i) uses += !occurrences_[ref_items_[i]].is_definition;
      md += fmt::format("\n\nUsed {} time{}. Write it as `${}.{}` or `${}_{}`.", uses, uses == 1 ? "" : "s", pd.bank, s.name, pd.bank, s.name);
      return md;
    }
    case SymbolKind::Bank: {
      md = fmt::format("**bank `{}`**\n\n", s.name);
      md += "| slider | value | min | max | step |\n|---|---|---|---|---|\n";
      for (const Symbol& p : symbols_) {
        if (p.parent != s.id || p.kind != SymbolKind::Parameter || !p.node.is_valid()) continue;
        const ir::ParamData& pn = m.param(p.node);
        md += fmt::format("| `{}` | {} | {} | {} | {} |\n", p.name, fmt_num(pn.value), fmt_num(pn.min), fmt_num(pn.max), fmt_num(pn.step));
      }
      return md;
    }
    default: break;
  }
  if (n == nullptr) return fmt::format("**{} `{}`**", symbol_kind_name(s.kind), s.name);
  md = fmt::format("**{} `{}`**", n->keyword, s.name);
  auto operand_line = [&](ir::OperandId o) {
    const ir::Operand& op = m.operand(o);
    std::vector<std::string> vals;
    for (ir::ExprId e : m.refs(op.exprs)) vals.push_back(value_of(e));
    return fmt::format("\n- `{}` ({})", op.name, fmt::join(vals, " | "));
  };
  if (n->kind == ir::NodeKind::Instance) {
    const ir::InstanceData& inst = n->as<ir::InstanceData>();
    if (inst.target.is_valid()) {
      const ir::Node& t = m.node(inst.target);
      md += fmt::format(" — instance of {} `{}`", t.keyword, t.name);
    }
    md += "\n";
    for (ir::OperandId o : m.operands_of(*n)) md += operand_line(o);
    if (inst.surface.is_valid()) md += fmt::format("\n- `surface` `{}`", m.node(inst.surface).name);
    if (inst.is_hidden) md += "\n- `hidden`";
    if (inst.target.is_valid()) {
      SymbolId ts = symbol_of(inst.target);
      if (ts >= 0 && symbols_[ts].kind == SymbolKind::Generator) md += "\n\n" + hover_symbol(symbols_[ts]);
    }
    return md;
  }
  if (std::string_view d = keyword_doc(n->keyword); !d.empty()) md += fmt::format(" — {}", d);
  md += "\n";
  if (n->kind == ir::NodeKind::SceneSetup) {
    // Viewing set-up: every field with its value, the defaults included.
    for (const auto& [field, text] : ir::scene_fields(m, *n, false)) md += fmt::format("\n- `{}` {}", field, text);
    return md;
  }
  if (n->kind == ir::NodeKind::Generator) {
    // The arguments as written, with their meanings from the generator catalogue.
    const ir::GeneratorInfo& info = ir::generator(n->as<ir::GeneratorData>().gen);
    md += "\n| argument | value | meaning |\n|---|---|---|\n";
    for (const ir::GenArgBinding& b : m.refs(n->as<ir::GeneratorData>().args)) {
      if (!b.value.is_valid() || m.operand(b.value).exprs.empty()) continue;
      const ir::Operand& op = m.operand(b.value);
      md += fmt::format("| `{}` | {} | {} |\n", op.name, value_of(m.refs(op.exprs)[0]), b.arg == ir::kNoArg ? "" : info.args[b.arg].doc);
    }
    return md;
  }
  int points = 0, faces = 0, instances = 0;
  for (ir::NodeId c : m.children(*n)) {
    switch (m.node(c).kind) {
      case ir::NodeKind::Point: ++points; break;
      case ir::NodeKind::Face: ++faces; break;
      case ir::NodeKind::Instance: ++instances; break;
      default: break;
    }
  }
  for (const Symbol& o : symbols_) instances += o.parent == s.id && o.kind == SymbolKind::Instance && !o.node.is_valid();
  if (points + faces > 0) md += fmt::format("\n{} point{}, {} face{} written here", points, points == 1 ? "" : "s", faces, faces == 1 ? "" : "s");
  if (instances > 0) md += fmt::format("\n{} instance{}", instances, instances == 1 ? "" : "s");
  for (ir::OperandId o : m.operands_of(*n)) md += operand_line(o);
  for (ir::Slice<ir::VertexRef> list : ir::vertex_lists_of(m, *n)) {
    std::vector<std::string> vs;
    for (const ir::VertexRef& v : m.refs(list)) vs.push_back(v.text);
    md += fmt::format("\n- `{}` ({})", n->kind == ir::NodeKind::Polyline ? "points" : "vertices", fmt::join(vs, " "));
  }
  if (n->kind == ir::NodeKind::Subdivision) {
    md += fmt::format("\n- rule {}", ir::subdivision_rule_name(n->as<ir::SubdivisionData>().rule));
  } else if (n->kind == ir::NodeKind::Offset) {
    md += fmt::format("\n- {} offset", ir::offset_kind_name(n->as<ir::OffsetData>().kind));
  }
  return md;
}

std::optional<Hover> Index::hover(FileId file, uint32_t offset) const {
  if (!file.is_valid() || file.index >= static_cast<int32_t>(sources_->file_count())) return std::nullopt;
  if (std::optional<Occurrence> o = occurrence_at(file, offset)) {
    return Hover{hover_symbol(symbols_[o->symbol]), o->range, o->symbol};
  }
  std::string_view text = sources_->text(file);
  if (offset > text.size()) return std::nullopt;
  uint32_t b = offset, e = offset;
  while (b > 0 && (is_name_part(text[b - 1]) || text[b - 1] == '$')) --b;
  while (e < text.size() && is_name_part(text[e])) ++e;
  if (b > 0 && text[b - 1] == '$') --b;
  if (b == e) return std::nullopt;
  // Inside a comment or string: nothing.
  for (const LexToken& t : lex_file(text.substr(0, e))) {
    if ((is_comment(t.kind) || is_text_literal(t.kind)) && t.begin <= b && b < t.end) return std::nullopt;
  }
  std::string_view w = text.substr(b, e - b);
  SourceRange r{file, b, e};
  if (w == "$time") return Hover{"**`$time`** — built-in: the animation time (`--time`, default 0)", r, -1};
  if (w == "$frame") return Hover{"**`$frame`** — built-in: the animation frame (`--frame`, default 0)", r, -1};
  for (const FunctionDoc& f : functions()) {
    if (f.name == w) return Hover{fmt::format("**`{}`** — {}", f.signature, f.doc), r, -1};
  }
  // A generator's option word: the meaning of its argument, default included (SLIDE's
  // quadrics have nomec's defaults, docs/dialects.md).
  const Context c = context_at(text, b, scan_start(*check_, file, b));
  if (c.have_stmt && c.paren_depth == 0) {
    if (const std::optional<ir::GenKind> gen = ir::generator_by_keyword(c.stmt_keyword)) {
      const ir::GeneratorInfo& info = ir::generator(*gen);
      if (std::optional<ir::ArgIndex> arg = info.option(check_->dialect, w)) {
        return Hover{fmt::format("**`{}`** (`{}`) — {}", w, c.stmt_keyword, info.args[*arg].doc), r, -1};
      }
    }
  }
  if (std::string_view d = keyword_doc(w); !d.empty()) return Hover{fmt::format("**`{}`** — {}", w, d), r, -1};
  return std::nullopt;
}

}  // namespace nomec::index
