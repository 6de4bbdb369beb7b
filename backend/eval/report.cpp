// Kernel errors as diagnostics (see context.h): at the face statement, generator or zipper
// that made the faces the kernel complains about, naming the instance that placed them.
#include <fmt/format.h>

#include "backend/eval/context.h"

namespace nomec::backend::eval {

void report(Context& c, const kernel::KernelError& e, const kernel::PolygonSoup& soup, SourceRange fallback,
            std::string_view what) {
  DiagKind kind = e.kind == kernel::KernelError::Kind::NonManifoldEdge ||
                          e.kind == kernel::KernelError::Kind::NonManifoldVertex ||
                          e.kind == kernel::KernelError::Kind::NonManifoldMerge
                      ? DiagKind::NonManifoldGeometry
                      : DiagKind::GeometryFailed;
  std::vector<std::pair<SourceRange, std::string>> places;
  for (kernel::FaceId f : e.faces) {
    if (f.index < 0 || static_cast<size_t>(f.index) >= soup.face_sources.size()) continue;
    const kernel::FaceSource& s = soup.face_sources[f.index];
    SourceRange r = s.source_face >= 0 ? c.m.nodes[s.source_face].range : fallback;
    std::string label;
    if (s.source_face >= 0) {
      const ir::Node& src = c.m.nodes[s.source_face];
      label = src.kind == ir::NodeKind::Face ? fmt::format("face `{}`", short_name(src.name))
                                             : fmt::format("`{}` `{}`", src.keyword, short_name(src.name));
    }
    auto it = c.instance_paths.find(s.instance);
    if (it != c.instance_paths.end()) {
      label += fmt::format(" of instance `{}`", it->second);
    }
    places.emplace_back(r, label);
    if (places.size() >= 4) break;
  }
  std::string where = places.empty() ? fmt::format(" in `{}`", what) : fmt::format(" ({})", places[0].second);
  SourceRange at = places.empty() ? fallback : places[0].first;
  std::string message = fmt::format("{}{}", e.message, where);
  auto d = kind == DiagKind::NonManifoldGeometry
               ? c.diags().emit(DiagKind::NonManifoldGeometry, at, std::move(message))
               : c.diags().emit(DiagKind::GeometryFailed, at, std::move(message));
  for (size_t i = 1; i < places.size(); ++i) {
    d.note(places[i].first, fmt::format("also involves {}", places[i].second));
  }
}

}  // namespace nomec::backend::eval
