// Argument validation and the quad-grid builder shared by the generators.
#include "backend/generators/common.h"

#include <algorithm>
#include <string>

namespace nomec::backend::detail {

void fail(ir::ArgIndex arg, std::string message) { throw Failure{GeneratorError{arg, std::move(message), ""}}; }

int ArgReader::as_count(ir::ArgIndex arg, const std::string& n, double v, int min) {
  // Counts are rounded to the nearest whole number (the checker's `NonIntegerCount`
  // warning says so); where the original truncated (NOME3, a NOME 2016 literal) the
  // backend has already cut the fraction off (`GenArgBinding::is_truncated`).
  if (std::round(v) < min) fail(arg, "`" + n + "` must be at least " + std::to_string(min) + ", got " + fmt_number(v));
  if (std::round(v) > kMaxSegments) {
    fail(arg, "`" + n + "` must be at most " + std::to_string(kMaxSegments) + ", got " + fmt_number(v));
  }
  return static_cast<int>(std::lround(v));
}

bool full_turn(double span, ir::ArgIndex arg, const std::string& name) {
  if (!(span > 0)) fail(arg, "angle range `" + name + "` must be positive, got " + fmt_number(span) + " degrees");
  if (span > 360.0 + 1e-9) fail(arg, "angle range `" + name + "` must be at most 360 degrees, got " + fmt_number(span));
  return span >= 360.0 - 1e-9;
}

void check_size(long long vertices, ir::ArgIndex arg) {
  if (vertices > kMaxVertices) {
    fail(arg, "too many vertices (" + std::to_string(vertices) + "; at most " + std::to_string(kMaxVertices) + ")");
  }
}

int32_t OriginalMesh::add(const glm::dvec3& position, std::string name) {
  positions_.push_back(position);
  names_.push_back(std::move(name));
  onto_.push_back(-1);
  return static_cast<int32_t>(positions_.size() - 1);
}

Generated OriginalMesh::finish() const {
  const size_t n = positions_.size();
  auto root = [&](int32_t v) {
    while (onto_[v] >= 0) v = onto_[v];
    return v;
  };
  std::vector<std::vector<int32_t>> faces;
  std::vector<bool> used(n, false);
  for (const std::vector<int32_t>& f : faces_) {
    std::vector<int32_t> out;
    for (int32_t v : f) {
      const int32_t r = root(v);
      if (std::find(out.begin(), out.end(), r) == out.end()) out.push_back(r);
    }
    if (out.size() < 3) continue;
    for (int32_t v : out) used[v] = true;
    faces.push_back(std::move(out));
  }
  Generated g;
  std::vector<int32_t> index(n, -1);
  for (size_t v = 0; v < n; ++v) {
    if (onto_[v] < 0 && used[v]) index[v] = g.soup.add_vertex(positions_[v], names_[v]);
  }
  for (size_t v = 0; v < n; ++v) {
    if (index[v] < 0) g.aliases.emplace_back(names_[v], positions_[v]);
  }
  for (std::vector<int32_t>& f : faces) {
    for (int32_t& v : f) v = index[v];
    g.soup.add_face(f);
  }
  return g;
}

int32_t add_grid(kernel::PolygonSoup& soup, int segs_i, int segs_j, bool wrap_i, bool wrap_j,
                 const std::function<glm::dvec3(int, int)>& pos, bool flip) {
  const int ni = wrap_i ? segs_i : segs_i + 1;
  const int nj = wrap_j ? segs_j : segs_j + 1;
  const int32_t base = soup.vertex_count();
  for (int i = 0; i < ni; ++i) {
    for (int j = 0; j < nj; ++j) {
      soup.add_vertex(pos(i, j), "v" + std::to_string(i) + "_" + std::to_string(j));
    }
  }
  auto at = [&](int i, int j) -> int32_t { return base + (i % ni) * nj + (j % nj); };
  for (int i = 0; i < segs_i; ++i) {
    for (int j = 0; j < segs_j; ++j) {
      if (flip) {
        soup.add_face({at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
      } else {
        soup.add_face({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
    }
  }
  return base;
}

}  // namespace nomec::backend::detail
