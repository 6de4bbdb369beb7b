// Option tables per block kind and the statement-body reader (see options.h).
#include "frontend/check/options.h"

#include <algorithm>
#include <array>
#include <fmt/format.h>

#include "frontend/check/handlers.h"

namespace nomec::check {

namespace {

// Display and UI options SLIDE attaches to many blocks; accepted, checked, not used.
// (`tolerance` is read: a block's merge tolerance.)
#define SLIDE_DISPLAY                                                                                    \
  {"lod", Shape::Any, Opt::Ignored}, {"shading", Shape::Any, Opt::Ignored},                              \
      {"drawcontrols", Shape::Any, Opt::Ignored}, {"drawcurrent", Shape::Any, Opt::Ignored},             \
      {"drawvertices", Shape::Any, Opt::Ignored}, {"solid", Shape::Any, Opt::Ignored},                   \
      {"errormetric", Shape::Any, Opt::Ignored}, {"uknots", Shape::Any, Opt::Ignored},                   \
      {"uorder", Shape::Any, Opt::Ignored}, {"vknots", Shape::Any, Opt::Ignored},                        \
      {"vorder", Shape::Any, Opt::Ignored}, {"tolerance", Shape::Scalar, Opt::Tolerance},                \
      {"facetsmax", Shape::Any, Opt::Ignored}, {"meshtype", Shape::Any, Opt::Ignored},                   \
      {"drawpath", Shape::Any, Opt::Ignored}, {"drawsweep", Shape::Any, Opt::Ignored}

const OptSpec kDisplay[] = {SLIDE_DISPLAY};
const OptSpec kSurface[] = {{"color", Shape::Vec3, Opt::Color}, {"reflectivity", Shape::Vec3, Opt::Reflectivity},
                            {"exponent", Shape::Scalar, Opt::Exponent}, {"metallic", Shape::Scalar, Opt::Metallic},
                            {"bitmap", Shape::Rest, Opt::Bitmap}};
const OptSpec kPoint[] = {{"texture", Shape::Vec2, Opt::Texture}};
const OptSpec kPolyline[] = {{"closed", Shape::FlagOrScalar, Opt::Closed},
                             {"isloop", Shape::Flag, Opt::Closed},
                             {"pointlist", Shape::PointNames, Opt::PointList}};
const OptSpec kFace[] = {{"surface", Shape::Surface, Opt::Surface}, {"backface", Shape::Backface, Opt::Backface}};
const OptSpec kObject[] = {{"surface", Shape::Surface, Opt::Surface}, SLIDE_DISPLAY};
const OptSpec kGroup[] = {{"lod", Shape::Symbol, Opt::Lod}, {"surface", Shape::Surface, Opt::Surface}, SLIDE_DISPLAY};
const OptSpec kInstance[] = {{"lod", Shape::Symbol, Opt::Lod},
                             {"translate", Shape::Vec3, Opt::Translate}, {"rotate", Shape::Rotate, Opt::Rotate},
                             {"scale", Shape::Vec3, Opt::Scale},         {"mirror", Shape::Vec4, Opt::Mirror},
                             {"surface", Shape::Surface, Opt::Surface},  {"hidden", Shape::Flag, Opt::Hidden},
                             {"id", Shape::Any, Opt::Id},                {"reverse", Shape::Flag, Opt::Reverse},
                             {"backface", Shape::Backface, Opt::Backface},
                             SLIDE_DISPLAY};
const OptSpec kTransform[] = {{"translate", Shape::Vec3, Opt::Translate},
                              {"rotate", Shape::Rotate, Opt::Rotate},
                              {"scale", Shape::Vec3, Opt::Scale}};
const OptSpec kSweep[] = {{"azimuth", Shape::Scalar, Opt::Azimuth}, {"twist", Shape::Scalar, Opt::Twist},
                          {"mintorsion", Shape::Flag, Opt::Mintorsion}, SLIDE_DISPLAY};
const OptSpec kCrosssection[] = {{"type", Shape::Any, Opt::Type},
                                 {"polyline", Shape::Ref, Opt::Curve},
                                 {"bsplinecurve", Shape::Ref, Opt::Curve},
                                 {"beziercurve", Shape::Ref, Opt::Curve},
                                 {"circle", Shape::Flag, Opt::Circle},
                                 {"radius", Shape::Scalar, Opt::Radius},
                                 {"outerradius", Shape::Scalar, Opt::Radius},
                                 {"innerradius", Shape::Scalar, Opt::InnerRadius},
                                 {"slices", Shape::Scalar, Opt::Slices},
                                 {"begincap", Shape::FlagOrScalar, Opt::BeginCap},
                                 {"endcap", Shape::FlagOrScalar, Opt::EndCap},
                                 {"reverse", Shape::Flag, Opt::Reverse},
                                 SLIDE_DISPLAY};
const OptSpec kPath[] = {{"mintorsion", Shape::Flag, Opt::Mintorsion},
                         {"minimizetorsion", Shape::Scalar, Opt::MinimizeTorsion},
                         {"azimuth", Shape::Scalar, Opt::Azimuth},
                         {"twist", Shape::Scalar, Opt::Twist},
                         {"cutbegin", Shape::Flag, Opt::CutBegin},
                         {"cutend", Shape::Flag, Opt::CutEnd}};
const OptSpec kControlpoint[] = {{"point", Shape::Ref, Opt::Point},
                                 {"scale", Shape::Vec3, Opt::Scale},
                                 {"rotate", Shape::Rotate, Opt::Rotate},
                                 {"translate", Shape::Vec3, Opt::Translate},
                                 {"crosssection", Shape::Ref, Opt::CrossSection},
                                 {"cross", Shape::Ref, Opt::CrossSection},
                                 {"reverse", Shape::Flag, Opt::Reverse}};
const OptSpec kBackface[] = {{"color", Shape::Vec3, Opt::Color}};
const OptSpec kSweepmorph[] = {{"begincap", Shape::Flag, Opt::BeginCap},
                               {"endcap", Shape::Flag, Opt::EndCap},
                               {"reverse", Shape::Flag, Opt::Reverse}};
const OptSpec kMorphvisualizer[] = {{"sweep", Shape::Ref, Opt::Sweep}, {"index", Shape::Scalar, Opt::Index}};
const OptSpec kZipper[] = {{"border", Shape::Vertices, Opt::Border}, {"penalty", Shape::Scalar, Opt::Penalty}};
const OptSpec kMerge[] = {{"tolerance", Shape::Scalar, Opt::Tolerance},
                          {"epsilon", Shape::Scalar, Opt::Tolerance},
                          {"instance", Shape::Any, Opt::InstanceRef}};
const OptSpec kSubdivision[] = {{"sd_type", Shape::Symbol, Opt::SubdivisionType},
                                {"sd_level", Shape::Scalar, Opt::Levels},
                                {"type", Shape::Symbol, Opt::SubdivisionType},
                                {"subdivisions", Shape::Scalar, Opt::Levels},
                                {"instance", Shape::Any, Opt::InstanceRef},
                                SLIDE_DISPLAY};
const OptSpec kOffset[] = {{"offset_type", Shape::Symbol, Opt::OffsetType}, {"height", Shape::Scalar, Opt::Height},
                           {"width", Shape::Scalar, Opt::Width},            {"type", Shape::Symbol, Opt::OffsetType},
                           {"min", Shape::Scalar, Opt::Height},             {"max", Shape::Scalar, Opt::Ignored},
                           {"step", Shape::Scalar, Opt::Ignored},           {"instance", Shape::Any, Opt::InstanceRef},
                           SLIDE_DISPLAY};
const OptSpec kHandle[] = {{"faces", Shape::Paths, Opt::Faces},         {"corners", Shape::Paths, Opt::Corners},
                           {"segments", Shape::Scalar, Opt::Segments},  {"weights", Shape::Vec2, Opt::Weights},
                           {"twist", Shape::Scalar, Opt::Twist}};
const OptSpec kRind[] = {{"thickness", Shape::Scalar, Opt::Thickness},
                         {"punch", Shape::Paths, Opt::Punch},
                         {"peel", Shape::Paths, Opt::Peel}};
const OptSpec kSierpinski[] = {{"level", Shape::Scalar, Opt::Level}};
const OptSpec kMenger[] = {{"level", Shape::Scalar, Opt::Level},
                           {"thickness", Shape::Scalar, Opt::Thickness},
                           {"collapse", Shape::Scalar, Opt::Collapse}};
// Viewing set-up (slide.md §3.18–3.20; NOME3's `NOME_…` words and `cameraID`, JIPCAD's light
// `direction`). `ribbegin`/`ribend` are RenderMan text: accepted, not used.
const OptSpec kCamera[] = {{"projection", Shape::Symbol, Opt::Projection}, {"frustum", Shape::Frustum, Opt::Frustum},
                           {"ribbegin", Shape::Text, Opt::Ignored}, {"ribend", Shape::Text, Opt::Ignored}};
const OptSpec kLight[] = {{"type", Shape::Symbol, Opt::LightType}, {"color", Shape::Vec3, Opt::Color},
                          {"direction", Shape::Vec3, Opt::Direction}, {"ribbegin", Shape::Text, Opt::Ignored},
                          {"ribend", Shape::Text, Opt::Ignored}};
const OptSpec kWindow[] = {{"background", Shape::Vec3, Opt::Background}, {"origin", Shape::Vec2, Opt::Origin},
                           {"size", Shape::Vec2, Opt::Size},             {"resize", Shape::Symbol, Opt::Resize},
                           {"ratio", Shape::Symbol, Opt::Ratio}};
const OptSpec kViewport[] = {{"origin", Shape::Vec2, Opt::Origin}, {"size", Shape::Vec2, Opt::Size},
                             {"cameraID", Shape::Ref, Opt::CameraId}};
const OptSpec kLookat[] = {{"eye", Shape::Vec3, Opt::Eye}, {"target", Shape::Vec3, Opt::Target}, {"up", Shape::Vec3, Opt::Up}};
const OptSpec kDisplayColor[] = {{"surface", Shape::Surface, Opt::Surface}};
#undef SLIDE_DISPLAY

// The shape an argument of the catalogue is read with when given as an option.
Shape shape_of(ir::ArgType t) {
  switch (t) {
    case ir::ArgType::Flag: return Shape::FlagOrScalar;
    case ir::ArgType::Function: return Shape::Raw;
    case ir::ArgType::Points: return Shape::PointNames;
    case ir::ArgType::Path: return Shape::Ref;
    case ir::ArgType::Count:
    case ir::ArgType::Whole:
    case ir::ArgType::Real:
    case ir::ArgType::Length:
    case ir::ArgType::Ratio:
    case ir::ArgType::Fraction:
    case ir::ArgType::Angle: return Shape::Scalar;
  }
  return Shape::Scalar;
}

}  // namespace

std::span<const OptSpec> options_for(BlockKind kind) {
  switch (kind) {
    case BlockKind::Surface: return kSurface;
    case BlockKind::Point:
    case BlockKind::Vertex: return kPoint;
    case BlockKind::Polyline: return kPolyline;
    case BlockKind::Face:
    case BlockKind::Facet: return kFace;
    case BlockKind::Object: return kObject;
    case BlockKind::Group: return kGroup;
    case BlockKind::Instance: return kInstance;
    case BlockKind::Transform: return kTransform;
    case BlockKind::Sweep: return kSweep;
    case BlockKind::Crosssection: return kCrosssection;
    case BlockKind::Path: return kPath;
    case BlockKind::Controlpoint: return kControlpoint;
    case BlockKind::Backface: return kBackface;
    case BlockKind::Sweepmorph: return kSweepmorph;
    case BlockKind::Morphvisualizer: return kMorphvisualizer;
    case BlockKind::Zipper: return kZipper;
    case BlockKind::Merge: return kMerge;
    case BlockKind::Subdivision: return kSubdivision;
    case BlockKind::Offset: return kOffset;
    case BlockKind::Handle: return kHandle;
    case BlockKind::Rind: return kRind;
    case BlockKind::Sierpinski: return kSierpinski;
    case BlockKind::Menger: return kMenger;
    case BlockKind::Mirror: return kObject;
    case BlockKind::Camera: return kCamera;
    case BlockKind::Light: return kLight;
    case BlockKind::Window: return kWindow;
    case BlockKind::Viewport: return kViewport;
    case BlockKind::Lookat: return kLookat;
    case BlockKind::Render: return {};  // positional, read by its handler (viewing.cpp)
    case BlockKind::Foreground:
    case BlockKind::Background:
    case BlockKind::Insidefaces:
    case BlockKind::Outsidefaces:
    case BlockKind::Offsetfaces: return kDisplayColor;
    case BlockKind::Bank:
    case BlockKind::Mesh:
    case BlockKind::Delete:
    case BlockKind::Sharp:
    case BlockKind::Savedparameter:
    case BlockKind::Consolidate:
    case BlockKind::Consolidateface:
    case BlockKind::Savedworkingmesh:
    case BlockKind::Frontcolor:
    case BlockKind::Backcolor:
    case BlockKind::Backgroundcolor: return {};  // a colour list only
    case BlockKind::Generator: return {};  // per generator and dialect: generator_options
  }
  return {};
}

std::span<const OptSpec> generator_options(ir::GenKind gen, Dialect dialect) {
  // Built once per generator and dialect from the catalogue.
  static const auto tables = [] {
    std::array<std::array<std::vector<OptSpec>, std::size(kDialects)>, ir::kGenKindCount> t;
    for (const ir::GeneratorInfo& g : ir::generators()) {
      for (Dialect d : kDialects) {
        std::vector<OptSpec>& v = t[static_cast<size_t>(g.kind)][static_cast<size_t>(d)];
        for (const ir::OptionInfo& o : g.options) {
          if ((o.dialects & dialect_bit(d)) == 0 || o.arg == ir::kNoArg) continue;
          v.push_back(OptSpec{o.word, shape_of(g.args[o.arg].type), Opt::GenArg, o.arg});
        }
        // SLIDE attaches its display options to every shape.
        if (d == Dialect::Slide) v.insert(v.end(), std::begin(kDisplay), std::end(kDisplay));
      }
    }
    return t;
  }();
  return tables[static_cast<size_t>(gen)][static_cast<size_t>(dialect)];
}

void check_color_list(Context& c, const ast::Ast& a, const ast::Item& list_item) {
  for (ast::ExprId e : a.list(list_item.list).elems) {
    // Evaluate through a throw-away IR expression (no new diagnostics).
    DiagnosticEngine scratch;
    std::swap(scratch, c.diags());
    ir::ExprId ie = lower_expr(c, a, e, false);
    std::swap(scratch, c.diags());
    ir::EvalResult r = ir::evaluate(c.module(), ie);
    if (r.ok && (r.value < 0 || r.value > 1)) {
      c.diags().emit(DiagKind::ColorOutOfRange, a.expr(e).range,
                     fmt::format("colour component {} is outside [0, 1]; colours are RGB fractions, e.g. `(1 0.5 0)`", r.value));
    }
  }
}

bool is_option(std::span<const OptSpec> opts, std::string_view word) {
  return std::any_of(opts.begin(), opts.end(), [&](const OptSpec& o) { return o.name == word; });
}

namespace {

bool is_block_keyword(std::string_view word) {
  const auto& kws = ast::all_open_keywords();
  return std::find(kws.begin(), kws.end(), word) != kws.end();
}

// NOME 2016 read an `instance` line token by token and skipped the tokens it did not know
// (compat.md §B2): in `nome` files they are warnings.
bool ignores_unknown_tokens(const Context& c, const ast::Stmt& s) {
  return c.dialect() == Dialect::Nome && s.kind == BlockKind::Instance;
}

// The option `word` misspells (one or two edits, see is_typo_of), when exactly one is
// closest.
const OptSpec* misspelt_option(std::span<const OptSpec> opts, std::string_view word) {
  const OptSpec* best = nullptr;
  size_t best_distance = SIZE_MAX;
  bool tie = false;
  for (const OptSpec& o : opts) {
    if (o.name.empty() || !is_typo_of(word, o.name)) continue;
    const size_t d = typo_distance(word, o.name, 2);
    if (d < best_distance) {
      best = &o;
      best_distance = d;
      tie = false;
    } else if (d == best_distance && o.name != best->name) {
      tie = true;
    }
  }
  return tie ? nullptr : best;
}

void report_unknown_word(Context& c, const ast::Stmt& s, const ast::Item& it, std::span<const OptSpec> opts) {
  std::vector<std::string_view> names;
  names.reserve(opts.size());
  for (const OptSpec& o : opts) names.push_back(o.name);
  std::string hint = closest_match(it.text, names);
  if (ignores_unknown_tokens(c, s)) {
    auto d = c.diags().emit(DiagKind::IgnoredInstanceToken, it.range,
                            fmt::format("unknown word `{}` on this `instance` line is ignored, as NOME 2016 ignored it{}",
                                        it.text, hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
    if (!hint.empty()) d.fixit(it.range, hint, fmt::format("replace with `{}`", hint));
    return;
  }
  auto d = c.diags().emit(DiagKind::UnknownArgument, it.range,
                          fmt::format("unknown argument `{}` for `{}`{}", it.text, s.keyword,
                                      hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
  if (!hint.empty()) d.fixit(it.range, hint, fmt::format("replace with `{}`", hint));
}


// The expressions of a list of `want` numbers, as an operand of node `id`.
ir::OperandId read_vector(Context& c, const ast::Ast& a, ir::NodeId id, std::string_view name, const ast::Item& list_item,
                          size_t want) {
  const ast::ParenList& list = a.list(list_item.list);
  c.check_commas(a, list_item.list);
  if (list.elems.size() != want) {
    c.diags().emit(DiagKind::ListArity, list.range,
                   fmt::format("`{}` needs {} numbers, got {}{}", name, want, list.elems.size(), c.split_text(a, list)));
  }
  SmallVec<ir::ExprId, 4> exprs;
  for (ast::ExprId e : list.elems) exprs.push_back(lower_expr(c, a, e, false));
  return c.add_operand(id, name, std::move(exprs), list.range);
}

// `rotate (ax ay az) (deg)`: the axis and the angle as one operand of 4 expressions.
bool read_rotate(Context& c, const ast::Ast& a, const ast::Stmt& s, const OptSpec& spec, const ast::Item& kw, size_t& pos,
                 ir::NodeId id, OptionValue& v) {
  auto next = [&]() -> const ast::Item* { return pos < s.items.size() ? &s.items[pos] : nullptr; };
  auto missing = [&](std::string_view what) {
    c.diags().emit(DiagKind::MissingArgument, kw.range, fmt::format("`{}` needs {}", spec.name, what));
  };
  const ast::Item* n = next();
  if (n == nullptr || n->kind != ItemKind::List) {
    missing("an axis `(x y z)` and an angle `(degrees)`");
    return false;
  }
  ++pos;
  const ast::ParenList& axis = a.list(n->list);
  if (axis.elems.size() != 3) {
    c.diags().emit(DiagKind::ListArity, axis.range,
                   fmt::format("`rotate` axis needs 3 numbers, got {}{}", axis.elems.size(), c.split_text(a, axis)));
  }
  SmallVec<ir::ExprId, 4> exprs;
  for (ast::ExprId e : axis.elems) exprs.push_back(lower_expr(c, a, e, false));
  if (const ast::Item* ang = next(); ang && ang->kind == ItemKind::List) {
    ++pos;
    const ast::ParenList& al = a.list(ang->list);
    if (al.elems.size() != 1) {
      c.diags().emit(DiagKind::ListArity, al.range,
                     fmt::format("`rotate` angle needs 1 number (degrees), got {}{}", al.elems.size(), c.split_text(a, al)));
    }
    for (ast::ExprId e : al.elems) exprs.push_back(lower_expr(c, a, e, false));
  } else if (s.kind == BlockKind::Instance || s.kind == BlockKind::Transform) {
    missing("an angle `(degrees)` after its axis");
  }
  v.operand = c.add_operand(id, spec.name, std::move(exprs), kw.range);
  return true;
}

// `frustum (xmin ymin zmin) (xmax ymax zmax)` (SLIDE) or `frustum (l r b t n f)` (NOME3): six
// expressions as one operand.
bool read_frustum(Context& c, const ast::Ast& a, const ast::Stmt& s, const OptSpec& spec, const ast::Item& kw,
                  size_t& pos, ir::NodeId id, OptionValue& v) {
  auto list_at = [&](size_t i) -> const ast::Item* {
    return i < s.items.size() && s.items[i].kind == ItemKind::List ? &s.items[i] : nullptr;
  };
  const ast::Item* first = list_at(pos);
  if (first == nullptr) {
    c.diags().emit(DiagKind::MissingArgument, kw.range,
                   "`frustum` needs two corners, `(xmin ymin zmin) (xmax ymax zmax)`");
    return false;
  }
  ++pos;
  SmallVec<ir::ExprId, 4> exprs;
  const ast::ParenList& l1 = a.list(first->list);
  c.check_commas(a, first->list);
  v.value_range = first->range;
  if (l1.elems.size() == 6 && list_at(pos) == nullptr) {
    v.is_single_list = true;  // NOME3: (left right bottom top near far)
  } else {
    const ast::Item* second = list_at(pos);
    if (l1.elems.size() != 3 || second == nullptr || a.list(second->list).elems.size() != 3) {
      c.diags().emit(DiagKind::ListArity, second == nullptr ? l1.range : SourceRange{l1.range.file, l1.range.begin, second->range.end},
                     fmt::format("`frustum` needs two corners of 3 numbers, `(xmin ymin zmin) (xmax ymax zmax)`{}",
                                 second == nullptr ? fmt::format("; got one list of {}", l1.elems.size()) : std::string()));
      if (second != nullptr) ++pos;
      for (ast::ExprId e : l1.elems) lower_expr(c, a, e, false);
      return false;
    }
    ++pos;
    c.check_commas(a, second->list);
    v.value_range = SourceRange{l1.range.file, l1.range.begin, second->range.end};
    for (ast::ExprId e : l1.elems) exprs.push_back(lower_expr(c, a, e, false));
    for (ast::ExprId e : a.list(second->list).elems) exprs.push_back(lower_expr(c, a, e, false));
    v.operand = c.add_operand(id, spec.name, std::move(exprs), v.value_range);
    return true;
  }
  for (ast::ExprId e : l1.elems) exprs.push_back(lower_expr(c, a, e, false));
  v.operand = c.add_operand(id, spec.name, std::move(exprs), v.value_range);
  return true;
}

// The node a `surface S`, `backface B` or other reference option names, checked for its kind:
// a backface named by `surface` is ignored, as JIPCAD did (compat.md F2); `backface` needs
// a backface colour.
ir::NodeId read_ref(Context& c, Shape shape, const ast::Item& n) {
  const std::string name(n.text);
  if (shape == Shape::Ref) return resolve_any(c, name, n.range);
  if (shape == Shape::Surface) {
    ir::NodeId ref = resolve(c, Ns::Surface, name, n.range, "a surface");
    if (ref.is_valid() && c.module().node(ref).kind == ir::NodeKind::Backface) {
      c.diags().emit(DiagKind::IgnoredReference, n.range,
                     fmt::format("`{}` is a backface colour, which `surface` ignores (as JIPCAD did); use `backface {}`",
                                 name, name));
      return ir::NodeId::None();
    }
    return ref;
  }
  ir::NodeId ref = resolve(c, Ns::Surface, name, n.range, "a backface colour");
  if (ref.is_valid() && c.module().node(ref).kind != ir::NodeKind::Backface) {
    c.diags()
        .emit(DiagKind::WrongKind, n.range,
              fmt::format("`{}` is a {}, but `backface` needs a `backface … color (r g b) endbackface`", name,
                          c.module().node(ref).keyword))
        .note(c.module().node(ref).range, "defined here");
    return ir::NodeId::None();
  }
  return ref;
}

// Reads the value of option `spec` (its word `kw` is already consumed) into `v`; false when
// the value is missing (reported).
bool read_option(Context& c, const ast::Ast& a, const ast::Stmt& s, std::span<const OptSpec> opts, const OptSpec& spec,
                 const ast::Item& kw, size_t& pos, ir::NodeId id, OptionValue& v) {
  auto next = [&]() -> const ast::Item* { return pos < s.items.size() ? &s.items[pos] : nullptr; };
  auto missing = [&](std::string_view what) {
    c.diags().emit(DiagKind::MissingArgument, kw.range, fmt::format("`{}` needs {}", spec.name, what));
  };
  v.spec = &spec;
  v.word = kw.range;
  v.value_range = kw.range;
  switch (spec.shape) {
    case Shape::Flag:
      return true;
    case Shape::FlagOrScalar:
      if (const ast::Item* n = next(); n && n->kind == ItemKind::Value) {
        SmallVec<ir::ExprId, 4> exprs;
        exprs.push_back(scalar_of_item(c, a, *n, false));
        v.operand = c.add_operand(id, spec.name, std::move(exprs), kw.range);
        v.value_range = n->range;
        ++pos;
      }
      return true;
    case Shape::Scalar: {
      const ast::Item* n = next();
      if (n == nullptr || n->kind == ItemKind::Block || (n->kind == ItemKind::Word && is_option(opts, n->text))) {
        missing("a value");
        return false;
      }
      SmallVec<ir::ExprId, 4> exprs;
      exprs.push_back(scalar_of_item(c, a, *n, false));
      v.operand = c.add_operand(id, spec.name, std::move(exprs), kw.range);
      v.value_range = n->range;
      if (n->kind == ItemKind::Value) v.value_expr = n->expr;
      ++pos;
      return true;
    }
    case Shape::Vec2:
    case Shape::Vec3:
    case Shape::Vec4: {
      const size_t want = spec.shape == Shape::Vec2 ? 2 : spec.shape == Shape::Vec3 ? 3 : 4;
      const ast::Item* n = next();
      if (n == nullptr || n->kind != ItemKind::List) {
        missing(fmt::format("a list of {} numbers", want));
        return false;
      }
      ++pos;
      v.operand = read_vector(c, a, id, spec.name, *n, want);
      v.value_range = n->range;
      if (spec.key == Opt::Color) check_color_list(c, a, *n);
      return true;
    }
    case Shape::Rotate:
      return read_rotate(c, a, s, spec, kw, pos, id, v);
    case Shape::Frustum:
      return read_frustum(c, a, s, spec, kw, pos, id, v);
    case Shape::Surface:
    case Shape::Ref:
    case Shape::Backface: {
      const ast::Item* n = next();
      if (n == nullptr || n->kind != ItemKind::Word) {
        missing(spec.shape == Shape::Backface ? "the name of a `backface` colour" : "a name");
        return false;
      }
      ++pos;
      v.value_range = n->range;
      v.ref = read_ref(c, spec.shape, *n);
      if (v.ref.is_valid()) c.module().deps.add_edge(v.ref, id);
      return true;
    }
    case Shape::Names:
    case Shape::PointNames: {
      const ast::Item* n = next();
      if (n == nullptr || n->kind != ItemKind::List) {
        missing("a list of names `(a b …)`");
        return false;
      }
      ++pos;
      v.names = read_names(c, a, *n, id, spec.shape == Shape::PointNames ? Ns::Point : Ns::Count);
      v.value_range = n->range;
      return true;
    }
    case Shape::Paths: {
      const ast::Item* n = next();
      if (n == nullptr || n->kind != ItemKind::List) {
        missing("a list of names `(a.f1 b.f2 …)`");
        return false;
      }
      ++pos;
      c.check_commas(a, n->list);
      for (ast::ExprId e : a.list(n->list).elems) {
        const ast::Expr& x = a.expr(e);
        if (x.kind != ast::ExprKind::Name) {
          c.diags().emit(DiagKind::ExpectedNameList, x.range,
                         fmt::format("expected a name in this list, found `{}`", Context::clip(c.sources().text(x.range))));
          continue;
        }
        v.paths.emplace_back(std::string(x.text), x.range);
      }
      v.value_range = n->range;
      return true;
    }
    case Shape::Vertices: {
      const ast::Item* n = next();
      if (n == nullptr || n->kind != ItemKind::List) {
        missing("a list of vertices `(v1 v2 …)`");
        return false;
      }
      ++pos;
      v.vertices = read_vertices(c, a, *n, id, ir::NodeId::None());
      v.value_range = n->range;
      return true;
    }
    case Shape::Symbol: {
      const ast::Item* n = next();
      if (n == nullptr || n->kind == ItemKind::Block) {
        missing("a value");
        return false;
      }
      ++pos;
      v.value_range = n->range;
      if (n->kind == ItemKind::Word) {
        v.symbol = n->text;
      } else {
        SmallVec<ir::ExprId, 4> exprs;
        exprs.push_back(scalar_of_item(c, a, *n, false));
        v.operand = c.add_operand(id, spec.name, std::move(exprs), n->range);
      }
      return true;
    }
    case Shape::Raw: {
      const ast::Item* n = next();
      if (n == nullptr || n->kind != ItemKind::Value || a.expr(n->expr).kind != ast::ExprKind::Raw) {
        missing("a function in brackets, e.g. `[sin(u)*cos(v)]`");
        return false;
      }
      ++pos;
      v.raw = n->expr;
      v.value_range = n->range;
      return true;
    }
    case Shape::Text: {
      const ast::Item* n = next();
      if (n == nullptr || n->kind != ItemKind::Value || a.expr(n->expr).kind != ast::ExprKind::String) {
        missing("a string in quotes");
        if (n != nullptr && n->kind == ItemKind::Value) ++pos;  // the value given instead
        return false;
      }
      ++pos;
      v.value_range = n->range;
      return true;
    }
    case Shape::Any: {
      const ast::Item* n = next();
      if (n == nullptr || n->kind == ItemKind::Block) {
        missing("a value");
        return false;
      }
      ++pos;
      v.value_range = n->range;
      if (n->kind == ItemKind::Word) v.symbol = n->text;
      if (n->kind == ItemKind::Value) scalar_of_item(c, a, *n, false);
      return true;
    }
    case Shape::Rest:
      while (pos < s.items.size() && s.items[pos].kind != ItemKind::Block) ++pos;
      return true;
  }
  return false;
}

}  // namespace

void read_body(Context& c, const ast::Ast& a, const ast::Stmt& s, size_t pos, ir::NodeId id, std::span<const OptSpec> opts,
               const OptionSink& sink, const PositionalHandler& positional) {
  Ctx child_ctx{id, s.kind, s.keyword, false};
  const bool rest = !opts.empty() && opts[0].shape == Shape::Rest && opts[0].name.empty();
  while (pos < s.items.size()) {
    const ast::Item& it = s.items[pos];
    if (it.kind == ItemKind::Block) {
      const ast::Stmt& child = a.stmt(it.block);
      ir::NodeId cid = handle_stmt(c, a, child, child_ctx);
      if (cid.is_valid() && child.kind != BlockKind::Instance && child.kind != BlockKind::Sharp) c.adopt(id, cid);
      ++pos;
      continue;
    }
    if (rest) {
      ++pos;
      continue;
    }
    if (it.kind == ItemKind::Word) {
      const OptSpec* spec = nullptr;
      for (const OptSpec& o : opts) {
        if (o.name == it.text) {
          spec = &o;
          break;
        }
      }
      if (spec != nullptr) {
        ++pos;
        OptionValue v;
        if (read_option(c, a, s, opts, *spec, it, pos, id, v) && sink) sink(v);
        continue;
      }
      if (positional && positional(it)) {
        ++pos;
        continue;
      }
      if (is_block_keyword(it.text)) {
        // `point p (0 0 0)` followed by `point q … endpoint`: the first one's end keyword is
        // missing, and the rest of this body belongs to the next statement.
        c.diags()
            .emit(DiagKind::MissingEndBeforeStatement, it.range,
                  fmt::format("`{}` starts a new statement, but the `{}` above is not closed; is `{}` missing before it?",
                              it.text, s.keyword, ast::end_keyword(s.keyword)))
            .note(s.open_kw, fmt::format("`{}` opened here", s.keyword))
            .fixit(SourceRange{it.range.file, it.range.begin, it.range.begin},
                   fmt::format("{}\n", ast::end_keyword(s.keyword)), fmt::format("insert `{}`", ast::end_keyword(s.keyword)));
        return;
      }
      // A misspelt option word (`colr (1 0 0)`): one error, and its values are read as the
      // option's, so they raise no errors of their own.
      if (const OptSpec* meant = misspelt_option(opts, it.text)) {
        if (ignores_unknown_tokens(c, s)) {
          // NOME 2016 skipped the word and the lists after it: one warning for them all.
          report_unknown_word(c, s, it, opts);
          ++pos;
          while (pos < s.items.size() && s.items[pos].kind != ItemKind::Word && s.items[pos].kind != ItemKind::Block) ++pos;
          continue;
        }
        c.diags()
            .emit(DiagKind::UnknownArgument, it.range,
                  fmt::format("unknown argument `{}` for `{}`; did you mean `{}`?", it.text, s.keyword, meant->name))
            .fixit(it.range, std::string(meant->name), fmt::format("replace with `{}`", meant->name));
        ++pos;
        OptionValue v;
        {
          // Its values' own problems are the typo's: not reported again.
          DiagnosticEngine scratch;
          std::swap(scratch, c.diags());
          const bool read = read_option(c, a, s, opts, *meant, it, pos, id, v);
          std::swap(scratch, c.diags());
          if (read && sink) sink(v);
        }
        continue;
      }
      report_unknown_word(c, s, it, opts);
      ++pos;
      continue;
    }
    if (positional && positional(it)) {
      ++pos;
      continue;
    }
    std::string what = it.kind == ItemKind::List ? "list" : "value";
    if (ignores_unknown_tokens(c, s)) {
      c.diags().emit(DiagKind::IgnoredInstanceToken, it.range,
                     fmt::format("unexpected {} `{}` on this `instance` line is ignored, as NOME 2016 ignored it", what,
                                 Context::clip(c.sources().text(it.range))));
      ++pos;
      continue;
    }
    c.diags().emit(DiagKind::UnexpectedItem, it.range,
                   fmt::format("unexpected {} `{}` in `{}`", what, Context::clip(c.sources().text(it.range)),
                               s.keyword));
    ++pos;
  }
}

}  // namespace nomec::check

namespace nomec {

std::vector<std::string_view> option_words(std::string_view keyword) {
  std::vector<std::string_view> out;
  const std::optional<ast::BlockKind> kind = ast::block_of_keyword(keyword);
  if (!kind) return out;
  const std::optional<ir::GenKind> gen = ir::generator_by_keyword(keyword);
  for (const check::OptSpec& o : gen ? check::generator_options(*gen, Dialect::Nome) : check::options_for(*kind)) {
    if (!o.name.empty()) out.push_back(o.name);
  }
  return out;
}

}  // namespace nomec
