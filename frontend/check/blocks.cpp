// Pipeline blocks (`merge`, `subdivision`, `offset`, the high-genus operators, SLIDE's
// `mirror`), sweeps with their path and cross section, and zippers (see handlers.h). Symbolic option values (`sd_type NOME_SD_CC_sharp`, `offset_type
// NOME_OFFSET_GRID`, SLIDE's `type SLF_…`) are resolved to the IR's enums here; a symbol
// nomec does not know is an error with the closest known one as a hint.
#include <algorithm>
#include <fmt/format.h>

#include "frontend/check/handlers.h"

namespace nomec::check {

namespace {

constexpr SymbolEntry<ir::SubdivisionRule> kSubdivisionRules[] = {
    {"NOME_SD_CC_sharp", ir::SubdivisionRule::CatmullClarkSharp},
    {"NOME_SD_CatmullClark", ir::SubdivisionRule::CatmullClark},
    {"NOME_SD_CC", ir::SubdivisionRule::CatmullClark},
    {"NOME_SD_DeRose", ir::SubdivisionRule::DeRose},
    {"SLF_SUBDIVISION_CATMULL_CLARK", ir::SubdivisionRule::CatmullClark},
    // SLIDE's corner-rounding tessellation is read as Catmull-Clark honouring creases.
    {"SLF_SUBDIVISION_CORNER_ROUNDING_TESSELATE", ir::SubdivisionRule::CatmullClarkSharp},
};

constexpr SymbolEntry<ir::OffsetKind> kOffsetKinds[] = {
    {"NOME_OFFSET_DEFAULT", ir::OffsetKind::Plain},
    {"NOME_OFFSET_GRID", ir::OffsetKind::Grid},
    {"SLF_OFFSET_ANGULAR", ir::OffsetKind::Plain},
    {"SLF_OFFSET_PERFORATED", ir::OffsetKind::Grid},
};

// NOME2's `instance X` inside a block names a top-level instance: the block takes it over
// (it is drawn through the block, no longer on its own).
void take_instance(Context& c, ir::NodeId id, const OptionValue& v) {
  if (v.symbol.empty()) return;  // the value was no name (reported by the reader)
  const std::string name(v.symbol);
  auto top = c.instance_scopes.find(0);
  const ir::NodeId inst = top == c.instance_scopes.end() || !top->second.contains(name) ? ir::NodeId::None()
                                                                                          : top->second.at(name);
  if (!inst.is_valid()) {
    c.listed_all_instances = true;
    const std::vector<std::string_view> names =
        top != c.instance_scopes.end() ? sorted_names(top->second) : std::vector<std::string_view>{};
    const std::string hint = closest_match(name, names);
    c.diags().emit(DiagKind::UnknownName, v.value_range,
                   fmt::format("`instance {}` in `{}` names no top-level instance{}", name, c.module().node(id).keyword,
                               hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
    return;
  }
  std::vector<ir::NodeId>& scene = c.module().scene;
  scene.erase(std::remove(scene.begin(), scene.end(), inst), scene.end());
  c.adopt(id, inst);
  // The block draws what it took over (in NOME 2016 files too, where top-level blocks are
  // otherwise drawn only through an instance).
  if (!c.module().node(id).parent.is_valid() && std::find(scene.begin(), scene.end(), id) == scene.end()) {
    scene.push_back(id);
  }
  if (c.name_uses != nullptr) c.name_uses->push_back(NameUse{v.value_range, inst});
}

// Stores an option of a pipeline block into its payload.
void block_option(Context& c, ir::NodeId id, const OptionValue& v, BlockPaths& paths) {
  if (v.spec->shape == Shape::Paths) {
    note_block_paths(paths, v);
    return;
  }
  if (v.spec->key == Opt::InstanceRef) {
    take_instance(c, id, v);
    return;
  }
  ir::Node& n = c.module().node(id);
  switch (n.kind) {
    case ir::NodeKind::Merge:
      if (v.spec->key == Opt::Tolerance) n.as<ir::MergeData>().tolerance = v.operand;
      return;
    case ir::NodeKind::Subdivision: {
      ir::SubdivisionData& d = n.as<ir::SubdivisionData>();
      if (v.spec->key == Opt::Levels) d.levels = v.operand;
      if (v.spec->key == Opt::Tolerance) d.tolerance = v.operand;
      if (v.spec->key == Opt::SubdivisionType) {
        if (v.operand.is_valid()) {
          d.rule_value = v.operand;
        } else if (auto rule = resolve_symbol(c, kSubdivisionRules, v, "subdivision type")) {
          c.module().get<ir::SubdivisionData>(id).rule = *rule;
        }
      }
      return;
    }
    case ir::NodeKind::Offset: {
      ir::OffsetData& d = n.as<ir::OffsetData>();
      if (v.spec->key == Opt::Height) d.height = v.operand;
      if (v.spec->key == Opt::Width) d.width = v.operand;
      if (v.spec->key == Opt::Tolerance) d.tolerance = v.operand;
      if (v.spec->key == Opt::OffsetType) {
        if (v.operand.is_valid()) {
          d.kind_value = v.operand;
        } else if (auto kind = resolve_symbol(c, kOffsetKinds, v, "offset type")) {
          c.module().get<ir::OffsetData>(id).kind = *kind;
        }
      }
      return;
    }
    case ir::NodeKind::Handle: {
      ir::HandleData& d = n.as<ir::HandleData>();
      if (v.spec->key == Opt::Segments) d.segments = v.operand;
      if (v.spec->key == Opt::Weights) d.weights = v.operand;
      if (v.spec->key == Opt::Twist) d.twist = v.operand;
      return;
    }
    case ir::NodeKind::Rind: {
      ir::RindData& d = n.as<ir::RindData>();
      if (v.spec->key == Opt::Thickness) d.thickness = v.operand;
      return;
    }
    case ir::NodeKind::Sierpinski:
      if (v.spec->key == Opt::Level) n.as<ir::SierpinskiData>().level = v.operand;
      return;
    case ir::NodeKind::Menger: {
      ir::MengerData& d = n.as<ir::MengerData>();
      if (v.spec->key == Opt::Level) d.level = v.operand;
      if (v.spec->key == Opt::Thickness) d.thickness = v.operand;
      if (v.spec->key == Opt::Collapse) d.collapse = v.operand;
      return;
    }
    default:
      return;  // SLIDE's `mirror`: display options only
  }
}

}  // namespace

ir::NodeId handle_block(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string_view kw = s.keyword;
  // NOME2's `merge epsilon E endmerge` has no name: it merges the whole scene.
  const bool scene_merge = s.kind == BlockKind::Merge && !s.items.empty() && s.items[0].kind == ItemKind::Word &&
                           s.items[0].text == "epsilon";
  std::string name =
      scene_merge ? std::string("merge") : c.read_name(s, pos, fmt::format("{} name … end{}", kw, kw)).value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  BlockPaths paths;
  read_body(c, a, s, pos, id, options_for(s.kind), [&c, id, &paths](const OptionValue& v) { block_option(c, id, v, paths); });
  finish_highgenus(c, s, id, paths);
  if (ctx.parent.is_valid()) c.module().deps.add_edge(id, ctx.parent);
  if (scene_merge && ctx.top) c.scene_merges.push_back(id);
  return id;
}

void finish_scene_merges(Context& c) {
  if (c.scene_merges.empty()) return;
  // The first `merge epsilon` takes every top-level instance; later ones merge nothing more.
  const ir::NodeId merge = c.scene_merges.front();
  std::vector<ir::NodeId>& scene = c.module().scene;
  std::vector<ir::NodeId> kept;
  for (ir::NodeId e : scene) {
    if (c.module().node(e).kind == ir::NodeKind::Instance) {
      c.adopt(merge, e);
    } else if (e == merge || std::find(c.scene_merges.begin(), c.scene_merges.end(), e) == c.scene_merges.end()) {
      kept.push_back(e);
    }
  }
  if (std::find(kept.begin(), kept.end(), merge) == kept.end()) kept.push_back(merge);
  scene = std::move(kept);
}

ir::NodeId handle_sweep(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string name = c.read_name(s, pos, "sweep s … endsweep").value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  read_body(c, a, s, pos, id, options_for(s.kind), [&c, id](const OptionValue& v) {
    ir::SweepData& d = c.module().get<ir::SweepData>(id);
    if (v.spec->key == Opt::Azimuth) d.azimuth = v.operand;
    if (v.spec->key == Opt::Twist) d.twist = v.operand;
    if (v.spec->key == Opt::Mintorsion) d.mintorsion = true;
  });
  if (ctx.parent.is_valid()) c.module().deps.add_edge(id, ctx.parent);
  return id;
}

// `path P … endpath` in a sweep; `crosssection C … endcrosssection` in a sweep (C names the
// curve) or at the top level (SLIDE: C is defined, its curve is `type polyline P`).
ir::NodeId handle_sweep_part(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  const bool is_path = s.kind == BlockKind::Path;
  size_t pos = 0;
  std::string name =
      c.read_name(s, pos, is_path ? "path p … endpath" : "crosssection c … endcrosssection").value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  ir::Module& m = c.module();
  if ((is_path || !ctx.top) && !name.empty()) {
    // Inside a sweep the name refers to a curve or polyline.
    ir::NodeId curve = resolve(c, Ns::Shape, name, s.items[0].range, "a curve or polyline");
    if (curve.is_valid()) m.deps.add_edge(curve, id);
    if (is_path) {
      auto& path = m.get<ir::SweepPathData>(id);
      path.curve = curve;
      path.curve_range = s.items[0].range;
    } else {
      auto& section = m.get<ir::CrossSectionData>(id);
      section.curve = curve;
      section.curve_range = s.items[0].range;
    }
  }
  if (is_path) {
    read_body(c, a, s, pos, id, options_for(s.kind), [&c, id](const OptionValue& v) {
      ir::SweepPathData& d = c.module().get<ir::SweepPathData>(id);
      if (v.spec->key == Opt::Azimuth) d.azimuth = v.operand;
      if (v.spec->key == Opt::Twist) d.twist = v.operand;
      if (v.spec->key == Opt::MinimizeTorsion) d.minimizetorsion = v.operand;
      if (v.spec->key == Opt::Mintorsion) d.mintorsion = true;
      if (v.spec->key == Opt::CutBegin) d.cut_begin = true;
      if (v.spec->key == Opt::CutEnd) d.cut_end = true;
    });
    return id;
  }
  auto positional = [&](const ast::Item& it) {
    // SLIDE `type polyline NAME`: the curve the cross section is made of.
    if (it.kind != ItemKind::Word) return false;
    ir::NodeId curve = resolve_any(c, it.text, it.range);
    if (curve.is_valid()) c.module().deps.add_edge(curve, id);
    c.module().get<ir::CrossSectionData>(id).curve = curve;
    c.module().get<ir::CrossSectionData>(id).curve_range = it.range;
    return true;
  };
  read_body(c, a, s, pos, id, options_for(s.kind), [&c, id](const OptionValue& v) {
    ir::CrossSectionData& d = c.module().get<ir::CrossSectionData>(id);
    switch (v.spec->key) {
      case Opt::Curve:
        d.curve = v.ref;
        d.curve_range = v.value_range;
        break;
      case Opt::Type:
        d.is_circle = d.is_circle || v.symbol == "circle";
        d.is_star = d.is_star || v.symbol == "star";
        break;
      case Opt::Circle: d.is_circle = true; break;
      case Opt::Radius: d.radius = v.operand; break;
      case Opt::InnerRadius: d.inner_radius = v.operand; break;
      case Opt::Slices: d.slices = v.operand; break;
      case Opt::BeginCap: d.begin_cap = ir::FlagArg{true, v.operand, v.word}; break;
      case Opt::EndCap: d.end_cap = ir::FlagArg{true, v.operand, v.word}; break;
      case Opt::Reverse: d.reverse = true; break;
      default: break;
    }
  }, positional);
  return id;
}

ir::NodeId handle_zipper(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string name = c.read_name(s, pos, "zipper z border (a b) border (c d) endzipper").value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  read_body(c, a, s, pos, id, options_for(s.kind), [&c, id](const OptionValue& v) {
    ir::ZipperData& d = c.module().get<ir::ZipperData>(id);
    if (v.spec->key == Opt::Penalty) d.penalty = v.operand;
    if (v.spec->key != Opt::Border) return;
    if (d.border_count < 2) d.borders[d.border_count] = v.vertices;
    ++d.border_count;
    if (v.vertices.size < 1 || v.vertices.size > 3) {
      c.diags().emit(DiagKind::ListArity, v.value_range,
                     fmt::format("a zipper `border` names 1 to 3 vertices of one border loop (start [end [a vertex "
                                 "between]]), got {}",
                                 v.vertices.size));
    }
  });
  const int32_t borders = c.module().get<ir::ZipperData>(id).border_count;
  if (borders != 2) {
    c.diags().emit(DiagKind::MissingArgument, s.open_kw,
                   fmt::format("`zipper` joins two borders and needs two `border (…)` lists, got {}", borders));
  }
  return id;
}

}  // namespace nomec::check
