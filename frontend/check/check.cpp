// Checker implementation. Order of work for one scene:
//   1. parse the file (and, for `.anom` saved work, its base scene first);
//   2. choose the dialect (language.md §1);
//   3. collect banks, then saved parameter values, then `-D` overrides;
//   4. declare every named top-level definition (so uses above a definition get a precise
//      "used before its definition" in NOME, and are legal in SLIDE, which binds late);
//   5. check each statement in order with its kind's handler, lowering into the IR.
// Handlers read a block's flat item list with `StmtReader` and an option table per kind.
#include "frontend/check/check.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <map>
#include <regex>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "backend/generators/domain.h"
#include "frontend/check/signatures.h"
#include "frontend/parse/parse.h"
#include "frontend/source/file_kinds.h"

namespace nomec {

namespace {

using ast::BlockKind;
using ast::ItemKind;

// Namespaces. NOME files share one namespace for shapes; SLIDE keeps surfaces, points and
// faces apart from shapes (`surface Y` and `point Y` coexist in real SLIDE files), and we do
// the same for every dialect because no valid NOME file depends on the difference.
enum class Ns : uint8_t { Surface, Point, Face, Shape, Scene, Count };

std::string_view ns_noun(Ns ns) {
  switch (ns) {
    case Ns::Surface: return "surface";
    case Ns::Point: return "point";
    case Ns::Face: return "face";
    case Ns::Shape: return "mesh, group, generator or curve";
    case Ns::Scene: return "camera, light or viewport";
    case Ns::Count: break;
  }
  return "name";
}

struct Symbol {
  ir::NodeId node;
  SourceRange range;
  int order = 0;  // top-level statement index of the definition
  BlockKind kind = BlockKind::Point;
};

// Option value shapes (see the option tables in `options_for`).
enum class Shape : uint8_t {
  Flag,          // `closed`
  FlagOrScalar,  // `closed` or SLIDE `closed 1`
  Scalar,        // `height 0.2`, `sd_level {expr $b.l}`, `azimuth ($b.a + 180)`
  Vec3,          // `color (1 0 0)`
  Vec2,          // `texture (0 1)`, `weights (1 1)`
  Vec4,          // `mirror (a b c d)`
  Rotate,        // `rotate (ax ay az) (deg)`; the angle list is optional in controlpoints
  Surface,       // `surface S`
  Ref,           // a shape name: `point P`, `cameraID cam1`
  Names,         // `(n1 n2 …)`
  Vertices,      // `(a.hc0 a.hc1)`: vertex references, as in faces
  Symbol,        // `sd_type NOME_SD_CC_sharp`, or a value in SLIDE
  Raw,           // `funcX [ … ]`
  Any,           // one item of any kind (display options of SLIDE/NOME3 we accept and ignore)
  Rest,          // everything up to the end of the block (scene setup)
};

struct OptSpec {
  std::string_view name;
  Shape shape;
};

// Display and UI options SLIDE attaches to many blocks; accepted, checked, not used.
#define SLIDE_DISPLAY                                                                    \
  {"lod", Shape::Any}, {"shading", Shape::Any}, {"drawcontrols", Shape::Any},            \
      {"drawcurrent", Shape::Any}, {"drawvertices", Shape::Any}, {"solid", Shape::Any},  \
      {"errormetric", Shape::Any}, {"uknots", Shape::Any}, {"uorder", Shape::Any},       \
      {"vknots", Shape::Any}, {"vorder", Shape::Any}, {"tolerance", Shape::Scalar},      \
      {"facetsmax", Shape::Any}, {"meshtype", Shape::Any}, {"drawpath", Shape::Any},     \
      {"drawsweep", Shape::Any}

const std::vector<OptSpec>& options_for(BlockKind kind) {
  static const std::vector<OptSpec> none;
  static const std::vector<OptSpec> surface = {{"color", Shape::Vec3}, {"reflectivity", Shape::Vec3},
      {"exponent", Shape::Scalar}, {"metallic", Shape::Scalar}, {"bitmap", Shape::Rest}};
  static const std::vector<OptSpec> point = {{"texture", Shape::Vec2}};
  static const std::vector<OptSpec> polyline = {{"closed", Shape::FlagOrScalar},
      {"isloop", Shape::Flag}, {"pointlist", Shape::Names}};
  static const std::vector<OptSpec> face = {{"surface", Shape::Surface}};
  static const std::vector<OptSpec> object = {{"surface", Shape::Surface}, SLIDE_DISPLAY};
  static const std::vector<OptSpec> group = {{"surface", Shape::Surface}, SLIDE_DISPLAY};
  static const std::vector<OptSpec> instance = {{"translate", Shape::Vec3},
      {"rotate", Shape::Rotate}, {"scale", Shape::Vec3}, {"mirror", Shape::Vec4},
      {"surface", Shape::Surface}, {"hidden", Shape::Flag}, {"id", Shape::Any}, SLIDE_DISPLAY};
  static const std::vector<OptSpec> transform = {{"translate", Shape::Vec3},
      {"rotate", Shape::Rotate}, {"scale", Shape::Vec3}};
  static const std::vector<OptSpec> sweep = {{"azimuth", Shape::Scalar}, {"twist", Shape::Scalar},
      {"mintorsion", Shape::Flag}, SLIDE_DISPLAY};
  static const std::vector<OptSpec> crosssection = {{"type", Shape::Any},
      {"polyline", Shape::Ref}, {"bsplinecurve", Shape::Ref}, {"beziercurve", Shape::Ref},
      {"circle", Shape::Flag}, {"radius", Shape::Scalar}, {"slices", Shape::Scalar},
      {"begincap", Shape::FlagOrScalar}, {"endcap", Shape::FlagOrScalar},
      {"reverse", Shape::Flag}, SLIDE_DISPLAY};
  static const std::vector<OptSpec> path = {{"mintorsion", Shape::Flag},
      {"minimizetorsion", Shape::Scalar}, {"azimuth", Shape::Scalar}, {"twist", Shape::Scalar}};
  static const std::vector<OptSpec> controlpoint = {{"point", Shape::Ref},
      {"scale", Shape::Vec3}, {"rotate", Shape::Rotate}, {"translate", Shape::Vec3}};
  static const std::vector<OptSpec> zipper = {{"border", Shape::Vertices}, {"penalty", Shape::Scalar}};
  static const std::vector<OptSpec> merge = {{"tolerance", Shape::Scalar}};
  static const std::vector<OptSpec> subdivision = {{"sd_type", Shape::Symbol},
      {"sd_level", Shape::Scalar}, {"type", Shape::Symbol}, {"subdivisions", Shape::Scalar},
      SLIDE_DISPLAY};
  static const std::vector<OptSpec> offset = {{"offset_type", Shape::Symbol},
      {"height", Shape::Scalar}, {"width", Shape::Scalar}, {"type", Shape::Symbol}, SLIDE_DISPLAY};
  static const std::vector<OptSpec> handle = {{"faces", Shape::Names}, {"corners", Shape::Names},
      {"segments", Shape::Scalar}, {"weights", Shape::Vec2}, {"twist", Shape::Scalar}};
  static const std::vector<OptSpec> rind = {{"thickness", Shape::Scalar}, {"punch", Shape::Names},
      {"peel", Shape::Names}};
  static const std::vector<OptSpec> sierpinski = {{"level", Shape::Scalar}};
  static const std::vector<OptSpec> menger = {{"level", Shape::Scalar},
      {"thickness", Shape::Scalar}, {"collapse", Shape::Scalar}};
  static const std::vector<OptSpec> rimribbon = {{"path", Shape::Ref}, {"width", Shape::Scalar},
      {"azimuth", Shape::Scalar}, {"twist", Shape::Scalar}};
  static const std::vector<OptSpec> curve = {{"order", Shape::Scalar}, {"segs", Shape::Scalar},
      {"slices", Shape::Scalar}, {"controlpointlist", Shape::Names},
      {"closed", Shape::FlagOrScalar}, SLIDE_DISPLAY};
  static const std::vector<OptSpec> surf_gen = {{"funcX", Shape::Raw}, {"funcY", Shape::Raw},
      {"funcZ", Shape::Raw}, {"func", Shape::Raw}};
  static const std::vector<OptSpec> cylinder = {{"thetaslices", Shape::Scalar},
      {"begincap", Shape::FlagOrScalar}, {"endcap", Shape::FlagOrScalar}, SLIDE_DISPLAY};
  static const std::vector<OptSpec> scene = {{"", Shape::Rest}};
  switch (kind) {
    case BlockKind::Surface: return surface;
    case BlockKind::Point:
    case BlockKind::Vertex: return point;
    case BlockKind::Polyline: return polyline;
    case BlockKind::Face:
    case BlockKind::Facet: return face;
    case BlockKind::Object: return object;
    case BlockKind::Group: return group;
    case BlockKind::Instance: return instance;
    case BlockKind::Transform: return transform;
    case BlockKind::Sweep: return sweep;
    case BlockKind::Crosssection: return crosssection;
    case BlockKind::Path: return path;
    case BlockKind::Controlpoint: return controlpoint;
    case BlockKind::Zipper: return zipper;
    case BlockKind::Merge: return merge;
    case BlockKind::Subdivision: return subdivision;
    case BlockKind::Offset: return offset;
    case BlockKind::Handle: return handle;
    case BlockKind::Rind: return rind;
    case BlockKind::Sierpinski: return sierpinski;
    case BlockKind::Menger: return menger;
    case BlockKind::Mirror: return object;
    case BlockKind::Rimribbon: return rimribbon;
    case BlockKind::Beziercurve:
    case BlockKind::Bspline:
    case BlockKind::Bsplinecurve: return curve;
    case BlockKind::Gencartesiansurf:
    case BlockKind::Genparametricsurf:
    case BlockKind::Genimplicitsurf: return surf_gen;
    case BlockKind::Cylinder: return cylinder;
    case BlockKind::Camera:
    case BlockKind::Light:
    case BlockKind::Window:
    case BlockKind::Viewport:
    case BlockKind::Render:
    case BlockKind::Lookat: return scene;
    case BlockKind::Bank:
    case BlockKind::Mesh:
    case BlockKind::Delete:
    case BlockKind::Sharp:
    case BlockKind::Savedparameter:
    case BlockKind::Consolidate:
    case BlockKind::Consolidateface:
    case BlockKind::Savedworkingmesh:
    case BlockKind::Funnel:
    case BlockKind::Tunnel:
    case BlockKind::Circle:
    case BlockKind::Sphere:
    case BlockKind::Ellipsoid:
    case BlockKind::Hyperboloid:
    case BlockKind::Dupin:
    case BlockKind::Mobiusstrip:
    case BlockKind::Helix:
    case BlockKind::Spiral:
    case BlockKind::Torus:
    case BlockKind::Torusknot: return none;
  }
  return none;
}
#undef SLIDE_DISPLAY

// Vertex naming of generators whose vertices faces may reference (`fun3.hc3`, `fun3_hc3`).
// Returns the ring/loop prefixes and the count argument that bounds the index.
struct VertexNaming {
  std::vector<std::string_view> prefixes;
  std::string_view count_arg;
};
std::optional<VertexNaming> naming_for(BlockKind kind, Dialect dialect) {
  switch (kind) {
    case BlockKind::Funnel:
      return VertexNaming{{"bc", "hc", "v1_", "v2_"}, "n"};
    case BlockKind::Tunnel:
      return VertexNaming{{"bc", "hc", "lc", "v1_", "v2_", "v3_"}, "n"};
    case BlockKind::Circle:
      return VertexNaming{{"v"}, "segs"};
    default:
      return std::nullopt;
  }
}

class Checker {
 public:
  Checker(SourceManager& sources, DiagnosticEngine& diags, const CheckOptions& options,
          ir::Module& module)
      : sources_(sources), diags_(diags), options_(options), m_(module) {}

  Dialect dialect_ = Dialect::Nome;

  // ---------------- dialect ----------------
  std::string choose_dialect(const ast::Ast& a, const std::string& path) {
    std::string ext(path_extension(path));
    if (options_.dialect) {
      dialect_ = *options_.dialect;
      return "chosen with --dialect";
    }
    if (ext == ".slf") {
      dialect_ = Dialect::Slide;
      return "`.slf` extension";
    }
    // Content signals.
    SourceRange nome_at, nome3_at;
    std::string nome_why, nome3_why;
    std::unordered_set<std::string_view> banks;  // views of the syntax tree's text
    for (const ast::Item& it : a.top) {
      if (it.kind == ItemKind::Block && a.stmt(it.block).kind == BlockKind::Bank) {
        const ast::Stmt& s = a.stmt(it.block);
        if (!s.items.empty() && s.items[0].kind == ItemKind::Word) {
          banks.insert(s.items[0].text);
        }
      }
    }
    auto note_nome = [&](SourceRange r, std::string why) {
      if (!nome_at.is_valid()) { nome_at = r; nome_why = std::move(why); }
    };
    auto note_nome3 = [&](SourceRange r, std::string why) {
      if (!nome3_at.is_valid()) { nome3_at = r; nome3_why = std::move(why); }
    };
    for (const ast::Stmt& s : a.stmts) {
      switch (s.kind) {
        case BlockKind::Consolidate:
        case BlockKind::Savedparameter:
        case BlockKind::Savedworkingmesh:
          note_nome(s.open_kw, fmt::format("`{}`", ast::open_keyword(s.kind)));
          break;
        case BlockKind::Tunnel:
          if (s.close_text == "endfunnel") note_nome(s.close_kw, "`tunnel … endfunnel`");
          break;
        case BlockKind::Sweep: case BlockKind::Circle: case BlockKind::Sphere:
        case BlockKind::Ellipsoid: case BlockKind::Hyperboloid: case BlockKind::Dupin:
        case BlockKind::Mobiusstrip: case BlockKind::Helix: case BlockKind::Spiral:
        case BlockKind::Torus: case BlockKind::Torusknot: case BlockKind::Bspline:
        case BlockKind::Gencartesiansurf: case BlockKind::Genparametricsurf:
        case BlockKind::Genimplicitsurf: case BlockKind::Sharp:
          note_nome3(s.open_kw, fmt::format("NOME3 command `{}`", ast::open_keyword(s.kind)));
          break;
        default:
          break;
      }
      for (const ast::Item& it : s.items) {
        if (it.kind == ItemKind::Word) {
          if (it.text == "isloop") note_nome(it.range, "`isloop`");
          if (it.text == "sd_type") note_nome3(it.range, "`sd_type`");
          if (it.text == "list" && s.kind == BlockKind::Bank) note_nome3(it.range, "`list` in a bank");
        }
      }
    }
    // Only the first signal of each kind is kept, so the scan stops once both are known.
    for (const ast::Expr& e : a.exprs) {
      if (nome_at.is_valid() && nome3_at.is_valid()) break;
      if (e.kind != ast::ExprKind::DollarRef) continue;
      std::string_view t = e.text.substr(1);
      if (auto dot = t.find('.'); dot != std::string_view::npos) {
        if (!nome3_at.is_valid() && banks.contains(t.substr(0, dot))) note_nome3(e.range, "`$bank.param`");
      } else if (!nome_at.is_valid()) {
        for (size_t u = t.find('_'); u != std::string_view::npos; u = t.find('_', u + 1)) {
          if (banks.contains(t.substr(0, u))) { note_nome(e.range, "`$bank_param`"); break; }
        }
      }
    }
    Dialect by_ext = ext == ".nom" ? Dialect::Nome3 : Dialect::Nome;
    if (nome_at.is_valid() && nome3_at.is_valid()) {
      dialect_ = by_ext;
      diags_.emit(DiagKind::DialectConflict, nome_at.begin < nome3_at.begin ? nome3_at : nome_at,
                  fmt::format("this file mixes NOME 2016 ({}) and NOME3 ({}) syntax; checking it as `{}`",
                              nome_why, nome3_why, dialect_name(dialect_)))
          .note(nome_at, fmt::format("NOME 2016 signal: {}", nome_why))
          .note(nome3_at, fmt::format("NOME3 signal: {}", nome3_why));
      return fmt::format("conflicting signals; `{}` extension decides", ext);
    }
    if (nome_at.is_valid()) { dialect_ = Dialect::Nome; return "content: " + nome_why; }
    if (nome3_at.is_valid()) { dialect_ = Dialect::Nome3; return "content: " + nome3_why; }
    dialect_ = by_ext;
    return fmt::format("no signals; `{}` extension", ext.empty() ? "(none)" : ext);
  }

  // ---------------- whole file ----------------
  void collect_tcl(const ast::Ast& a) {
    // Names Tcl code creates: `CreateScale NAME PARENT VAR …` gives NAME_VAR (or, inside a
    // proc, `$name_VAR` for whatever name the proc is called with), `set var …` globals,
    // and slideui objects (`CreateSLIDESubdivisionObject oSubdivision`).
    static const std::regex scale_re(R"(CreateScale\s+(\S+)\s+\S+\s+([A-Za-z_][A-Za-z0-9_]*))");
    static const std::regex set_re(R"((?:^|[\s;{])set\s+([A-Za-z_][A-Za-z0-9_]*))");
    static const std::regex obj_re(R"(CreateSLIDE\w*Object\s+([A-Za-z_][A-Za-z0-9_]*))");
    for (const ast::Item& it : a.top) {
      if (it.kind != ItemKind::Tcl) continue;
      std::string text(it.text);
      for (std::sregex_iterator i(text.begin(), text.end(), scale_re), e; i != e; ++i) {
        std::string owner = (*i)[1];
        std::string var = (*i)[2];
        if (!owner.empty() && owner[0] == '$') {
          tcl_suffixes_.insert("_" + var);
        } else {
          tcl_vars_.insert(owner + "_" + var);
        }
      }
      for (std::sregex_iterator i(text.begin(), text.end(), set_re), e; i != e; ++i) {
        tcl_vars_.insert((*i)[1]);
      }
      for (std::sregex_iterator i(text.begin(), text.end(), obj_re), e; i != e; ++i) {
        tcl_vars_.insert((*i)[1]);
      }
      has_tcl_ = true;
    }
  }

  void collect_banks(const ast::Ast& a) {
    for (const ast::Item& it : a.top) {
      if (it.kind == ItemKind::Block && a.stmt(it.block).kind == BlockKind::Bank) {
        handle_bank(a, a.stmt(it.block));
      }
    }
  }

  void apply_saved(const ast::Ast& a) {
    for (const ast::Item& it : a.top) {
      if (it.kind == ItemKind::Block && a.stmt(it.block).kind == BlockKind::Savedparameter) {
        handle_savedparameter(a, a.stmt(it.block));
      }
    }
  }

  void apply_overrides() {
    for (const auto& [name, value] : options_.overrides) {
      std::string key = name;
      ir::NodeId p = lookup_param_text(key);
      if (!p.is_valid()) {
        std::vector<std::string> all;
        for (auto& [k, v] : params_) all.push_back(k);
        std::string hint = closest_match(key, all);
        diags_.emit(DiagKind::OverrideUnknown, SourceRange{},
                    fmt::format("`-D {}={}`: no parameter `{}` in this file{}", name, value, name,
                                hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
        continue;
      }
      ir::Node& n = m_.node(p);
      if ((value < n.min || value > n.max) && !options_.allow_out_of_range) {
        diags_.emit(DiagKind::OverrideOutOfRange, n.range,
                    fmt::format("`-D {}={}` is outside the slider range [{}, {}] of `{}`; pass "
                                "--allow-out-of-range to use it anyway",
                                name, value, n.min, n.max, n.name));
        continue;
      }
      n.value = value;
    }
  }

  void declare(const ast::Ast& a, int order_base) {
    reserve_for(a);
    int order = order_base;
    for (const ast::Item& it : a.top) {
      ++order;
      if (it.kind != ItemKind::Block) continue;
      const ast::Stmt& s = a.stmt(it.block);
      declare_stmt(a, s, order);
    }
  }

  void declare_stmt(const ast::Ast& a, const ast::Stmt& s, int order) {
    Ns ns;
    switch (s.kind) {
      case BlockKind::Surface: ns = Ns::Surface; break;
      case BlockKind::Point: ns = Ns::Point; break;
      case BlockKind::Face: case BlockKind::Facet: ns = Ns::Face; break;
      case BlockKind::Camera: case BlockKind::Light: case BlockKind::Window:
      case BlockKind::Viewport: ns = Ns::Scene; break;
      case BlockKind::Bank: case BlockKind::Instance: case BlockKind::Delete:
      case BlockKind::Sharp: case BlockKind::Savedparameter: case BlockKind::Consolidate:
      case BlockKind::Render: case BlockKind::Zipper: case BlockKind::Vertex:
      case BlockKind::Path: case BlockKind::Transform: case BlockKind::Lookat:
      case BlockKind::Consolidateface:
        return;
      default: ns = Ns::Shape; break;
    }
    if (s.items.empty() || s.items[0].kind != ItemKind::Word) return;  // reported later
    std::string name(s.items[0].text);
    ir::Node node;
    node.kind = node_kind_for(s.kind);
    node.keyword = ast::open_keyword(s.kind);
    node.name = name;
    node.range = s.range;
    ir::NodeId id = m_.add_node(std::move(node));
    define(ns, name, Symbol{id, s.items[0].range, order, s.kind});
    if (ir::NodeId* d = declared_slot(s)) *d = id;
  }

  void define(Ns ns, const std::string& name, Symbol sym) {
    auto& table = scopes_[static_cast<int>(ns)];
    auto [it, inserted] = table.emplace(name, sym);
    if (!inserted) {
      diags_.emit(DiagKind::DuplicateDefinition, sym.range,
                  fmt::format("`{}` is already defined as a {}", name, ast::open_keyword(it->second.kind)))
          .note(it->second.range, "previous definition is here");
    }
  }

  // About one IR expression per syntax expression and two nodes (the statement and a
  // value node) per statement: reserving once avoids moving the arrays while they grow.
  void reserve_for(const ast::Ast& a) {
    m_.exprs.reserve(m_.exprs.size() + a.exprs.size() + a.exprs.size() / 4);
    m_.nodes.reserve(m_.nodes.size() + 2 * a.stmts.size());
    m_.deps.reserve(m_.nodes.capacity());
    declared_.push_back({&a, std::vector<ir::NodeId>(a.stmts.size(), ir::NodeId::None())});
  }

  void process(const ast::Ast& a, int order_base) {
    int order = order_base;
    bool in_stray_run = false;
    for (const ast::Item& it : a.top) {
      ++order;
      order_ = order;
      if (it.kind != ItemKind::Block && it.kind != ItemKind::Tcl && it.kind != ItemKind::Include) {
        if (!in_stray_run) report_stray(it);
        in_stray_run = true;
        continue;
      }
      in_stray_run = false;
      if (it.kind == ItemKind::Include) {
        handle_include(a, it);
        continue;
      }
      if (it.kind == ItemKind::Block) {
        ir::NodeId id = handle_stmt(a, a.stmt(it.block), Ctx{});
        if (id.is_valid()) {
          const ir::Node& n = m_.node(id);
          bool visible = n.kind == ir::NodeKind::Instance ||
                         (n.kind == ir::NodeKind::Pipeline && dialect_ == Dialect::Nome3);
          if (visible && !n.is_hidden) m_.scene.push_back(id);
        }
      }
    }
  }

  void report_stray(const ast::Item& it) {
    if (it.kind == ItemKind::Word) {
      if (it.text == "set" || it.text == "list") {
        diags_.emit(DiagKind::StrayTopLevelItem, it.range,
                    fmt::format("`{}` outside a bank; sliders are declared inside `bank NAME … endbank`", it.text));
        return;
      }
      std::vector<std::string> kws;
      for (std::string_view kw : ast::all_open_keywords()) kws.emplace_back(kw);
      kws.emplace_back("include");
      kws.emplace_back("tclinit");
      std::string hint = closest_match(it.text, kws);
      if (dialect_ == Dialect::Slide && hint.empty()) {
        // language.md §7: SLIDE statements nomec does not implement are named as such.
        diags_.emit(DiagKind::UnsupportedSlideSyntax, it.range,
                    fmt::format("`{}` is SLIDE syntax that nomec does not support yet; the statement is skipped", it.text));
        return;
      }
      auto d = diags_.emit(DiagKind::StrayTopLevelItem, it.range,
                           hint.empty()
                               ? fmt::format("unexpected `{}` at the top level; statements start with a keyword such as `point`, `mesh` or `instance`", it.text)
                               : fmt::format("unknown statement `{}`; did you mean `{}`?", it.text, hint));
      if (!hint.empty()) d.fixit(it.range, hint, fmt::format("replace with `{}`", hint));
      return;
    }
    diags_.emit(DiagKind::StrayTopLevelItem, it.range,
                "unexpected value at the top level; values belong inside a statement such as `point NAME (x y z) endpoint`");
  }

  void handle_include(const ast::Ast& a, const ast::Item& it) {
    std::string rel(it.text);
    std::string_view including = sources_.name(a.file);
    const size_t slash = including.find_last_of('/');
    std::string path = slash == std::string_view::npos || rel.starts_with("/") ? rel : std::string(including.substr(0, slash + 1)) + rel;
    if (rel.empty()) {
      diags_.emit(DiagKind::IncludeFailed, it.range, "`include` needs a file name in quotes, e.g. `include \"viewing.slf\"`");
      return;
    }
    if (include_depth_ >= 16) {
      diags_.emit(DiagKind::IncludeFailed, it.range,
                  fmt::format("`include \"{}\"` nests more than 16 files deep; does a file include itself?", rel));
      return;
    }
    std::optional<std::string> text;
    if (options_.read_file) text = options_.read_file(path);
    if (!text) {
      diags_.emit(DiagKind::IncludeFailed, it.range,
                  fmt::format("cannot read included file `{}` (looked for `{}`)", rel, path));
      return;
    }
    FileId f = sources_.add_file(path, std::move(*text));
    owned_asts_.push_back(std::make_unique<ast::Ast>(parse_file(sources_, f, diags_)));
    const ast::Ast& inc = *owned_asts_.back();
    ++include_depth_;
    collect_tcl(inc);
    collect_banks(inc);
    // An included file sees every definition of the including file (SLIDE binds late).
    int base_order = 1 << 20;
    declare(inc, base_order * include_depth_);
    int saved_order = order_;
    process(inc, base_order * include_depth_);
    order_ = saved_order;
    --include_depth_;
  }

  // ---------------- statements ----------------
  struct Ctx {
    ir::NodeId parent;          // enclosing mesh/group/pipeline node
    BlockKind parent_kind = BlockKind::Bank;  // Bank = top level
    bool top = true;
  };

  static ir::NodeKind node_kind_for(BlockKind k) {
    switch (ast::category(k)) {
      case ast::BlockCategory::Gen:
        return k == BlockKind::Beziercurve || k == BlockKind::Bspline || k == BlockKind::Bsplinecurve ||
                       k == BlockKind::Circle || k == BlockKind::Helix || k == BlockKind::Spiral
                   ? ir::NodeKind::Curve
                   : k == BlockKind::Sweep ? ir::NodeKind::Sweep : ir::NodeKind::Generator;
      case ast::BlockCategory::Pipe: return ir::NodeKind::Pipeline;
      case ast::BlockCategory::Edit: return ir::NodeKind::Edit;
      default: break;
    }
    switch (k) {
      case BlockKind::Surface: return ir::NodeKind::Surface;
      case BlockKind::Point: case BlockKind::Vertex: return ir::NodeKind::Point;
      case BlockKind::Polyline: return ir::NodeKind::Polyline;
      case BlockKind::Face: case BlockKind::Facet: return ir::NodeKind::Face;
      case BlockKind::Object: case BlockKind::Mesh: case BlockKind::Savedworkingmesh:
      case BlockKind::Consolidate: return ir::NodeKind::Mesh;
      case BlockKind::Group: return ir::NodeKind::Group;
      case BlockKind::Instance: return ir::NodeKind::Instance;
      case BlockKind::Savedparameter: return ir::NodeKind::Saved;
      default: return ir::NodeKind::Edit;
    }
  }

  static BlockKind kind_by_open(std::string_view kw) {
    for (int k = 0; k < ast::kBlockKindCount; ++k) {
      auto kind = static_cast<BlockKind>(k);
      if (ast::open_keyword(kind) == kw) return kind;
    }
    return BlockKind::Point;
  }

  // Creates (or reuses the declared) node for a statement.
  ir::NodeId node_for(const ast::Stmt& s, std::string name, const Ctx& ctx) {
    if (const ir::NodeId* d = declared_slot(s); d != nullptr && d->is_valid()) return *d;
    ir::Node node;
    node.kind = node_kind_for(s.kind);
    node.keyword = ast::open_keyword(s.kind);
    node.name = std::move(name);
    node.range = s.range;
    node.parent = ctx.parent;
    return m_.add_node(std::move(node));
  }

  // Reads the name that follows the keyword; reports MissingName if absent.
  std::optional<std::string> read_name(const ast::Stmt& s, size_t& pos, std::string_view example) {
    if (pos < s.items.size() && s.items[pos].kind == ItemKind::Word) {
      return std::string(s.items[pos++].text);
    }
    diags_.emit(DiagKind::MissingName, s.open_kw,
                fmt::format("`{}` needs a name, e.g. `{}`", ast::open_keyword(s.kind), example));
    return std::nullopt;
  }

  ir::NodeId handle_stmt(const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
    switch (s.kind) {
      case BlockKind::Bank:
      case BlockKind::Savedparameter:
        if (!ctx.top) misplaced(s, ctx);
        return ir::NodeId::None();  // handled before everything else
      case BlockKind::Surface: return handle_generic(a, s, ctx, "surface S color (1 0 0) endsurface");
      case BlockKind::Point: return handle_point(a, s, ctx);
      case BlockKind::Vertex: return handle_vertex(a, s, ctx);
      case BlockKind::Polyline: return handle_generic(a, s, ctx, "polyline l (p1 p2) endpolyline");
      case BlockKind::Face:
      case BlockKind::Facet: return handle_face(a, s, ctx);
      case BlockKind::Object: return handle_generic(a, s, ctx, "object o (f1 f2) endobject");
      case BlockKind::Mesh: return handle_container(a, s, ctx, "mesh m … endmesh");
      case BlockKind::Group: return handle_container(a, s, ctx, "group g … endgroup");
      case BlockKind::Instance: return handle_instance(a, s, ctx);
      case BlockKind::Sweep: return handle_container(a, s, ctx, "sweep s … endsweep");
      case BlockKind::Crosssection: return handle_generic(a, s, ctx, "crosssection c … endcrosssection");
      case BlockKind::Path: return handle_generic(a, s, ctx, "path p … endpath");
      case BlockKind::Controlpoint: return handle_generic(a, s, ctx, "controlpoint cp point p endcontrolpoint");
      case BlockKind::Transform: return handle_generic(a, s, ctx, "");
      case BlockKind::Delete: return handle_container(a, s, ctx, "");
      case BlockKind::Sharp: return handle_sharp(a, s, ctx);
      case BlockKind::Zipper: return handle_generic(a, s, ctx, "zipper z border (a b) border (c d) endzipper");
      case BlockKind::Merge: case BlockKind::Subdivision: case BlockKind::Offset:
      case BlockKind::Handle: case BlockKind::Rind: case BlockKind::Sierpinski:
      case BlockKind::Menger: case BlockKind::Mirror:
        return handle_container(a, s, ctx, fmt::format("{} name … end{}", ast::open_keyword(s.kind), ast::open_keyword(s.kind)));
      case BlockKind::Consolidate: return handle_container(a, s, ctx, "");
      case BlockKind::Consolidateface: return handle_container(a, s, ctx, "");
      case BlockKind::Savedworkingmesh: return handle_container(a, s, ctx, "savedworkingmesh m … endsavedworkingmesh");
      case BlockKind::Camera: case BlockKind::Light: case BlockKind::Window:
      case BlockKind::Viewport: case BlockKind::Render: case BlockKind::Lookat:
        return handle_scene(a, s, ctx);
      case BlockKind::Funnel: case BlockKind::Tunnel: case BlockKind::Rimribbon:
      case BlockKind::Circle: case BlockKind::Sphere: case BlockKind::Ellipsoid:
      case BlockKind::Cylinder: case BlockKind::Hyperboloid: case BlockKind::Dupin:
      case BlockKind::Mobiusstrip: case BlockKind::Helix: case BlockKind::Spiral:
      case BlockKind::Torus: case BlockKind::Torusknot: case BlockKind::Beziercurve:
      case BlockKind::Bspline: case BlockKind::Bsplinecurve: case BlockKind::Gencartesiansurf:
      case BlockKind::Genparametricsurf: case BlockKind::Genimplicitsurf:
        return handle_generator(a, s, ctx);
    }
    return ir::NodeId::None();
  }

  void misplaced(const ast::Stmt& s, const Ctx& ctx) {
    diags_.emit(DiagKind::MisplacedStatement, s.open_kw,
                fmt::format("`{}` cannot appear inside `{}`", ast::open_keyword(s.kind),
                            ast::open_keyword(ctx.parent_kind)));
  }

  // -------- banks and saved parameters --------
  void handle_bank(const ast::Ast& a, const ast::Stmt& s) {
    size_t pos = 0;
    auto name = read_name(s, pos, "bank b set n 8 3 10 1 endbank");
    if (!name) return;
    param_text_memo_.clear();  // a new bank may change how `bank_param` resolves
    if (auto [it, ok] = banks_.emplace(*name, s.items[0].range); !ok) {
      diags_.emit(DiagKind::DuplicateDefinition, s.items[0].range,
                  fmt::format("bank `{}` is already defined", *name))
          .note(it->second, "previous definition is here");
    }
    while (pos < s.items.size()) {
      const ast::Item& it = s.items[pos];
      if (it.kind == ItemKind::Word && it.text == "set") {
        ++pos;
        handle_set(a, s, *name, it, pos);
      } else if (it.kind == ItemKind::Word && it.text == "list") {
        ++pos;
        if (pos < s.items.size() && s.items[pos].kind == ItemKind::List) {
          for (ast::ExprId e : a.list(s.items[pos].list).elems) {
            const ast::Expr& ex = a.expr(e);
            if (ex.kind != ast::ExprKind::Name) {
              diags_.emit(DiagKind::ExpectedNameList, ex.range, "`list` names the sliders to show; expected a parameter name");
            } else if (!params_.contains(*name + "." + std::string(ex.text))) {
              pending_list_.push_back({*name, std::string(ex.text), ex.range});
            }
          }
          check_commas(a, s.items[pos].list);
          ++pos;
        } else if (pos < s.items.size() && s.items[pos].kind == ItemKind::Word &&
                   s.items[pos].text == "set") {
          // `list` with no names (NOME3 allowed an empty `list` line).
        } else if (pos >= s.items.size()) {
        } else {
          diags_.emit(DiagKind::MissingArgument, it.range, "`list` needs a parenthesised list of slider names, e.g. `list (n ro)`");
        }
      } else {
        std::string what = it.kind == ItemKind::Word ? fmt::format("`{}`", it.text)
                                                     : fmt::format("value `{}`", clip(sources_.text(it.range)));
        auto d = diags_.emit(DiagKind::UnknownArgument, it.range,
                             fmt::format("unexpected {} in bank `{}`; a bank holds `set NAME value min max step` lines and an optional `list (…)`", what, *name));
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

  void handle_set(const ast::Ast& a, const ast::Stmt& bank, const std::string& bank_name,
                  const ast::Item& set_kw, size_t& pos) {
    if (pos >= bank.items.size() || bank.items[pos].kind != ItemKind::Word ||
        bank.items[pos].text == "set" || bank.items[pos].text == "list") {
      diags_.emit(DiagKind::MissingName, set_kw.range, "`set` needs a slider name: `set NAME value min max step`");
      while (pos < bank.items.size() && bank.items[pos].kind != ItemKind::Word) ++pos;  // its values
      return;
    }
    const ast::Item& name_item = bank.items[pos++];
    std::string pname(name_item.text);
    std::vector<const ast::Item*> vals;
    while (pos < bank.items.size() && bank.items[pos].kind != ItemKind::Word) {
      vals.push_back(&bank.items[pos++]);
    }
    double v[4] = {0, 0, 0, 1};
    bool ok = true;
    if (vals.size() != 4) {
      SourceRange r = vals.empty() ? name_item.range : SourceRange{name_item.range.file, vals.front()->range.begin, vals.back()->range.end};
      std::vector<std::string> shown;
      for (auto* it : vals) shown.push_back(fmt::format("`{}`", sources_.text(it->range)));
      diags_.emit(DiagKind::ListArity, r,
                  fmt::format("`set {}` needs 4 numbers (value min max step), got {}{}", pname, vals.size(),
                              shown.empty() ? "" : fmt::format(": {}", fmt::join(shown, " | "))));
      ok = false;
    }
    for (size_t i = 0; i < vals.size() && i < 4; ++i) {
      ir::ExprId e = scalar_of_item(a, *vals[i], /*constant=*/true);
      ir::EvalResult r = ir::evaluate(m_, e);
      if (!r.ok) { ok = false; continue; }
      v[i] = r.value;
    }
    std::string key = bank_name + "." + pname;
    if (params_.contains(key)) {
      diags_.emit(DiagKind::DuplicateDefinition, name_item.range,
                  fmt::format("slider `{}` is already defined in bank `{}`", pname, bank_name))
          .note(m_.node(params_[key]).range, "previous definition is here");
      return;
    }
    ir::Node p;
    p.kind = ir::NodeKind::Param;
    p.keyword = "set";
    p.name = key;
    p.bank = bank_name;
    p.range = name_item.range;
    p.value = v[0];
    p.min = v[1];
    p.max = v[2];
    p.step = v[3];
    ir::NodeId id = m_.add_node(std::move(p));
    params_[key] = id;
    param_text_memo_.clear();  // a new slider may change how `bank_param` resolves
    if (!ok || vals.size() != 4) return;
    if (v[1] > v[2]) {
      diags_.emit(DiagKind::BankRange, vals[1]->range,
                  fmt::format("slider `{}`: min {} is greater than max {}", key, v[1], v[2]))
          .note(vals[2]->range, "max is here");
    } else if (v[3] <= 0) {
      diags_.emit(DiagKind::BankRange, vals[3]->range,
                  fmt::format("slider `{}`: step {} must be positive", key, v[3]));
    } else if (v[0] < v[1] || v[0] > v[2]) {
      diags_.emit(DiagKind::ValueOutOfRange, vals[0]->range,
                  fmt::format("slider `{}`: value {} is outside its range [{}, {}]", key, v[0], v[1], v[2]));
    }
  }

  void handle_savedparameter(const ast::Ast& a, const ast::Stmt& s) {
    for (size_t i = 0; i < s.items.size(); ++i) {
      const ast::Item& it = s.items[i];
      if (it.kind != ItemKind::Word) {
        diags_.emit(DiagKind::UnexpectedItem, it.range, "expected `bank_param value` pairs in `savedparameter`");
        continue;
      }
      if (i + 1 >= s.items.size() || s.items[i + 1].kind != ItemKind::Value) {
        diags_.emit(DiagKind::MissingArgument, it.range, fmt::format("saved parameter `{}` has no value", it.text));
        continue;
      }
      ir::ExprId e = scalar_of_item(a, s.items[++i], true);
      ir::EvalResult r = ir::evaluate(m_, e);
      std::string key(it.text);
      ir::NodeId p = lookup_param_text(key);
      if (!p.is_valid()) {
        // Saved work may name sliders the scene no longer has (real files do): warn.
        diags_.emit(DiagKind::StaleSavedParameter, it.range,
                    fmt::format("saved value for `{}`, but the scene has no such slider; the value is ignored", key));
        continue;
      }
      if (r.ok) m_.node(p).value = r.value;
    }
  }

  // -------- generic statements driven by option tables --------
  ir::NodeId handle_generic(const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx, std::string_view example) {
    size_t pos = 0;
    std::string name;
    bool named = s.kind != BlockKind::Transform;
    if (named) {
      if (auto n = read_name(s, pos, example)) name = *n;
    }
    ir::NodeId id = node_for(s, qualify(ctx, name), ctx);
    if (s.kind == BlockKind::Path || (s.kind == BlockKind::Crosssection && !ctx.top)) {
      // Sweep clauses: the name refers to a curve or cross section.
      if (!name.empty()) {
        ir::NodeId target = resolve(Ns::Shape, name, s.items[0].range, "a curve or polyline");
        add_ref_field(id, s.kind == BlockKind::Path ? "path" : "crosssection", target, s.items[0].range);
      }
    }
    auto positional = [&](const ast::Item& it) -> bool {
      switch (s.kind) {
        case BlockKind::Polyline:
          if (it.kind != ItemKind::List) return false;
          add_vertices_field(a, id, "points", it, ir::NodeId::None());
          if (a.list(it.list).elems.size() < 2) {
            diags_.emit(DiagKind::ListArity, it.range, "a polyline needs at least 2 points");
          }
          return true;
        case BlockKind::Object:
          if (it.kind != ItemKind::List) return false;
          add_names_field(a, id, "faces", it, Ns::Face);
          return true;
        case BlockKind::Crosssection:
          // SLIDE `type polyline NAME`: the curve the cross section is made of.
          if (it.kind != ItemKind::Word) return false;
          add_ref_field(id, "shape", resolve_any(std::string(it.text), it.range), it.range);
          return true;
        default:
          return false;
      }
    };
    read_body(a, s, pos, id, ctx, positional);
    return id;
  }

  ir::NodeId handle_point(const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
    size_t pos = 0;
    auto name = read_name(s, pos, "point p (1 0 0) endpoint");
    ir::NodeId id = node_for(s, qualify(ctx, name.value_or("")), ctx);
    if (!ctx.top) {
      if (ctx.parent_kind != BlockKind::Mesh) { misplaced(s, ctx); }
      if (name) mesh_points_[ctx.parent.index][*name] = id;
    }
    if (pos < s.items.size() && s.items[pos].kind == ItemKind::List) {
      add_vector_field(a, id, "position", s.items[pos], 3);
      ++pos;
    } else {
      diags_.emit(DiagKind::MissingArgument, name ? s.items[0].range : s.open_kw,
                  "a point needs a position `(x y z)`");
    }
    read_body(a, s, pos, id, ctx);
    return id;
  }

  // `vertex` is a SLIDE mesh point (`vertex p (x y z) endvertex`) or a 2016 saved-work
  // vertex reference (`vertex fun3_hc3 endvertex`).
  ir::NodeId handle_vertex(const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
    if (ctx.parent_kind == BlockKind::Mesh) return handle_point(a, s, ctx);
    if (s.items.size() != 1 || s.items[0].kind != ItemKind::Word) {
      diags_.emit(DiagKind::MissingArgument, s.open_kw, "`vertex` names one vertex: `vertex fun3_hc3 endvertex`");
      return ir::NodeId::None();
    }
    if (ctx.parent.is_valid()) {
      ir::Node& parent = m_.node(ctx.parent);
      if (parent.fields.empty() || parent.fields.back().name != "vertices") {
        ir::Field f;
        f.name = "vertices";
        f.kind = ir::FieldKind::Vertices;
        f.range = s.range;
        parent.fields.push_back(f);
      }
      ir::VertexRef ref = resolve_vertex(std::string(s.items[0].text), s.items[0].range, ir::NodeId::None());
      add_vertex_edges(ctx.parent, ref);
      m_.node(ctx.parent).fields.back().vertices.push_back(std::move(ref));
    }
    return ir::NodeId::None();
  }

  ir::NodeId handle_face(const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
    size_t pos = 0;
    if (ctx.parent_kind == BlockKind::Delete) {
      // `face inst_face endface`: a face to delete, by 2016 name.
      if (s.items.size() == 1 && s.items[0].kind == ItemKind::Word) {
        ir::Node& del = m_.node(ctx.parent);
        if (del.fields.empty()) {
          ir::Field f;
          f.name = "faces";
          f.kind = ir::FieldKind::Text;
          del.fields.push_back(f);
        }
        del.fields[0].text += (del.fields[0].text.empty() ? "" : " ") + std::string(s.items[0].text);
        return ir::NodeId::None();
      }
      diags_.emit(DiagKind::MissingArgument, s.open_kw, "a face to delete is named alone: `face inst_f endface`");
      return ir::NodeId::None();
    }
    if (ctx.parent_kind == BlockKind::Savedworkingmesh) {
      ir::NodeId id = node_for(s, qualify(ctx, ""), ctx);
      m_.node(ctx.parent).children.push_back(id);
      m_.deps.add_edge(id, ctx.parent);
      read_body(a, s, pos, id, Ctx{id, BlockKind::Face, false});
      check_face_vertices(id, s.open_kw);
      return id;
    }
    auto name = read_name(s, pos, "face f (p1 p2 p3) endface");
    ir::NodeId id = node_for(s, qualify(ctx, name.value_or("")), ctx);
    if (pos < s.items.size() && s.items[pos].kind == ItemKind::List) {
      add_vertices_field(a, id, "vertices", s.items[pos], ctx.parent_kind == BlockKind::Mesh ? ctx.parent : ir::NodeId::None());
      ++pos;
      check_face_vertices(id, s.range);
    } else if (name) {
      diags_.emit(DiagKind::MissingArgument, s.items[0].range, "a face needs its vertices `(v1 v2 v3 …)`");
    }
    read_body(a, s, pos, id, ctx);
    return id;
  }

  void check_face_vertices(ir::NodeId face, SourceRange at) {
    const ir::Node& f = m_.node(face);
    for (const ir::Field& fld : f.fields) {
      if (fld.kind != ir::FieldKind::Vertices) continue;
      if (fld.vertices.size() < 3) {
        diags_.emit(DiagKind::FaceTooFewVertices, fld.range.is_valid() ? fld.range : at,
                    fmt::format("a face needs at least 3 vertices, got {}", fld.vertices.size()));
      }
      for (size_t i = 0; i < fld.vertices.size(); ++i) {
        for (size_t j = i + 1; j < fld.vertices.size(); ++j) {
          if (fld.vertices[i].text == fld.vertices[j].text) {
            diags_.emit(DiagKind::FaceRepeatedVertex, fld.vertices[j].range,
                        fmt::format("vertex `{}` appears twice in this face", fld.vertices[j].text))
                .note(fld.vertices[i].range, "first use is here");
          }
        }
      }
    }
  }

  ir::NodeId handle_sharp(const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
    if (ctx.parent_kind != BlockKind::Mesh) {
      diags_.emit(DiagKind::MisplacedStatement, s.open_kw,
                  "`sharp` marks edges of a mesh and must be inside `mesh … endmesh`");
    }
    ir::NodeId id = node_for(s, "", ctx);
    size_t pos = 0;
    if (pos < s.items.size() && (s.items[pos].kind == ItemKind::Value)) {
      ir::Field f;
      f.name = "sharpness";
      f.kind = ir::FieldKind::Scalar;
      f.range = s.items[pos].range;
      f.exprs.push_back(scalar_of_item(a, s.items[pos], false));
      add_field(id, std::move(f));
      ++pos;
    } else {
      diags_.emit(DiagKind::MissingArgument, s.open_kw, "`sharp` needs a sharpness value first: `sharp 9 (v1 v2 v3) endsharp`");
    }
    bool any = false;
    for (; pos < s.items.size(); ++pos) {
      if (s.items[pos].kind == ItemKind::List) {
        add_vertices_field(a, id, "edges", s.items[pos], ctx.parent);
        any = true;
      } else {
        diags_.emit(DiagKind::UnexpectedItem, s.items[pos].range, "`sharp` takes vertex lists `(v1 v2 …)` after its sharpness");
      }
    }
    if (!any) diags_.emit(DiagKind::MissingArgument, s.open_kw, "`sharp` needs at least one vertex list `(v1 v2 …)`");
    if (ctx.parent.is_valid()) {
      m_.node(ctx.parent).children.push_back(id);
      m_.deps.add_edge(id, ctx.parent);
    }
    return id;
  }

  // mesh, group, sweep, delete, pipelines, consolidate, savedworkingmesh: name + options +
  // nested statements.
  ir::NodeId handle_container(const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx, std::string_view example) {
    size_t pos = 0;
    std::string name;
    bool needs_name = s.kind != BlockKind::Delete && s.kind != BlockKind::Consolidate &&
                      s.kind != BlockKind::Consolidateface;
    if (needs_name) {
      if (auto n = read_name(s, pos, example)) name = *n;
    }
    if (s.kind == BlockKind::Consolidate && name.empty()) {
      name = "consolidatemesh";
      // `consolidate` defines the mesh `consolidatemesh` (language.md §6.5).
      if (!scopes_[static_cast<int>(Ns::Shape)].contains(name)) {
        ir::NodeId id = node_for(s, name, ctx);
        define(Ns::Shape, name, Symbol{id, s.open_kw, order_, s.kind});
        if (ir::NodeId* d = declared_slot(s)) *d = id;
      }
    }
    ir::NodeId id = node_for(s, qualify(ctx, name), ctx);
    if (s.kind == BlockKind::Delete || s.kind == BlockKind::Consolidate) {
      m_.node(id).name = name;
    }
    read_body(a, s, pos, id, Ctx{id, s.kind, false});
    if (s.kind == BlockKind::Consolidateface) check_face_vertices(id, s.open_kw);
    if (ctx.parent.is_valid()) m_.deps.add_edge(id, ctx.parent);
    return id;
  }

  ir::NodeId handle_scene(const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
    if (s.kind != BlockKind::Lookat) {
      diags_.emit(DiagKind::IgnoredStatement, s.open_kw,
                  fmt::format("`{}` sets up viewing, which nomec does not render; accepted and ignored", ast::open_keyword(s.kind)));
    }
    std::string name;
    if (!s.items.empty() && s.items[0].kind == ItemKind::Word && s.kind != BlockKind::Lookat) name = std::string(s.items[0].text);
    ir::NodeId id = node_for(s, qualify(ctx, name), ctx);
    // Parameter references inside still resolve (they are part of the scene's sliders).
    for (const ast::Item& it : s.items) {
      if (it.kind == ItemKind::Value) scalar_of_item(a, it, false, id);
      if (it.kind == ItemKind::List) {
        for (ast::ExprId e : a.list(it.list).elems) {
          if (a.expr(e).kind != ast::ExprKind::Name) to_ir(a, e, false, id);
        }
      }
    }
    return id;
  }

  ir::NodeId handle_instance(const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
    size_t pos = 0;
    std::string name;
    const ast::Item* target_item = nullptr;
    bool slide_form = dialect_ == Dialect::Slide;
    // A NOME instance is `instance NAME TARGET`; SLIDE's is `instance TARGET [id NAME]`.
    if (!slide_form) {
      if (auto n = read_name(s, pos, "instance i mesh_name endinstance")) name = *n;
      if (pos < s.items.size() && s.items[pos].kind == ItemKind::Word && !is_option(s.kind, s.items[pos].text)) {
        target_item = &s.items[pos++];
      } else if (!name.empty()) {
        diags_.emit(DiagKind::MissingArgument, s.items[0].range,
                    fmt::format("instance `{}` needs a target after its name: `instance {} MESH endinstance`", name, name));
      }
    } else {
      if (pos < s.items.size() && s.items[pos].kind == ItemKind::Word) {
        target_item = &s.items[pos++];
        name = std::string(target_item->text);
      } else {
        diags_.emit(DiagKind::MissingName, s.open_kw, "`instance` needs a target: `instance MESH endinstance`");
      }
      for (size_t i = pos; i + 1 < s.items.size(); ++i) {
        if (s.items[i].kind == ItemKind::Word && s.items[i].text == "id" && s.items[i + 1].kind == ItemKind::Word) {
          name = std::string(s.items[i + 1].text);
        }
      }
    }
    ir::NodeId id = node_for(s, qualify(ctx, name), ctx);
    if (target_item != nullptr) {
      ir::NodeId target = resolve_target(std::string(target_item->text), target_item->range);
      m_.node(id).target = target;
      m_.deps.add_edge(target, id);
    }
    // Instance names live in the scope of their parent (top level, group or block).
    if (!name.empty()) {
      auto& scope = instance_scopes_[ctx.parent.index + 1];
      if (auto it = scope.find(name); it != scope.end()) {
        diags_.emit(DiagKind::DuplicateInstanceName, s.items[0].range,
                    fmt::format("instance name `{}` is used twice in this {}; paths through `{}` will be ambiguous",
                                name, ctx.top ? "file" : ast::open_keyword(ctx.parent_kind), name))
            .note(m_.node(it->second).range, "first instance with this name");
      } else {
        scope[name] = id;
      }
    }
    read_body(a, s, pos, id, Ctx{id, BlockKind::Instance, false});
    if (ctx.parent.is_valid()) {
      m_.node(ctx.parent).children.push_back(id);
      m_.deps.add_edge(id, ctx.parent);
    }
    for (const ir::Field& f : m_.node(id).fields) {
      if (f.kind == ir::FieldKind::Flag && f.name == "hidden") m_.node(id).is_hidden = true;
    }
    return id;
  }

  ir::NodeId handle_generator(const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
    size_t pos = 0;
    auto name = read_name(s, pos, fmt::format("{} g (…) end{}", ast::open_keyword(s.kind), ast::open_keyword(s.kind)));
    ir::NodeId id = node_for(s, qualify(ctx, name.value_or("")), ctx);
    if (s.kind == BlockKind::Tunnel && s.close_text == "endfunnel") {
      diags_.emit(DiagKind::TunnelEndfunnel, s.close_kw, "`tunnel` closed with `endfunnel` (NOME 2016 style)")
          .fixit(s.close_kw, "endtunnel", "replace with `endtunnel`");
    }
    const GenSignature* sig = signature_for(s.kind, dialect_);
    bool took_args = false;
    bool arity_ok = true;
    auto on_positional = [&](const ast::Item& it) -> bool {
      if (it.kind == ItemKind::List && sig != nullptr && !took_args) {
        took_args = true;
        arity_ok = check_gen_args(a, s, id, *sig, it);
        return true;
      }
      if (it.kind == ItemKind::List && (s.kind == BlockKind::Beziercurve || s.kind == BlockKind::Bspline)) {
        add_names_field(a, id, "controlpoints", it, Ns::Point);
        return true;
      }
      return false;
    };
    read_body(a, s, pos, id, ctx, on_positional);
    if (sig != nullptr && !took_args) {
      diags_.emit(DiagKind::MissingArgument, name ? s.items[0].range : s.open_kw,
                  fmt::format("`{}` needs its arguments `({})`", ast::open_keyword(s.kind), fmt::join(sig->args, " ")));
    }
    if (arity_ok) check_generator_domain(s, id);
    return id;
  }

  // The generator's own argument-domain rules (backend/generators/domain.h) on the values
  // known now, so that `--check` rejects what `--emit` would, with the same message.
  void check_generator_domain(const ast::Stmt& s, ir::NodeId id) {
    backend::KnownArguments known;
    for (const ir::Field& f : m_.node(id).fields) {
      if (f.kind != ir::FieldKind::Scalar || f.exprs.size() != 1) continue;
      ir::EvalResult v = ir::evaluate(m_, f.exprs[0]);
      if (v.ok) known[f.name] = v.value;
    }
    auto problem = backend::check_generator_arguments(ast::open_keyword(s.kind), dialect_name(dialect_), known);
    if (!problem) return;
    SourceRange at = s.open_kw;
    for (const ir::Field& f : m_.node(id).fields) {
      if (f.name == problem->argument && f.range.is_valid()) at = f.range;
    }
    diags_.emit(DiagKind::GeometryFailed, at,
                fmt::format("`{}` `{}`: {}", ast::open_keyword(s.kind),
                            m_.node(id).name.substr(m_.node(id).name.rfind('.') + 1), problem->message))
        .note(SourceRange{}, problem->hint);
  }

  // Returns false when the list has the wrong number of arguments.
  bool check_gen_args(const ast::Ast& a, const ast::Stmt& s, ir::NodeId id, const GenSignature& sig, const ast::Item& list_item) {
    const ast::ParenList& list = a.list(list_item.list);
    check_commas(a, list_item.list);
    size_t n = list.elems.size();
    size_t want = sig.args.size();
    if (n != want && n != want + sig.optional.size()) {
      std::string expect = sig.optional.empty()
                               ? fmt::format("{} arguments ({})", want, fmt::join(sig.args, " "))
                               : fmt::format("{} or {} arguments ({} [{}])", want, want + sig.optional.size(),
                                             fmt::join(sig.args, " "), fmt::join(sig.optional, " "));
      auto d = diags_.emit(DiagKind::ListArity, list.range,
                           fmt::format("`{}` takes {}, got {}{}", ast::open_keyword(s.kind), expect, n, split_text(a, list)));
      if (s.kind == BlockKind::Funnel) {
        d.note(SourceRange{}, fmt::format("in the `{}` dialect the funnel arguments are ({})", dialect_name(dialect_), fmt::join(sig.args, " ")));
      }
    }
    for (size_t i = 0; i < n; ++i) {
      std::string_view arg_name = i < want ? sig.args[i] : i - want < sig.optional.size() ? sig.optional[i - want] : "extra";
      ir::Field f;
      f.name = std::string(arg_name);
      f.kind = ir::FieldKind::Scalar;
      f.range = a.expr(list.elems[i]).range;
      f.exprs.push_back(to_ir(a, list.elems[i], false, id));
      if (std::find(sig.counts.begin(), sig.counts.end(), arg_name) != sig.counts.end()) {
        check_count(f.exprs[0], f.range, f.name);
      }
      add_field(id, std::move(f));
    }
    return n == want || n == want + sig.optional.size();
  }

  void check_count(ir::ExprId e, SourceRange r, std::string_view what) {
    ir::EvalResult v = ir::evaluate(m_, e);
    if (v.ok && std::fabs(v.value - std::round(v.value)) > 1e-9) {
      diags_.emit(DiagKind::NonIntegerCount, r,
                  fmt::format("`{}` is a count but has the value {}; it will be rounded to {}", what, v.value, std::round(v.value)));
    }
  }

  // -------- body reading --------
  bool is_option(BlockKind kind, std::string_view word) const {
    for (const OptSpec& o : options_for(kind)) {
      if (o.name == word) return true;
    }
    return false;
  }

  void read_body(const ast::Ast& a, const ast::Stmt& s, size_t pos, ir::NodeId id, const Ctx& ctx,
                 const std::function<bool(const ast::Item&)>& positional = {}) {
    const std::vector<OptSpec>& opts = options_for(s.kind);
    Ctx child_ctx{id, s.kind, false};
    bool rest = !opts.empty() && opts[0].shape == Shape::Rest && opts[0].name.empty();
    while (pos < s.items.size()) {
      const ast::Item& it = s.items[pos];
      if (it.kind == ItemKind::Block) {
        const ast::Stmt& child = a.stmt(it.block);
        ir::NodeId cid = handle_stmt(a, child, child_ctx);
        if (cid.is_valid() && child.kind != BlockKind::Instance && child.kind != BlockKind::Sharp) {
          m_.node(id).children.push_back(cid);
          m_.deps.add_edge(cid, id);
        }
        ++pos;
        continue;
      }
      if (rest) { ++pos; continue; }
      if (it.kind == ItemKind::Word) {
        const OptSpec* spec = nullptr;
        for (const OptSpec& o : opts) {
          if (o.name == it.text) { spec = &o; break; }
        }
        if (spec != nullptr) {
          ++pos;
          read_option(a, s, *spec, it, pos, id);
          continue;
        }
        if (positional && positional(it)) { ++pos; continue; }
        if (is_block_keyword(it.text)) {
          // `point p (0 0 0)` followed by `point q … endpoint`: the first one's end keyword is
          // missing, and the rest of this body belongs to the next statement.
          diags_.emit(DiagKind::MissingEndBeforeStatement, it.range,
                      fmt::format("`{}` starts a new statement, but the `{}` above is not closed; is `{}` missing before it?",
                                  it.text, ast::open_keyword(s.kind), ast::close_keyword(s.kind)))
              .note(s.open_kw, fmt::format("`{}` opened here", ast::open_keyword(s.kind)))
              .fixit(SourceRange{it.range.file, it.range.begin, it.range.begin},
                     fmt::format("{}\n", ast::close_keyword(s.kind)),
                     fmt::format("insert `{}`", ast::close_keyword(s.kind)));
          return;
        }
        report_unknown_word(s, it, opts);
        ++pos;
        continue;
      }
      if (positional && positional(it)) { ++pos; continue; }
      std::string what = it.kind == ItemKind::List ? "list" : "value";
      diags_.emit(DiagKind::UnexpectedItem, it.range,
                  fmt::format("unexpected {} `{}` in `{}`", what, clip(sources_.text(it.range)), ast::open_keyword(s.kind)));
      ++pos;
    }
  }

  static bool is_block_keyword(std::string_view word) {
    const auto& kws = ast::all_open_keywords();
    return std::find(kws.begin(), kws.end(), word) != kws.end();
  }

  void report_unknown_word(const ast::Stmt& s, const ast::Item& it, const std::vector<OptSpec>& opts) {
    std::vector<std::string> names;
    for (const OptSpec& o : opts) names.emplace_back(o.name);
    std::string hint = closest_match(it.text, names);
    auto d = diags_.emit(DiagKind::UnknownArgument, it.range,
                         fmt::format("unknown argument `{}` for `{}`{}", it.text, ast::open_keyword(s.kind),
                                     hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
    if (!hint.empty()) d.fixit(it.range, hint, fmt::format("replace with `{}`", hint));
  }

  static std::string clip(std::string_view t) {
    std::string s(t.substr(0, 40));
    std::replace(s.begin(), s.end(), '\n', ' ');
    return t.size() > 40 ? s + "…" : s;
  }

  void read_option(const ast::Ast& a, const ast::Stmt& s, const OptSpec& spec, const ast::Item& kw, size_t& pos, ir::NodeId id) {
    auto next = [&]() -> const ast::Item* { return pos < s.items.size() ? &s.items[pos] : nullptr; };
    auto missing = [&](std::string_view what) {
      diags_.emit(DiagKind::MissingArgument, kw.range, fmt::format("`{}` needs {}", spec.name, what));
    };
    ir::Field f;
    f.name = std::string(spec.name);
    f.range = kw.range;
    switch (spec.shape) {
      case Shape::Flag:
        f.kind = ir::FieldKind::Flag;
        break;
      case Shape::FlagOrScalar:
        f.kind = ir::FieldKind::Flag;
        if (const ast::Item* n = next(); n && n->kind == ItemKind::Value) {
          f.kind = ir::FieldKind::Scalar;
          f.exprs.push_back(scalar_of_item(a, *n, false, id));
          ++pos;
        }
        break;
      case Shape::Scalar: {
        const ast::Item* n = next();
        if (n == nullptr || n->kind == ItemKind::Block || (n->kind == ItemKind::Word && is_option(s.kind, n->text))) {
          missing("a value");
          return;
        }
        f.kind = ir::FieldKind::Scalar;
        f.exprs.push_back(scalar_of_item(a, *n, false, id));
        ++pos;
        break;
      }
      case Shape::Vec2:
      case Shape::Vec3:
      case Shape::Vec4: {
        size_t want = spec.shape == Shape::Vec2 ? 2 : spec.shape == Shape::Vec3 ? 3 : 4;
        const ast::Item* n = next();
        if (n == nullptr || n->kind != ItemKind::List) {
          missing(fmt::format("a list of {} numbers", want));
          return;
        }
        ++pos;
        add_vector_field(a, id, f.name, *n, want, kw.range);
        if (spec.name == "color") check_color(a, *n);
        return;
      }
      case Shape::Rotate: {
        const ast::Item* n = next();
        if (n == nullptr || n->kind != ItemKind::List) {
          missing("an axis `(x y z)` and an angle `(degrees)`");
          return;
        }
        ++pos;
        f.kind = ir::FieldKind::Vector;
        const ast::ParenList& axis = a.list(n->list);
        if (axis.elems.size() != 3) {
          diags_.emit(DiagKind::ListArity, axis.range,
                      fmt::format("`rotate` axis needs 3 numbers, got {}{}", axis.elems.size(), split_text(a, axis)));
        }
        for (ast::ExprId e : axis.elems) f.exprs.push_back(to_ir(a, e, false, id));
        if (const ast::Item* ang = next(); ang && ang->kind == ItemKind::List) {
          ++pos;
          const ast::ParenList& al = a.list(ang->list);
          if (al.elems.size() != 1) {
            diags_.emit(DiagKind::ListArity, al.range,
                        fmt::format("`rotate` angle needs 1 number (degrees), got {}{}", al.elems.size(), split_text(a, al)));
          }
          for (ast::ExprId e : al.elems) f.exprs.push_back(to_ir(a, e, false, id));
        } else if (s.kind == BlockKind::Instance || s.kind == BlockKind::Transform) {
          missing("an angle `(degrees)` after its axis");
        }
        break;
      }
      case Shape::Surface:
      case Shape::Ref: {
        const ast::Item* n = next();
        if (n == nullptr || n->kind != ItemKind::Word) {
          missing("a name");
          return;
        }
        ++pos;
        ir::NodeId target = spec.shape == Shape::Surface
                                ? resolve(Ns::Surface, std::string(n->text), n->range, "a surface")
                                : resolve_any(std::string(n->text), n->range);
        add_ref_field(id, f.name, target, n->range);
        return;
      }
      case Shape::Names: {
        const ast::Item* n = next();
        if (n == nullptr || n->kind != ItemKind::List) {
          missing("a list of names `(a b …)`");
          return;
        }
        ++pos;
        Ns ns = spec.name == "pointlist" || spec.name == "controlpointlist" ? Ns::Point : Ns::Count;
        add_names_field(a, id, f.name, *n, ns);
        return;
      }
      case Shape::Vertices: {
        const ast::Item* n = next();
        if (n == nullptr || n->kind != ItemKind::List) {
          missing("a list of vertices `(v1 v2 …)`");
          return;
        }
        ++pos;
        add_vertices_field(a, id, f.name, *n, ir::NodeId::None());
        return;
      }
      case Shape::Symbol: {
        const ast::Item* n = next();
        if (n == nullptr || n->kind == ItemKind::Block) {
          missing("a value");
          return;
        }
        ++pos;
        if (n->kind == ItemKind::Word) {
          f.kind = ir::FieldKind::Text;
          f.text = std::string(n->text);
        } else {
          f.kind = ir::FieldKind::Scalar;
          f.exprs.push_back(scalar_of_item(a, *n, false, id));
        }
        break;
      }
      case Shape::Raw: {
        const ast::Item* n = next();
        if (n == nullptr || n->kind != ItemKind::Value || a.expr(n->expr).kind != ast::ExprKind::Raw) {
          missing("a function in brackets, e.g. `[sin(u)*cos(v)]`");
          return;
        }
        ++pos;
        f.kind = ir::FieldKind::Text;
        f.text = std::string(a.expr(n->expr).text);
        break;
      }
      case Shape::Any: {
        const ast::Item* n = next();
        if (n == nullptr || n->kind == ItemKind::Block) {
          missing("a value");
          return;
        }
        ++pos;
        f.kind = ir::FieldKind::Text;
        f.text = clip(sources_.text(n->range));
        if (n->kind == ItemKind::Value) scalar_of_item(a, *n, false, id);
        // `type polyline NAME` in SLIDE cross sections: let the next word be read as an option.
        break;
      }
      case Shape::Rest:
        while (pos < s.items.size() && s.items[pos].kind != ItemKind::Block) ++pos;
        f.kind = ir::FieldKind::Flag;
        break;
    }
    add_field(id, std::move(f));
  }

  void check_color(const ast::Ast& a, const ast::Item& list_item) {
    for (ast::ExprId e : a.list(list_item.list).elems) {
      // Evaluate through a throw-away IR expression (no new diagnostics).
      DiagnosticEngine scratch;
      std::swap(scratch, diags_);
      ir::ExprId ie = to_ir(a, e, false, ir::NodeId::None());
      std::swap(scratch, diags_);
      ir::EvalResult r = ir::evaluate(m_, ie);
      if (r.ok && (r.value < 0 || r.value > 1)) {
        diags_.emit(DiagKind::ColorOutOfRange, a.expr(e).range,
                    fmt::format("colour component {} is outside [0, 1]; colours are RGB fractions, e.g. `(1 0.5 0)`", r.value));
      }
    }
  }

  // -------- fields --------
  void add_field(ir::NodeId id, ir::Field f) {
    // A Value node for fields whose expressions depend on parameters.
    std::vector<int32_t>& params = params_scratch_;
    params.clear();
    for (ir::ExprId e : f.exprs) collect_params(e, params);
    std::sort(params.begin(), params.end());
    params.erase(std::unique(params.begin(), params.end()), params.end());
    if (!params.empty()) {
      ir::Node v;
      v.kind = ir::NodeKind::Value;
      v.keyword = "value";
      const std::string& owner = m_.node(id).name;
      v.name.reserve(owner.size() + 1 + f.name.size());
      v.name.append(owner).append(1, '.').append(f.name);
      v.range = f.range;
      v.owner = id;
      ir::NodeId vid = m_.add_node(std::move(v));
      for (int32_t p : params) m_.deps.add_edge(ir::NodeId{p}, vid);
      m_.deps.add_edge(vid, id);
      f.value_node = vid;
    }
    std::vector<ir::Field>& fields = m_.node(id).fields;
    if (fields.empty()) fields.reserve(2);  // most statements have one or two fields
    fields.push_back(std::move(f));
  }

  void collect_params(ir::ExprId e, std::vector<int32_t>& out) const {
    if (!e.is_valid()) return;
    const ir::Expr& x = m_.expr(e);
    if (x.kind == ir::ExprKind::Param) out.push_back(x.param.index);
    collect_params(x.lhs, out);
    collect_params(x.rhs, out);
    for (ir::ExprId c : x.args) collect_params(c, out);
  }

  void add_vector_field(const ast::Ast& a, ir::NodeId id, std::string name, const ast::Item& list_item, size_t want, SourceRange kw = {}) {
    const ast::ParenList& list = a.list(list_item.list);
    check_commas(a, list_item.list);
    if (list.elems.size() != want) {
      diags_.emit(DiagKind::ListArity, list.range,
                  fmt::format("`{}` needs {} numbers, got {}{}", name, want, list.elems.size(), split_text(a, list)));
    }
    ir::Field f;
    f.name = std::move(name);
    f.kind = ir::FieldKind::Vector;
    f.range = list.range;
    f.exprs.reserve(list.elems.size());
    for (ast::ExprId e : list.elems) f.exprs.push_back(to_ir(a, e, false, id));
    add_field(id, std::move(f));
  }

  void add_ref_field(ir::NodeId id, std::string name, ir::NodeId target, SourceRange r) {
    ir::Field f;
    f.name = std::move(name);
    f.kind = ir::FieldKind::Ref;
    f.range = r;
    f.refs.push_back(target);
    if (target.is_valid()) m_.deps.add_edge(target, id);
    add_field(id, std::move(f));
  }

  void add_names_field(const ast::Ast& a, ir::NodeId id, std::string name, const ast::Item& list_item, Ns ns) {
    const ast::ParenList& list = a.list(list_item.list);
    check_commas(a, list_item.list);
    ir::Field f;
    f.name = std::move(name);
    f.kind = ir::FieldKind::Refs;
    f.range = list.range;
    for (ast::ExprId e : list.elems) {
      const ast::Expr& x = a.expr(e);
      if (x.kind != ast::ExprKind::Name) {
        diags_.emit(DiagKind::ExpectedNameList, x.range, fmt::format("expected a name in this list, found `{}`", clip(x.text.empty() ? sources_.text(x.range) : x.text)));
        continue;
      }
      ir::NodeId t = ns == Ns::Count  ? resolve_any(std::string(x.text), x.range)
                     : ns == Ns::Face ? resolve(Ns::Face, std::string(x.text), x.range, "a face")
                                      : resolve_point_like(std::string(x.text), x.range);
      f.refs.push_back(t);
      if (t.is_valid()) m_.deps.add_edge(t, id);
    }
    add_field(id, std::move(f));
  }

  void add_vertices_field(const ast::Ast& a, ir::NodeId id, std::string name, const ast::Item& list_item, ir::NodeId mesh) {
    const ast::ParenList& list = a.list(list_item.list);
    check_commas(a, list_item.list);
    ir::Field f;
    f.name = std::move(name);
    f.kind = ir::FieldKind::Vertices;
    f.range = list.range;
    f.vertices.reserve(list.elems.size());
    for (ast::ExprId e : list.elems) {
      const ast::Expr& x = a.expr(e);
      if (x.kind != ast::ExprKind::Name) {
        diags_.emit(DiagKind::ExpectedNameList, x.range,
                    fmt::format("expected a vertex name in this list, found `{}`", clip(sources_.text(x.range))));
        continue;
      }
      ir::VertexRef ref = resolve_vertex(std::string(x.text), x.range, mesh);
      add_vertex_edges(id, ref);
      f.vertices.push_back(std::move(ref));
    }
    add_field(id, std::move(f));
  }

  void add_vertex_edges(ir::NodeId id, const ir::VertexRef& ref) {
    if (ref.point.is_valid()) m_.deps.add_edge(ref.point, id);
    if (!ref.instances.empty()) m_.deps.add_edge(ref.instances.front(), id);
  }

  void check_commas(const ast::Ast& a, ast::ListId list) {
    const ast::ParenList& l = a.list(list);
    if (l.commas.empty()) return;
    auto d = diags_.emit(DiagKind::CommaInList, l.commas.front(),
                         "NOME lists are separated by spaces; commas are ignored");
    for (SourceRange c : l.commas) d.fixit(c, "", "remove `,`");
  }

  std::string split_text(const ast::Ast& a, const ast::ParenList& list) const {
    if (list.elems.empty()) return "";
    std::vector<std::string> parts;
    for (ast::ExprId e : list.elems) parts.push_back(fmt::format("`{}`", clip(sources_.text(a.expr(e).range))));
    return fmt::format("; the list was read as: {}", fmt::join(parts, " | "));
  }

  std::string qualify(const Ctx& ctx, const std::string& name) const {
    if (!ctx.parent.is_valid() || name.empty()) return name;
    return fmt::format("{}.{}", m_.node(ctx.parent).name, name);
  }

  // -------- names --------
  ir::NodeId lookup(Ns ns, const std::string& name, SourceRange use, bool report_order) {
    auto& table = scopes_[static_cast<int>(ns)];
    auto it = table.find(name);
    if (it == table.end()) return ir::NodeId::None();
    if (name_uses_ != nullptr) name_uses_->push_back({use, it->second.node});
    if (report_order && dialect_ != Dialect::Slide && it->second.order > order_ && order_ < (1 << 20)) {
      diags_.emit(DiagKind::UseBeforeDefinition, use,
                  fmt::format("`{}` is used before its definition; NOME requires definitions above their uses", name))
          .note(it->second.range, "defined here");
    }
    return it->second.node;
  }

  std::vector<std::string> names_in(Ns ns) const {
    std::vector<std::string> out;
    for (auto& [k, v] : scopes_[static_cast<int>(ns)]) out.push_back(k);
    std::sort(out.begin(), out.end());  // "did you mean" prefers the first best match
    return out;
  }

  // Names only Tcl defines are reported once per name (real SLIDE files use them hundreds
  // of times); later uses stay quiet.
  bool first_tcl_report(const std::string& name) { return tcl_reported_.insert(name).second; }

  ir::NodeId report_unknown(Ns ns, const std::string& name, SourceRange use, std::string_view wanted) {
    if (dialect_ == Dialect::Slide && has_tcl_) {
      if (!first_tcl_report(name)) return ir::NodeId::None();
      diags_.emit(DiagKind::TclDefinedName, use,
                  fmt::format("`{}` is not defined in this file; it may be created by Tcl code in a `tclinit` block, which nomec does not evaluate yet", name));
      return ir::NodeId::None();
    }
    std::string hint = closest_match(name, names_in(ns));
    auto d = diags_.emit(DiagKind::UnknownName, use,
                         fmt::format("unknown {} `{}`{}", wanted, name, hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
    if (!hint.empty()) d.fixit(use, hint, fmt::format("replace with `{}`", hint));
    return ir::NodeId::None();
  }

  ir::NodeId resolve(Ns ns, const std::string& name, SourceRange use, std::string_view wanted) {
    ir::NodeId id = lookup(ns, name, use, true);
    if (id.is_valid()) return id;
    // Same name in another namespace: a kind error, not a typo.
    for (int other = 0; other < static_cast<int>(Ns::Count); ++other) {
      if (other == static_cast<int>(ns)) continue;
      auto& table = scopes_[other];
      if (auto it = table.find(name); it != table.end()) {
        diags_.emit(DiagKind::WrongKind, use,
                    fmt::format("`{}` is a {}, but {} is needed here", name, ast::open_keyword(it->second.kind), wanted))
            .note(it->second.range, "defined here");
        return ir::NodeId::None();
      }
    }
    return report_unknown(ns, name, use, wanted);
  }

  ir::NodeId resolve_any(const std::string& name, SourceRange use) {
    for (Ns ns : {Ns::Shape, Ns::Point, Ns::Face, Ns::Surface, Ns::Scene}) {
      ir::NodeId id = lookup(ns, name, use, true);
      if (id.is_valid()) return id;
    }
    return report_unknown(Ns::Shape, name, use, "name");
  }

  ir::NodeId resolve_point_like(const std::string& name, SourceRange use) {
    for (Ns ns : {Ns::Point, Ns::Shape}) {
      ir::NodeId id = lookup(ns, name, use, true);
      if (id.is_valid()) return id;
    }
    return report_unknown(Ns::Point, name, use, "point");
  }

  ir::NodeId resolve_target(const std::string& name, SourceRange use) {
    for (Ns ns : {Ns::Shape, Ns::Scene}) {
      ir::NodeId id = lookup(ns, name, use, true);
      if (id.is_valid()) return id;
    }
    for (Ns ns : {Ns::Point, Ns::Face, Ns::Surface}) {
      auto& table = scopes_[static_cast<int>(ns)];
      if (auto it = table.find(name); it != table.end()) {
        diags_.emit(DiagKind::WrongKind, use,
                    fmt::format("`{}` is a {}; an instance needs a mesh, group, generator, curve or block", name,
                                ast::open_keyword(it->second.kind)))
            .note(it->second.range, "defined here");
        return ir::NodeId::None();
      }
    }
    if (name == "consolidatemesh" && (is_saved_work_ || base_loaded_)) {
      diags_.emit(DiagKind::UnknownName, use, "`consolidatemesh` is defined by a `consolidate` block, and this scene has none");
      return ir::NodeId::None();
    }
    return report_unknown(Ns::Shape, name, use, "mesh, group or generator");
  }

  // Vertex references (language.md §5.1): a point of the current mesh; a global point; a
  // path through instances (`inst.v`, `.inst.sub.v`); 2016 `inst_sub_v`.
  ir::VertexRef resolve_vertex(const std::string& text, SourceRange use, ir::NodeId mesh) {
    ir::VertexRef ref;
    ref.text = text;
    ref.range = use;
    if (mesh.is_valid()) {
      auto& local = mesh_points_[mesh.index];
      if (auto it = local.find(text); it != local.end()) {
        ref.point = it->second;
        return ref;
      }
    }
    if (ir::NodeId p = lookup(Ns::Point, text, use, true); p.is_valid()) {
      ref.point = p;
      return ref;
    }
    std::string path = text;
    if (!path.empty() && path[0] == '.') path = path.substr(1);
    if (path.find('.') != std::string::npos) {
      if (resolve_dotted(path, ref)) return ref;
    } else if (resolve_underscored(path, ref)) {
      return ref;
    }
    if (dialect_ == Dialect::Slide && has_tcl_) {
      if (first_tcl_report(text)) {
        diags_.emit(DiagKind::TclDefinedName, use,
                    fmt::format("`{}` is not defined in this file; it may be created by Tcl code in a `tclinit` block, which nomec does not evaluate yet", text));
      }
      return ref;
    }
    std::vector<std::string> cands = names_in(Ns::Point);
    if (mesh.is_valid()) for (auto& [k, v] : mesh_points_[mesh.index]) cands.push_back(k);
    std::string hint = closest_match(text, cands);
    auto d = diags_.emit(DiagKind::UnknownVertex, use,
                         fmt::format("unknown vertex `{}`: it is not a point, and no instance path leads to it{}", text,
                                     hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
    if (!hint.empty()) d.fixit(use, hint, fmt::format("replace with `{}`", hint));
    return ref;
  }

  // Instances visible at the start of a path: top-level instances, then (2016 files omit
  // outer instance names, e.g. `fun3_hc3` for `cf.fun3.hc3`) instances nested in groups.
  std::vector<ir::NodeId> instances_named(const std::string& name, ir::NodeId scope_owner) const {
    std::vector<ir::NodeId> out;
    auto it = instance_scopes_.find(scope_owner.index + 1);
    if (it != instance_scopes_.end()) {
      if (auto j = it->second.find(name); j != it->second.end()) out.push_back(j->second);
    }
    return out;
  }

  // Children instances of the instance's target (through groups and blocks).
  ir::NodeId child_instance(ir::NodeId inst, const std::string& name) const {
    ir::NodeId target = m_.node(inst).target;
    if (!target.is_valid()) return ir::NodeId::None();
    auto it = instance_scopes_.find(target.index + 1);
    if (it == instance_scopes_.end()) return ir::NodeId::None();
    auto j = it->second.find(name);
    return j == it->second.end() ? ir::NodeId::None() : j->second;
  }

  // Does `vertex` name a vertex of the instance's target?
  bool target_has_vertex(ir::NodeId inst, const std::string& vertex, std::string* why) const {
    ir::NodeId t = m_.node(inst).target;
    if (!t.is_valid()) return true;  // target already reported
    const ir::Node& target = m_.node(t);
    BlockKind kind = kind_by_open(target.keyword);
    if (auto naming = naming_for(kind, dialect_)) {
      for (std::string_view prefix : naming->prefixes) {
        if (vertex.size() > prefix.size() && vertex.compare(0, prefix.size(), prefix) == 0 &&
            std::all_of(vertex.begin() + prefix.size(), vertex.end(), ::isdigit)) {
          long idx = std::stol(vertex.substr(prefix.size()));
          for (const ir::Field& f : target.fields) {
            if (f.name == naming->count_arg && !f.exprs.empty()) {
              ir::EvalResult r = ir::evaluate(m_, f.exprs[0]);
              long n = r.ok ? std::lround(r.value) : -1;
              if (n >= 0 && idx >= n) {
                *why = fmt::format("`{}` `{}` has vertices {}0…{}{} with {} = {}", target.keyword, target.name, prefix, prefix, n - 1, naming->count_arg, n);
                return false;
              }
            }
          }
          return true;
        }
      }
      std::vector<std::string> shown;
      for (std::string_view p : naming->prefixes) shown.push_back(fmt::format("`{}N`", p));
      *why = fmt::format("`{}` vertices are named {}", target.keyword, fmt::join(shown, ", "));
      return false;
    }
    if (target.kind == ir::NodeKind::Mesh || target.kind == ir::NodeKind::Polyline) {
      // Points of the mesh, and points its faces use.
      if (auto it = mesh_points_.find(t.index); it != mesh_points_.end() && it->second.contains(vertex)) return true;
      std::function<bool(ir::NodeId)> uses = [&](ir::NodeId n) {
        for (const ir::Field& f : m_.node(n).fields) {
          for (const ir::VertexRef& v : f.vertices) if (v.text == vertex) return true;
          for (ir::NodeId r : f.refs) if (r.is_valid() && m_.node(r).name == vertex) return true;
        }
        for (ir::NodeId c : m_.node(n).children) if (uses(c)) return true;
        return false;
      };
      if (uses(t)) return true;
      *why = fmt::format("`{}` `{}` has no vertex `{}`", target.keyword, target.name, vertex);
      return false;
    }
    return true;  // generators whose vertex naming is not fixed yet, groups (skipped)
  }

  bool resolve_dotted(const std::string& path, ir::VertexRef& ref) {
    std::vector<std::string> parts;
    size_t start = 0;
    for (size_t dot; (dot = path.find('.', start)) != std::string::npos; start = dot + 1) parts.push_back(path.substr(start, dot - start));
    parts.push_back(path.substr(start));
    std::vector<ir::NodeId> first = instances_named(parts[0], ir::NodeId::None());
    if (first.empty()) return false;
    ir::NodeId cur = first[0];
    ref.instances.push_back(cur);
    for (size_t i = 1; i + 1 < parts.size(); ++i) {
      cur = child_instance(cur, parts[i]);
      if (!cur.is_valid()) {
        diags_.emit(DiagKind::UnknownVertex, ref.range,
                    fmt::format("in `{}`: `{}` is not an instance inside `{}`", path, parts[i], parts[i - 1]));
        return true;
      }
      ref.instances.push_back(cur);
    }
    ref.vertex = parts.back();
    std::string why;
    if (!target_has_vertex(cur, ref.vertex, &why)) {
      diags_.emit(DiagKind::UnknownVertex, ref.range, fmt::format("in `{}`: {}", path, why));
    }
    return true;
  }

  // 2016 `_`-joined references: `fun3_hc3`, `cf_fun3_hc3`, `_ir_i1`. Instance names are
  // matched as prefixes; the remainder names the vertex.
  bool resolve_underscored(const std::string& text, ir::VertexRef& ref) {
    std::string path = text;
    while (!path.empty() && path[0] == '_') path = path.substr(1);
    struct Match { std::vector<ir::NodeId> chain; std::string vertex; };
    std::vector<Match> matches;
    // Try the top-level scope, then any instance scope (2016 names may omit outer instances).
    std::function<void(const std::map<std::string, ir::NodeId>&, size_t, std::vector<ir::NodeId>&)> try_scope =
        [&](const std::map<std::string, ir::NodeId>& scope, size_t at, std::vector<ir::NodeId>& chain) {
          // The names that can match are the prefixes of `path[at:]` that end before an
          // `_`; looking each up (shortest first, which is the map's order among them)
          // costs the underscores in the reference instead of every name in the scope.
          for (size_t u = path.find('_', at); u != std::string::npos; u = path.find('_', u + 1)) {
            auto found = scope.find(path.substr(at, u - at));
            if (found == scope.end()) continue;
            ir::NodeId inst = found->second;
            chain.push_back(inst);
            size_t rest = u + 1;
            ir::NodeId t = m_.node(inst).target;
            auto sub = t.is_valid() ? instance_scopes_.find(t.index + 1) : instance_scopes_.end();
            size_t before = matches.size();
            if (sub != instance_scopes_.end()) try_scope(sub->second, rest, chain);
            if (matches.size() == before) {
              std::string why;
              if (target_has_vertex(inst, path.substr(rest), &why)) matches.push_back({chain, path.substr(rest)});
            }
            chain.pop_back();
          }
        };
    std::vector<ir::NodeId> chain;
    if (auto top = instance_scopes_.find(0); top != instance_scopes_.end()) try_scope(top->second, 0, chain);
    if (matches.empty()) {
      for (auto& [owner, scope] : instance_scopes_) {
        if (owner == 0) continue;
        try_scope(scope, 0, chain);
      }
    }
    if (matches.empty()) return false;
    ref.instances = matches[0].chain;
    ref.vertex = matches[0].vertex;
    if (matches.size() > 1) {
      std::set<std::vector<int32_t>> distinct;
      for (auto& mt : matches) {
        std::vector<int32_t> k;
        for (auto n : mt.chain) k.push_back(n.index);
        distinct.insert(k);
      }
      if (distinct.size() > 1) {
        diags_.emit(DiagKind::AmbiguousName, ref.range,
                    fmt::format("`{}` matches {} instance paths; write it with dots to choose one, e.g. `{}`", text,
                                distinct.size(), dotted(matches[0].chain, matches[0].vertex)));
      }
    }
    return true;
  }

  std::string dotted(const std::vector<ir::NodeId>& chain, const std::string& vertex) const {
    std::vector<std::string> parts;
    for (ir::NodeId n : chain) {
      std::string nm = m_.node(n).name;
      if (auto d = nm.rfind('.'); d != std::string::npos) nm = nm.substr(d + 1);
      parts.push_back(nm);
    }
    parts.push_back(vertex);
    return fmt::format("{}", fmt::join(parts, "."));
  }

  // -------- expressions --------
  // Memoized: a scene refers to the same sliders over and over (`$b_r` in every point).
  // The memo is cleared whenever a bank or slider is declared.
  ir::NodeId lookup_param_text(const std::string& text) const {
    if (auto it = param_text_memo_.find(text); it != param_text_memo_.end()) return it->second;
    ir::NodeId found = lookup_param_text_uncached(text);
    param_text_memo_.emplace(text, found);
    return found;
  }
  ir::NodeId lookup_param_text_uncached(const std::string& text) const {
    if (auto it = params_.find(text); it != params_.end()) return it->second;
    // `bank_param`: the longest declared bank prefix.
    for (size_t u = text.rfind('_'); u != std::string::npos && u > 0; u = text.rfind('_', u - 1)) {
      std::string bank = text.substr(0, u);
      if (banks_.contains(bank)) {
        if (auto it = params_.find(bank + "." + text.substr(u + 1)); it != params_.end()) return it->second;
      }
      if (u == 0) break;
    }
    return ir::NodeId::None();
  }

  ir::ExprId scalar_of_item(const ast::Ast& a, const ast::Item& it, bool constant, ir::NodeId owner = ir::NodeId::None()) {
    switch (it.kind) {
      case ItemKind::Value:
        return to_ir(a, it.expr, constant, owner);
      case ItemKind::List: {
        const ast::ParenList& l = a.list(it.list);
        if (l.elems.size() == 1) return to_ir(a, l.elems[0], constant, owner);
        diags_.emit(DiagKind::ListArity, l.range,
                    fmt::format("expected one value, got a list of {}{}", l.elems.size(), split_text(a, l)));
        return error_ir(l.range);
      }
      case ItemKind::Word: {
        // A bare `bank.param` word as a value.
        ir::NodeId p = lookup_param_text(std::string(it.text));
        if (p.is_valid() && !constant) return param_ir(p, it.range);
        diags_.emit(DiagKind::ExpectedNumber, it.range, fmt::format("expected a number, found `{}`", it.text));
        return error_ir(it.range);
      }
      default:
        return error_ir(it.range);
    }
  }

  ir::ExprId error_ir(SourceRange r) {
    ir::Expr e;
    e.kind = ir::ExprKind::Error;
    e.range = r;
    return m_.add_expr(std::move(e));
  }

  ir::ExprId param_ir(ir::NodeId p, SourceRange r) {
    ir::Expr e;
    e.kind = ir::ExprKind::Param;
    e.param = p;
    e.range = r;
    return m_.add_expr(std::move(e));
  }

  ir::ExprId to_ir(const ast::Ast& a, ast::ExprId id, bool constant, ir::NodeId owner) {
    ir::ExprId out = to_ir_rec(a, id, constant);
    ir::EvalResult r = ir::evaluate(m_, out);
    if (!r.ok && !r.problem.empty()) {
      diags_.emit(DiagKind::ExpressionDomain, r.where.is_valid() ? r.where : a.expr(id).range, r.problem);
      return error_ir(a.expr(id).range);
    }
    return out;
  }

  std::string tcl_var_hint(std::string_view name) const {
    for (const std::string& suf : tcl_suffixes_) {
      if (name.size() > suf.size() && name.substr(name.size() - suf.size()) == suf) return "a slider made by `CreateScale` inside a Tcl proc";
    }
    if (tcl_vars_.contains(std::string(name))) return "a Tcl variable set in a `tclinit` block";
    return "";
  }

  // Expressions deeper than this (e.g. `1+1+…+1` with thousands of terms) are refused, so
  // evaluation, printing and the backend never recurse without bound.
  static constexpr int kMaxExprDepth = 1000;

  ir::ExprId to_ir_rec(const ast::Ast& a, ast::ExprId id, bool constant, int depth = 0) {
    const ast::Expr& x = a.expr(id);
    ir::Expr e;
    e.range = x.range;
    if (depth > kMaxExprDepth) {
      if (!reported_deep_expr_) {
        reported_deep_expr_ = true;
        diags_.emit(DiagKind::NestingTooDeep, x.range,
                    fmt::format("expression nests more than {} operations deep; split it into sliders or points", kMaxExprDepth));
      }
      return error_ir(x.range);
    }
    switch (x.kind) {
      case ast::ExprKind::Number:
        e.kind = ir::ExprKind::Const;
        e.value = x.number;
        return m_.add_expr(std::move(e));
      case ast::ExprKind::Error:
        return error_ir(x.range);
      case ast::ExprKind::DollarRef:
      case ast::ExprKind::Name: {
        std::string name(x.kind == ast::ExprKind::DollarRef ? x.text.substr(1) : x.text);
        if (x.kind == ast::ExprKind::Name && (name == "pi" || name == "e")) {
          e.kind = ir::ExprKind::Const;
          e.value = name == "pi" ? M_PI : M_E;
          return m_.add_expr(std::move(e));
        }
        if (x.kind == ast::ExprKind::DollarRef && name == "SLF_PI") {
          e.kind = ir::ExprKind::Const;
          e.value = M_PI;
          return m_.add_expr(std::move(e));
        }
        if (x.kind == ast::ExprKind::DollarRef && (name == "time" || name == "frame")) {
          e.kind = ir::ExprKind::Builtin;
          e.name = name == "time" ? std::string_view("time") : std::string_view("frame");
          return m_.add_expr(std::move(e));
        }
        ir::NodeId p = lookup_param_text(name);
        if (p.is_valid()) {
          if (constant) {
            diags_.emit(DiagKind::NotAConstant, x.range,
                        fmt::format("slider values must be constant, but this refers to `{}`", m_.node(p).name));
            return error_ir(x.range);
          }
          return param_ir(p, x.range);
        }
        if (dialect_ == Dialect::Slide && x.kind == ast::ExprKind::DollarRef) {
          std::string why = tcl_var_hint(name);
          if (first_tcl_report("$" + name))
          diags_.emit(DiagKind::TclDefinedName, x.range,
                      fmt::format("`${}` is {}; nomec does not evaluate Tcl yet, so values that use it are not checked yet",
                                  name, why.empty() ? "not a slider of this file; it may be defined by Tcl code" : why));
          return error_ir(x.range);
        }
        std::vector<std::string> all;
        bool dotted_style = name.find('.') != std::string::npos || dialect_ == Dialect::Nome3;
        for (auto& [k, v] : params_) {
          std::string shown = k;
          if (!dotted_style) std::replace(shown.begin(), shown.end(), '.', '_');
          all.push_back(shown);
        }
        if (x.kind == ast::ExprKind::Name) {
          std::string hint = closest_match(name, all);
          diags_.emit(DiagKind::ExpectedNumber, x.range,
                      fmt::format("`{}` is not a number or a slider{}", name, hint.empty() ? "" : fmt::format("; did you mean `${}`?", hint)));
          return error_ir(x.range);
        }
        std::string hint = closest_match(name, all);
        auto d = diags_.emit(DiagKind::UnknownParameter, x.range,
                             fmt::format("unknown slider `${}`{}", name, hint.empty() ? "" : fmt::format("; did you mean `${}`?", hint)));
        if (!hint.empty()) d.fixit(x.range, "$" + hint, fmt::format("replace with `${}`", hint));
        return error_ir(x.range);
      }
      case ast::ExprKind::TclArrayRef: {
        if (dialect_ == Dialect::Slide) {
          if (first_tcl_report(std::string(x.text)))
          diags_.emit(DiagKind::TclDefinedName, x.range,
                      fmt::format("`{}` is an element of a Tcl array made by a `slideui` object in `tclinit`; nomec does not evaluate Tcl yet, so values that use it are not checked yet", x.text));
          return error_ir(x.range);
        }
        diags_.emit(DiagKind::UnknownParameter, x.range,
                    fmt::format("`{}` is a Tcl array element, which only SLIDE files can use", x.text));
        return error_ir(x.range);
      }
      case ast::ExprKind::Raw:
        if (dialect_ == Dialect::Slide && x.in_braces) {
          diags_.emit(DiagKind::TclDefinedName, x.range,
                      fmt::format("this value is a Tcl script (`{}`); nomec does not evaluate Tcl yet, so values that use it are not checked yet", clip(x.text)));
          return error_ir(x.range);
        }
        diags_.emit(DiagKind::ExpectedNumber, x.range, fmt::format("expected a number, found raw text `{}`", clip(x.text)));
        return error_ir(x.range);
      case ast::ExprKind::String:
        diags_.emit(DiagKind::ExpectedNumber, x.range, fmt::format("expected a number, found the string {}", x.text));
        return error_ir(x.range);
      case ast::ExprKind::Unary: {
        e.kind = ir::ExprKind::Unary;
        e.op = x.op;
        e.lhs = to_ir_rec(a, x.lhs, constant, depth + 1);
        const ast::Expr& operand = a.expr(x.lhs);
        if (dialect_ == Dialect::Nome3 && x.op == '-' && operand.kind == ast::ExprKind::Binary && operand.op == '^') {
          ir::EvalResult v = ir::evaluate(m_, e.lhs);
          if (v.ok) {
            ir::ExprId base_e = to_ir_rec(a, a.expr(x.lhs).lhs, constant, depth + 1);
            ir::ExprId exp_e = to_ir_rec(a, a.expr(x.lhs).rhs, constant, depth + 1);
            ir::EvalResult b = ir::evaluate(m_, base_e), p = ir::evaluate(m_, exp_e);
            double nome3 = b.ok && p.ok ? std::pow(-b.value, p.value) : 0;
            diags_.emit(DiagKind::UnaryMinusPower, x.range,
                        fmt::format("`-` applies after `^` here, giving {}; NOME3 applied it first, giving {}", -v.value, nome3))
                .fixit(x.range, fmt::format("-({})", sources_.text(operand.range)), "add parentheses to keep this meaning");
          }
        }
        return m_.add_expr(std::move(e));
      }
      case ast::ExprKind::Binary:
        e.kind = ir::ExprKind::Binary;
        e.op = x.op;
        e.lhs = to_ir_rec(a, x.lhs, constant, depth + 1);
        e.rhs = to_ir_rec(a, x.rhs, constant, depth + 1);
        return m_.add_expr(std::move(e));
      case ast::ExprKind::Call: {
        std::optional<ir::Func> f = ir::func_by_name(x.text);
        SmallVec<ir::ExprId, 2> args;
        for (ast::ExprId arg : x.args) args.push_back(to_ir_rec(a, arg, constant, depth + 1));
        if (!f) {
          static const std::vector<std::string> names = {"sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh", "sqrt", "abs", "exp", "log", "ln", "log10", "pow", "min", "max", "floor", "ceil", "round", "sign", "mod"};
          std::string hint = closest_match(x.text, names);
          auto d = diags_.emit(DiagKind::UnknownFunction, x.range,
                               fmt::format("unknown function `{}`{}", x.text, hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
          if (!hint.empty()) {
            d.fixit(SourceRange{x.range.file, x.range.begin, static_cast<uint32_t>(x.range.begin + x.text.size())}, hint, fmt::format("replace with `{}`", hint));
          }
          return error_ir(x.range);
        }
        int arity = ir::func_arity(*f);
        if ((arity >= 0 && static_cast<int>(args.size()) != arity) || (arity < 0 && args.empty())) {
          diags_.emit(DiagKind::FunctionArity, x.range,
                      fmt::format("`{}` takes {} argument{}, got {}", x.text, arity < 0 ? std::string("at least 1") : std::to_string(arity),
                                  arity == 1 ? "" : "s", args.size()));
          return error_ir(x.range);
        }
        e.kind = ir::ExprKind::Call;
        e.func = *f;
        e.args = std::move(args);
        return m_.add_expr(std::move(e));
      }
    }
    return error_ir(x.range);
  }

  void finish() {
    for (const auto& pl : pending_list_) {
      if (!params_.contains(pl.bank + "." + pl.name)) {
        std::vector<std::string> cands;
        for (auto& [k, v] : params_) {
          if (k.rfind(pl.bank + ".", 0) == 0) cands.push_back(k.substr(pl.bank.size() + 1));
        }
        std::string hint = closest_match(pl.name, cands);
        diags_.emit(DiagKind::UnknownParameter, pl.range,
                    fmt::format("`list` names `{}`, which bank `{}` does not define{}", pl.name, pl.bank,
                                hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
      }
    }
    m_.deps.finalize();
    std::vector<ir::NodeId> cycle;
    m_.deps.topo_order(&cycle);
    if (!cycle.empty()) report_cycle(cycle);
  }

  // Reports one cycle of the dependency graph, following its edges from the first node so
  // the message reads in dependency order: `a` → `a.b` → `b` → `b.a` → `a`.
  void report_cycle(const std::vector<ir::NodeId>& cycle_nodes) {
    std::set<int32_t> in_cycle;
    for (ir::NodeId n : cycle_nodes) in_cycle.insert(n.index);
    // Kahn leaves nodes downstream of a cycle too; find a node that reaches itself.
    std::vector<ir::NodeId> path;
    for (ir::NodeId start : cycle_nodes) {
      std::vector<ir::NodeId> stack{start};
      std::map<int32_t, int32_t> parent;
      bool found = false;
      while (!stack.empty() && !found) {
        ir::NodeId n = stack.back();
        stack.pop_back();
        for (ir::NodeId to : m_.deps.users(n)) {
          if (!in_cycle.contains(to.index)) continue;
          if (to == start) {
            for (ir::NodeId p = n;; p = ir::NodeId{parent[p.index]}) {
              path.push_back(p);
              if (p == start) break;
            }
            std::reverse(path.begin(), path.end());
            found = true;
            break;
          }
          if (!parent.contains(to.index)) {
            parent[to.index] = n.index;
            stack.push_back(to);
          }
        }
      }
      if (found) break;
    }
    if (path.empty()) return;
    std::vector<std::string> names;
    for (ir::NodeId n : path) {
      if (m_.node(n).kind != ir::NodeKind::Value) names.push_back(fmt::format("`{}`", m_.node(n).name));
    }
    names.push_back(names.front());
    auto d = diags_.emit(DiagKind::DependencyCycle, m_.node(path.front()).range,
                         fmt::format("these definitions depend on each other in a cycle: {}", fmt::join(names, " → ")));
    for (size_t i = 1; i < path.size(); ++i) {
      const ir::Node& n = m_.node(path[i]);
      if (n.kind != ir::NodeKind::Value) d.note(n.range, fmt::format("`{}` is part of the cycle", n.name));
    }
  }

  bool is_saved_work_ = false;
  bool base_loaded_ = false;
  std::vector<NameUse>* name_uses_ = nullptr;  // CheckOptions::record_names
  std::vector<std::unique_ptr<ast::Ast>> owned_asts_;

 private:
  struct PendingList { std::string bank, name; SourceRange range; };

  SourceManager& sources_;
  DiagnosticEngine& diags_;
  const CheckOptions& options_;
  ir::Module& m_;
  std::unordered_map<std::string, Symbol> scopes_[static_cast<int>(Ns::Count)];
  std::map<std::string, ir::NodeId> params_;  // "bank.param"
  mutable std::unordered_map<std::string, ir::NodeId> param_text_memo_;  // see lookup_param_text
  std::map<std::string, SourceRange> banks_;
  // The node declared for each statement, by statement index, per syntax tree (the main
  // file, its base scene, its includes: each is declared before it is processed).
  struct Declared {
    const ast::Ast* ast;
    std::vector<ir::NodeId> ids;
  };
  std::vector<Declared> declared_;
  std::vector<int32_t> params_scratch_;  // add_field: the parameters a field reads
  // The slot of `s`, or null for a statement of no declared tree.
  ir::NodeId* declared_slot(const ast::Stmt& s) {
    for (Declared& d : declared_) {
      const std::vector<ast::Stmt>& v = d.ast->stmts;
      if (!v.empty() && &s >= v.data() && &s < v.data() + v.size()) return &d.ids[static_cast<size_t>(&s - v.data())];
    }
    return nullptr;
  }
  std::unordered_map<int32_t, std::map<std::string, ir::NodeId>> mesh_points_;
  // Instance scopes keyed by owner node index + 1 (0 = top level).
  std::map<int32_t, std::map<std::string, ir::NodeId>> instance_scopes_;
  std::set<std::string> tcl_vars_;
  std::set<std::string> tcl_suffixes_;
  std::set<std::string> tcl_reported_;
  bool reported_deep_expr_ = false;
  std::vector<PendingList> pending_list_;
  bool has_tcl_ = false;
  int order_ = 0;
  int include_depth_ = 0;
};

// The base scene of a saved-work file: `--base`, else the `.nom`/`.nome` named like its
// folder, else the only one in the folder (listed through `options.list_folder`).
std::optional<std::string> find_base(const std::string& path, const CheckOptions& options) {
  if (options.base_file) return options.base_file;
  if (!options.list_folder) return std::nullopt;
  const size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash == 0 ? 1 : slash);
  std::optional<FolderListing> listing = options.list_folder(dir);
  if (!listing) return std::nullopt;
  std::vector<std::string> candidates;
  for (const std::string& f : listing->files) {
    if (is_base_scene_path(f)) candidates.push_back(f);
  }
  auto full = [&](const std::string& name) { return (dir.empty() ? std::string(".") : dir) + "/" + name; };
  for (const std::string& c : candidates) {
    if (c.substr(0, c.size() - path_extension(c).size()) == listing->name) return full(c);
  }
  if (candidates.size() == 1) return full(candidates[0]);
  return std::nullopt;
}

}  // namespace

std::vector<std::string_view> option_words(ast::BlockKind kind) {
  std::vector<std::string_view> out;
  for (const OptSpec& o : options_for(kind)) {
    if (!o.name.empty()) out.push_back(o.name);
  }
  return out;
}

CheckResult check_source(SourceManager& sources, const std::string& path, std::string text,
                         const CheckOptions& options, DiagnosticEngine& diags) {
  return check_source(sources, path, std::move(text), options, diags, nullptr);
}

CheckResult check_source(SourceManager& sources, const std::string& path, std::string text,
                         const CheckOptions& options, DiagnosticEngine& diags,
                         ParseCache* cache) {
  CheckResult result;
  result.module.time = options.time;
  result.module.frame = options.frame;
  Checker checker(sources, diags, options, result.module);
  if (options.record_names) checker.name_uses_ = &result.name_uses;
  FileId file = sources.add_file(path, std::move(text));
  ast::Ast main_ast =
      cache != nullptr ? cache->parse(sources, file, diags) : parse_file(sources, file, diags);

  // Saved work (`.anom`) is checked on top of its base scene.
  std::unique_ptr<ast::Ast> base_ast;
  if (is_saved_work_path(path)) {
    checker.is_saved_work_ = true;
    std::optional<std::string> base = find_base(path, options);
    std::optional<std::string> base_text;
    if (base && options.read_file) base_text = options.read_file(*base);
    if (base_text) {
      FileId bf = sources.add_file(*base, std::move(*base_text));
      DiagnosticEngine base_diags;  // the base file is checked on its own; only its scope is reused
      base_ast = std::make_unique<ast::Ast>(parse_file(sources, bf, base_diags));
      result.base_file = *base;
      checker.base_loaded_ = true;
    } else {
      diags.emit(DiagKind::MissingBaseFile, SourceRange{file, 0, 0},
                 "saved-work file without its base scene: its instance vertices cannot be resolved; pass `--base SCENE.nom`");
    }
  }

  result.dialect_reason = checker.choose_dialect(base_ast ? *base_ast : main_ast, base_ast ? result.base_file : path);
  result.dialect = checker.dialect_;
  result.module.dialect = std::string(dialect_name(checker.dialect_));

  if (base_ast) {
    checker.collect_tcl(*base_ast);
    checker.collect_banks(*base_ast);
    checker.apply_saved(*base_ast);
  }
  checker.collect_tcl(main_ast);
  checker.collect_banks(main_ast);
  checker.apply_saved(main_ast);
  checker.apply_overrides();
  if (base_ast) {
    // The base scene is checked with a scratch engine: its problems belong to its own check,
    // and only the saved work is reported here.
    checker.declare(*base_ast, -(1 << 21));
    DiagnosticEngine scratch;
    std::swap(scratch, diags);
    checker.process(*base_ast, -(1 << 21));
    std::swap(scratch, diags);
  }
  checker.declare(main_ast, 0);
  checker.process(main_ast, 0);
  checker.finish();
  if (options.record_names) {
    result.asts.push_back(std::make_shared<ast::Ast>(std::move(main_ast)));
    if (base_ast) result.asts.push_back(std::move(base_ast));
    for (auto& inc : checker.owned_asts_) result.asts.push_back(std::move(inc));
  }
  return result;
}

}  // namespace nomec
