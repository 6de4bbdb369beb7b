// The NOME writer of `--emit nome` (see save.h): the source text with each moved slider's
// value token replaced. The backend has no syntax tree, so the value tokens are found in the
// text: a small scanner of NOME's tokens (comments, strings, brace groups and `tclinit`
// bodies skipped whole) for `set` values and `savedparameter` entries, and a small Tcl
// parser (words, braces, quotes, command substitution) for the calls SLIDE's sliders are
// made by.
#include "backend/save.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fmt/format.h>
#include <map>
#include <optional>
#include <vector>

namespace nomec::backend {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

/// The number a value token spells, if it is a plain number (`8`, `-0.5`, `+2`, `7.45e-009`).
std::optional<double> plain_number(std::string_view t) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  if (t.empty()) return std::nullopt;
  double v = 0;
  auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || p != t.data() + t.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// ---- NOME tokens -------------------------------------------------------------------------

enum class Tok : uint8_t { Word, Group, TclBody, Punct, End };

struct Token {
  Tok kind = Tok::End;
  uint32_t begin = 0, end = 0;
  uint32_t body_begin = 0, body_end = 0;  // TclBody: inside the braces
};

// The end of the brace group opening at `at` (just past its `}`), counting braces as Tcl
// does (a backslash escapes the next character), or `limit` when it is not closed.
uint32_t brace_end(std::string_view t, uint32_t at, uint32_t limit) {
  int depth = 0;
  for (uint32_t i = at; i < limit; ++i) {
    if (t[i] == '\\') {
      ++i;
    } else if (t[i] == '{') {
      ++depth;
    } else if (t[i] == '}' && --depth == 0) {
      return i + 1;
    }
  }
  return limit;
}

// Whitespace and comments (`# …`, nested `(* … *)`) from `at`.
uint32_t skip_blank(std::string_view t, uint32_t at) {
  while (at < t.size()) {
    if (is_space(t[at])) {
      ++at;
    } else if (t[at] == '#') {
      while (at < t.size() && t[at] != '\n') ++at;
    } else if (t[at] == '(' && at + 1 < t.size() && t[at + 1] == '*') {
      int depth = 0;
      while (at < t.size()) {
        if (t.compare(at, 2, "(*") == 0) {
          ++depth;
          at += 2;
        } else if (t.compare(at, 2, "*)") == 0) {
          at += 2;
          if (--depth == 0) break;
        } else {
          ++at;
        }
      }
    } else {
      break;
    }
  }
  return at;
}

bool ends_word(char c) {
  return is_space(c) || c == '(' || c == ')' || c == '{' || c == '}' || c == '[' || c == ']' || c == ',' || c == '"' ||
         c == '#';
}

// The token at `at` (after blanks): a word or number, a group (`( … )` is not one: its
// parentheses are punctuation; `{ … }`, `[ … ]`, `%{ … }%`, `"…"` are), or a whole
// `tclinit { … }` / `tclupdate { … }`.
Token next_token(std::string_view t, uint32_t at) {
  at = skip_blank(t, at);
  Token k;
  k.begin = at;
  const auto n = static_cast<uint32_t>(t.size());
  if (at >= n) {
    k.end = at;
    return k;
  }
  const char c = t[at];
  if (c == '{') {
    k.kind = Tok::Group;
    k.end = brace_end(t, at, n);
  } else if (c == '[') {
    k.kind = Tok::Group;
    const size_t close = t.find(']', at);
    k.end = close == std::string_view::npos ? n : static_cast<uint32_t>(close + 1);
  } else if (c == '%' && at + 1 < n && t[at + 1] == '{') {
    k.kind = Tok::Group;
    const size_t close = t.find("}%", at);
    k.end = close == std::string_view::npos ? n : static_cast<uint32_t>(close + 2);
  } else if (c == '"') {
    k.kind = Tok::Group;
    uint32_t i = at + 1;
    while (i < n && t[i] != '"' && t[i] != '\n') ++i;
    k.end = std::min(n, i + 1);
  } else if (c == '(' || c == ')' || c == ',' || c == '}' || c == ']') {
    k.kind = Tok::Punct;
    k.end = at + 1;
  } else {
    k.kind = Tok::Word;
    uint32_t i = at;
    while (i < n && !ends_word(t[i])) ++i;
    k.end = std::max(i, at + 1);
    const std::string_view w = t.substr(at, k.end - at);
    if (w == "tclinit" || w == "tclupdate") {
      const uint32_t open = skip_blank(t, k.end);
      if (open < n && t[open] == '{') {
        k.kind = Tok::TclBody;
        k.end = brace_end(t, open, n);
        k.body_begin = open + 1;
        k.body_end = std::max(k.body_begin, k.end - (k.end > open + 1 && t[k.end - 1] == '}' ? 1 : 0));
      }
    }
  }
  return k;
}

std::vector<Token> tokens_of(std::string_view t) {
  std::vector<Token> out;
  for (uint32_t at = 0;;) {
    Token k = next_token(t, at);
    if (k.kind == Tok::End) break;
    out.push_back(k);
    at = k.end;
  }
  return out;
}

// The value token after `at` (a `set` name's end): a word, a brace group, or a
// parenthesised expression as a whole.
Token value_token_after(std::string_view t, uint32_t at) {
  Token k = next_token(t, at);
  if (k.kind == Tok::Punct && t[k.begin] == '(') {
    int depth = 1;
    uint32_t i = k.end;
    while (i < t.size() && depth > 0) {
      Token inner = next_token(t, i);
      if (inner.kind == Tok::End) break;
      if (inner.kind == Tok::Punct && t[inner.begin] == '(') ++depth;
      if (inner.kind == Tok::Punct && t[inner.begin] == ')') --depth;
      i = inner.end;
    }
    k.kind = Tok::Group;
    k.end = i;
  }
  return k;
}

// ---- Tcl commands --------------------------------------------------------------------------

struct TclWord {
  uint32_t begin, end;
};
struct TclCommand {
  std::vector<TclWord> words;
  int depth = 0;  // 0: a command of the `tclinit` body itself
  size_t size() const { return words.size(); }
  const TclWord& operator[](size_t i) const { return words[i]; }
};

constexpr int kMaxTclDepth = 100;  // nesting a hostile file may use before the rest is skipped

uint32_t bracket_end(std::string_view t, uint32_t at, uint32_t limit);

bool tcl_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// Every command of the script in [b, e), and of the scripts nested in its braces and
// brackets (procedure bodies, `if` branches, `[CreateScale …]`), into `out`.
void tcl_commands(std::string_view t, uint32_t b, uint32_t e, std::vector<TclCommand>& out, int depth) {
  if (depth > kMaxTclDepth) return;
  uint32_t at = b;
  auto skip_continuation = [&](uint32_t& i) {
    while (i + 1 < e && t[i] == '\\' && t[i + 1] == '\n') i += 2;
  };
  while (at < e) {
    // A command's start: blanks, line breaks, `;`, backslash-newline.
    while (at < e && (is_space(t[at]) || t[at] == ';' || (t[at] == '\\' && at + 1 < e && t[at + 1] == '\n'))) {
      at += t[at] == '\\' ? 2 : 1;
    }
    if (at >= e) break;
    if (t[at] == '#') {  // a comment, continued by backslash-newline
      while (at < e && t[at] != '\n') at += t[at] == '\\' ? 2 : 1;
      continue;
    }
    TclCommand command;
    command.depth = depth;
    std::vector<TclWord>& words = command.words;
    while (at < e) {
      while (at < e && (tcl_blank(t[at]) || (t[at] == '\\' && at + 1 < e && t[at + 1] == '\n'))) {
        at += t[at] == '\\' ? 2 : 1;
      }
      if (at >= e || t[at] == '\n' || t[at] == ';') break;
      const uint32_t start = at;
      if (t[at] == '{') {
        at = std::min(e, brace_end(t, at, e));
        tcl_commands(t, start + 1, at > start + 1 ? at - 1 : at, out, depth + 1);
      } else if (t[at] == '"') {
        ++at;
        while (at < e && t[at] != '"') {
          if (t[at] == '\\') {
            at += 2;
          } else if (t[at] == '[') {
            const uint32_t close = bracket_end(t, at, e);
            tcl_commands(t, at + 1, close > at + 1 ? close - 1 : close, out, depth + 1);
            at = close;
          } else {
            ++at;
          }
        }
        at = std::min(e, at + 1);
      } else {
        while (at < e && !is_space(t[at]) && t[at] != ';') {
          if (t[at] == '\\') {
            at += 2;
          } else if (t[at] == '[') {
            const uint32_t close = bracket_end(t, at, e);
            tcl_commands(t, at + 1, close > at + 1 ? close - 1 : close, out, depth + 1);
            at = close;
          } else if (t[at] == '$' && at + 1 < e && t[at + 1] == '{') {
            const size_t close = t.find('}', at);
            at = close == std::string_view::npos || close >= e ? e : static_cast<uint32_t>(close + 1);
          } else {
            ++at;
          }
        }
        at = std::min(at, e);
      }
      skip_continuation(at);
      words.push_back(TclWord{start, at});
    }
    if (!words.empty()) out.push_back(std::move(command));
  }
}

// The end of the command substitution opening at `at` (just past its `]`).
uint32_t bracket_end(std::string_view t, uint32_t at, uint32_t limit) {
  int depth = 0;
  for (uint32_t i = at; i < limit; ++i) {
    if (t[i] == '\\') {
      ++i;
    } else if (t[i] == '{') {
      i = brace_end(t, i, limit) - 1;
    } else if (t[i] == '[') {
      ++depth;
    } else if (t[i] == ']' && --depth == 0) {
      return i + 1;
    }
  }
  return limit;
}

// A word with no substitution, quoting or escape: its text is its value.
bool is_literal(std::string_view w) {
  return !w.empty() && w.find_first_of("$[]{}\"\\") == std::string_view::npos;
}

// ---- where each slider's value is written ---------------------------------------------------

struct Site {
  int32_t file = -1;
  uint32_t begin = 0, end = 0;
};

// The Tcl variables a slider `bank.name` may be: `bank_name` (SLIDEUI's CreateScale),
// `bank(name)` (an array element), `name` (a plain variable: bank and name alike).
std::vector<std::string> tcl_variables(const std::string& bank, const std::string& name) {
  std::vector<std::string> v = {bank + "_" + name, bank + "(" + name + ")"};
  if (bank == name) v.push_back(name);
  return v;
}

bool ends_with(std::string_view s, std::string_view tail) {
  return s.size() > tail.size() && s.substr(s.size() - tail.size()) == tail;
}

// How surely a Tcl command writes a slider's value: the best kind found wins, the last
// of that kind in the text when there are several.
enum class Match : uint8_t { None, Suffix, Substituted, Exact };

struct TclSite {
  Match match = Match::None;
  Site site;
  bool is_number = false;
};

// Which of `vars` the Tcl word `word` names, and how surely: a literal (`x0`, `par_q0x`,
// `prm(v0)`, `::x0`) exactly; a substitution followed by an array element or the rest of a
// name (`[subst $this](v0)`, `${name}_x`) by that tail. The index of the variable, or -1.
std::pair<Match, int> names_variable(std::string_view word, const std::vector<std::string>& vars) {
  if (word.substr(0, 2) == "::") word.remove_prefix(2);
  if (word.empty()) return {Match::None, -1};
  if (is_literal(word)) {
    for (size_t i = 0; i < vars.size(); ++i) {
      if (vars[i] == word) return {Match::Exact, static_cast<int>(i)};
    }
    return {Match::None, -1};
  }
  uint32_t prefix = 0;
  if (word[0] == '[') prefix = bracket_end(word, 0, static_cast<uint32_t>(word.size()));
  if (word.substr(0, 2) == "${") prefix = static_cast<uint32_t>(std::min(word.size(), word.find('}') + 1));
  const std::string_view tail = word.substr(std::min<size_t>(prefix, word.size()));
  if (prefix == 0 || tail.size() < 2 || (tail[0] != '(' && tail[0] != '_') || !is_literal(tail)) return {Match::None, -1};
  for (size_t i = 0; i < vars.size(); ++i) {
    if (ends_with(vars[i], tail)) return {Match::Substituted, static_cast<int>(i)};
  }
  return {Match::None, -1};
}

// The value the command `w` gives the slider whose variables are `vars` (short name `name`).
void match_tcl_command(std::string_view t, int32_t file, const TclCommand& w, const std::vector<std::string>& vars,
                       const std::string& name, TclSite& best) {
  auto text = [&](size_t i) { return t.substr(w[i].begin, w[i].end - w[i].begin); };
  std::string_view cmd = text(0);
  if (cmd.substr(0, 2) == "::") cmd.remove_prefix(2);
  auto consider = [&](Match m, size_t value_word) {
    if (m < best.match) return;
    best.match = m;
    best.site = Site{file, w[value_word].begin, w[value_word].end};
    best.is_number = plain_number(text(value_word)).has_value();
  };
  // A scale made from a NAME and a THIS (variable `NAME_THIS`) with a default value.
  auto scale_call = [&](size_t name_word, size_t this_word, size_t value_word) {
    const std::string_view owner = text(name_word), self = text(this_word);
    if (!is_literal(self)) return;
    const std::string var = std::string(owner) + "_" + std::string(self);
    if (is_literal(owner)) {
      if (std::find(vars.begin(), vars.end(), var) != vars.end()) consider(Match::Exact, value_word);
    } else if (self == name) {
      consider(Match::Substituted, value_word);
    } else if (ends_with(vars.front(), "_" + std::string(self))) {
      consider(Match::Suffix, value_word);
    }
  };
  if ((cmd == "CreateScale" || cmd == "CreateScaleCmd" || cmd == "CreateScaleL") && w.size() >= 10) {
    // SLIDEUI.tcl: NAME PARENT THIS TEXT DEFAULT MIN MAX RESOLUTION TICKINTS ORIENT [CMD|LENGTH].
    scale_call(1, 3, 5);
  } else if (cmd == "CreateDoubleScale" && w.size() >= 14) {
    // NAME PARENT THIS THIS_A THIS_B TEXT_A TEXT_B MIN DEFAULT_A DEFAULT_B MAX RES TICKINTS ORIENT.
    scale_call(1, 4, 9);
    scale_call(1, 5, 10);
  } else if (cmd == "set" && w.size() == 3) {
    const auto [m, index] = names_variable(text(1), vars);
    if (m != Match::None) consider(m, 2);
  }
}

// A `savedparameter` entry: the slider it names as written and its value token.
struct SavedEntry {
  std::string_view name;
  Site value;
};

bool is_tcl_name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// Whether `text` holds `word` as a whole Tcl name (not inside a longer one).
bool mentions(std::string_view text, std::string_view word) {
  for (size_t at = text.find(word); at != std::string_view::npos; at = text.find(word, at + 1)) {
    const bool starts = at == 0 || !is_tcl_name_char(text[at - 1]);
    const bool ends = at + word.size() >= text.size() || !is_tcl_name_char(text[at + word.size()]);
    if (starts && ends) return true;
  }
  return false;
}

// Which of a slider's possible variables `vars` the file uses, when no command of it writes
// the slider's value: the variable a `scale -variable` or slideui's `CreateScale PARENT THIS
// VAR …` names, else the one the file reads (`{expr $oSubdivision(subdivisions)}`). -1: none.
int variable_used(std::string_view text, const std::vector<TclCommand>& commands, const std::vector<std::string>& vars) {
  for (const TclCommand& c : commands) {
    auto word = [&](size_t i) { return text.substr(c[i].begin, c[i].end - c[i].begin); };
    std::string_view cmd = word(0);
    if (cmd.substr(0, 2) == "::") cmd.remove_prefix(2);
    if (cmd == "scale") {
      for (size_t i = 2; i + 1 < c.size(); ++i) {
        if (word(i) != "-variable" && word(i) != "-var") continue;
        if (const int v = names_variable(word(i + 1), vars).second; v >= 0) return v;
      }
    } else if (cmd == "CreateScale" && (c.size() == 8 || c.size() == 9)) {  // slideui: PARENT THIS VAR …
      if (const int v = names_variable(word(3), vars).second; v >= 0) return v;
    }
  }
  for (size_t i = 0; i < vars.size(); ++i) {
    const std::string& v = vars[i];
    const size_t open = v.find('(');
    const std::vector<std::string> reads =
        open == std::string::npos ? std::vector<std::string>{"$" + v, "${" + v + "}"}
                                  : std::vector<std::string>{"$" + v, "${" + v.substr(0, open) + "}" + v.substr(open)};
    for (const std::string& r : reads) {
      for (size_t at = text.find(r); at != std::string_view::npos; at = text.find(r, at + 1)) {
        const size_t after = at + r.size();
        // `$par_n` is not a read of `$par`; `$x(…)` is an element of `x`, not `x` itself.
        if (r.back() == '}' || r.back() == ')' ||
            (after >= text.size() || (!is_tcl_name_char(text[after]) && text[after] != '('))) {
          return static_cast<int>(i);
        }
      }
    }
  }
  return -1;
}

}  // namespace

std::vector<std::string> lost_values(const ir::Module& module, const SavedScene& saved, const ir::Module& saved_module) {
  std::map<std::string, double, std::less<>> values;
  for (ir::NodeId id : saved_module.params()) values[saved_module.node(id).name] = saved_module.param(id).value;
  std::map<ir::NodeId, std::string> reasons;
  for (const UnsavedSlider& u : saved.unsaved) reasons[u.param] = u.reason;
  std::vector<std::string> lines;
  for (ir::NodeId id : module.params()) {
    const ir::Node& p = module.node(id);
    const ir::ParamData& d = module.param(id);
    const auto got = values.find(p.name);
    if (got != values.end() && std::fabs(got->second - d.value) <= std::max(d.step, 0.0) * 1e-6) continue;
    const auto why = reasons.find(id);
    lines.push_back(fmt::format("slider `{}` = {} cannot be saved: {}", p.name, slider_value_text(d.value, d.step),
                                why != reasons.end()    ? why->second
                                : got == values.end()   ? std::string("the saved file has no such slider")
                                                        : fmt::format("the saved file gives it {}", got->second)));
  }
  return lines;
}

std::string slider_value_text(double value, double step) {
  if (!std::isfinite(value)) return fmt::format("{}", value);
  const double tolerance = step > 0 && std::isfinite(step) ? step * 1e-6 : 0;
  for (int decimals = 0; decimals <= 17; ++decimals) {
    std::string s = fmt::format("{:.{}f}", value, decimals);
    if (std::fabs(std::strtod(s.c_str(), nullptr) - value) <= tolerance) {
      if (s.find_first_not_of("-0.") == std::string::npos) return "0";  // not `-0`
      return s;
    }
  }
  return fmt::format("{}", value);
}

namespace {

// A flat mesh file's scene as NOME: its vertices as points `v0, v1, …` (global, as NOME
// 2016's saved work names them), one mesh of its faces, instanced once.
std::string flat_scene_text(const ir::Node& n) {
  const ir::FlatMeshData& d = n.as<ir::FlatMeshData>();
  std::string out = fmt::format("# The mesh of `{}`, written out as NOME.\n", n.name);
  if (d.geometry == nullptr) return out;
  const ir::FlatGeometry& g = *d.geometry;
  for (size_t k = 0; k < g.positions.size(); ++k) {
    out += fmt::format("point v{} ({} {} {}) endpoint\n", k, g.positions[k][0], g.positions[k][1], g.positions[k][2]);
  }
  out += fmt::format("mesh {}\n", n.name);
  for (int32_t f = 0; f < g.face_count(); ++f) {
    out += fmt::format("    face f{} (", f);
    for (int32_t i = g.face_starts[static_cast<size_t>(f)]; i < g.face_starts[static_cast<size_t>(f) + 1]; ++i) {
      out += fmt::format("{}v{}", i == g.face_starts[static_cast<size_t>(f)] ? "" : " ", g.corners[static_cast<size_t>(i)]);
    }
    out += ") endface\n";
  }
  out += fmt::format("endmesh\ninstance {} {} endinstance\n", n.name, n.name);
  return out;
}

constexpr std::string_view kHeader = "# Saved by nomec --emit nome";

}  // namespace

SavedScene save_scene(const ir::Module& module, const ir::Module& as_written, const SourceManager& sources,
                      std::string_view main_file, std::string_view base_file) {
  SavedScene saved;
  // The files written: the base scene first, the compiled file last. Included files stay
  // included, so a slider's value in one of them has no place in the saved text.
  std::vector<FileId> files;
  FileId main;
  for (size_t i = 0; i < sources.file_count(); ++i) {
    const FileId f{static_cast<int32_t>(i)};
    if (sources.name(f) == main_file && !main.is_valid()) main = f;
  }
  for (size_t i = 0; i < sources.file_count() && !base_file.empty(); ++i) {
    const FileId f{static_cast<int32_t>(i)};
    if (f != main && sources.name(f) == base_file) {
      files.push_back(f);
      break;
    }
  }
  if (main.is_valid()) files.push_back(main);

  // Each written file's tokens, its `savedparameter` entries and its Tcl commands.
  struct Scanned {
    std::vector<Token> tokens;
    std::vector<SavedEntry> saved;
    std::vector<TclCommand> tcl;
    std::vector<Token> tcl_blocks;  // `tclinit { … }` and `tclupdate { … }`, keyword included
  };
  std::map<int32_t, Scanned> scanned;
  for (FileId f : files) {
    Scanned& s = scanned[f.index];
    const std::string_view text = sources.text(f);
    s.tokens = tokens_of(text);
    for (size_t i = 0; i < s.tokens.size(); ++i) {
      const Token& k = s.tokens[i];
      auto word = [&](size_t j) { return text.substr(s.tokens[j].begin, s.tokens[j].end - s.tokens[j].begin); };
      if (k.kind == Tok::TclBody) {
        tcl_commands(text, k.body_begin, k.body_end, s.tcl, 0);
        s.tcl_blocks.push_back(k);
      }
      if (k.kind != Tok::Word || word(i) != "savedparameter") continue;
      for (++i; i < s.tokens.size() && !(s.tokens[i].kind == Tok::Word && word(i) == "endsavedparameter"); ++i) {
        if (s.tokens[i].kind != Tok::Word || i + 1 >= s.tokens.size()) continue;
        const Token value = value_token_after(text, s.tokens[i].end);
        s.saved.push_back(SavedEntry{word(i), Site{f.index, value.begin, value.end}});
        while (i + 1 < s.tokens.size() && s.tokens[i + 1].begin < value.end) ++i;
      }
    }
  }

  // The `savedparameter` entry that sets each slider: the last one naming it (`bank_param`
  // or `bank.param`; for `a_b_c`, the slider of the longest bank, as the checker reads it).
  const std::vector<ir::NodeId> params = module.params();
  std::map<std::string, ir::NodeId, std::less<>> by_written_name;
  for (ir::NodeId id : params) {
    const ir::Node& p = module.node(id);
    const ir::ParamData& d = module.param(id);
    by_written_name.emplace(p.name, id);
    const std::string flat = p.name.size() > d.bank.size() ? d.bank + "_" + p.name.substr(d.bank.size() + 1) : p.name;
    auto [it, added] = by_written_name.emplace(flat, id);
    if (!added && module.param(it->second).bank.size() < d.bank.size()) it->second = id;
  }
  std::map<ir::NodeId, Site> saved_entry;
  for (FileId f : files) {
    for (const SavedEntry& e : scanned[f.index].saved) {
      if (auto it = by_written_name.find(e.name); it != by_written_name.end()) saved_entry[it->second] = e.value;
    }
  }

  // The sliders moved away from their value as written: only they are written.
  std::map<std::string, double, std::less<>> written_values;
  for (ir::NodeId id : as_written.params()) written_values[as_written.node(id).name] = as_written.param(id).value;
  auto is_moved = [&](ir::NodeId id) {
    const ir::ParamData& d = module.param(id);
    const auto w = written_values.find(module.node(id).name);
    return w == written_values.end() || std::fabs(w->second - d.value) > std::max(d.step, 0.0) * 1e-6;
  };

  struct Edit {
    uint32_t begin, end;
    std::string text;
  };
  std::map<int32_t, std::vector<Edit>> edits;
  for (ir::NodeId id : params) {
    if (!is_moved(id)) continue;
    const ir::Node& p = module.node(id);
    const ir::ParamData& d = module.param(id);
    const std::string value_text = slider_value_text(d.value, d.step);
    std::optional<Site> site;
    std::string why;
    const bool in_written_file = p.range.is_valid() && scanned.contains(p.range.file.index);
    bool in_tcl = false;
    if (in_written_file) {
      for (const Token& k : scanned[p.range.file.index].tcl_blocks) {
        in_tcl = in_tcl || (p.range.begin >= k.begin && p.range.end <= k.end);
      }
    }
    if (auto e = saved_entry.find(id); e != saved_entry.end()) {
      site = e->second;
    } else if (in_tcl || (module.dialect == Dialect::Slide && !p.range.is_valid())) {
      // A SLIDE slider: the short name (`q0x` of `par.q0x`) and the variables it may be.
      const std::string name = p.name.size() > d.bank.size() ? p.name.substr(d.bank.size() + 1) : p.name;
      const std::vector<std::string> vars = tcl_variables(d.bank, name);
      TclSite best;
      for (FileId f : files) {
        for (const TclCommand& c : scanned[f.index].tcl) match_tcl_command(sources.text(f), f.index, c, vars, name, best);
      }
      if (best.match != Match::None && best.is_number) {
        site = best.site;
      } else if (best.match != Match::None) {
        why = fmt::format("its value is an expression in `{}`, not a number", sources.name(FileId{best.site.file}));
      } else {
        // Made by a procedure of another file (SLIDE's `CreateSLIDESubdivisionUI …`): the
        // value is set just before the last command of a `tclinit` block that names the
        // slider's bank (the one that makes it, after the object that holds its default).
        const FileId last = files.back();
        const std::string_view text = sources.text(last);
        const int v = variable_used(text, scanned[last.index].tcl, vars);
        const TclCommand* maker = nullptr;
        for (const TclCommand& c : scanned[last.index].tcl) {
          if (c.depth == 0 && mentions(text.substr(c[0].begin, c.words.back().end - c[0].begin), d.bank)) maker = &c;
        }
        if (v >= 0 && maker != nullptr) {
          const uint32_t at = maker->words.front().begin;
          uint32_t line = at;
          while (line > 0 && (text[line - 1] == ' ' || text[line - 1] == '\t')) --line;
          const bool own_line = line == 0 || text[line - 1] == '\n';
          const std::string indent(text.substr(line, at - line));
          edits[last.index].push_back(Edit{at, at, fmt::format("set {} {}{}", vars[static_cast<size_t>(v)], value_text,
                                                               own_line ? "\n" + indent : "; ")});
          continue;
        }
        why = fmt::format("its value is not written in `{}` (a Tcl procedure of another file sets it){}", main_file,
                          v < 0 ? ", and the file does not read it" : "");
      }
    } else if (in_written_file) {
      // `set NAME value min max step`: the value is the token after the name.
      const Token k = value_token_after(sources.text(p.range.file), p.range.end);
      if (k.kind != Tok::End) site = Site{p.range.file.index, k.begin, k.end};
    } else {
      why = p.range.is_valid() ? fmt::format("it is defined in the included file `{}`", sources.name(p.range.file))
                               : "it is not defined in the file";
    }
    if (!site) {
      saved.unsaved.push_back(UnsavedSlider{id, why.empty() ? "its value has no place in the file" : why});
      continue;
    }
    const std::string_view written = sources.text(FileId{site->file}).substr(site->begin, site->end - site->begin);
    const std::optional<double> now = plain_number(written);
    if (now && std::fabs(*now - d.value) <= std::max(d.step, 0.0) * 1e-6) continue;  // already spelt: keep it
    edits[site->file].push_back(Edit{site->begin, site->end, value_text});
  }

  // Flat mesh files: the scene's is written as NOME; an included one stays included.
  std::map<int32_t, const ir::Node*> flat_files;
  for (const ir::Node& n : module.nodes) {
    if (n.kind == ir::NodeKind::FlatMesh && n.range.is_valid()) flat_files[n.range.file.index] = &n;
  }
  std::string& out = saved.text;
  out = fmt::format("{} from `{}`{}: sliders at their current values.\n", kHeader, main_file,
                    files.size() > 1 ? " and its base scene" : "");
  for (FileId f : files) {
    if (files.size() > 1) out += fmt::format("\n# ---- from `{}` ----\n", sources.name(f));
    if (auto flat = flat_files.find(f.index); flat != flat_files.end()) {
      if (flat->second->as<ir::FlatMeshData>().is_scene) out += flat_scene_text(*flat->second);
      continue;  // (an included mesh stays included)
    }
    std::string_view text = sources.text(f);
    std::vector<Edit>& es = edits[f.index];
    std::stable_sort(es.begin(), es.end(), [](const Edit& a, const Edit& b) { return a.begin < b.begin; });
    uint32_t at = 0;
    // A file saved before starts with our header line: the new one replaces it.
    if (text.substr(0, kHeader.size()) == kHeader) {
      const size_t eol = text.find('\n');
      at = eol == std::string_view::npos ? static_cast<uint32_t>(text.size()) : static_cast<uint32_t>(eol + 1);
    }
    for (const Edit& e : es) {
      // Two sliders on one token cannot happen in a checked file; insertions at one place
      // (sliders made by one command) all go in, in order.
      if (e.begin < at) continue;
      out.append(text.substr(at, e.begin - at));
      out += e.text;
      at = e.end;
    }
    out.append(text.substr(at));
    if (f != files.back() && !out.empty() && out.back() != '\n') out += '\n';  // before the next file's
  }
  return saved;
}

}  // namespace nomec::backend
