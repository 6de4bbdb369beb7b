// Top-level statements and dispatch (see handlers.h): each statement goes to the handler of
// its kind (a `switch` over block_kinds.def, compiled with -Wswitch); stray words and values
// at the top level are explained; `include "file.slf"` is read, declared and checked in
// place (an included file sees every definition of the including file: SLIDE binds late),
// within the check's input limits (depth, count and bytes, a repeat counting again);
// `include "file.sif"` (also `.obj`, `.stl`) defines a mesh (flat_meshes.cpp).
#include <algorithm>
#include <fmt/format.h>

#include "base/input_limits.h"
#include "frontend/check/handlers.h"
#include "frontend/parse/parse.h"

namespace nomec::check {

namespace {

void report_stray(Context& c, const ast::Item& it) {
  if (it.kind != ItemKind::Word) {
    c.diags().emit(DiagKind::StrayTopLevelItem, it.range,
                   "unexpected value at the top level; values belong inside a statement such as `point NAME (x y z) endpoint`");
    return;
  }
  if (it.text == "set" || it.text == "list") {
    c.diags().emit(DiagKind::StrayTopLevelItem, it.range,
                   fmt::format("`{}` outside a bank; sliders are declared inside `bank NAME … endbank`", it.text));
    return;
  }
  static const std::vector<std::string_view> kws = [] {
    std::vector<std::string_view> k = ast::all_open_keywords();
    k.push_back("include");
    k.push_back("tclinit");
    k.push_back("tclupdate");
    return k;
  }();
  std::string hint = closest_match(it.text, kws);
  if (c.dialect() == Dialect::Slide && hint.empty()) {
    // language.md §7: SLIDE statements nomec does not implement are named as such.
    c.diags().emit(DiagKind::UnsupportedSlideSyntax, it.range,
                   fmt::format("`{}` is SLIDE syntax that nomec does not support yet; the statement is skipped", it.text));
    return;
  }
  auto d = c.diags().emit(DiagKind::StrayTopLevelItem, it.range,
                          hint.empty() ? fmt::format("unexpected `{}` at the top level; statements start with a keyword such as "
                                                     "`point`, `mesh` or `instance`",
                                                     it.text)
                                       : fmt::format("unknown statement `{}`; did you mean `{}`?", it.text, hint));
  if (!hint.empty()) d.fixit(it.range, hint, fmt::format("replace with `{}`", hint));
}

void handle_include(Context& c, const ast::Ast& a, const ast::Item& it) {
  std::string rel(it.text);
  std::string_view including = c.sources().name(a.file);
  const size_t slash = including.find_last_of('/');
  std::string path = slash == std::string_view::npos || rel.starts_with("/") ? rel
                                                                             : std::string(including.substr(0, slash + 1)) + rel;
  if (rel.empty()) {
    c.diags().emit(DiagKind::IncludeFailed, it.range, "`include` needs a file name in quotes, e.g. `include \"viewing.slf\"`");
    return;
  }
  if (include_flat(c, path, rel, it)) return;  // `.sif`, `.obj`, `.stl`: a mesh
  IncludeRead read = read_include(c, path, rel, it);
  if (read.is_stopped) return;
  if (!read.text) {
    c.diags().emit(DiagKind::IncludeFailed, it.range,
                   fmt::format("cannot read included file `{}` (looked for `{}`){}", rel, path,
                               read.problem.empty() ? "" : ": " + read.problem));
    return;
  }
  FileId f = c.sources().add_file(path, std::move(*read.text));
  c.owned_asts.push_back(std::make_unique<ast::Ast>(parse_file(c.sources(), f, c.diags())));
  const ast::Ast& inc = *c.owned_asts.back();
  ++c.include_depth;
  c.include_chain.push_back(rel);
  collect_tcl(c, inc);
  collect_banks(c, inc);
  // An included file sees every definition of the including file (SLIDE binds late).
  const int base_order = (1 << 20) * c.include_depth;
  declare(c, inc, base_order);
  const int saved_order = c.order;
  process(c, inc, base_order);
  c.order = saved_order;
  c.include_chain.pop_back();
  --c.include_depth;
}

// A single-line statement whose end the parser found at the end of its line (frontend/parse,
// compat.md §B2): NOME 2016 read it so, and in its files that is a warning; elsewhere the
// end keyword is missing or wrong.
void report_line_end(Context& c, const ast::Stmt& s) {
  const std::string expected = ast::end_keyword(s.keyword);
  const bool nome2016 = c.dialect() == Dialect::Nome;
  if (s.close_repair == ast::CloseRepair::Inserted) {
    auto d = nome2016 ? c.diags().emit(DiagKind::EndOfLineStatement, s.open_kw,
                                       fmt::format("`{}` has no `{}`; it ends at the end of its line, as in NOME 2016",
                                                   s.keyword, expected))
                      : c.diags().emit(DiagKind::MissingEndKeyword, s.open_kw,
                                       fmt::format("`{}` is not closed: `{}` is missing at the end of its line",
                                                   s.keyword, expected));
    d.fixit(s.close_kw, " " + expected, fmt::format("insert `{}`", expected));
    return;
  }
  const bool is_end_keyword = ast::block_of_end_keyword(s.close_text).has_value();
  if (!is_end_keyword && !nome2016) {
    // A misspelt end keyword (`endinstnace`), read as the one meant: as the structure pass
    // reports the others (frontend/parse/recovery.h).
    c.diags()
        .emit(DiagKind::MisspelledKeyword, s.close_kw, fmt::format("unknown `{}`; did you mean `{}`?", s.close_text, expected))
        .fixit(s.close_kw, expected, fmt::format("replace with `{}`", expected));
    return;
  }
  const std::string what = is_end_keyword ? fmt::format("`{}` does not close `{}`", s.close_text, s.keyword)
                                          : fmt::format("`{}` is not an end keyword", s.close_text);
  auto d = nome2016 ? c.diags().emit(DiagKind::EndOfLineStatement, s.close_kw,
                                     fmt::format("{}; `{}` ends at the end of its line, as in NOME 2016", what, s.keyword))
                    : c.diags().emit(is_end_keyword ? DiagKind::MismatchedEndKeyword : DiagKind::MissingEndKeyword,
                                     s.close_kw, fmt::format("{}; expected `{}`", what, expected));
  d.note(s.open_kw, fmt::format("`{}` opened here", s.keyword));
  d.fixit(s.close_kw, expected, fmt::format("replace with `{}`", expected));
}

}  // namespace

void process(Context& c, const ast::Ast& a, int order_base, bool* stray_run) {
  int order = order_base;
  bool own_stray_run = false;
  bool& in_stray_run = stray_run != nullptr ? *stray_run : own_stray_run;
  // The main file's own statements (not a base scene's, an include's or Tcl's, numbered
  // below 0 or from 1 << 20): an incremental check may process only some of them, and
  // marks what each one reported.
  const bool main = a.file == c.main_file && order_base >= 0 && order_base < (1 << 20);
  for (const ast::Item& it : a.top) {
    ++order;
    c.order = order;
    const int32_t item = order - 1;  // of the main file, whichever of its pieces `a` is
    if (item % 64 == 0 && c.options().is_cancelled()) {
      c.cancelled = true;
      return;
    }
    const bool stray = it.kind != ItemKind::Block && it.kind != ItemKind::Tcl && it.kind != ItemKind::Include;
    if (main && c.only_items != nullptr && !(*c.only_items)[static_cast<size_t>(item)]) {
      in_stray_run = stray;
      continue;
    }
    struct Mark {  // after the item, however it ends
      Context& c;
      bool on;
      int32_t item;
      ~Mark() {
        if (on) c.item_marks->push_back({item, static_cast<uint32_t>(c.diags().diagnostics().size())});
      }
    } mark{c, main && c.item_marks != nullptr, item};
    if (stray) {
      if (!in_stray_run) report_stray(c, it);
      in_stray_run = true;
      continue;
    }
    in_stray_run = false;
    if (it.kind == ItemKind::Include) {
      handle_include(c, a, it);
      continue;
    }
    if (it.kind != ItemKind::Block) continue;
    ir::NodeId id = handle_stmt(c, a, a.stmt(it.block), Ctx{});
    if (!id.is_valid()) continue;
    const ir::Node& n = c.module().node(id);
    // Top-level instances are drawn (unless hidden); NOME2 and NOME3 draw top-level blocks too.
    const bool visible = (n.kind == ir::NodeKind::Instance && !n.as<ir::InstanceData>().is_hidden) ||
                         (ir::is_block(n.kind) && (c.dialect() == Dialect::Nome3 || c.dialect() == Dialect::Nome2));
    std::vector<ir::NodeId>& scene = c.module().scene;
    if (visible && std::find(scene.begin(), scene.end(), id) == scene.end()) scene.push_back(id);
  }
}

ir::NodeId handle_stmt(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  if (s.close_repair != ast::CloseRepair::None) report_line_end(c, s);
  switch (s.kind) {
    case BlockKind::Bank:
    case BlockKind::Savedparameter:
      if (!ctx.top) c.misplaced(s, ctx);
      return ir::NodeId::None();  // handled before everything else
    case BlockKind::Surface: return handle_surface(c, a, s, ctx);
    case BlockKind::Point: return handle_point(c, a, s, ctx);
    case BlockKind::Vertex: return handle_vertex(c, a, s, ctx);
    case BlockKind::Polyline: return handle_polyline(c, a, s, ctx);
    case BlockKind::Face:
    case BlockKind::Facet: return handle_face(c, a, s, ctx);
    case BlockKind::Object: return handle_object(c, a, s, ctx);
    case BlockKind::Mesh:
    case BlockKind::Consolidate:
    case BlockKind::Consolidateface:
    case BlockKind::Savedworkingmesh: return handle_mesh(c, a, s, ctx);
    case BlockKind::Group: return handle_group(c, a, s, ctx);
    case BlockKind::Instance: return handle_instance(c, a, s, ctx);
    case BlockKind::Transform: return handle_transform(c, a, s, ctx);
    case BlockKind::Sweep: return handle_sweep(c, a, s, ctx);
    case BlockKind::Crosssection:
    case BlockKind::Path: return handle_sweep_part(c, a, s, ctx);
    case BlockKind::Controlpoint: return handle_controlpoint(c, a, s, ctx);
    case BlockKind::Delete: return handle_delete(c, a, s, ctx);
    case BlockKind::Sharp: return handle_sharp(c, a, s, ctx);
    case BlockKind::Zipper: return handle_zipper(c, a, s, ctx);
    case BlockKind::Merge:
    case BlockKind::Subdivision:
    case BlockKind::Offset:
    case BlockKind::Handle:
    case BlockKind::Rind:
    case BlockKind::Sierpinski:
    case BlockKind::Menger:
    case BlockKind::Mirror: return handle_block(c, a, s, ctx);
    case BlockKind::Camera:
    case BlockKind::Light:
    case BlockKind::Window:
    case BlockKind::Viewport:
    case BlockKind::Render:
    case BlockKind::Lookat:
    case BlockKind::Foreground:
    case BlockKind::Background:
    case BlockKind::Insidefaces:
    case BlockKind::Outsidefaces:
    case BlockKind::Offsetfaces: return handle_scene(c, a, s, ctx);
    case BlockKind::Frontcolor:
    case BlockKind::Backcolor:
    case BlockKind::Backgroundcolor: return handle_scene_color(c, a, s, ctx);
    case BlockKind::Backface: return handle_backface(c, a, s, ctx);
    case BlockKind::Sweepmorph: return handle_sweepmorph(c, a, s, ctx);
    case BlockKind::Morphvisualizer: return handle_morphvisualizer(c, a, s, ctx);
    case BlockKind::Generator: return handle_generator(c, a, s, ctx);
  }
  return ir::NodeId::None();
}

IncludeRead read_include(Context& c, const std::string& path, const std::string& rel, const ast::Item& it) {
  IncludeRead r;
  if (c.is_include_limit_reached) {
    r.is_stopped = true;
    return r;
  }
  // The files that include this one, outermost first: `scene.slf → a.slf → b.slf`.
  auto chain = [&] {
    const std::string_view main = c.sources().name(c.main_file);
    std::string out(main.substr(main.find_last_of('/') + 1));
    for (const std::string& f : c.include_chain) out += " → " + f;
    return out + " → " + rel;
  };
  auto stop = [&](const std::string& message, std::string_view hint) {
    c.is_include_limit_reached = true;
    r.is_stopped = true;
    c.diags().emit(DiagKind::IncludeLimit, it.range, message).note(SourceRange{}, std::string(hint));
  };
  if (c.include_depth >= kMaxIncludeDepth) {
    stop(fmt::format("`include \"{}\"` nests more than {} files deep: {}", rel, kMaxIncludeDepth, chain()),
         "does a file include itself? nomec reads no include after this one");
    return r;
  }
  if (c.include_count >= kMaxIncludes) {
    stop(fmt::format("`include \"{}\"` is one more than the {} includes nomec reads for one scene, repeats counted: {}", rel,
                     kMaxIncludes, chain()),
         "does a file include itself, or include a file many times? nomec reads no include after this one");
    return r;
  }
  ++c.include_count;
  if (c.options().read_file) r.text = c.options().read_file(path);
  if (!r.text) {
    if (c.options().read_problem) r.problem = c.options().read_problem(path);
    return r;
  }
  const bool mesh = is_mesh_file_path(path);
  int64_t& spent = mesh ? c.mesh_bytes : c.input_bytes;
  const int64_t cap = mesh ? c.options().max_mesh_bytes : c.options().max_input_bytes;
  const int64_t total = spent + static_cast<int64_t>(r.text->size());
  if (total > cap) {
    r.text.reset();
    stop(fmt::format("`include \"{}\"` brings the scene's {} to {}, more than the {} nomec reads (`{}`): {}", rel,
                     mesh ? "mesh files" : "text", byte_size_text(total), byte_size_text(cap),
                     mesh ? "--max-mesh-size" : "--max-file-size", chain()),
         "a file included again is read again and counts again; nomec reads no include after this one");
    return r;
  }
  spent = total;
  return r;
}

}  // namespace nomec::check
