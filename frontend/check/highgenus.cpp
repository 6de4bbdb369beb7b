// The high-genus blocks of the second seed (`handle`, `rind`, `sierpinski`, `menger`, see
// handlers.h): face and vertex paths are resolved from the block's own instances once its
// body is read, required options are checked, and a level whose result could not be
// built in memory is an error here rather than an exhausted machine later.
#include <cmath>
#include <fmt/format.h>

#include "frontend/check/handlers.h"

namespace nomec::check {

namespace {

// Levels above these make tens of millions of faces from the smallest input (a
// tetrahedron multiplies its faces by about 4 per Sierpinski level, a cube by about 13
// per Menger level).
constexpr int kMaxSierpinskiLevel = 7;
constexpr int kMaxMengerLevel = 4;

void require(Context& c, const ast::Stmt& s, bool present, std::string_view option, std::string_view example) {
  if (present) return;
  c.diags().emit(DiagKind::MissingArgument, s.open_kw,
                 fmt::format("`{}` needs `{}`, e.g. `{}`", s.keyword, option, example));
}

void check_level(Context& c, const ast::Stmt& s, ir::OperandId level, int max, std::string_view why) {
  if (!level.is_valid()) return;
  const ir::Operand& op = c.module().operand(level);
  if (op.exprs.empty()) return;
  const ir::EvalResult v = ir::evaluate(c.module(), c.module().refs(op.exprs)[0]);
  if (!v.ok || std::lround(v.value) <= max) return;
  c.diags()
      .emit(DiagKind::LevelTooHigh, op.range,
            fmt::format("`{}` level {} is too high: the most is {}", s.keyword, std::lround(v.value), max))
      .note(SourceRange{}, std::string(why));
}

ir::Slice<ir::DeletedFace> resolve_faces(Context& c, ir::NodeId id,
                                         const std::vector<std::pair<std::string, SourceRange>>& paths) {
  ir::Module& m = c.module();
  const uint32_t begin = static_cast<uint32_t>(m.deleted_faces.size());
  for (const auto& [text, range] : paths) {
    ir::DeletedFace f = resolve_block_face(c, text, range, id);
    for (ir::NodeId inst : f.instances) m.deps.add_edge(inst, id);
    m.deleted_faces.push_back(std::move(f));
  }
  return {begin, static_cast<uint32_t>(m.deleted_faces.size()) - begin};
}

}  // namespace

void note_block_paths(BlockPaths& p, const OptionValue& v) {
  switch (v.spec->key) {
    case Opt::Faces:
      p.faces = v.paths;
      p.faces_range = v.value_range;
      p.has_faces = true;
      return;
    case Opt::Corners:
      p.corners = v.paths;
      p.corners_range = v.value_range;
      p.has_corners = true;
      return;
    case Opt::Punch: p.punch.insert(p.punch.end(), v.paths.begin(), v.paths.end()); return;
    case Opt::Peel: p.peel.insert(p.peel.end(), v.paths.begin(), v.paths.end()); return;
    default: return;
  }
}

void finish_highgenus(Context& c, const ast::Stmt& s, ir::NodeId id, const BlockPaths& p) {
  ir::Module& m = c.module();
  switch (m.node(id).kind) {
    case ir::NodeKind::Handle: {
      require(c, s, p.has_faces, "faces", "faces (c.f1 c.f2)");
      if (p.has_faces && p.faces.size() != 2) {
        c.diags().emit(DiagKind::ListArity, p.faces_range,
                       fmt::format("a handle joins 2 faces, but `faces` lists {}", p.faces.size()));
      }
      if (p.has_corners && p.corners.size() != 2) {
        c.diags().emit(DiagKind::ListArity, p.corners_range,
                       fmt::format("`corners` names one vertex of each face (2), but lists {}", p.corners.size()));
      }
      const ir::Slice<ir::DeletedFace> faces = resolve_faces(c, id, p.faces);
      std::vector<ir::VertexRef> corners;
      for (const auto& [text, range] : p.corners) corners.push_back(resolve_block_vertex(c, text, range, id));
      for (const ir::VertexRef& r : corners) {
        for (ir::NodeId inst : r.instances) m.deps.add_edge(inst, id);
      }
      const ir::Slice<ir::VertexRef> refs = m.add_vertex_refs(std::move(corners));
      ir::HandleData& d = m.get<ir::HandleData>(id);
      d.faces = faces;
      d.corners = refs;
      return;
    }
    case ir::NodeKind::Rind: {
      require(c, s, m.get<ir::RindData>(id).thickness.is_valid(), "thickness", "thickness 0.1");
      const ir::Slice<ir::DeletedFace> punch = resolve_faces(c, id, p.punch);
      const ir::Slice<ir::DeletedFace> peel = resolve_faces(c, id, p.peel);
      m.get<ir::RindData>(id).punch = punch;
      m.get<ir::RindData>(id).peel = peel;
      return;
    }
    case ir::NodeKind::Sierpinski: {
      const ir::OperandId level = m.get<ir::SierpinskiData>(id).level;
      require(c, s, level.is_valid(), "level", "level 2");
      check_level(c, s, level, kMaxSierpinskiLevel,
                  "each Sierpinski level makes about 4 times as many faces");
      return;
    }
    case ir::NodeKind::Menger: {
      const ir::MengerData& d = m.get<ir::MengerData>(id);
      require(c, s, d.level.is_valid(), "level", "level 2");
      require(c, s, d.thickness.is_valid(), "thickness", "thickness 0.33");
      check_level(c, s, d.level, kMaxMengerLevel, "each Menger level makes about 13 times as many faces");
      return;
    }
    default:
      return;
  }
}

}  // namespace nomec::check
