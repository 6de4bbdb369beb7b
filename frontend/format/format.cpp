// Formatter implementation. The text is parsed (files with syntax errors are refused), lexed
// with comments kept (parse layer `lex_file`), and re-emitted unit by unit: a unit is a token,
// or a verbatim range taken whole from the AST (`tclinit { … }`, raw Tcl braces, `[raw]`,
// `%{ }%`). Only whitespace between units changes: indentation from the AST's block nesting
// (plus open brackets for continuation lines), line breaks kept (blank-line runs collapsed
// to one) or added before statements, and canonical spacing inside lists and `{expr …}`.
// The result is parsed again and its AST compared with the original's; if they differ the
// formatter refuses rather than change the meaning.
#include "frontend/format/format.h"

#include <algorithm>
#include <cctype>
#include <fmt/format.h>
#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "frontend/diagnostics/diagnostic.h"
#include "frontend/parse/parse.h"

namespace nomec {

namespace {

// What the AST says about a token, keyed by its byte offset.
enum class Role : uint8_t { None, Binary, Unary, CallParen };

struct Structure {
  std::unordered_set<uint32_t> opens;        // opening keyword of a block
  std::unordered_set<uint32_t> bank_opens;   // ... of a `bank` (its `set` rows are aligned)
  std::unordered_set<uint32_t> closes;       // closing keyword of a block
  std::unordered_set<uint32_t> line_starts;  // a unit that must begin a line
  std::unordered_map<uint32_t, Role> roles;  // operators and call parentheses
  std::vector<std::pair<uint32_t, uint32_t>> verbatim;  // copied byte for byte
  std::vector<std::pair<uint32_t, uint32_t>> binary_gaps;  // operator lies in [first, second)
  std::vector<uint32_t> call_names_end;  // the call's `(` is the first `(` from here
};

class StructureBuilder {
 public:
  StructureBuilder(const ast::Ast& tree, std::string_view text, Structure& out)
      : ast_(tree), text_(text), out_(out) {}

  void build() {
    for (const ast::Item& item : ast_.top) {
      out_.line_starts.insert(item.range.begin);
      this->item(item);
    }
  }

 private:
  bool spans_lines(uint32_t begin, uint32_t end) const {
    // A lone `\r` counts: the printer turns it into a line break.
    return text_.substr(begin, end - begin).find_first_of("\n\r") != std::string_view::npos;
  }

  void item(const ast::Item& it) {
    switch (it.kind) {
      case ast::ItemKind::Word:
      case ast::ItemKind::Include:
        return;
      case ast::ItemKind::Tcl:
        out_.verbatim.emplace_back(it.range.begin, it.range.end);
        return;
      case ast::ItemKind::Value:
        expr(it.expr);
        return;
      case ast::ItemKind::List:
        for (ast::ExprId e : ast_.list(it.list).elems) expr(e);
        return;
      case ast::ItemKind::Block:
        stmt(ast_.stmt(it.block));
        return;
    }
  }

  void stmt(const ast::Stmt& s) {
    out_.opens.insert(s.open_kw.begin);
    if (s.kind == ast::BlockKind::Bank) out_.bank_opens.insert(s.open_kw.begin);
    bool multi_line = false;
    if (s.close_kw.is_valid() && s.close_kw.end > s.close_kw.begin) {
      out_.closes.insert(s.close_kw.begin);
      multi_line = spans_lines(s.open_kw.begin, s.close_kw.begin);
      // A container (its body ends with a nested block) closes on a line of its own; a
      // simple block keeps `endface` after its last list: `face f (a b\n  c d) endface`.
      if (multi_line && !s.items.empty() && s.items.back().kind == ast::ItemKind::Block) {
        out_.line_starts.insert(s.close_kw.begin);
      }
    }
    for (const ast::Item& it : s.items) {
      if (multi_line && it.kind == ast::ItemKind::Block) out_.line_starts.insert(it.range.begin);
      item(it);
    }
  }

  void expr(ast::ExprId id) {
    // Binary chains are left-nested: walk the left spine iteratively.
    while (id.is_valid()) {
      const ast::Expr& e = ast_.expr(id);
      switch (e.kind) {
        case ast::ExprKind::Raw:
          out_.verbatim.emplace_back(e.range.begin, e.range.end);
          return;
        case ast::ExprKind::Binary:
          out_.binary_gaps.emplace_back(ast_.expr(e.lhs()).range.end, ast_.expr(e.rhs()).range.begin);
          expr(e.rhs());
          id = e.lhs();
          continue;
        case ast::ExprKind::Unary:
          out_.roles[e.range.begin] = Role::Unary;
          id = e.lhs();
          continue;
        case ast::ExprKind::Call:
          out_.call_names_end.push_back(e.range.begin + static_cast<uint32_t>(e.text.size()));
          for (ast::ExprId a : ast_.args_of(e)) expr(a);
          return;
        default:
          return;
      }
    }
  }

  const ast::Ast& ast_;
  std::string_view text_;
  Structure& out_;
};

// A structural fingerprint of an AST: everything that carries meaning, no positions.
class Fingerprint {
 public:
  explicit Fingerprint(const ast::Ast& tree) : ast_(tree) {}

  std::string of_file() {
    for (const ast::Item& it : ast_.top) item(it);
    return std::move(out_);
  }

 private:
  void text(std::string_view t) {
    for (char c : t) {
      if (c != '\r') out_ += c;
    }
    out_ += '\x1f';
  }
  void item(const ast::Item& it) {
    out_ += fmt::format("i{}:", static_cast<int>(it.kind));
    switch (it.kind) {
      case ast::ItemKind::Word:
      case ast::ItemKind::Tcl:
      case ast::ItemKind::Include:
        text(it.text);
        return;
      case ast::ItemKind::Value:
        expr(it.expr);
        return;
      case ast::ItemKind::List: {
        const ast::ParenList& l = ast_.list(it.list);
        out_ += fmt::format("({},{}:", l.elems.size(), ast_.commas_of(it.list).size());
        for (ast::ExprId e : l.elems) expr(e);
        out_ += ')';
        return;
      }
      case ast::ItemKind::Block: {
        const ast::Stmt& s = ast_.stmt(it.block);
        out_ += fmt::format("B{}:", static_cast<int>(s.kind));
        text(s.close_text);
        for (const ast::Item& sub : s.items) item(sub);
        out_ += 'E';
        return;
      }
    }
  }
  void expr(ast::ExprId id) {
    if (!id.is_valid()) {
      out_ += '-';
      return;
    }
    const ast::Expr& e = ast_.expr(id);
    out_ += fmt::format("e{}{}{}:", static_cast<int>(e.kind), e.op == 0 ? '_' : e.op,
                        e.in_braces ? 'b' : 'n');
    text(e.text);
    if (e.kind == ast::ExprKind::Binary || e.kind == ast::ExprKind::Unary) {
      expr(e.lhs());
      expr(e.rhs());
    }
    for (ast::ExprId a : ast_.args_of(e)) expr(a);
    out_ += ';';
  }

  const ast::Ast& ast_;
  std::string out_;
};

struct Parsed {
  std::unique_ptr<SourceManager> sources;  // owns the text the AST's views point into
  ast::Ast tree;
  std::string error;  // empty when the text parses without errors
};

Parsed parse_text(std::string_view text) {
  Parsed p;
  p.sources = std::make_unique<SourceManager>();
  SourceManager& sources = *p.sources;
  FileId file = sources.add_file("<format>", std::string(text));
  DiagnosticEngine diags;
  p.tree = parse_file(sources, file, diags);
  diags.sort_and_dedupe();
  for (const Diagnostic& d : diags.diagnostics()) {
    if (d.severity == Severity::Error) {
      LineCol lc = sources.line_col(file, d.range.begin);
      p.error = fmt::format("{}:{}: {}", lc.line, lc.column, d.message);
      break;
    }
  }
  // A statement the parser ended at the end of its line (NOME 2016 leniency) depends on
  // where the line breaks are, which is what a formatter changes: ask for its end keyword.
  if (p.error.empty()) {
    for (const ast::Stmt& s : p.tree.stmts) {
      if (s.close_repair != ast::CloseRepair::Inserted) continue;
      LineCol lc = sources.line_col(file, s.open_kw.begin);
      p.error = fmt::format("{}:{}: `{}` has no `{}` and ends at the end of its line; add the end keyword "
                            "(`nomec --check` offers it as a fix-it) before formatting",
                            lc.line, lc.column, s.keyword, ast::end_keyword(s.keyword));
      break;
    }
  }
  return p;
}

// One piece of output: a token, or a verbatim range.
struct Unit {
  LexKind kind;
  uint32_t begin;
  uint32_t end;
  bool verbatim;
};

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

bool is_number_cell(std::string_view cell) {
  if (!cell.empty() && (cell[0] == '-' || cell[0] == '+')) cell.remove_prefix(1);
  if (cell.empty()) return false;
  return std::all_of(cell.begin(), cell.end(), [](char c) {
    return (c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '-' || c == '+';
  }) && ((cell[0] >= '0' && cell[0] <= '9') || cell[0] == '.') &&
         ((cell.back() >= '0' && cell.back() <= '9') || cell.back() == '.');
}

// Aligns runs of consecutive bank rows (`set name value min max step`) into columns: words
// left-aligned, numbers right-aligned, a trailing comment after the widest row. Only the
// spaces between cells change, and every cell keeps at least one space before it.
std::string align_tables(std::string text, const std::vector<int>& rows) {
  if (rows.empty()) return text;
  std::vector<std::string> lines;
  for (size_t start = 0; start < text.size();) {
    size_t nl = text.find('\n', start);
    if (nl == std::string::npos) nl = text.size();
    lines.push_back(text.substr(start, nl - start));
    start = nl + 1;
  }
  auto align_group = [&](size_t first, size_t last) {  // rows[first..last]
    struct Row {
      std::string indent;
      std::vector<std::string> cells;
      std::string comment;
    };
    std::vector<Row> parsed;
    std::vector<size_t> width;
    for (size_t r = first; r <= last; ++r) {
      const std::string& line = lines[static_cast<size_t>(rows[r])];
      Row row;
      size_t at = line.find_first_not_of(" \t");
      if (at == std::string::npos || line.compare(at, 4, "set ") != 0) return;  // not a row
      size_t hash_at = line.find('#', at);
      if (hash_at != std::string::npos && line[hash_at - 1] != ' ') return;  // `+#`: keep glued
      row.indent = line.substr(0, at);
      size_t hash = line.find('#', at);
      std::string code = line.substr(at, hash == std::string::npos ? std::string::npos : hash - at);
      if (hash != std::string::npos) row.comment = line.substr(hash);
      for (size_t p = 0; p < code.size();) {
        size_t sp = code.find(' ', p);
        if (sp == std::string::npos) sp = code.size();
        if (sp > p) row.cells.push_back(code.substr(p, sp - p));
        p = sp + 1;
      }
      for (size_t c = 0; c < row.cells.size(); ++c) {
        if (width.size() <= c) width.push_back(0);
        width[c] = std::max(width[c], row.cells[c].size());
      }
      parsed.push_back(std::move(row));
    }
    size_t code_width = 0;
    std::vector<std::string> built;
    for (const Row& row : parsed) {
      std::string out = row.indent;
      for (size_t c = 0; c < row.cells.size(); ++c) {
        if (c > 0) out += ' ';
        const std::string& cell = row.cells[c];
        std::string pad(width[c] - cell.size(), ' ');
        bool last = c + 1 == row.cells.size();
        if (is_number_cell(cell)) {
          out += pad + cell;
        } else {
          out += cell;
          if (!last || !row.comment.empty()) out += pad;
        }
      }
      code_width = std::max(code_width, out.size());
      built.push_back(std::move(out));
    }
    for (size_t r = first; r <= last; ++r) {
      std::string& out = built[r - first];
      const Row& row = parsed[r - first];
      if (!row.comment.empty()) {
        out.append(code_width - out.size(), ' ');
        out += ' ';
        out += row.comment;
      }
      while (!out.empty() && out.back() == ' ') out.pop_back();
      lines[static_cast<size_t>(rows[r])] = std::move(out);
    }
  };
  for (size_t i = 0; i < rows.size();) {
    size_t j = i;
    while (j + 1 < rows.size() && rows[j + 1] == rows[j] + 1) ++j;
    if (j > i) align_group(i, j);
    i = j + 1;
  }
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < lines.size(); ++i) {
    out += lines[i];
    out += '\n';
  }
  if (!text.empty() && text.back() != '\n') out.pop_back();
  return out;
}

class Printer {
 public:
  Printer(std::string_view text, const Structure& structure, const FormatOptions& options)
      : text_(text), s_(structure), options_(options) {}

  std::string print(const std::vector<Unit>& units) {
    for (size_t i = 0; i < units.size(); ++i) {
      const Unit& u = units[i];
      if (!u.verbatim && u.kind == LexKind::Word && s_.closes.contains(u.begin) && depth_ > 0) {
        --depth_;
        if (!in_bank_.empty()) in_bank_.pop_back();
      }
      bool started_line = true;
      if (i == 0) {
        start_line(u, 0);
      } else {
        const Unit& p = units[i - 1];
        std::string_view gap = text_.substr(p.end, u.begin - p.end);
        // A lone `\r` (CRLF was already folded) ends a `#` comment too: it is a line break.
        size_t newlines = static_cast<size_t>(
            std::count_if(gap.begin(), gap.end(), [](char c) { return c == '\n' || c == '\r'; }));
        bool forced = line_has_code_ && s_.line_starts.contains(u.begin);
        if (newlines > 0 || forced) {
          out_ += newlines >= 2 ? "\n\n" : "\n";
          line_has_code_ = false;
          start_line(u, newlines >= 2 ? 2 : 1);
        } else {
          started_line = false;
          if (space(units, i, !gap.empty())) out_ += ' ';
        }
      }
      prev_started_line_ = started_line;
      std::string_view body = text_.substr(u.begin, u.end - u.begin);
      if (u.kind == LexKind::LineComment) {
        while (!body.empty() && is_space(body.back())) body.remove_suffix(1);
      }
      out_ += body;
      // Multi-line comments and verbatim text move the output line count on too.
      line_no_ += static_cast<int>(std::count(body.begin(), body.end(), '\n'));
      bool table_cell = !u.verbatim && (u.kind == LexKind::Word || u.kind == LexKind::Number ||
                                        u.kind == LexKind::DollarRef || u.kind == LexKind::Operator ||
                                        u.kind == LexKind::LineComment);
      if (!table_cell) row_ok_ = false;
      if (u.kind != LexKind::LineComment && u.kind != LexKind::BlockComment) {
        line_has_code_ = true;
      }
      if (u.verbatim) continue;
      if (u.kind == LexKind::Word && s_.opens.contains(u.begin)) {
        ++depth_;
        in_bank_.push_back(s_.bank_opens.contains(u.begin));
      }
      if (u.kind == LexKind::LParen || u.kind == LexKind::LBrace) {
        bracket_levels_.push_back(line_level_);
        if (u.kind == LexKind::LBrace) ++braces_;
      } else if (u.kind == LexKind::RParen || u.kind == LexKind::RBrace) {
        if (!bracket_levels_.empty()) bracket_levels_.pop_back();
        if (u.kind == LexKind::RBrace && braces_ > 0) --braces_;
      }
    }
    if (!out_.empty()) out_ += '\n';
    finish_row();
    return align_tables(std::move(out_), table_rows_);
  }

 private:
  // A new output line starts with `first`, `newlines` after the previous one. Lines of a
  // bank that start with `set` and hold only words, numbers and signs are table rows.
  void start_line(const Unit& first, int newlines) {
    finish_row();
    line_no_ += newlines;
    indent(first);
    row_ok_ = !first.verbatim && first.kind == LexKind::Word && !in_bank_.empty() &&
              in_bank_.back() && bracket_levels_.empty() &&
              text_.substr(first.begin, first.end - first.begin) == "set";
  }
  void finish_row() {
    if (row_ok_) table_rows_.push_back(line_no_);
    row_ok_ = false;
  }

  // Indents a new line: one level per enclosing block; inside brackets, one level more than
  // the line that opened the innermost bracket (its closer goes back to that line's level).
  void indent(const Unit& first) {
    int level = depth_;
    if (!bracket_levels_.empty()) {
      bool closer = !first.verbatim && (first.kind == LexKind::RParen || first.kind == LexKind::RBrace);
      level = bracket_levels_.back() + (closer ? 0 : 1);
    }
    level = std::max(level, 0);
    line_level_ = level;
    if (options_.insert_spaces) {
      out_.append(static_cast<size_t>(level) * static_cast<size_t>(std::max(options_.indent_width, 0)), ' ');
    } else {
      out_.append(static_cast<size_t>(level), '\t');
    }
  }

  Role role(const Unit& u) const {
    if (u.verbatim) return Role::None;
    auto it = s_.roles.find(u.begin);
    return it == s_.roles.end() ? Role::None : it->second;
  }

  // Whether the input separates operator `units[k]` from an operand by spaces on either
  // side. A side where a comment or a line break follows is not counted (the formatter
  // decides that spacing), so the answer is the same for the output.
  bool op_has_space_around(const std::vector<Unit>& units, size_t k) const {
    auto spaced = [&](const Unit& a, const Unit& b, const Unit& other) {
      std::string_view gap = text_.substr(a.end, b.begin - a.end);
      bool comment = !other.verbatim && (other.kind == LexKind::LineComment || other.kind == LexKind::BlockComment);
      return !comment && !gap.empty() && gap.find_first_of("\n\r") == std::string_view::npos;
    };
    bool before = k > 0 && spaced(units[k - 1], units[k], units[k - 1]);
    bool after = k + 1 < units.size() && spaced(units[k], units[k + 1], units[k + 1]);
    return before || after;
  }

  // Whether one space separates `p` and `u` on the same line. `ws`: the input had some.
  bool space(const std::vector<Unit>& units, size_t i, bool ws) const {
    const Unit& p = units[i - 1];
    const Unit& u = units[i];
    auto plain = [](const Unit& x, LexKind k) { return !x.verbatim && x.kind == k; };
    // `+#` / `-(*`: a sign glued to a comment stays glued (a space would make it binary).
    if (plain(u, LexKind::LineComment)) return ws || !plain(p, LexKind::Operator);
    if (plain(u, LexKind::BlockComment) || plain(p, LexKind::BlockComment)) return ws;
    if (plain(p, LexKind::LParen)) {
      // `( *` must not become the comment opener `(*`.
      return plain(u, LexKind::Operator) && text_[u.begin] == '*';
    }
    if (plain(u, LexKind::RParen)) return false;
    if (plain(p, LexKind::LBrace) || plain(u, LexKind::RBrace)) return false;
    if (plain(u, LexKind::Comma)) return false;
    if (plain(p, LexKind::Comma)) return true;
    if (plain(u, LexKind::LParen) && role(u) == Role::CallParen) return false;
    if (plain(p, LexKind::Operator) && role(p) == Role::Unary) {
      // Glue `- 2` to `-2`, except after a word glued to the sign: `1e- 1` must not become
      // the number `1e-1`.
      bool glued_to_word = !prev_started_line_ && i >= 2 && units[i - 2].end == p.begin &&
                           std::isalnum(static_cast<unsigned char>(text_[p.begin - 1])) != 0;
      return glued_to_word && ws;
    }
    for (size_t k : {i - 1, i}) {
      if (plain(units[k], LexKind::Operator) && role(units[k]) == Role::Binary) {
        return braces_ > 0 || op_has_space_around(units, k);
      }
    }
    return ws;
  }

  std::string_view text_;
  const Structure& s_;
  const FormatOptions& options_;
  std::string out_;
  int depth_ = 0;
  int line_level_ = 0;                // indentation level of the current line
  std::vector<int> bracket_levels_;   // per open bracket: the level of the line opening it
  int braces_ = 0;
  bool line_has_code_ = false;
  bool prev_started_line_ = false;  // the previous unit began its output line
  std::vector<bool> in_bank_;     // per open block: is it a bank
  int line_no_ = 0;               // output line of the current line (0-based)
  bool row_ok_ = false;           // the current line is still a table row
  std::vector<int> table_rows_;   // output lines that are bank table rows
};

// Tokens -> units: tokens inside a verbatim range become that one range.
std::vector<Unit> make_units(const std::vector<LexToken>& tokens,
                             std::vector<std::pair<uint32_t, uint32_t>> verbatim) {
  std::sort(verbatim.begin(), verbatim.end());
  std::vector<Unit> units;
  units.reserve(tokens.size());
  size_t v = 0;
  for (const LexToken& t : tokens) {
    while (v < verbatim.size() && verbatim[v].second <= t.begin) ++v;
    if (v < verbatim.size() && verbatim[v].first <= t.begin && t.end <= verbatim[v].second) {
      if (units.empty() || !units.back().verbatim || units.back().begin != verbatim[v].first) {
        units.push_back(Unit{LexKind::Raw, verbatim[v].first, verbatim[v].second, true});
      }
      continue;
    }
    bool whole = t.kind == LexKind::TclInit || t.kind == LexKind::String || t.kind == LexKind::Raw;
    units.push_back(Unit{t.kind, t.begin, t.end, whole});
  }
  return units;
}

// Resolves operator roles that the AST gives as positions between operands.
void resolve_roles(const std::vector<LexToken>& tokens, Structure& s) {
  auto first_at = [&](uint32_t offset) {
    return std::lower_bound(tokens.begin(), tokens.end(), offset,
                            [](const LexToken& t, uint32_t o) { return t.begin < o; });
  };
  for (auto [lo, hi] : s.binary_gaps) {
    for (auto it = first_at(lo); it != tokens.end() && it->begin < hi; ++it) {
      if (it->kind == LexKind::Operator) {
        s.roles[it->begin] = Role::Binary;
        break;
      }
    }
  }
  for (uint32_t name_end : s.call_names_end) {
    for (auto it = first_at(name_end); it != tokens.end(); ++it) {
      if (it->kind == LexKind::LParen) {
        s.roles[it->begin] = Role::CallParen;
        break;
      }
      if (it->kind != LexKind::LineComment && it->kind != LexKind::BlockComment) break;
    }
  }
}

std::vector<std::string> comments_of(std::string_view text, const std::vector<LexToken>& tokens) {
  std::vector<std::string> out;
  for (const LexToken& t : tokens) {
    if (t.kind == LexKind::LineComment || t.kind == LexKind::BlockComment) {
      std::string_view c = text.substr(t.begin, t.end - t.begin);
      while (!c.empty() && is_space(c.back())) c.remove_suffix(1);
      out.emplace_back(c);
    }
  }
  return out;
}

}  // namespace

FormatResult format_source(std::string_view input, const FormatOptions& options) {
  FormatResult result;
  // A leading byte order mark is kept as it is, in front of the formatted text.
  const std::string_view bom = input.substr(0, utf8_bom_length(input));
  input.remove_prefix(bom.size());
  // Line endings: work on LF; write CRLF back if the file's first line ends with CRLF.
  size_t first_nl = input.find('\n');
  bool crlf = first_nl != std::string_view::npos && first_nl > 0 && input[first_nl - 1] == '\r';
  std::string text;
  text.reserve(input.size());
  for (size_t i = 0; i < input.size(); ++i) {
    if (input[i] == '\r' && i + 1 < input.size() && input[i + 1] == '\n') continue;
    text += input[i];
  }

  Parsed original = parse_text(text);
  if (!original.error.empty()) {
    result.error = original.error;
    return result;
  }
  Structure structure;
  StructureBuilder(original.tree, text, structure).build();
  std::vector<LexToken> tokens = lex_file(text);
  resolve_roles(tokens, structure);
  std::vector<Unit> units = make_units(tokens, structure.verbatim);
  std::string formatted = Printer(text, structure, options).print(units);

  // Never change the meaning: the result must parse to the same AST, with the same comments.
  Parsed again = parse_text(formatted);
  if (!again.error.empty() || Fingerprint(original.tree).of_file() != Fingerprint(again.tree).of_file() ||
      comments_of(text, tokens) != comments_of(formatted, lex_file(formatted))) {
    result.error = "1:1: the formatter would change this file's meaning; it was left unchanged "
                   "(please report this file)";
    return result;
  }
  if (crlf) {
    std::string with_cr;
    with_cr.reserve(formatted.size() + formatted.size() / 16);
    for (char c : formatted) {
      if (c == '\n') with_cr += '\r';
      with_cr += c;
    }
    formatted = std::move(with_cr);
  }
  result.ok = true;
  result.text = std::string(bom) + formatted;
  return result;
}

}  // namespace nomec
