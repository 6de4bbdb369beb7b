// The IR's nodes: the kinds of node_kinds.def, each with a typed payload that says what the
// node means once the checker has resolved it (names to node IDs, symbols such as
// `NOME_SD_CC_sharp` to enums, per-dialect argument orders to catalogue arguments), and the
// pieces payloads are made of: operands (expressions with the Value node tracking the
// sliders they read), vertex references, transforms, generator argument bindings.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "base/small_vec.h"
#include "frontend/source/source_manager.h"
#include "ir/dep_graph.h"
#include "ir/generator_catalogue.h"
#include "ir/ids.h"

namespace nomec::ir {

/// An argument given by expressions, e.g. `translate (0 0 {expr $fp_z})`: its expressions,
/// where it is written, the node it belongs to, and the Value node that tracks the sliders
/// it reads (none for constants). Every operand of a node is listed in `Node::operands`, in
/// written order, so dumps, hover and the dependency graph see them without knowing the
/// node's kind; the payload names the ones that mean something to the backend.
struct Operand {
  std::string_view name;  // as the file writes it: `translate`, `ro`, `sd_level` (static text)
  Slice<ExprId> exprs;    // Module::expr_lists: `module.refs(operand.exprs)`
  SourceRange range;
  NodeId owner;
  NodeId value_node;
};

/// A vertex reference in a face, polyline or consolidate block: either a point node, or a
/// path through instances to a generated/mesh vertex (`fun3.hc3`, 2016 `cf_fun3_hc3`).
struct VertexRef {
  std::string text;               // as written
  std::string vertex;             // vertex name inside the innermost instance target
  std::vector<NodeId> instances;  // resolved instance chain, outermost first
  SourceRange range;
  NodeId point;                   // resolved point, if it names a point
};

/// A flag word, possibly with a value in SLIDE: `closed`, `closed 1`, `begincap 0`. Set when
/// present and its value (if any) is not 0.
struct FlagArg {
  bool is_present = false;
  OperandId value;  // SLIDE writes a number after the word
  SourceRange range;
};

enum class TransformKind : uint8_t { Translate, Rotate, Scale, Mirror, LookAt };
/// One step of an instance's transform chain, e.g. `rotate (1 0 0) (90)`: its operand holds
/// the axis and the angle in degrees (4 expressions); `mirror (a b c d)` the plane. SLIDE's
/// `lookat eye (…) target (…) up (…) endlookat` is three operands (`args` the eye, then
/// `target` and `up`; each may be absent: eye (0 0 0), target (0 0 -1), up (0 1 0)): it puts
/// the origin at the eye and turns −z towards the target and +y towards up.
struct TransformOp {
  TransformKind kind = TransformKind::Translate;
  OperandId args;
  OperandId target, up;  // LookAt only
};

/// A generator argument as the file gives it, e.g. `ro` = `{expr $fp_ro}` of a funnel, or
/// the control points of a curve: a value (numbers, a function, a flag's value), a named
/// node (a path) or a list of nodes (points).
struct GenArgBinding {
  ArgIndex arg = kNoArg;
  OperandId value;
  NodeId ref;
  Slice<NodeId> refs;
  bool is_flag = false;  // a Flag argument given as a bare word
  /// A count written as a number in a NOME 2016 / NOME2 file: the original read it with
  /// `stoi`, which truncates (`6.6` is 6), where an `{expr …}` count is rounded.
  bool is_truncated = false;
  SourceRange range;
};

/// A face named by a `delete` block, e.g. `face cube1_c4 endface`: the instance chain that
/// places it and which face of the instanced mesh (a face node) or generator (an index).
struct DeletedFace {
  std::string text;
  SourceRange range;
  NodeId scope;                   // the group or block the path starts in, if it names one
  std::vector<NodeId> instances;  // outermost written first; outer instances may be omitted
  NodeId face;                    // a face of the innermost instance's mesh, or
  int32_t index = -1;             // the index of a face of its mesh or generator
};

// ---- Payloads, one per node kind ----

/// `set n 8 3 10 1` in bank `fp`: the slider `fp.n`.
struct ParamData {
  double value = 0, min = 0, max = 0, step = 0;
  std::string bank;
  /// Position in its bank's NOME3 `list (…)` (the order a slider panel shows), or -1.
  int32_t list_index = -1;
};
/// The value of one operand whose expressions read parameters (a node of the graph).
struct ValueData {
  OperandId operand;
};
/// `surface S color (1 0 0) endsurface`.
struct SurfaceData {
  OperandId color, reflectivity, exponent, metallic;
};
/// `point p (1 0 0) endpoint`, or a mesh's own point.
struct PointData {
  OperandId position, texture;
};
/// NOME3 `controlpoint cp point p scale (…) rotate (…) crosssection C reverse endcontrolpoint`:
/// a point (its position is `point`'s) that carries sweep data: the scale and rotation of the
/// cross-section at this point, the cross-section curve a `sweepmorph` reaches here (NOME3
/// spells it `cross C`), and `reverse`.
struct ControlPointData {
  NodeId point;
  OperandId scale, rotate, translate;
  NodeId cross_section;
  SourceRange cross_section_range;
  bool reverse = false;
};
/// `polyline l (p1 p2 p3) closed endpolyline` (2016 `isloop`).
struct PolylineData {
  Slice<VertexRef> points;
  Slice<NodeId> point_list;  // SLIDE `pointlist (…)`
  FlagArg closed;
};
/// `face f (a b c) surface S backface B endface`; also `facet` and a saved `consolidateface`.
struct FaceData {
  Slice<VertexRef> vertices;
  NodeId surface;
  NodeId backface;  // JIPCAD: the colour of its back
};
enum class MeshForm : uint8_t { Mesh, Object, Consolidate, SavedWorkingMesh };
/// `mesh m … endmesh`, `object o (f1 f2) endobject`, and the meshes of 2016 saved work.
struct MeshData {
  MeshForm form = MeshForm::Mesh;
  Slice<NodeId> faces;  // an object's face list
  NodeId surface;
};
enum class FlatFormat : uint8_t { Sif, Obj, Stl };
std::string_view flat_format_name(FlatFormat f);
/// The geometry of a flat file (frontend/flat reads it): vertex `k` is named `v<k>`; face
/// `f` is `corners[face_starts[f] .. face_starts[f + 1])`, vertex indices in written order.
struct FlatGeometry {
  std::vector<std::array<double, 3>> positions;
  std::vector<int32_t> face_starts{0};
  std::vector<int32_t> corners;
  int32_t face_count() const { return static_cast<int32_t>(face_starts.size()) - 1; }
};
/// A mesh read from a flat file, e.g. the scene `Zero_6.sif` or `include "hull.stl"`: fixed
/// positions, no parameters. The geometry is shared (immutable) between copies of the module.
struct FlatMeshData {
  FlatFormat format = FlatFormat::Sif;
  std::shared_ptr<const FlatGeometry> geometry;
  bool is_scene = false;  // the file is the scene (or saved work's base), not an `include`
  /// The vertex index a name `v<k>` gives (k < vertex count), or -1.
  int32_t vertex_index(std::string_view name) const;
};
/// A generator of the catalogue, e.g. `funnel fun (8 0.4 -0.2 0.2) endfunnel`.
struct GeneratorData {
  GenKind gen = GenKind::Funnel;
  Slice<GenArgBinding> args;  // in written order
};
/// `sweep s crosssection c … path p … endsweep`: its own options; its cross section and path
/// are child nodes (CrossSection, SweepPath).
struct SweepData {
  OperandId azimuth, twist;
  bool mintorsion = false;
};
/// `path P [mintorsion] [azimuth E] [twist E] [cutbegin] [cutend] endpath` inside a sweep or
/// a sweepmorph.
struct SweepPathData {
  NodeId curve;
  SourceRange curve_range;
  OperandId azimuth, twist, minimizetorsion;
  bool mintorsion = false;
  bool cut_begin = false, cut_end = false;  // JIPCAD
};
/// `crosssection C … endcrosssection`: a curve (by name inside a sweep, or SLIDE `type
/// polyline P` / `polyline P`) or a SLIDE circle, with caps.
struct CrossSectionData {
  NodeId curve;
  SourceRange curve_range;
  bool is_circle = false;
  bool is_star = false;  // SLIDE `type star outerradius R innerradius r slices n`
  OperandId radius, inner_radius, slices;
  FlagArg begin_cap, end_cap;
  bool reverse = false;
};
/// SLIDE `transform translate (…) endtransform`.
struct TransformData {
  Slice<TransformOp> ops;
};
/// `group g … endgroup`.
struct GroupData {
  NodeId surface;
  OperandId lod;  // SLIDE's level of detail: `SLF_OFF` (0) removes the group (slide.md §5)
};
/// `instance i target translate (…) rotate (…) (…) surface S backface B endinstance`.
struct InstanceData {
  NodeId target;
  Slice<TransformOp> transforms;  // in written order; the first written acts first
  NodeId surface;
  NodeId backface;  // JIPCAD: the colour of its faces' backs
  bool is_hidden = false;
  bool is_reversed = false;  // NOME2's `reverse`: every face of the target turned around
  OperandId lod;  // SLIDE's level of detail: `SLF_OFF` (0) removes the instance (slide.md §5)
};
/// `merge m [tolerance E] … endmerge`; NOME2's `merge epsilon E endmerge` (the whole scene).
struct MergeData {
  OperandId tolerance;
};
enum class SubdivisionRule : uint8_t {
  CatmullClarkSharp,  // NOME_SD_CC_sharp (the default): honour `sharp`
  CatmullClark,       // NOME_SD_CatmullClark, NOME_SD_CC, SLF_SUBDIVISION_CATMULL_CLARK
  DeRose,             // NOME_SD_DeRose
};
std::string_view subdivision_rule_name(SubdivisionRule r);
/// `subdivision s [sd_type T] [sd_level E] … endsubdivision` (SLIDE `type T subdivisions E`).
struct SubdivisionData {
  SubdivisionRule rule = SubdivisionRule::CatmullClarkSharp;
  OperandId levels;
  OperandId rule_value;  // SLIDE `type {expr …}`: a Tcl value nomec cannot read yet
  OperandId tolerance;   // merge tolerance
};
enum class OffsetKind : uint8_t {
  Plain,  // the seed's offset (default)
  Grid,   // NOME_OFFSET_GRID, SLF_OFFSET_PERFORATED: a lattice when `width` > 0
};
std::string_view offset_kind_name(OffsetKind k);
/// `offset o [offset_type T] [height E] [width E] … endoffset`.
struct OffsetData {
  OffsetKind kind = OffsetKind::Plain;
  OperandId height, width;
  OperandId kind_value;  // SLIDE `type {expr …}`
  OperandId tolerance;
};
/// `handle h faces (F1 F2) [corners (V1 V2)] [segments E] [weights (E E)] [twist E] … endhandle`.
/// `faces` are resolved from the block's instances (like `delete` entries); `corners` are
/// vertices of those faces, or empty for the automatic pairing.
struct HandleData {
  Slice<DeletedFace> faces;
  Slice<VertexRef> corners;
  OperandId segments, weights, twist;
};
/// `rind r thickness E [punch (F…)] [peel (F…)] … endrind`.
struct RindData {
  OperandId thickness;
  Slice<DeletedFace> punch, peel;
};
/// `sierpinski s level E … endsierpinski`.
struct SierpinskiData {
  OperandId level;
};
/// `menger m level E thickness E [collapse E] … endmenger`.
struct MengerData {
  OperandId level, thickness, collapse;
};
/// SLIDE `mirror m instance … endmirror`: reverses the orientation of its instances' faces.
struct FaceReversalData {};
/// `delete face cube1_c4 endface … enddelete`.
struct DeleteData {
  Slice<DeletedFace> faces;
};
/// `sharp 9 (v1 v2 v3) (v4 v5) endsharp` inside a mesh: crease chains.
struct SharpData {
  OperandId sharpness;
  Slice<Slice<VertexRef>> chains;
};
/// `zipper z border (a.v0 a.v3) border (b.v0 b.v3) [penalty E] endzipper`.
struct ZipperData {
  Slice<VertexRef> borders[2];
  int32_t border_count = 0;  // as written (the checker reports anything but 2)
  OperandId penalty;
};
enum class SceneKind : uint8_t { Camera, Light, Window, Viewport, Render, DisplayColor };
enum class Projection : uint8_t { Parallel, Perspective };  // SLF_PARALLEL 0, SLF_PERSPECTIVE 1
std::string_view projection_name(Projection p);
enum class LightType : uint8_t { Ambient, Directional, Point, Spot };  // SLF_AMBIENT 0 … SLF_SPOT 3
std::string_view light_type_name(LightType t);
/// An enumerated field given as a symbol (`projection SLF_PERSPECTIVE`, resolved to the enum)
/// or as a Tcl value (`{expr $SLF_PERSPECTIVE}`: `value`, read as the enum's number).
template <typename E>
struct SceneEnum {
  E symbol{};
  OperandId value;
  bool is_written = false;
};
/// A SLIDE path to a camera or light: `gCam.iCam.cam` = root group `gCam`, its instance
/// `iCam`, whose target is `cam`; or just `lAmbient` (the node, untransformed). Resolved once
/// every instance is known; `node` stays None when the path does not resolve (reported).
struct ScenePath {
  std::string text;
  SourceRange range;
  NodeId root;                    // the first name when the path has instances
  std::vector<NodeId> instances;  // outermost first
  NodeId node;                    // the camera or light at the end
};
/// `light PATH [onoff]` of a `render`.
struct RenderLight {
  ScenePath path;
  SceneEnum<bool> on;  // SLF_ON when not written
};
/// Viewing set-up, kept for the live preview (no geometry; STL/OBJ do not carry it). Which
/// members mean something depends on `kind`; an absent operand takes the default below.
///   camera C [projection P] [frustum (min) (max)] endcamera (SLIDE; NOME3 writes one list
///     `(left right bottom top near far)`, `frustum_is_lrbtnf`)
///   light L [type T] [color (r g b)] [direction (x y z)] endlight (`direction`: JIPCAD)
///   window W [background (r g b)] [origin (x y)] [size (w h)] [resize F] [ratio F] endwindow
///   viewport V WINDOW [origin (x y)] [size (w h)] endviewport (NOME3: `cameraID C`)
///   render VIEWPORT CAMERA_PATH ROOT (light PATH [onoff])* endrender
/// NOME2's display colours (`foreground surface S endforeground` …) are `DisplayColor`.
struct SceneData {
  SceneKind kind = SceneKind::Camera;
  SceneEnum<Projection> projection;  // camera (default SLF_PARALLEL)
  OperandId frustum;                 // camera: six values
  bool frustum_is_lrbtnf = false;
  SceneEnum<LightType> light_type;   // light (default SLF_AMBIENT, see kDefaultLightType)
  OperandId color, direction;        // light
  OperandId background, origin, size;  // window; viewport: origin, size
  SceneEnum<bool> resize, ratio;       // window (SLF_ON when not written)
  NodeId window, camera;             // viewport: its window; NOME3's `cameraID`
  NodeId viewport, root;             // render
  ScenePath camera_path;             // render
  std::vector<RenderLight> lights;   // render
};
// SLIDE's defaults (slide.md §3.18–3.20). A light's type and colour are not in the sources;
// nomec takes SLIDEUI.tcl's light panel presets (type 0, colour 0.5).
inline constexpr std::array<double, 6> kDefaultFrustum{-1.0, -1.0, -100.0, 1.0, 1.0, -0.02};
inline constexpr std::array<double, 3> kDefaultLightColor{0.5, 0.5, 0.5};
inline constexpr LightType kDefaultLightType = LightType::Ambient;
inline constexpr std::array<double, 3> kDefaultBackground{0.0, 0.0, 0.0};
inline constexpr std::array<double, 2> kDefaultWindowOrigin{0.25, 0.25};
inline constexpr std::array<double, 2> kDefaultWindowSize{0.5, 0.5};
inline constexpr std::array<double, 2> kDefaultViewportOrigin{0.0, 0.0};
inline constexpr std::array<double, 2> kDefaultViewportSize{1.0, 1.0};

enum class SceneColorKind : uint8_t { Front, Back, Background };
std::string_view scene_color_name(SceneColorKind k);
/// JIPCAD's viewer colours: `frontcolor (1 0.5 0) endfrontcolor`, `backcolor …`,
/// `backgroundcolor …`. No geometry; the last of each kind in the file is in effect.
struct SceneColorData {
  SceneColorKind kind = SceneColorKind::Front;
  OperandId color;
};
/// JIPCAD `backface B color (r g b) endbackface`: a back-face colour that `face … backface B`
/// and `instance … backface B` apply.
struct BackfaceData {
  OperandId color;
};
/// JIPCAD `sweepmorph S [begincap] [endcap] [reverse] path P … endpath endsweepmorph`: a sweep
/// whose cross-section at each ring is interpolated between the cross-sections of the
/// path's control points. Its path is a child node (SweepPath).
struct SweepMorphData {
  bool begin_cap = false, end_cap = false, reverse = false;
};
/// JIPCAD `morphvisualizer V sweep S index E endmorphvisualizer`: the index-th interpolated
/// cross-section of sweepmorph `S`, placed on its ring, as a line strip `v{index}_{i}`.
struct MorphVisualizerData {
  NodeId sweep;
  OperandId index;
};

// ---- Nodes ----

enum class NodeKind : uint8_t {
#define NOMEC_IR_NODE(Kind, Payload, Name) Kind,
#include "ir/node_kinds.def"
};
std::string_view node_kind_name(NodeKind kind);

/// A payload kept out of line, with value semantics (copies copy the payload): for the
/// large ones few nodes have, which would otherwise size every node's variant.
template <typename T>
class Boxed {
 public:
  Boxed() : p_(std::make_unique<T>()) {}
  Boxed(const Boxed& o) : p_(std::make_unique<T>(*o.p_)) {}
  Boxed(Boxed&&) noexcept = default;
  Boxed& operator=(const Boxed& o) {
    if (this != &o) p_ = std::make_unique<T>(*o.p_);
    return *this;
  }
  Boxed& operator=(Boxed&&) noexcept = default;
  ~Boxed() = default;
  T& get() { return *p_; }
  const T& get() const { return *p_; }

 private:
  std::unique_ptr<T> p_;
};
/// Which payloads are boxed: SceneData (200 bytes; cameras, lights, windows, renders),
/// CrossSectionData (76; sweeps only), ParamData (72; a parameter per few dozen nodes),
/// ControlPointData and PolylineData (36; sweeps and curves), so that the variant is sized
/// by payloads of at most 32 bytes.
template <typename T>
inline constexpr bool kIsBoxed = std::is_same_v<T, SceneData> || std::is_same_v<T, CrossSectionData> ||
                                 std::is_same_v<T, ParamData> || std::is_same_v<T, ControlPointData> ||
                                 std::is_same_v<T, PolylineData>;
template <typename T>
using Stored = std::conditional_t<kIsBoxed<T>, Boxed<T>, T>;

/// The payloads in node_kinds.def order: `data.index()` is always the node's kind. Read
/// them with Node::as<T>() and Node::is<T>(), which see through Boxed.
using Payload = std::variant<
#define NOMEC_IR_NODE(Kind, Payload, Name) Stored<Payload>,
#include "ir/node_kinds.def"
    std::monostate>;

/// Makes `data` hold `kind`'s payload, default-constructed in place.
void emplace_payload(Payload& data, NodeKind kind);

/// True for the pipeline blocks, whose children are the instances they work on (merge,
/// subdivision, offset, handle, rind, sierpinski, menger, SLIDE mirror).
bool is_block(NodeKind kind);

/// Where a node's children or operands are in the module's `links` (see Module::children).
struct LinkList {
  int32_t first = -1;
  int32_t last = -1;
  bool empty() const { return first < 0; }
};

/// One IR node. Examples: Param `fp.n`; Generator `fun` with GenKind::Funnel; Instance
/// `cf.fun1` whose payload holds its target and transform chain.
// Rationale: a large scene has tens of thousands of nodes, so members are ordered to leave
// no padding, the variant is sized by the common payloads (the large rare ones are boxed,
// see Stored) and the lists of children and operands are threaded through one array of
// the module instead of a vector in each node: 128 bytes a node instead of 200.
struct Node {
  /// The statement's keyword as written (`facet`, `object`, `bsplinecurve`): for display in
  /// hover, dumps and messages only; code decides by `kind` and the payload.
  std::string_view keyword;
  std::string name;  // qualified, e.g. "cubeMadeByFunnel.fun1"; "" if anonymous
  /// Mesh points/faces/sharps, group/block instances, sweep parts: `module.children(node)`.
  LinkList children;
  LinkList operands;  // every operand, in written order: `module.operands_of(node)`
  SourceRange range;
  NodeId parent;                // enclosing mesh/group/block
  NodeKind kind = NodeKind::Value;
  Payload data{std::in_place_type<std::monostate>};  // Module::add_node sets the kind's

  template <typename T>
  const T& as() const {
    if constexpr (kIsBoxed<T>) {
      return std::get_if<Boxed<T>>(&data)->get();
    } else {
      return *std::get_if<T>(&data);
    }
  }
  template <typename T>
  T& as() {
    if constexpr (kIsBoxed<T>) {
      return std::get_if<Boxed<T>>(&data)->get();
    } else {
      return *std::get_if<T>(&data);
    }
  }
  template <typename T>
  bool is() const {
    return std::holds_alternative<Stored<T>>(data);
  }
};
static_assert(sizeof(Payload) <= 40 && sizeof(Node) <= 128, "see the rationale above Node");

}  // namespace nomec::ir
