// The high-genus blocks for the evaluator (see context.h): the block's faces and corners,
// named through its instances, are found in its merged input by their provenance (the
// instance that placed a face and the face node or generator face number), then the
// kernel's handle, rind, Sierpinski or Menger construction runs on the merged mesh.
#include <cmath>
#include <fmt/format.h>

#include "backend/eval/context.h"
#include "kernel/highgenus.h"

namespace nomec::backend::eval {

namespace {

// The faces of `soup` that `d` names: faces placed by its innermost instance that come
// from its face node, or its `index`-th face of each placement of that instance.
std::vector<int32_t> faces_named(const kernel::PolygonSoup& soup, const ir::DeletedFace& d) {
  std::vector<int32_t> out;
  if (d.instances.empty()) return out;
  const int32_t inst = d.instances.back().index;
  int32_t ordinal = 0;
  for (int32_t f = 0; f < soup.face_count(); ++f) {
    const kernel::FaceSource& s = soup.face_sources[f];
    if (s.instance != inst) {
      ordinal = 0;
      continue;
    }
    if (d.face.is_valid() ? s.source_face == d.face.index : ordinal == d.index) out.push_back(f);
    ++ordinal;
  }
  return out;
}

// The one face of the merged mesh that `d` names, or nullopt (reported).
std::optional<kernel::FaceId> one_face(Context& c, const ir::Node& p, const kernel::PolygonSoup& soup,
                                       const ir::DeletedFace& d) {
  if (d.instances.empty()) return std::nullopt;  // the checker reported it
  const std::vector<int32_t> found = faces_named(soup, d);
  if (found.size() == 1) return kernel::FaceId(found[0]);
  c.diags().emit(DiagKind::GeometryFailed, d.range,
                 found.empty() ? fmt::format("`{}` `{}`: the face `{}` is not in the block's input (was it deleted?)",
                                             p.keyword, short_name(p.name), d.text)
                               : fmt::format("`{}` `{}`: `{}` names {} faces, because its instance is placed {} "
                                             "times; name a face placed once",
                                             p.keyword, short_name(p.name), d.text, found.size(), found.size()));
  return std::nullopt;
}

// The merged vertex of face `f` (a soup face) that `r` names, or None (reported).
kernel::VertexId corner(Context& c, const ir::Node& p, const kernel::PolygonSoup& soup, int32_t f,
                        const std::vector<kernel::VertexId>& vertex_map, const ir::VertexRef& r) {
  if (r.instances.empty()) return kernel::VertexId::None();  // the checker reported it
  const kernel::FaceSource& s = soup.face_sources[f];
  const ir::Node& src = c.m.node(ir::NodeId(s.source_face));
  const std::string wanted = src.kind == ir::NodeKind::Generator
                                 ? ir::canonical_vertex_name(src.as<ir::GeneratorData>().gen, r.vertex)
                                 : r.vertex;
  size_t at = 0;
  for (int32_t g = 0; g < f; ++g) at += soup.face_sizes[g];
  const bool same_instance = s.instance == r.instances.back().index;
  for (int32_t k = 0; k < soup.face_sizes[f] && same_instance; ++k) {
    const int32_t v = soup.face_vertices[at + k];
    if (static_cast<size_t>(v) < soup.names.size() && (soup.names[v] == wanted || soup.names[v] == r.vertex)) {
      return vertex_map[v];
    }
  }
  c.diags().emit(DiagKind::GeometryFailed, r.range,
                 fmt::format("`{}` `{}`: `{}` is not a corner of the face it is paired with", p.keyword,
                             short_name(p.name), r.text));
  return kernel::VertexId::None();
}

int64_t face_limit(const Context& c) { return std::max<int64_t>(c.vertex_budget, 1); }

kernel::Result<kernel::Mesh> run_handle(Context& c, const ir::Node& p, const kernel::Mesh& mesh,
                                        const kernel::PolygonSoup& soup, const std::vector<kernel::VertexId>& vertex_map,
                                        bool& reported) {
  const ir::HandleData& d = p.as<ir::HandleData>();
  const std::span<const ir::DeletedFace> faces = c.m.refs(d.faces);
  const std::span<const ir::VertexRef> corners = c.m.refs(d.corners);
  kernel::HandleOptions o;
  reported = true;
  if (faces.size() != 2) return kernel::KernelError{};  // the checker reported it
  for (int k = 0; k < 2; ++k) {
    auto f = one_face(c, p, soup, faces[k]);
    if (!f) return kernel::KernelError{};
    o.faces[k] = *f;
    if (corners.size() == 2) {
      o.corners[k] = corner(c, p, soup, f->index, vertex_map, corners[k]);
      if (!o.corners[k].is_valid()) return kernel::KernelError{};
    }
  }
  reported = false;
  o.segments = static_cast<int32_t>(std::lround(scalar(c, d.segments, 0, 1)));
  o.weights[0] = scalar(c, d.weights, 0, 1);
  o.weights[1] = scalar(c, d.weights, 1, 1);
  o.twist = scalar(c, d.twist, 0, 0);
  return kernel::connect_faces(mesh, o);
}

kernel::Result<kernel::Mesh> run_rind(Context& c, const ir::Node& p, const kernel::Mesh& mesh,
                                      const kernel::PolygonSoup& soup, bool& reported) {
  const ir::RindData& d = p.as<ir::RindData>();
  kernel::RindOptions o;
  o.thickness = scalar(c, d.thickness, 0, 0.1);
  reported = true;
  for (int which = 0; which < 2; ++which) {
    for (const ir::DeletedFace& face : c.m.refs(which == 0 ? d.punch : d.peel)) {
      auto f = one_face(c, p, soup, face);
      if (!f) return kernel::KernelError{};
      (which == 0 ? o.punch : o.peel).push_back(*f);
    }
  }
  reported = false;
  return kernel::rind(mesh, o);
}

}  // namespace

bool is_high_genus(ir::NodeKind k) {
  return k == ir::NodeKind::Handle || k == ir::NodeKind::Rind || k == ir::NodeKind::Sierpinski ||
         k == ir::NodeKind::Menger;
}

std::optional<kernel::Mesh> high_genus(Context& c, ir::NodeId pid, const kernel::Mesh& mesh,
                                       const kernel::PolygonSoup& soup, const std::vector<kernel::VertexId>& vertex_map) {
  const ir::Node& p = c.m.node(pid);
  bool reported = false;
  SourceRange at = p.range;
  ++c.counters.kernel_ops;
  auto result = [&]() -> kernel::Result<kernel::Mesh> {
    switch (p.kind) {
      case ir::NodeKind::Handle: return run_handle(c, p, mesh, soup, vertex_map, reported);
      case ir::NodeKind::Rind: return run_rind(c, p, mesh, soup, reported);
      case ir::NodeKind::Sierpinski: {
        const ir::SierpinskiData& d = p.as<ir::SierpinskiData>();
        if (d.level.is_valid()) at = c.m.operand(d.level).range;
        return kernel::sierpinski(mesh, {static_cast<int32_t>(std::lround(scalar(c, d.level, 0, 1))), face_limit(c)});
      }
      case ir::NodeKind::Menger: {
        const ir::MengerData& d = p.as<ir::MengerData>();
        if (d.level.is_valid()) at = c.m.operand(d.level).range;
        kernel::MengerOptions o;
        o.levels = static_cast<int32_t>(std::lround(scalar(c, d.level, 0, 1)));
        o.thickness = scalar(c, d.thickness, 0, 0.1);
        o.collapse = scalar(c, d.collapse, 0, 0);
        o.max_faces = face_limit(c);
        return kernel::menger(mesh, o);
      }
      default: return kernel::KernelError{kernel::KernelError::Kind::InvalidArgument, "not a high-genus block", {}, {}, {}};
    }
  }();
  if (result) return std::move(*result);
  if (!reported) {
    kernel::KernelError e = result.error();
    e.vertices.clear();  // merged-mesh vertices; the faces are the input's
    report(c, e, soup, at, short_name(p.name));
  }
  return std::nullopt;
}

}  // namespace nomec::backend::eval
