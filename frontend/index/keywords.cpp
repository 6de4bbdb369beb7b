// Keyword descriptions and classification for the index (see keywords.h). Block keywords
// come from frontend/ast/block_kinds.def, option words from the checker's option tables and
// generators' descriptions from the generator catalogue, so this file only adds the human
// descriptions of the other keywords.
#include "frontend/index/keywords.h"

#include <deque>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "frontend/check/check.h"
#include "ir/generator_catalogue.h"
#include "ir/ir.h"

namespace nomec::index {

using ast::BlockKind;

namespace {

struct KwDoc {
  std::string_view word, doc;
};

const KwDoc kDocs[] = {
    {"bank", "a bank of sliders: `bank NAME set n 8 3 10 1 … endbank`; use them as `$NAME.n`"},
    {"set", "a slider in a bank: `set NAME value min max step`"},
    {"list", "which sliders of the bank a UI shows, in order: `list (n ro)`"},
    {"surface", "a named colour: `surface S color (r g b) endsurface`; as an option, colours a face or instance"},
    {"point", "a named point: `point p (x y z) endpoint`"},
    {"polyline", "a polyline through points: `polyline l (p1 p2 …) [closed] endpolyline`"},
    {"face", "a polygon: `face f (v1 v2 v3 …) endface`; the vertex order gives its orientation"},
    {"facet", "a SLIDE face of a mesh: `facet f (v1 v2 v3 …) endfacet`"},
    {"vertex", "a SLIDE mesh point `vertex p (x y z) endvertex`, or a saved-work vertex reference"},
    {"object", "a mesh built from top-level faces: `object o (f1 f2 …) endobject`"},
    {"mesh", "a mesh built from the points and faces inside it: `mesh m … endmesh`"},
    {"group", "a group of instances that can itself be instanced: `group g … endgroup`"},
    {"instance", "places a mesh, group, generator or block in the scene: `instance NAME TARGET [transforms] endinstance`"},
    {"sweep", "a surface swept along a path: `sweep s crosssection … path … endsweep`"},
    {"crosssection", "the profile curve of a sweep"},
    {"path", "the curve a sweep follows"},
    {"controlpoint", "a control point with its own scale and rotation, for sweeps"},
    {"transform", "a transform block (`translate`, `rotate`, `scale`)"},
    {"lookat", "aims an instance (SLIDE): `lookat eye (x y z) target (x y z) up (x y z) endlookat` puts the origin at the eye, −z towards the target"},
    {"delete", "deletes faces of instances: `delete face inst_f endface enddelete`"},
    {"sharp", "crease sharpness on edges of a mesh: `sharp 9 (v1 v2 …) endsharp`"},
    {"zipper", "zips two border segments together with new faces: `zipper z border (a b) border (c d) endzipper`"},
    {"merge", "merges coinciding border vertices of its instances into one mesh"},
    {"subdivision", "Catmull-Clark subdivision of its merged instances: `sd_type`, `sd_level`"},
    {"offset", "thickens its merged instances into a closed solid: `height`, `width`, `offset_type`"},
    {"handle", "joins two faces by a pipe or a curved, twisted handle: `handle h faces (k.f1 k.f2) [corners (k.a k.b)] [segments E] [weights (E E)] [twist E] … endhandle`"},
    {"rind", "makes a crust of its instances with punched holes and peeled patches: `rind r thickness E [punch (k.f…)] [peel (k.f…)] … endrind`"},
    {"sierpinski", "the generalized Sierpinski polyhedron (corners cut off, joined at the edge midpoints): `sierpinski s level E … endsierpinski`"},
    {"menger", "the generalized Menger sponge (a tunnel through every face): `menger m level E thickness E [collapse E] … endmenger`"},
    {"mirror", "mirrors its instances (SLIDE); as an instance option, `mirror (a b c d)` reflects in the plane ax+by+cz=d"},
    {"savedparameter", "NOME 2016 saved slider values: `savedparameter fp_n 8 … endsavedparameter`"},
    {"consolidate", "NOME 2016 saved work: defines the mesh `consolidatemesh` from instance vertices"},
    {"consolidateface", "a face of `consolidatemesh`, from instance vertices"},
    {"savedworkingmesh", "NOME 2016 saved working mesh"},
    {"camera", "a camera (viewing, used by the preview): `camera C projection SLF_PERSPECTIVE frustum (min) (max) endcamera`"},
    {"light", "a light (viewing, used by the preview): `light L type SLF_DIRECTIONAL color (r g b) endlight`, aimed along its −z"},
    {"window", "a window (viewing): `window W background (r g b) endwindow`; the preview uses its background"},
    {"viewport", "a viewport (viewing): `viewport V WINDOW [origin (x y)] [size (w h)] endviewport`"},
    {"render", "what the preview shows: `render VIEWPORT CAMERA_PATH ROOT (light LIGHT_PATH [SLF_ON|SLF_OFF])* endrender`"},
    {"foreground", "NOME2 display colour of the scene: `foreground surface S endforeground` (accepted and ignored)"},
    {"background", "NOME2 background colour: `background surface S endbackground` (accepted and ignored)"},
    {"insidefaces", "NOME2 colour of inside faces: `insidefaces surface S endinsidefaces` (accepted and ignored)"},
    {"outsidefaces", "NOME2 colour of outside faces: `outsidefaces surface S endoutsidefaces` (accepted and ignored)"},
    {"offsetfaces", "NOME2 colour of offset faces: `offsetfaces surface S endoffsetfaces` (accepted and ignored)"},
    {"frontcolor", "JIPCAD: the viewer's colour of front faces: `frontcolor (r g b) endfrontcolor`"},
    {"backcolor", "JIPCAD: the viewer's colour of back faces: `backcolor (r g b) endbackcolor`"},
    {"backgroundcolor", "JIPCAD: the viewer's background colour: `backgroundcolor (r g b) endbackgroundcolor`"},
    {"backface", "JIPCAD: a named back-face colour `backface NAME color (r g b) endbackface`; as an option, `backface NAME` gives a face or instance that colour on its back"},
    {"sweepmorph", "JIPCAD: a sweep whose cross-section morphs between the cross-sections of its path's control points"},
    {"morphvisualizer", "JIPCAD: one interpolated cross-section of a `sweepmorph`, as a line strip: `morphvisualizer NAME sweep S index E endmorphvisualizer`"},
    {"cross", "NOME3: a control point's cross-section curve (`crosssection` in JIPCAD)"},
    {"include", "reads another file: `include \"file.slf\"`"},
    {"expr", "an expression value: `{expr $fp.n * 2}`"},
    {"tclinit", "SLIDE Tcl code, run once when the scene is read (before names are resolved); `scale` widgets bound to a variable become sliders"},
    {"tclupdate", "SLIDE Tcl code run before every frame; nomec compiles one frame, so it runs once after every `tclinit`"},
    {"translate", "moves the instance: `translate (x y z)`"},
    {"rotate", "rotates the instance: `rotate (ax ay az) (degrees)` about an axis through the origin"},
    {"scale", "scales the instance: `scale (x y z)`"},
    {"hidden", "keeps the instance out of the output; its vertices can still be referenced"},
    {"color", "an RGB colour with components in [0, 1]: `color (1 0.5 0)`"},
    {"closed", "closes the polyline or curve into a loop"},
    {"isloop", "NOME 2016: closes the polyline into a loop"},
    {"sd_type", "subdivision rule: `NOME_SD_CC_sharp` (default), `NOME_SD_CatmullClark`, `NOME_SD_DeRose`"},
    {"sd_level", "number of subdivision steps"},
    {"subdivisions", "SLIDE: number of subdivision steps"},
    {"offset_type", "offset style: plain thickening, or `NOME_OFFSET_GRID` for a lattice"},
    {"height", "offset distance along the vertex normals"},
    {"width", "lattice bar width (grid offset) or ribbon width"},
    {"tolerance", "distance within which border vertices are merged"},
    {"border", "a border segment by its end vertices: `border (a b [m])`"},
    {"penalty", "extra cost per triangle when zipping (default 1.3)"},
    {"id", "SLIDE: the instance's name: `id NAME`"},
    {"azimuth", "start direction of a sweep or ribbon, in degrees"},
    {"twist", "total twist along a sweep or ribbon, in degrees; extra turns of a handle's cross-section"},
    {"mintorsion", "minimise the torsion of the sweep's frame"},
    {"level", "how many times `sierpinski` or `menger` is applied"},
    {"thickness", "distance between a rind's sheets; a Menger sponge's frame width and tunnel depth"},
    {"segments", "rings of quads along a handle (1: a straight pipe)"},
    {"faces", "the two faces a handle joins, through the block's instances: `faces (k.f1 k.f2)`"},
    {"corners", "the corners of a handle's faces to pair first: `corners (k.a k.b)`"},
    {"weights", "a handle's end tangents, as multiples of the distance between its faces"},
    {"punch", "faces of a rind opened into holes through the crust"},
    {"peel", "faces of a rind whose outer sheet is lowered half way"},
    {"collapse", "a Menger sponge's inner walls shorter than this times the thickness collapse"},
    {"pointlist", "SLIDE: the points of a polyline"},
    {"controlpointlist", "the control points of a curve"},
    {"funcX", "x as a function of u and v: `funcX [u*cos(v)]`"},
    {"funcY", "y as a function of u and v"},
    {"funcZ", "z as a function of u and v"},
    {"func", "the function of the surface: `func [x*x - y*y]`"},
};

const std::unordered_map<std::string_view, std::string_view>& doc_map() {
  // Generators are documented by the catalogue; these strings outlive the map's views.
  static const std::vector<std::string> generator_docs = [] {
    std::vector<std::string> out;
    for (const ir::GeneratorInfo& g : ir::generators()) out.push_back("generator: " + std::string(g.summary));
    return out;
  }();
  static const std::unordered_map<std::string_view, std::string_view> m = [] {
    std::unordered_map<std::string_view, std::string_view> out;
    for (const KwDoc& d : kDocs) out.emplace(d.word, d.doc);
    for (const ir::GeneratorInfo& g : ir::generators()) {
      for (std::string_view k : g.keywords) out.emplace(k, generator_docs[static_cast<size_t>(g.kind)]);
    }
    return out;
  }();
  return m;
}

struct Tables {
  std::unordered_set<std::string_view> keywords;
  std::deque<std::string> end_words;  // storage for the views below
  std::unordered_map<std::string_view, std::string> end_docs;
};

const Tables& tables() {
  static const Tables t = [] {
    Tables out;
    for (std::string_view open : ast::all_open_keywords()) {
      std::string_view close = out.end_words.emplace_back(ast::end_keyword(open));
      out.keywords.insert(open);
      out.keywords.insert(close);
      out.end_docs.emplace(close, "closes `" + std::string(open) + "`");
      for (std::string_view w : option_words(open)) out.keywords.insert(w);
    }
    for (std::string_view w : {"set", "list", "include", "expr", "tclinit", "tclupdate"}) out.keywords.insert(w);
    return out;
  }();
  return t;
}

}  // namespace

std::string_view keyword_doc(std::string_view word) {
  const auto& m = doc_map();
  if (auto it = m.find(word); it != m.end()) return it->second;
  const Tables& t = tables();
  if (auto it = t.end_docs.find(word); it != t.end_docs.end()) return it->second;
  if (t.keywords.contains(word)) return "an option word of a statement";
  return {};
}

bool is_keyword(std::string_view word) { return tables().keywords.contains(word); }

bool block_by_open(std::string_view word, BlockKind* kind) {
  const std::optional<BlockKind> k = ast::block_of_keyword(word);
  if (k) *kind = *k;
  return k.has_value();
}

bool block_by_close(std::string_view word, BlockKind* kind) {
  const std::optional<BlockKind> k = ast::block_of_end_keyword(word);
  if (k) *kind = *k;
  return k.has_value();
}

bool closes(std::string_view open, std::string_view close) {
  if (close == ast::end_keyword(open)) return true;
  const std::optional<ir::GenKind> gen = ir::generator_by_keyword(open);
  return gen && ir::generator(*gen).closes_with(open, close);
}

std::vector<BlockKind> child_blocks(BlockKind parent) {
  switch (parent) {
    case BlockKind::Mesh: return {BlockKind::Point, BlockKind::Face, BlockKind::Sharp, BlockKind::Vertex, BlockKind::Facet};
    case BlockKind::Group: return {BlockKind::Instance};
    case BlockKind::Instance: return {BlockKind::Transform};
    case BlockKind::Sweep: return {BlockKind::Crosssection, BlockKind::Path, BlockKind::Controlpoint};
    case BlockKind::Delete: return {BlockKind::Face};
    case BlockKind::Consolidate: return {BlockKind::Consolidateface};
    case BlockKind::Consolidateface: return {BlockKind::Vertex};
    case BlockKind::Savedworkingmesh: return {BlockKind::Face};
    case BlockKind::Merge: case BlockKind::Subdivision: case BlockKind::Offset: case BlockKind::Handle:
    case BlockKind::Rind: case BlockKind::Sierpinski: case BlockKind::Menger: case BlockKind::Mirror:
      return {BlockKind::Instance, BlockKind::Merge, BlockKind::Subdivision, BlockKind::Offset};
    default: return {};
  }
}

const std::vector<FunctionDoc>& functions() {
  static const std::vector<FunctionDoc> f = {
      {"sin", "sin(x)", "sine of x (radians)"},       {"cos", "cos(x)", "cosine of x (radians)"},
      {"tan", "tan(x)", "tangent of x (radians)"},    {"asin", "asin(x)", "arc sine, in radians"},
      {"acos", "acos(x)", "arc cosine, in radians"},  {"atan", "atan(x)", "arc tangent, in radians"},
      {"atan2", "atan2(y, x)", "angle of the point (x, y), in radians"},
      {"sinh", "sinh(x)", "hyperbolic sine"},         {"cosh", "cosh(x)", "hyperbolic cosine"},
      {"tanh", "tanh(x)", "hyperbolic tangent"},      {"sqrt", "sqrt(x)", "square root"},
      {"abs", "abs(x)", "absolute value"},            {"exp", "exp(x)", "e to the power x"},
      {"log", "log(x)", "natural logarithm"},         {"ln", "ln(x)", "natural logarithm"},
      {"log10", "log10(x)", "base-10 logarithm"},     {"pow", "pow(x, y)", "x to the power y"},
      {"min", "min(a, …)", "smallest argument"},      {"max", "max(a, …)", "largest argument"},
      {"floor", "floor(x)", "round down"},            {"ceil", "ceil(x)", "round up"},
      {"round", "round(x)", "round to the nearest whole number"},
      {"sign", "sign(x)", "−1, 0 or 1"},              {"mod", "mod(x, y)", "remainder of x / y"},
  };
  return f;
}

}  // namespace nomec::index
