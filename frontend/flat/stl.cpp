// `.stl`, binary or ASCII: triangles given by their corner positions. Corners at exactly
// equal positions are one vertex (so triangles share vertices and edges), named `v0, v1, …`
// in order of first appearance; facet normals are not used. A file whose size is 84 + 50·n
// bytes for the n its header declares is binary (even if it starts with `solid`, as some
// exporters write); otherwise a file starting with `solid` is ASCII.
#include <array>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fmt/format.h>
#include <map>
#include <vector>

#include "frontend/flat/flat_internal.h"

namespace nomec::flat {

namespace {

// Welds corners at exactly equal positions (-0 equals 0).
class Welder {
 public:
  explicit Welder(ir::FlatGeometry& g) : g_(g) {}
  int32_t operator()(std::array<double, 3> p) {
    for (double& x : p) x = x == 0 ? 0.0 : x;
    auto [it, inserted] = index_.emplace(p, static_cast<int32_t>(g_.positions.size()));
    if (inserted) g_.positions.push_back(p);
    return it->second;
  }

 private:
  ir::FlatGeometry& g_;
  std::map<std::array<double, 3>, int32_t> index_;
};

uint32_t read_u32(std::string_view t, size_t at) {
  uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(t[at + static_cast<size_t>(k)]);
  return v;
}

float read_f32(std::string_view t, size_t at) {
  const uint32_t bits = read_u32(t, at);
  float f = 0;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

void read_binary(std::string_view t, FileId file, ir::FlatGeometry& g, DiagnosticEngine& diags, int& dropped) {
  Welder weld(g);
  const uint32_t n = read_u32(t, 80);
  for (uint32_t i = 0; i < n; ++i) {
    const size_t at = 84 + 50 * static_cast<size_t>(i);
    const SourceRange r{file, static_cast<uint32_t>(at), static_cast<uint32_t>(at + 50)};
    int32_t vs[3];
    bool ok = true;
    for (size_t k = 0; k < 3 && ok; ++k) {
      std::array<double, 3> p{};
      for (size_t c = 0; c < 3; ++c) p[c] = read_f32(t, at + 12 + 12 * k + 4 * c);
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
        diags.emit(DiagKind::FlatSyntax, r, fmt::format("triangle {} has a corner that is not a finite number; it is skipped", i));
        ok = false;
        break;
      }
      vs[k] = weld(p);
    }
    if (ok) detail::add_face(g, vs, r, fmt::format("triangle {}", i), diags, dropped);
  }
}

struct Word {
  std::string_view text;
  uint32_t begin = 0;
};

void read_ascii(std::string_view t, FileId file, ir::FlatGeometry& g, DiagnosticEngine& diags, int& dropped) {
  Welder weld(g);
  std::vector<Word> words;
  for (size_t i = utf8_bom_length(t); i < t.size();) {  // after a leading byte order mark
    while (i < t.size() && std::isspace(static_cast<unsigned char>(t[i]))) ++i;
    size_t j = i;
    while (j < t.size() && !std::isspace(static_cast<unsigned char>(t[j]))) ++j;
    if (j > i) words.push_back(Word{t.substr(i, j - i), static_cast<uint32_t>(i)});
    i = j;
  }
  auto range = [file](const Word& w) { return SourceRange{file, w.begin, w.begin + static_cast<uint32_t>(w.text.size())}; };
  std::vector<int32_t> corners;
  Word facet{};
  bool in_facet = false;
  bool facet_bad = false;  // a corner was misread (reported): the facet is left out
  int triangle = 0;
  for (size_t i = 0; i < words.size(); ++i) {
    const std::string_view w = words[i].text;
    if (w == "facet") {
      if (in_facet) diags.emit(DiagKind::FlatSyntax, range(words[i]), "`facet` inside a facet: the previous one has no `endfacet`");
      in_facet = true;
      facet_bad = false;
      facet = words[i];
      corners.clear();
    } else if (w == "vertex") {
      std::array<double, 3> p{};
      bool ok = i + 3 < words.size();
      for (size_t c = 0; c < 3 && ok; ++c) {
        std::optional<double> x = detail::parse_number(words[i + 1 + c].text);
        if (!x) {
          diags.emit(DiagKind::FlatSyntax, range(words[i + 1 + c]),
                     fmt::format("`{}` is not a number", words[i + 1 + c].text.substr(0, 40)));
          ok = false;
        } else {
          p[c] = *x;
        }
      }
      if (i + 3 >= words.size()) diags.emit(DiagKind::FlatSyntax, range(words[i]), "`vertex` needs 3 numbers `x y z`");
      if (ok) corners.push_back(weld(p));
      facet_bad = facet_bad || !ok;
      i += 3;
    } else if (w == "endfacet") {
      const SourceRange r{file, facet.begin, words[i].begin + static_cast<uint32_t>(w.size())};
      if (!in_facet) {
        diags.emit(DiagKind::FlatSyntax, range(words[i]), "`endfacet` closes no `facet`");
      } else if (facet_bad) {
        // already reported
      } else if (corners.size() < 3) {
        diags.emit(DiagKind::FlatSyntax, r, fmt::format("a facet needs 3 `vertex` lines, this one has {}", corners.size()));
      } else {
        detail::add_face(g, corners, r, fmt::format("facet {}", triangle), diags, dropped);
      }
      ++triangle;
      in_facet = false;
    }
    // `solid NAME`, `normal`, `outer loop`, `endloop`, `endsolid NAME` and the normal's
    // numbers carry nothing nomec uses.
  }
  if (in_facet) diags.emit(DiagKind::FlatSyntax, range(facet), "this `facet` is never closed with `endfacet`");
}

}  // namespace

std::shared_ptr<const ir::FlatGeometry> read_stl(const SourceManager& sources, FileId file, DiagnosticEngine& diags) {
  const std::string_view t = sources.text(file);
  auto g = std::make_shared<ir::FlatGeometry>();
  const bool binary = t.size() >= 84 && t.size() == 84 + 50 * static_cast<uint64_t>(read_u32(t, 80));
  size_t first = utf8_bom_length(t);  // an ASCII file may start with a byte order mark
  while (first < t.size() && std::isspace(static_cast<unsigned char>(t[first]))) ++first;
  int dropped = 0;
  if (binary) {
    read_binary(t, file, *g, diags, dropped);
  } else if (t.compare(first, 5, "solid") == 0) {
    read_ascii(t, file, *g, diags, dropped);
  } else {
    diags.emit(DiagKind::FlatSyntax, SourceRange{file, 0, static_cast<uint32_t>(std::min<size_t>(t.size(), 5))},
               t.size() >= 84 ? fmt::format("not an STL file: binary STL is 84 + 50·n bytes for the n triangles its header "
                                            "declares ({} here, so {} bytes), and ASCII STL starts with `solid`",
                                            read_u32(t, 80), 84 + 50 * static_cast<uint64_t>(read_u32(t, 80)))
                              : "not an STL file: binary STL is at least 84 bytes, and ASCII STL starts with `solid`");
  }
  detail::report_dropped(dropped, file, diags);
  return g;
}

}  // namespace nomec::flat
