// The flat-file front door (see flat.h): the format by extension, dispatch to the readers,
// and the helpers they share.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <optional>
#include <string>
#include <unordered_set>

#include "frontend/flat/flat_internal.h"

namespace nomec::flat {

std::optional<ir::FlatFormat> format_of_path(std::string_view path) {
  const size_t slash = path.find_last_of('/');
  const std::string_view name = slash == std::string_view::npos ? path : path.substr(slash + 1);
  const size_t dot = name.rfind('.');
  if (dot == std::string_view::npos || dot == 0) return std::nullopt;
  std::string ext(name.substr(dot + 1));
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  if (ext == "sif") return ir::FlatFormat::Sif;
  if (ext == "obj") return ir::FlatFormat::Obj;
  if (ext == "stl") return ir::FlatFormat::Stl;
  return std::nullopt;
}

std::shared_ptr<const ir::FlatGeometry> read(const SourceManager& sources, FileId file, ir::FlatFormat format,
                                             DiagnosticEngine& diags, const ReadOptions& options) {
  switch (format) {
    case ir::FlatFormat::Sif: return read_sif(sources, file, diags, options);
    case ir::FlatFormat::Obj: return read_obj(sources, file, diags);
    case ir::FlatFormat::Stl: return read_stl(sources, file, diags);
  }
  return std::make_shared<const ir::FlatGeometry>();
}

namespace detail {

std::optional<double> parse_number(std::string_view text) {
  if (!text.empty() && text[0] == '+') text.remove_prefix(1);
  if (text.empty() || text[0] == '+') return std::nullopt;
  double v = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<int64_t> parse_integer(std::string_view text) {
  bool negative = false;
  if (!text.empty() && (text[0] == '+' || text[0] == '-')) {
    negative = text[0] == '-';
    text.remove_prefix(1);
  }
  if (text.empty()) return std::nullopt;
  int64_t v = 0;
  for (char ch : text) {
    if (ch < '0' || ch > '9') return std::nullopt;
    v = std::min<int64_t>(v * 10 + (ch - '0'), int64_t{1} << 40);
  }
  return negative ? -v : v;
}

bool add_face(ir::FlatGeometry& g, std::span<const int32_t> vertices, SourceRange at, std::string_view what,
              DiagnosticEngine& diags, int& dropped) {
  // The first vertex (in the face's order) that the face uses again. Pairwise for the
  // faces of real meshes; in one pass from the end for long ones (a face of a million
  // corners in a hostile file would take hours pairwise).
  std::optional<int32_t> repeated;
  if (vertices.size() <= 32) {
    for (size_t i = 0; i < vertices.size() && !repeated; ++i) {
      for (size_t j = i + 1; j < vertices.size(); ++j) {
        if (vertices[i] == vertices[j]) {
          repeated = vertices[i];
          break;
        }
      }
    }
  } else {
    std::unordered_set<int32_t> later;
    later.reserve(vertices.size());
    for (size_t i = vertices.size(); i-- > 0;) {
      if (!later.insert(vertices[i]).second) repeated = vertices[i];
    }
  }
  if (repeated) {
    if (++dropped > kShownDropped) return false;
    diags.emit(DiagKind::FlatDegenerateFace, at,
               fmt::format("{} uses vertex v{} twice (after welding); the face is dropped", what, *repeated));
    return false;
  }
  g.corners.insert(g.corners.end(), vertices.begin(), vertices.end());
  g.face_starts.push_back(static_cast<int32_t>(g.corners.size()));
  return true;
}

void report_dropped(int dropped, FileId file, DiagnosticEngine& diags) {
  if (dropped <= kShownDropped) return;
  diags.emit(DiagKind::FlatDegenerateFace, SourceRange{file, 0, 0},
             fmt::format("{} more faces of this file use a vertex twice (after welding) and are dropped", dropped - kShownDropped));
}

}  // namespace detail

}  // namespace nomec::flat
