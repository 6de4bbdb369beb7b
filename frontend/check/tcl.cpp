// SLIDE's Tcl (see handlers.h, slide.md §2, §6, §7): after the whole file is parsed, its
// `tclinit` blocks run in file order in the scene's own interpreter (frontend/tcl), then its
// `tclupdate` blocks once; every Tk `scale` bound to a variable becomes a slider (a
// parameter like a bank entry); Tcl's problems become diagnostics at the line they happened
// on; and `{expr …}` values are evaluated by Tcl's `expr`, reading sliders as parameters.
#include <cmath>
#include <fmt/format.h>

#include "frontend/check/handlers.h"
#include "frontend/flat/flat.h"
#include "frontend/parse/parse.h"

namespace nomec::check {

namespace {

// The body of a `tclinit { … }` item: its offset in the file and its text (inside the braces).
struct TclBody {
  uint32_t begin = 0;
  std::string_view text;
  bool update = false;  // `tclupdate`
  SourceRange keyword;
};

TclBody body_of(const ast::Item& it) {
  TclBody b;
  const size_t open = it.text.find('{');
  const size_t close = it.text.rfind('}');
  b.update = it.text.rfind("tclupdate", 0) == 0;
  const size_t kw_len = b.update ? 9 : 7;
  b.keyword = SourceRange{it.range.file, it.range.begin, static_cast<uint32_t>(it.range.begin + kw_len)};
  if (open == std::string_view::npos || close == std::string_view::npos || close <= open) return b;
  b.begin = static_cast<uint32_t>(it.range.begin + open + 1);
  b.text = it.text.substr(open + 1, close - open - 1);
  return b;
}

// The range of line `line` (1-based) of a script that starts at `begin` in the file, without
// its leading blanks; the whole `fallback` when the line is unknown.
SourceRange line_range(FileId file, uint32_t begin, std::string_view text, int line, SourceRange fallback) {
  if (line <= 0) return fallback;
  size_t at = 0;
  for (int l = 1; l < line; ++l) {
    size_t nl = text.find('\n', at);
    if (nl == std::string_view::npos) return fallback;
    at = nl + 1;
  }
  size_t end = text.find('\n', at);
  if (end == std::string_view::npos) end = text.size();
  while (at < end && (text[at] == ' ' || text[at] == '\t')) ++at;
  while (end > at && (text[end - 1] == '\r' || text[end - 1] == ' ' || text[end - 1] == '\t')) --end;
  if (end <= at) return fallback;
  return SourceRange{file, static_cast<uint32_t>(begin + at), static_cast<uint32_t>(begin + end)};
}

// The first line of Tcl's errorInfo trace that names a procedure or a sourced file, as a note.
std::string trace_note(const std::string& trace) {
  std::string out;
  size_t at = 0;
  while (at < trace.size()) {
    size_t nl = trace.find('\n', at);
    std::string_view line = std::string_view(trace).substr(at, nl == std::string::npos ? std::string::npos : nl - at);
    if (line.find("(procedure") != std::string_view::npos || line.find("(file") != std::string_view::npos) {
      while (!line.empty() && line.front() == ' ') line.remove_prefix(1);
      if (!out.empty()) out += "; ";
      out += line;
    }
    if (nl == std::string::npos) break;
    at = nl + 1;
  }
  return out;
}

// The body of `proc NAME ARGS {BODY}` in one of the scene's Tcl blocks: the offset of the
// text after its `{` and that text; nullopt when the scene does not spell it.
std::optional<std::pair<uint32_t, std::string_view>> proc_body(std::string_view block, std::string_view name) {
  auto word_char = [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == ':'; };
  auto skip_blanks = [&](size_t i) {
    while (i < block.size() && (block[i] == ' ' || block[i] == '\t' || block[i] == '\\' || block[i] == '\n')) ++i;
    return i;
  };
  auto skip_word = [&](size_t i) {  // a braced or bare word
    if (i < block.size() && block[i] == '{') {
      for (int depth = 0; i < block.size(); ++i) {
        if (block[i] == '{') ++depth;
        if (block[i] == '}' && --depth == 0) return i + 1;
      }
      return i;
    }
    while (i < block.size() && !std::isspace(static_cast<unsigned char>(block[i]))) ++i;
    return i;
  };
  for (size_t at = block.find("proc"); at != std::string_view::npos; at = block.find("proc", at + 4)) {
    if ((at > 0 && word_char(block[at - 1])) || at + 4 >= block.size() || !std::isspace(static_cast<unsigned char>(block[at + 4]))) continue;
    size_t n = skip_blanks(at + 4);
    size_t e = skip_word(n);
    std::string_view written = block.substr(n, e - n);
    while (written.substr(0, 2) == "::") written.remove_prefix(2);
    if (written != name) continue;
    size_t body = skip_blanks(skip_word(skip_blanks(e)));
    if (body >= block.size() || block[body] != '{') continue;
    size_t end = skip_word(body);
    if (end <= body + 1) continue;
    return std::make_pair(static_cast<uint32_t>(body + 1), block.substr(body + 1, end - body - 2));
  }
  return std::nullopt;
}

// Where Tcl stopped inside a procedure the scene defines: errorInfo's innermost
// `(procedure "NAME" line N)` mapped to line N of NAME's body in the file.
std::optional<SourceRange> proc_error_range(Context& c, const std::string& trace) {
  static const std::string kTag = "(procedure \"";
  const size_t at = trace.find(kTag);
  if (at == std::string::npos) return std::nullopt;
  const size_t name_begin = at + kTag.size();
  const size_t name_end = trace.find('"', name_begin);
  if (name_end == std::string::npos) return std::nullopt;
  std::string_view name = std::string_view(trace).substr(name_begin, name_end - name_begin);
  while (name.substr(0, 2) == "::") name.remove_prefix(2);
  const size_t line_at = trace.find("line ", name_end);
  if (line_at == std::string::npos) return std::nullopt;
  const int line = std::atoi(trace.c_str() + line_at + 5);
  for (const SourceRange& block : c.tcl_blocks) {
    std::string_view text = c.sources().text(block);
    if (auto body = proc_body(text, name)) {
      SourceRange fallback{block.file, block.begin + body->first, block.begin + body->first};
      SourceRange r = line_range(block.file, block.begin + body->first, body->second, line, fallback);
      if (r.begin != r.end) return r;
    }
  }
  return std::nullopt;
}

void report(Context& c, const tcl::Problem& p, SourceRange where, std::string_view what) {
  if (std::optional<SourceRange> inside = proc_error_range(c, p.trace)) where = *inside;
  const std::string_view subject = what.empty() ? std::string_view("the scene's Tcl") : what;
  switch (p.kind) {
    case tcl::ProblemKind::Error: {
      auto d = c.diags().emit(DiagKind::TclError, where, fmt::format("Tcl error in {}: {}", what, p.message));
      if (std::string n = trace_note(p.trace); !n.empty()) d.note(where, fmt::format("Tcl's trace: {}", n));
      return;
    }
    case tcl::ProblemKind::Limit:
      c.tcl_stop_reported = true;
      c.diags()
          .emit(DiagKind::TclLimit, where,
                fmt::format("{} was stopped: {}{}", subject, p.message,
                            p.message.ends_with("limit exceeded") ? " (a loop that never ends?)" : ""))
          .note(where, fmt::format("nomec stops a scene's Tcl script after 1 million commands, and all of a file's "
                                   "Tcl after {} s in all (`--tcl-seconds` gives it more)",
                                   c.options().tcl_milliseconds / 1000.0));
      return;
    case tcl::ProblemKind::Crashed:
    case tcl::ProblemKind::Stopped:
      // What stopped the scene's Tcl is reported once, where it happened; the blocks and
      // values after it are not run and say nothing more, so the file does not fill with
      // one message per value.
      if (p.kind == tcl::ProblemKind::Stopped && c.tcl_stop_reported) return;
      c.tcl_stop_reported = true;
      c.diags()
          .emit(DiagKind::TclCrashed, where,
                fmt::format("{} was {}: {}", subject, p.kind == tcl::ProblemKind::Crashed ? "stopped" : "not run",
                            p.message))
          .note(where, "nomec runs a scene's Tcl in a process of its own: only the scene's Tcl stopped, and nomec "
                       "runs none of it after this (the values it would have computed are errors)");
      return;
    case tcl::ProblemKind::Unavailable:
      c.tcl_stop_reported = true;
      c.diags().emit(DiagKind::TclUnavailable, where, p.message);
      return;
    case tcl::ProblemKind::Refused:
      c.diags().emit(DiagKind::TclRefused, where, p.message);
      return;
    case tcl::ProblemKind::Memory:
      c.diags()
          .emit(DiagKind::TclMemory, where, fmt::format("{} was stopped: {}", subject, p.message))
          .note(where, "a scene is code; nomec bounds the values and memory its Tcl may use so that no scene can exhaust them");
      return;
    case tcl::ProblemKind::MissingSource:
      c.diags().emit(DiagKind::TclSourceMissing, where, fmt::format("{}: {}", what, p.message));
      return;
    case tcl::ProblemKind::Fallback:
      c.diags().emit(DiagKind::TclFallback, where, p.message);
      return;
  }
}

// `swp_q0x` → bank `swp`, slider `q0x`; `oSubdivision(subdivisions)` → `oSubdivision`,
// `subdivisions`; a name without `_` is its own bank.
std::pair<std::string, std::string> slider_key(const std::string& var) {
  if (size_t open = var.find('('); open != std::string::npos && var.back() == ')') {
    return {var.substr(0, open), var.substr(open + 1, var.size() - open - 2)};
  }
  if (size_t u = var.find('_'); u != std::string::npos && u > 0 && u + 1 < var.size()) {
    return {var.substr(0, u), var.substr(u + 1)};
  }
  return {var, var};
}

// Where a slider is defined: the first `tclinit` word naming its variable's slider part
// (`q0x` in `CreateScale swp $root q0x …`), else the block's keyword.
SourceRange slider_range(const std::vector<TclBody>& bodies, const std::string& short_name, SourceRange fallback) {
  for (const TclBody& b : bodies) {
    size_t at = 0;
    while ((at = b.text.find(short_name, at)) != std::string_view::npos) {
      auto word_char = [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; };
      const bool starts = at == 0 || !word_char(b.text[at - 1]);
      const bool ends = at + short_name.size() >= b.text.size() || !word_char(b.text[at + short_name.size()]);
      if (starts && ends) {
        return SourceRange{b.keyword.file, static_cast<uint32_t>(b.begin + at),
                           static_cast<uint32_t>(b.begin + at + short_name.size())};
      }
      at += short_name.size();
    }
  }
  return fallback;
}

void make_sliders(Context& c, const std::vector<TclBody>& bodies) {
  for (const tcl::Slider& s : c.tcl->sliders()) {
    auto [bank, name] = slider_key(s.variable);
    std::string key = bank + "." + name;
    if (c.params.contains(key)) continue;
    // The slider's own name where the file spells it, else its bank's (the call of a helper
    // that made it: `CreateSLIDESubdivisionUI $w oSubdivision`), else the first block.
    SourceRange at = slider_range(bodies, name, slider_range(bodies, bank, bodies.empty() ? SourceRange{} : bodies.front().keyword));
    ir::NodeId id = c.module().add_node(ir::NodeKind::Param, "scale", key, at);
    ir::ParamData& p = c.module().param(id);
    p.bank = bank;
    p.value = s.value;
    p.min = std::min(s.from, s.to);
    p.max = std::max(s.from, s.to);
    p.step = s.resolution > 0 ? s.resolution : 0;
    c.params[key] = id;
    c.tcl_sliders[s.variable] = id;
    if (!c.banks.contains(bank)) c.banks[bank] = at;
    c.tcl->watch(s.variable);
  }
  c.param_text_memo.clear();
}

// A `-D` value for a Tcl variable that is about to become a slider (set before the rest of
// `tclinit` reads it), when it is within the slider's range or out-of-range values are allowed.
std::optional<double> preset_for(const CheckOptions& o, const std::string& var, double from, double to) {
  auto [bank, name] = slider_key(var);
  const std::string dotted = bank + "." + name;
  for (auto it = o.overrides.rbegin(); it != o.overrides.rend(); ++it) {
    if (it->first != dotted && it->first != var && it->first != bank + "_" + name) continue;
    if (!o.allow_out_of_range && (it->second < std::min(from, to) || it->second > std::max(from, to))) return std::nullopt;
    return it->second;
  }
  return std::nullopt;
}

// One element of a Tcl list (`{expr $r * cos(0.3)}` → `expr $r * cos(0.3)`), split the way
// Tcl's own `list` quoting writes them: words separated by blanks, braces grouping.
std::vector<std::string> tcl_list(std::string_view s) {
  std::vector<std::string> out;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    if (i >= s.size()) break;
    if (s[i] == '{') {
      size_t depth = 0, j = i;
      for (; j < s.size(); ++j) {
        if (s[j] == '{') ++depth;
        if (s[j] == '}' && --depth == 0) break;
      }
      out.emplace_back(s.substr(i + 1, j - i - 1));
      i = j + 1;
      continue;
    }
    size_t j = i;
    while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j]))) ++j;
    out.emplace_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

// A word SLIDE reads as a name (`pRandomCloud3`, `sRed`).
bool is_slide_name(std::string_view v) {
  return !v.empty() && (std::isalpha(static_cast<unsigned char>(v[0])) || v[0] == '_') &&
         std::all_of(v.begin(), v.end(), [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; });
}

// The point names of `slide create convexhull NAME POINTS…` (one list or several words),
// and the first element that is not a name, if any.
std::pair<std::vector<std::string>, std::string> hull_points(const std::vector<std::string>& w) {
  std::pair<std::vector<std::string>, std::string> out;
  for (size_t i = 3; i < w.size() && (w[i].empty() || w[i][0] != '-'); ++i) {
    for (const std::string& v : tcl_list(w[i])) {
      if (is_slide_name(v)) out.first.push_back(v);
      else if (out.second.empty()) out.second = v;
    }
  }
  return out;
}

// A coordinate as SLIDE text: a number stays, a script becomes a `{…}` value.
std::string slide_value(const std::string& v) {
  if (is_slide_name(v)) return v;  // a name (`-surface sRed`)
  char* end = nullptr;
  std::strtod(v.c_str(), &end);
  if (!v.empty() && end != nullptr && *end == '\0') return v;
  if (v.rfind("expr", 0) == 0) return "{" + v + "}";
  return "{expr " + v + "}";
}

// `-xforms { {rotate (0 0 1) 45} {translate (1 0 0)} }` as SLIDE transforms.
std::string slide_xforms(const std::string& list) {
  std::string out;
  for (const std::string& x : tcl_list(list)) {
    const size_t open = x.find('('), close = x.find(')');
    if (open == std::string::npos || close == std::string::npos || close < open) continue;
    std::string head = x.substr(0, open), axis = x.substr(open, close - open + 1), rest = x.substr(close + 1);
    while (!rest.empty() && std::isspace(static_cast<unsigned char>(rest.front()))) rest.erase(0, 1);
    out += " " + head + axis;
    if (!rest.empty()) out += rest.front() == '(' ? " " + rest : " (" + slide_value(rest) + ")";
  }
  return out;
}

// The options after the positional arguments (`-surface sRed`) as SLIDE fields.
std::string slide_fields(const std::vector<std::string>& w, size_t from) {
  std::string out;
  for (size_t i = from; i + 1 < w.size(); i += 2) {
    if (w[i].empty() || w[i][0] != '-') continue;
    const std::string field = w[i].substr(1);
    if (field == "xforms") continue;
    const std::vector<std::string> parts = tcl_list(w[i + 1]);
    if (field == "pointlist" || field == "controlpointlist" || parts.size() > 1) {
      out += " " + field + " (";
      for (const std::string& p : parts) out += " " + (field.find("list") != std::string::npos ? p : slide_value(p));
      out += " )";
    } else {
      out += " " + field + " " + (parts.empty() ? std::string("0") : slide_value(parts[0]));
    }
  }
  return out;
}

// SLIDE's quadrics, whose `slide create TYPE NAME -field value …` are their named fields.
bool is_slide_quadric(std::string_view type) {
  static const std::set<std::string, std::less<>> kQuadrics = {"sphere", "cylinder", "cone", "disk",
                                                               "ring",   "torus",    "cyclide"};
  return kQuadrics.contains(type);
}

// The SLIDE text of the `slide create` calls that survive the `slide delete`s: statements,
// and (for instances into groups the file itself defines) a group per target group.
std::string slide_text(const std::vector<tcl::SlideCall>& calls, std::map<std::string, std::string>& into) {
  std::vector<std::pair<std::string, std::string>> made;  // (type:name, text)
  std::map<std::string, std::string> group_items;           // instances for Tcl-made groups
  for (const tcl::SlideCall& call : calls) {
    const std::vector<std::string>& w = call.words;
    const std::string key = w[1] + ":" + w[2];
    std::erase_if(made, [&](const auto& m) { return m.first == key; });
    if (w[0] == "delete") continue;
    const std::string& type = w[1];
    const std::string& name = w[2];
    std::string text;
    if (type == "point" && w.size() >= 4) {
      text = "point " + name + " (";
      for (const std::string& v : tcl_list(w[3])) text += " " + slide_value(v);
      text += " )" + slide_fields(w, 4) + " endpoint";
    } else if ((type == "face" || type == "object") && w.size() >= 4) {
      text = type + " " + name + " (";
      size_t i = 3;
      for (; i < w.size() && (w[i].empty() || w[i][0] != '-'); ++i) {
        for (const std::string& v : tcl_list(w[i])) text += " " + v;
      }
      text += " )" + slide_fields(w, i) + " end" + type;
    } else if (type == "convexhull" && w.size() >= 4) {
      // A generator over the named points (backend/generators/hull.cpp); points that are not
      // names are reported by the caller, and such a hull is left out.
      auto [points, bad] = hull_points(w);
      if (!bad.empty()) continue;
      text = "convexhull " + name + " (";
      for (const std::string& p : points) text += " " + p;
      size_t i = 3;
      while (i < w.size() && (w[i].empty() || w[i][0] != '-')) ++i;
      text += " )" + slide_fields(w, i) + " endconvexhull";
    } else if (type == "instance" && w.size() >= 5) {
      std::string xf;
      for (size_t i = 5; i + 1 < w.size(); i += 2) {
        if (w[i] == "-xforms") xf = slide_xforms(w[i + 1]);
      }
      into[w[3]] += "instance " + w[4] + " id " + name + xf + " endinstance\n";
      continue;
    } else if (type == "import" && w[0] == "import" && w.size() >= 4) {
      // The mesh file is the object `oNAME` (made by make_slide_nodes); its group holds it.
      text = "group g" + name + "\n  instance o" + name + " endinstance\nendgroup";
    } else if (type == "group" || type == "polyline" || type == "beziercurve" || type == "bsplinecurve" ||
               type == "surface" || is_slide_quadric(type)) {
      text = type + " " + name + slide_fields(w, 3) + " end" + type;
    } else {
      continue;  // reported by the caller
    }
    made.emplace_back(key, std::move(text));
  }
  std::string out;
  for (auto& [key, text] : made) {
    const size_t colon = key.find(':');
    if (key.compare(0, colon, "group") == 0) {
      const std::string name = key.substr(colon + 1);
      if (auto it = into.find(name); it != into.end()) {
        text = "group " + name + "\n" + it->second + "endgroup";
        into.erase(it);
      }
    }
    out += text + "\n";
  }
  return out;
}

// Reads what the scene's Tcl names next to the scene (`source`, a mesh parselib imports):
// beneath the scene's folder when the caller can read so, else through its file reader.
tcl::ReadFile beside_scene(Context& c) {
  const CheckOptions& opts = c.options();
  return [&opts, dir = c.tcl_dir](const std::string& path) -> std::optional<std::string> {
    if (opts.read_beneath && path.compare(0, dir.size(), dir) == 0) {
      return opts.read_beneath(dir.empty() ? "." : dir, path.substr(dir.size()));
    }
    return opts.read_file ? opts.read_file(path) : std::nullopt;
  };
}

// parselib's `CreateSTLObject NAME FILE` (or `CreateSIFObject`): the mesh file next to the
// scene becomes the flat mesh `oNAME` (its group `gNAME` is made in `slide_text`).
void import_mesh(Context& c, const std::string& name, const std::string& file, SourceRange where) {
  const std::string path = c.tcl_dir + file;
  std::optional<ir::FlatFormat> format = flat::format_of_path(path);
  std::optional<std::string> text = beside_scene(c)(path);
  if (!format || !text) {
    c.diags().emit(DiagKind::IncludeFailed, where,
                   fmt::format("`o{}` would be the mesh file `{}`, which nomec cannot read as {}", name, file,
                               format ? "a mesh" : "a `.stl`, `.sif` or `.obj` file"));
    return;
  }
  FileId f = c.sources().add_file(path, std::move(*text));
  add_flat_mesh(c, f, *format, where, "o" + name);
}

void make_slide_nodes(Context& c, const std::string& path, const std::vector<TclBody>& bodies) {
  const std::vector<tcl::SlideCall>& calls = c.tcl->slide_calls();
  if (calls.empty()) return;
  static const std::set<std::string> kKnown = {"point", "face", "object", "instance", "group", "polyline",
                                               "beziercurve", "bsplinecurve", "surface", "convexhull"};
  std::set<std::string> reported;
  for (const tcl::SlideCall& call : calls) {
    const std::vector<std::string>& w = call.words;
    if (w[0] == "create" && w[1] == "convexhull") {
      const std::string bad = w.size() >= 4 ? hull_points(w).second : "";
      if (w.size() < 4 || !bad.empty()) {
        c.diags().emit(DiagKind::UnsupportedSlideSyntax, bodies.front().keyword,
                       fmt::format("`slide create convexhull {}` in Tcl takes the names of points made before (`slide "
                                   "create point NAME {{x y z}}`){}; this hull is not made",
                                   w[2], bad.empty() ? ", and none is given" : fmt::format(", but `{}` is not a point name", bad)));
      }
    }
    if (w[0] == "import") {
      import_mesh(c, w[2], w[3], bodies.front().keyword);
      continue;
    }
    if (kKnown.contains(w[1]) || is_slide_quadric(w[1]) || !reported.insert(w[1]).second) continue;
    c.diags().emit(DiagKind::UnsupportedSlideSyntax, bodies.front().keyword,
                   fmt::format("`slide {} {}` in Tcl: nomec makes points, faces, objects, quadrics, convex hulls, "
                               "instances, groups, curves and surfaces from Tcl, not `{}`; it is ignored",
                               w[0], w[1], w[1]));
  }
  std::map<std::string, std::string> into;
  std::string text = slide_text(calls, into);
  // The Tcl-made statements are files of their own (named after the scene), parsed like it:
  // the statements, and the instances added to groups the scene defines.
  FileId file = c.sources().add_file(path + " (made by slide create)", std::move(text));
  c.owned_asts.push_back(std::make_unique<ast::Ast>(parse_file(c.sources(), file, c.diags())));
  c.tcl_ast = c.owned_asts.back().get();
  if (into.empty()) return;
  std::string added;
  for (const auto& [group, items] : into) added += "group " + group + "\n" + items + "endgroup\n";
  FileId added_file = c.sources().add_file(path + " (instances added by slide create)", std::move(added));
  c.owned_asts.push_back(std::make_unique<ast::Ast>(parse_file(c.sources(), added_file, c.diags())));
  const ast::Ast& adds = *c.owned_asts.back();
  for (const ast::Item& it : adds.top) {
    if (it.kind != ItemKind::Block) continue;
    const ast::Stmt& s = adds.stmt(it.block);
    if (s.kind == BlockKind::Group && !s.items.empty()) c.tcl_group_additions[std::string(s.items[0].text)] = {&adds, &s};
  }
}

}  // namespace

tcl::Interp* scene_tcl(Context& c) {
  if (c.tcl || !c.tcl_available) return c.tcl.get();
  // What the scene's Tcl reads is remembered for the interpreters that re-evaluate its
  // values when sliders move (tcl_live.cpp).
  tcl::ReadFile reader = c.tcl_files->recording(beside_scene(c));
  const CheckOptions& opts = c.options();
  tcl::Limits limits;
  limits.milliseconds = std::max(opts.tcl_milliseconds, 1);
  c.tcl = std::make_unique<tcl::Interp>(c.tcl_dir, reader, limits,
                                        [&opts](const std::string& var, double from, double to) {
                                          return preset_for(opts, var, from, to);
                                        });
  // One budget for everything the file's Tcl runs while it is checked (blocks, values, and
  // the evaluator's replay for values that follow sliders).
  c.tcl_budget = std::make_shared<tcl::Budget>(limits.milliseconds);
  c.tcl->use_budget(c.tcl_budget);
  return c.tcl.get();
}

// The one error of a SLIDE file checked without running its Tcl (CheckOptions::run_tcl).
void report_tcl_not_run(Context& c, SourceRange where) {
  if (c.tcl_stop_reported) return;
  c.tcl_stop_reported = true;
  report(c, {tcl::ProblemKind::Unavailable, "this file's Tcl is not run (`--no-tcl`): its sliders and the values only Tcl computes are missing", 0, ""}, where, "");
}

void run_tcl(Context& c, std::span<const ast::Ast> trees, const std::string& path) {
  if (c.dialect() != Dialect::Slide || c.tcl_available) return;
  if (!c.options().run_tcl) {
    for (const ast::Ast& a : trees) {
      for (const ast::Item& it : a.top) {
        if (it.kind == ItemKind::Tcl) {
          report_tcl_not_run(c, body_of(it).keyword);
          return;
        }
      }
    }
    return;
  }
  const size_t slash = path.rfind('/');
  c.tcl_dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  c.tcl_available = true;
  std::vector<TclBody> bodies;
  for (const ast::Ast& a : trees) {
    for (const ast::Item& it : a.top) {
      if (it.kind != ItemKind::Tcl) continue;
      bodies.push_back(body_of(it));
      const TclBody& b = bodies.back();
      c.tcl_blocks.push_back(SourceRange{b.keyword.file, b.begin, static_cast<uint32_t>(b.begin + b.text.size())});
    }
  }
  if (bodies.empty()) return;  // the interpreter is made when a value needs it
  scene_tcl(c);
  bool noted_update = false;
  for (int pass = 0; pass < 2; ++pass) {  // `tclinit` blocks, then `tclupdate` blocks
    for (const TclBody& b : bodies) {
      if (b.update != (pass == 1)) continue;
      c.has_tcl = true;
      if (b.update && !noted_update) {
        noted_update = true;
        c.diags().emit(DiagKind::TclUpdateStatic, b.keyword,
                       "`tclupdate` runs before every frame in SLIDE; nomec runs it after the `tclinit` blocks, and "
                       "again whenever a slider moves, before the values that read what it sets (not per frame: what "
                       "it animates stays still)");
      }
      (b.update ? c.tcl_update_texts : c.tcl_init_texts).emplace_back(b.text);
      tcl::Outcome o = b.update ? c.tcl->run_tracking_writes(b.text) : c.tcl->run(b.text);
      if (b.update) note_tcl_update(c, o, b.text);
      for (const tcl::Problem& p : c.tcl->take_notes()) report(c, p, b.keyword, "");
      for (const tcl::Problem& p : o.problems) {
        report(c, p, line_range(b.keyword.file, b.begin, b.text, p.line, b.keyword),
               b.update ? "this `tclupdate` block" : "this `tclinit` block");
      }
    }
    // The sliders the `tclinit` blocks made are watched while `tclupdate` runs.
    if (pass == 0) make_sliders(c, bodies);
  }
  make_sliders(c, bodies);  // any a `tclupdate` block made
  make_slide_nodes(c, path, bodies);
}

std::optional<TclValue> tcl_value(Context& c, std::string_view script, SourceRange where) {
  if (!c.options().run_tcl && c.dialect() == Dialect::Slide) report_tcl_not_run(c, where);
  if (scene_tcl(c) == nullptr) return std::nullopt;
  tcl::Outcome o = c.tcl->value(script);
  for (const tcl::Problem& p : c.tcl->take_notes()) report(c, p, where, "");
  if (!o.ok) {
    for (const tcl::Problem& p : o.problems) report(c, p, where, "this value");
    return TclValue{false, 0, {}, {}};
  }
  TclValue v{true, o.number, {}, o.reads};
  for (const std::string& r : o.reads) {
    if (auto it = c.tcl_sliders.find(r); it != c.tcl_sliders.end()) v.sliders.push_back(it->second);
  }
  return v;
}

void report_unplaced_tcl_instances(Context& c) {
  for (const auto& [group, added] : c.tcl_group_additions) {
    c.diags().emit(DiagKind::UnknownName, added.second->items.empty() ? added.second->range : added.second->items[0].range,
                   fmt::format("`slide create instance … {} …` in Tcl adds to the group `{}`, which the scene does not "
                               "define; the instance is not drawn",
                               group, group));
  }
  c.tcl_group_additions.clear();
}

std::optional<double> tcl_number(Context& c, std::string_view name, SourceRange where) {
  if (scene_tcl(c) == nullptr) return std::nullopt;
  std::optional<std::string> v = c.tcl->get(name);
  for (const tcl::Problem& p : c.tcl->take_notes()) report(c, p, where, "");
  if (!v) return std::nullopt;
  char* end = nullptr;
  double d = std::strtod(v->c_str(), &end);
  if (end == v->c_str()) return std::nullopt;
  while (*end == ' ') ++end;
  if (*end != '\0' || !std::isfinite(d)) return std::nullopt;
  return d;
}

}  // namespace nomec::check
