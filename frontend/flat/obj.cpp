// Wavefront `.obj`: `v x y z [w]` vertices (named `v0, v1, …` in file order; OBJ shares
// vertices by index, so nothing is welded), `f` faces whose corners are `a`, `a/t`, `a//n`
// or `a/t/n` with 1-based indices or negative ones counted back from the last vertex read.
// `vt`, `vn`, `vp`, `g`, `o`, `s`, `usemtl`, `mtllib` are read and not used: groups and
// objects stay one mesh (the file is one mesh of the scene). Other statements (`l`, curves)
// are ignored with a warning.
#include <algorithm>
#include <array>
#include <fmt/format.h>
#include <string>
#include <vector>

#include "frontend/flat/flat_internal.h"

namespace nomec::flat {

namespace {

struct Word {
  std::string_view text;
  uint32_t begin = 0;
};

struct PendingFace {
  std::vector<int64_t> vertices;  // 0-based, possibly out of range (checked at the end)
  std::vector<SourceRange> ranges;
  SourceRange range;
};

std::vector<Word> split(std::string_view line, uint32_t offset) {
  std::vector<Word> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
    if (j > i) out.push_back(Word{line.substr(i, j - i), offset + static_cast<uint32_t>(i)});
    i = j;
  }
  return out;
}

bool is_unused_statement(std::string_view k) {
  return k == "vt" || k == "vn" || k == "vp" || k == "g" || k == "o" || k == "s" || k == "usemtl" || k == "mtllib";
}

}  // namespace

std::shared_ptr<const ir::FlatGeometry> read_obj(const SourceManager& sources, FileId file, DiagnosticEngine& diags) {
  const std::string_view text = sources.text(file);
  auto g = std::make_shared<ir::FlatGeometry>();
  auto range = [file](const Word& w) { return SourceRange{file, w.begin, w.begin + static_cast<uint32_t>(w.text.size())}; };
  std::vector<PendingFace> faces;
  std::vector<std::string> warned;
  size_t start = utf8_bom_length(text);  // a leading byte order mark is not part of the mesh
  while (start < text.size()) {
    size_t nl = text.find('\n', start);
    if (nl == std::string_view::npos) nl = text.size();
    std::string_view line = text.substr(start, nl - start);
    if (const size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    std::vector<Word> w = split(line, static_cast<uint32_t>(start));
    start = nl + 1;
    if (w.empty()) continue;
    const SourceRange whole{file, w.front().begin, w.back().begin + static_cast<uint32_t>(w.back().text.size())};
    if (w[0].text == "v") {
      std::array<double, 3> p{0, 0, 0};
      if (w.size() < 4) {
        diags.emit(DiagKind::FlatSyntax, whole, fmt::format("a vertex is `v x y z`, this one has {} numbers", w.size() - 1));
      }
      for (size_t k = 1; k < w.size(); ++k) {
        std::optional<double> x = detail::parse_number(w[k].text);
        if (!x) {
          diags.emit(DiagKind::FlatSyntax, range(w[k]), fmt::format("`{}` is not a number", w[k].text));
        } else if (k <= 3) {
          p[k - 1] = *x;
        }
      }
      g->positions.push_back(p);
    } else if (w[0].text == "f") {
      PendingFace f;
      f.range = whole;
      bool ok = true;
      for (size_t k = 1; k < w.size(); ++k) {
        const std::string_view corner = w[k].text;
        const std::string_view index = corner.substr(0, corner.find('/'));
        std::optional<int64_t> i = detail::parse_integer(index);
        if (!i || *i == 0) {
          diags.emit(DiagKind::FlatSyntax, range(w[k]),
                     fmt::format("`{}` is not a face corner: write a vertex number from 1 (or from -1 counting back), "
                                 "optionally followed by `/texture/normal`",
                                 corner));
          ok = false;
          continue;
        }
        f.vertices.push_back(*i > 0 ? *i - 1 : static_cast<int64_t>(g->positions.size()) + *i);
        f.ranges.push_back(range(w[k]));
      }
      if (ok && f.vertices.size() < 3) {
        diags.emit(DiagKind::FlatSyntax, whole, fmt::format("a face needs at least 3 corners, this one has {}", f.vertices.size()));
        ok = false;
      }
      if (ok) faces.push_back(std::move(f));
    } else if (!is_unused_statement(w[0].text)) {
      const std::string k(w[0].text);
      if (std::find(warned.begin(), warned.end(), k) == warned.end()) {
        diags.emit(DiagKind::FlatIgnoredStatement, range(w[0]),
                   fmt::format("`{}` is not used: nomec reads the vertices (`v`) and faces (`f`) of an `.obj` file",
                               k.size() > 20 ? k.substr(0, 20) + "…" : k));
        warned.push_back(k);
      }
    }
  }
  const int64_t n = static_cast<int64_t>(g->positions.size());
  int dropped = 0;
  for (const PendingFace& f : faces) {
    std::vector<int32_t> vs;
    for (size_t k = 0; k < f.vertices.size(); ++k) {
      if (f.vertices[k] < 0 || f.vertices[k] >= n) {
        const std::string_view written = sources.text(f.ranges[k]).substr(0, sources.text(f.ranges[k]).find('/'));
        diags.emit(DiagKind::FlatIndexOutOfRange, f.ranges[k],
                   written.starts_with("-")
                       ? fmt::format("vertex {} is out of range: it counts back past the first vertex (negative indices count "
                                     "back from the last vertex read before the face)",
                                     written)
                       : fmt::format("vertex {} is out of range: the file has {} vertices, numbered from 1", written, n));
        vs.clear();
        break;
      }
      vs.push_back(static_cast<int32_t>(f.vertices[k]));
    }
    if (!vs.empty()) detail::add_face(*g, vs, f.range, fmt::format("face `{}`", sources.text(f.range).substr(0, 60)), diags, dropped);
  }
  detail::report_dropped(dropped, file, diags);
  return g;
}

}  // namespace nomec::flat
