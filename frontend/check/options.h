// The options a statement accepts after its name (`translate (0 0 1)`, `sd_level 2`,
// `surface S`, `closed`): per block kind, each option word with the shape of its value and
// its meaning, synonyms sharing one meaning (`sd_level` and SLIDE's `subdivisions` are both
// `Opt::Levels`). `read_body` reads a statement's items against its table, nested
// statements included, and hands each option it reads to the statement's handler, already
// lowered (an operand of the node, a resolved name, a vertex list); the handler stores it
// in the node's payload by meaning.
#pragma once

#include <functional>
#include <span>
#include <string_view>
#include <vector>

#include "frontend/check/context.h"

namespace nomec::check {

// Option value shapes.
enum class Shape : uint8_t {
  Flag,          // `closed`
  FlagOrScalar,  // `closed` or SLIDE `closed 1`
  Scalar,        // `height 0.2`, `sd_level {expr $b.l}`, `azimuth ($b.a + 180)`
  Vec3,          // `color (1 0 0)`
  Vec2,          // `texture (0 1)`, `weights (1 1)`
  Vec4,          // `mirror (a b c d)`
  Frustum,       // SLIDE `frustum (xmin ymin zmin) (xmax ymax zmax)`, NOME3 `frustum (l r b t n f)`
  Rotate,        // `rotate (ax ay az) (deg)`; the angle list is optional in controlpoints
  Surface,       // `surface S`
  Backface,      // `backface B` (JIPCAD)
  Ref,           // a shape name: `point P`, `cameraID cam1`
  Names,         // `(n1 n2 …)`, any kind of definition
  PointNames,    // `(p1 p2 …)`: points
  Vertices,      // `(a.hc0 a.hc1)`: vertex references, as in faces
  Paths,         // `(c.f1 c.f2)`: names the block resolves once its instances are read
  Symbol,        // `sd_type NOME_SD_CC_sharp`, or a value in SLIDE
  Raw,           // `funcX [ … ]`
  Text,          // `ribbegin "…"`: a string
  Any,           // one item of any kind (display options of SLIDE/NOME3 we accept and ignore)
  Rest,          // everything up to the end of the block (scene setup)
};

// What an option means. Synonyms share one.
enum class Opt : uint8_t {
  Ignored,  // SLIDE display and UI options: accepted, their values checked, not used
  Color, Reflectivity, Exponent, Metallic, Bitmap, Texture,
  Closed, PointList, Surface,
  Translate, Rotate, Scale, Mirror, Hidden, Id,
  Azimuth, Twist, Mintorsion, MinimizeTorsion,
  Type, Curve, Circle, Radius, InnerRadius, Slices, BeginCap, EndCap, Reverse,
  Point, Border, Penalty, Tolerance,
  SubdivisionType, Levels, OffsetType, Height, Width,
  Faces, Corners, Segments, Weights, Thickness, Punch, Peel, Level, Collapse,
  InstanceRef,  // NOME2's `instance X` inside a block: a top-level instance the block takes over
  Backface, CutBegin, CutEnd, CrossSection, Sweep, Index,
  Lod,  // SLIDE's level of detail of an instance or group (`SLF_OFF` removes it)
  // Viewing set-up (camera, light, window, viewport, lookat)
  Projection, Frustum, LightType, Direction, Background, Origin, Size, Resize, Ratio, CameraId, Eye, Target, Up,
  Rest,
  GenArg,  // a generator argument of the catalogue (`OptSpec::arg`)
};

struct OptSpec {
  std::string_view name;
  Shape shape;
  Opt key;
  ir::ArgIndex arg = ir::kNoArg;  // Opt::GenArg
};

/// One option as read: the spec, where its word is, and its value in the form its shape
/// gives (only the member of that shape is set).
struct OptionValue {
  const OptSpec* spec = nullptr;
  SourceRange word;
  ir::OperandId operand;            // Scalar, Vec*, Rotate, a FlagOrScalar's value, a Symbol's value
  ir::NodeId ref;                   // Surface, Ref
  ir::Slice<ir::NodeId> names;      // Names, PointNames
  ir::Slice<ir::VertexRef> vertices;  // Vertices
  std::vector<std::pair<std::string, SourceRange>> paths;  // Paths, as written
  std::string_view symbol;          // Symbol or Any given as a word
  SourceRange value_range;          // where the value is
  ast::ExprId raw;                  // Raw
  ast::ExprId value_expr;           // Scalar: the value as written, when it is a value item
  bool is_single_list = false;      // Frustum: NOME3's one list of six
};

/// The options of a block kind (empty for kinds that take none). Generators take theirs
/// from the catalogue (`generator_options`).
std::span<const OptSpec> options_for(BlockKind kind);
/// A generator's options in `dialect`: the catalogue's option words, plus the display
/// options SLIDE attaches to every shape.
std::span<const OptSpec> generator_options(ir::GenKind gen, Dialect dialect);

/// Called with each option read, in written order.
using OptionSink = std::function<void(const OptionValue&)>;
/// Called with an item that is not an option word; returns true when it took the item.
using PositionalHandler = std::function<bool(const ast::Item&)>;

/// Reads the items of `s` from `pos`: options (through `sink`), nested statements (checked
/// as children of `id`), positional items (through `positional`); reports anything else.
void read_body(Context& c, const ast::Ast& a, const ast::Stmt& s, size_t pos, ir::NodeId id,
               std::span<const OptSpec> opts, const OptionSink& sink, const PositionalHandler& positional = {});
/// Warns about each component of a colour list `(r g b)` outside [0, 1].
void check_color_list(Context& c, const ast::Ast& a, const ast::Item& list_item);
/// True if `word` is an option of `opts`.
bool is_option(std::span<const OptSpec> opts, std::string_view word);

}  // namespace nomec::check
