// STL/OBJ/PLY rendering and atomic file replacement (see write.h).
#include "backend/write.h"

#include "backend/number_text.h"
#include "kernel/offset.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <algorithm>
#include <bit>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <iterator>
#include <functional>
#include <map>
#include <memory>
#include <new>
#include <string_view>

namespace nomec::backend {
namespace write_detail {

// The next corner of a face of n corners (no division: this runs for every face written).
inline int32_t next_corner(int32_t i, int32_t n) { return i + 1 == n ? 0 : i + 1; }

glm::dvec3 newell(const glm::dvec3* pos, const int32_t* v, int32_t n) {
  glm::dvec3 nrm(0.0);
  if (n == 0) return nrm;
  const glm::dvec3* b = &pos[v[0]];
  for (int32_t i = 0; i < n; ++i) {
    const glm::dvec3& a = *b;
    b = &pos[v[next_corner(i, n)]];
    nrm += kernel::newell_term(a, *b);
  }
  return nrm;
}

bool is_convex(const glm::dvec3* pos, const int32_t* v, int32_t n, glm::dvec3 nrm) {
  if (n == 0) return true;
  // Corners i, i + 1, i + 2 (around the face), each position loaded once.
  glm::dvec3 a = pos[v[0]], b = pos[v[next_corner(0, n)]];
  for (int32_t i = 0, k = next_corner(next_corner(0, n), n); i < n; ++i, k = next_corner(k, n)) {
    const glm::dvec3 c = pos[v[k]];
    if (glm::dot(glm::cross(b - a, c - b), nrm) < 0) return false;
    a = b;
    b = c;
  }
  return true;
}

// The same arithmetic as is_convex(pos, v, 4, newell(pos, v, 4)), in the same order, without
// the loops' early exits: the four corners' tests are independent, so the processor
// overlaps them (most faces written are quads, and this test was about half of the binary
// STL writer's time).
bool is_convex_quad(const glm::dvec3* pos, const int32_t* v) {
  const glm::dvec3 p[4] = {pos[v[0]], pos[v[1]], pos[v[2]], pos[v[3]]};
  glm::dvec3 nrm(0.0);
  for (int i = 0; i < 4; ++i) nrm += kernel::newell_term(p[i], p[(i + 1) & 3]);
  bool convex = true;
  for (int i = 0; i < 4; ++i) {
    const glm::dvec3 &a = p[i], &b = p[(i + 1) & 3], &c = p[(i + 2) & 3];
    convex &= !(glm::dot(glm::cross(b - a, c - b), nrm) < 0);
  }
  return convex;
}

}  // namespace write_detail

namespace {

using write_detail::is_convex;
using write_detail::is_convex_quad;
using write_detail::newell;

// Ear clipping of one polygon projected onto the plane orthogonal to `nrm`.
bool ear_clip(const glm::dvec3* pos, const int32_t* v, int32_t n, glm::dvec3 nrm,
              std::vector<int32_t>& out) {
  // Project to 2D: drop the dominant axis of the normal, keep the orientation.
  int axis = std::fabs(nrm.x) > std::fabs(nrm.y) ? (std::fabs(nrm.x) > std::fabs(nrm.z) ? 0 : 2)
                                                 : (std::fabs(nrm.y) > std::fabs(nrm.z) ? 1 : 2);
  int u = (axis + 1) % 3, w = (axis + 2) % 3;
  double sign = nrm[axis] >= 0 ? 1.0 : -1.0;
  std::vector<glm::dvec2> p(n);
  for (int32_t i = 0; i < n; ++i) p[i] = {pos[v[i]][u], pos[v[i]][w]};
  std::vector<int32_t> idx(n);
  for (int32_t i = 0; i < n; ++i) idx[i] = i;
  auto cross = [](glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  };
  size_t guard = 0;
  while (idx.size() > 3 && guard++ < static_cast<size_t>(n) * n) {
    bool clipped = false;
    for (size_t i = 0; i < idx.size(); ++i) {
      int32_t a = idx[(i + idx.size() - 1) % idx.size()], b = idx[i], c = idx[(i + 1) % idx.size()];
      if (sign * cross(p[a], p[b], p[c]) <= 0) continue;  // reflex or degenerate
      bool inside = false;
      for (int32_t q : idx) {
        if (q == a || q == b || q == c) continue;
        if (sign * cross(p[a], p[b], p[q]) >= 0 && sign * cross(p[b], p[c], p[q]) >= 0 &&
            sign * cross(p[c], p[a], p[q]) >= 0) {
          inside = true;
          break;
        }
      }
      if (inside) continue;
      out.insert(out.end(), {v[a], v[b], v[c]});
      idx.erase(idx.begin() + static_cast<long>(i));
      clipped = true;
      break;
    }
    if (!clipped) return false;
  }
  if (idx.size() == 3) out.insert(out.end(), {v[idx[0]], v[idx[1]], v[idx[2]]});
  return true;
}

std::string color_name(const glm::vec3& c) {
  auto q = [](float x) { return static_cast<int>(std::lround(std::clamp(x, 0.0f, 1.0f) * 255)); };
  return fmt::format("c{:02x}{:02x}{:02x}", q(c.r), q(c.g), q(c.b));
}

// Little-endian stores into a buffer sized beforehand.
void put_u32(char* at, uint32_t x) {
  for (int i = 0; i < 4; ++i) at[i] = static_cast<char>((x >> (8 * i)) & 0xff);
}
void put_f32s(char* at, const float (&f)[12]) {
  if constexpr (std::endian::native == std::endian::little) {
    std::memcpy(at, f, sizeof f);
  } else {
    for (int i = 0; i < 12; ++i) {
      uint32_t x;
      std::memcpy(&x, &f[i], 4);
      put_u32(at + 4 * i, x);
    }
  }
}

glm::dvec3 tri_normal(const glm::dvec3* pos, int32_t a, int32_t b, int32_t c) {
  const glm::dvec3 u = pos[b] - pos[a], w = pos[c] - pos[a];
  glm::dvec3 n = glm::cross(u, w);
  double l = glm::length(n);
  if (!std::isfinite(l)) {
    // A huge triangle (sides near 1e154 and more) overflows the cross product or its
    // length: the same direction from the sides scaled down.
    const double s = std::max({std::fabs(u.x), std::fabs(u.y), std::fabs(u.z), std::fabs(w.x), std::fabs(w.y), std::fabs(w.z)});
    n = glm::cross(u / s, w / s);
    l = glm::length(n);
  }
  return l > 0 && std::isfinite(l) ? n / l : glm::dvec3(0.0);  // no direction: 0 0 0, as STL allows
}

// A face that is not fanned from its first vertex (a non-convex one whose ear clipping
// succeeds) appends its triangles to `out` and returns true; other faces append nothing.
bool clip_face(const glm::dvec3* pos, const int32_t* v, int32_t n, std::vector<int32_t>& out) {
  if (n == 3) return false;
  if (n == 4 && is_convex_quad(pos, v)) return false;
  const glm::dvec3 nrm = newell(pos, v, n);
  if (n != 4 && is_convex(pos, v, n, nrm)) return false;
  const size_t before = out.size();
  if (ear_clip(pos, v, n, nrm, out)) return true;
  out.resize(before);  // a failed clip falls back to the fan
  return false;
}

}  // namespace

std::vector<int32_t> triangulate(const kernel::PolygonSoup& s) {
  std::vector<int32_t> out;
  const size_t corners = s.face_vertices.size(), faces = static_cast<size_t>(s.face_count());
  if (corners > 2 * faces) out.reserve(3 * (corners - 2 * faces));  // n − 2 triangles per n-gon
  size_t at = 0;
  for (int32_t f = 0; f < s.face_count(); ++f) {
    const int32_t n = s.face_sizes[f];
    const int32_t* v = s.face_vertices.data() + at;
    at += n;
    if (clip_face(s.positions.data(), v, n, out)) continue;
    for (int32_t i = 1; i + 1 < n; ++i) out.insert(out.end(), {v[0], v[i], v[i + 1]});
  }
  return out;
}

namespace {

// Whether `out` is a pipeline output made without its polygon list
// (`PipelineOptions::polygon_lists`), whose faces are read from its mesh.
bool faces_in_mesh_only(const OutputMesh& out) { return out.soup.face_count() == 0 && out.mesh.face_count() > 0; }

// The positions the writers read: the polygon list's, or (faces_in_mesh_only) the mesh's.
std::span<const glm::dvec3> written_positions(const OutputMesh& out) {
  if (faces_in_mesh_only(out)) return {out.mesh.positions().data(), static_cast<size_t>(out.mesh.vertex_count())};
  return out.soup.positions;
}

// The first vertex of `out` whose position is not finite or beyond ±`limit`, or -1.
int64_t first_unwritable_vertex(const OutputMesh& out, double limit) {
  const std::span<const glm::dvec3> positions = written_positions(out);
  for (size_t v = 0; v < positions.size(); ++v) {
    const glm::dvec3& p = positions[v];
    // `!(|x| <= limit)` is also true for NaN.
    if (!(std::fabs(p.x) <= limit && std::fabs(p.y) <= limit && std::fabs(p.z) <= limit)) return static_cast<int64_t>(v);
  }
  return -1;
}

bool all_writable(std::span<const OutputMesh> meshes, double limit) {
  return std::all_of(meshes.begin(), meshes.end(),
                     [&](const OutputMesh& m) { return first_unwritable_vertex(m, limit) < 0; });
}

// Calls `fn(positions, v, n)` for each face of `out` in order, `v` its `n` corners: from the
// polygon list, or (faces_in_mesh_only) walked in the mesh exactly as `kernel::to_soup` lists
// it, so both give the same faces.
template <typename Fn>
bool for_each_face(const OutputMesh& out, std::vector<int32_t>& corners, Fn&& fn) {
  const kernel::PolygonSoup& s = out.soup;
  if (!faces_in_mesh_only(out)) {
    size_t at = 0;
    for (int32_t f = 0; f < s.face_count(); ++f) {
      if (!fn(s.positions.data(), s.face_vertices.data() + at, s.face_sizes[f])) return false;
      at += static_cast<size_t>(s.face_sizes[f]);
    }
    return true;
  }
  const kernel::Mesh& mesh = out.mesh;
  for (int32_t f = 0; f < mesh.face_count(); ++f) {
    corners.clear();
    mesh.for_each_face_use(kernel::FaceId(f), [&](kernel::EdgeUse u) { corners.push_back(mesh.use_tail(u).index); });
    if (!fn(mesh.positions().data(), corners.data(), static_cast<int32_t>(corners.size()))) return false;
  }
  return true;
}

// Binary STL in pieces: `buffers` (1 or 2) of the caller's buffers `bufs`, of about a
// megabyte, filled in turn, each handed to `sink` when full. With two, a piece stays
// untouched until the sink has been called with the next one and has returned (what
// `OverlappedSink` relies on); the caller keeps `bufs` until the sink is done with the last.
bool write_stl_pieces(std::span<const OutputMesh> meshes, std::vector<char> (&bufs)[2], int buffers,
                      const std::function<bool(std::string_view)>& sink) {
  // The triangle count for the header: a face of n corners makes n - 2 triangles, whether it
  // is fanned or ear clipped (each ear is one triangle, the last three corners another, and
  // a failed clipping falls back to the fan), so the faces need not be visited twice.
  uint32_t count = 0;
  for (const OutputMesh& out : meshes) {
    if (!faces_in_mesh_only(out)) {
      for (int32_t n : out.soup.face_sizes) count += static_cast<uint32_t>(n - 2);
      continue;
    }
    // A mesh's corners are its edge uses that have a face.
    const kernel::Mesh& mesh = out.mesh;
    uint32_t corners = 0;
    for (int32_t e = 0; e < mesh.edge_count(); ++e) {
      for (int side = 0; side < 2; ++side) corners += mesh.edge_face(kernel::EdgeId(e), side).is_valid() ? 1 : 0;
    }
    count += corners - 2 * static_cast<uint32_t>(mesh.face_count());
  }
  std::vector<int32_t> corners;    // a mesh face's corners (for_each_face)
  std::vector<int32_t> clipped;    // an ear-clipped face's triangles
  // 50-byte records (12 little-endian floats and a zero attribute word) into a buffer of
  // about a megabyte that goes to `sink` whenever it is full.
  constexpr size_t kChunk = 50 * 20000;
  bufs[0].resize(kChunk + 84);
  std::vector<char>* buf = &bufs[0];
  const std::string_view header = "nomec binary STL";
  std::copy(header.begin(), header.end(), buf->begin());
  put_u32(buf->data() + 80, count);
  size_t used = 84;
  int current = 0;
  auto emit = [&](const glm::dvec3* pos, int32_t a, int32_t b, int32_t c) {
    if (used + 50 > buf->size()) {
      if (!sink(std::string_view(buf->data(), used))) return false;
      used = 0;
      if (buffers > 1) {
        current ^= 1;
        buf = &bufs[current];
        if (buf->empty()) buf->resize(kChunk + 84);
      }
    }
    const glm::dvec3 n = tri_normal(pos, a, b, c);
    const glm::dvec3& pa = pos[a];
    const glm::dvec3& pb = pos[b];
    const glm::dvec3& pc = pos[c];
    const float f[12] = {static_cast<float>(n.x),  static_cast<float>(n.y),  static_cast<float>(n.z),
                         static_cast<float>(pa.x), static_cast<float>(pa.y), static_cast<float>(pa.z),
                         static_cast<float>(pb.x), static_cast<float>(pb.y), static_cast<float>(pb.z),
                         static_cast<float>(pc.x), static_cast<float>(pc.y), static_cast<float>(pc.z)};
    char* at = buf->data() + used;
    put_f32s(at, f);
    at[48] = at[49] = 0;
    used += 50;
    return true;
  };
  for (const OutputMesh& out : meshes) {
    const bool written = for_each_face(out, corners, [&](const glm::dvec3* pos, const int32_t* v, int32_t n) {
      clipped.clear();
      if (!clip_face(pos, v, n, clipped)) {
        for (int32_t i = 1; i + 1 < n; ++i) {
          if (!emit(pos, v[0], v[i], v[i + 1])) return false;
        }
        return true;
      }
      for (size_t k = 0; k < clipped.size(); k += 3) {
        if (!emit(pos, clipped[k], clipped[k + 1], clipped[k + 2])) return false;
      }
      return true;
    });
    if (!written) return false;
  }
  return sink(std::string_view(buf->data(), used));
}

// Calls a sink on a second thread, one piece at a time and in order, while the caller
// makes the next piece: `submit` waits until the previous piece has been written, so the
// caller may reuse a piece's memory once the submission after it has returned.
class OverlappedSink {
 public:
  explicit OverlappedSink(const std::function<bool(std::string_view)>& sink)
      : sink_(sink), worker_([this] { run(); }) {}
  ~OverlappedSink() { (void)finish(); }
  OverlappedSink(const OverlappedSink&) = delete;
  OverlappedSink& operator=(const OverlappedSink&) = delete;

  // False once a piece has failed (this one is then not written).
  bool submit(std::string_view piece) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return !has_piece_; });
    if (!is_ok_) return false;
    piece_ = piece;
    has_piece_ = true;
    changed_.notify_all();
    return true;
  }
  // Waits for the last piece; true if every piece was written.
  bool finish() {
    {
      std::unique_lock lock(mutex_);
      changed_.wait(lock, [&] { return !has_piece_; });
      is_stopping_ = true;
      changed_.notify_all();
    }
    if (worker_.joinable()) worker_.join();
    return is_ok_;
  }

 private:
  void run() {
    std::unique_lock lock(mutex_);
    for (;;) {
      changed_.wait(lock, [&] { return has_piece_ || is_stopping_; });
      if (!has_piece_) return;
      const std::string_view piece = piece_;
      lock.unlock();
      const bool ok = sink_(piece);
      lock.lock();
      is_ok_ = is_ok_ && ok;
      has_piece_ = false;
      changed_.notify_all();
    }
  }

  const std::function<bool(std::string_view)>& sink_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::string_view piece_;
  bool has_piece_ = false;
  bool is_stopping_ = false;
  bool is_ok_ = true;
  std::thread worker_;  // last: starts once the members above exist
};

}  // namespace

bool check_coordinates(std::span<const OutputMesh> meshes, const ir::Module& module, double limit,
                       DiagnosticEngine& diags) {
  bool ok = true;
  for (const OutputMesh& out : meshes) {
    const int64_t bad = first_unwritable_vertex(out, limit);
    if (bad < 0) continue;
    ok = false;
    // What made the vertex: the source of the first face that uses it.
    kernel::FaceSource source;
    std::vector<int32_t> corners;
    int32_t face = 0;
    for_each_face(out, corners, [&](const glm::dvec3*, const int32_t* v, int32_t n) {
      if (std::find(v, v + n, bad) != v + n) {
        source = faces_in_mesh_only(out)                     ? out.mesh.face_source(kernel::FaceId(face))
                 : face < static_cast<int32_t>(out.soup.face_sources.size()) ? out.soup.face_sources[face]
                                                                             : kernel::FaceSource{};
        return false;
      }
      ++face;
      return true;
    });
    auto node = [&](int32_t index) -> const ir::Node* {
      return index >= 0 && static_cast<size_t>(index) < module.nodes.size() ? &module.nodes[index] : nullptr;
    };
    std::string made_by;
    SourceRange at = out.scene_node.is_valid() ? module.node(out.scene_node).range : SourceRange{};
    if (const ir::Node* src = node(source.source_face)) {
      at = src->range;
      made_by = src->kind == ir::NodeKind::Face ? fmt::format("face `{}`", src->name)
                                                : fmt::format("`{}` `{}`", src->keyword, src->name);
    }
    if (const ir::Node* inst = node(source.instance); inst != nullptr && inst->kind == ir::NodeKind::Instance) {
      made_by += fmt::format("{}placed by instance `{}`", made_by.empty() ? "" : " ", inst->name);
    }
    const glm::dvec3 p = written_positions(out)[static_cast<size_t>(bad)];
    const bool is_finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    diags.emit(DiagKind::NonFiniteCoordinate, at,
               fmt::format("output `{}` has a vertex at ({}, {}, {}){}{}; nothing was written{}", out.name, p.x, p.y, p.z,
                           is_finite ? ", beyond the ±3.4e38 that binary STL's 32-bit numbers hold"
                                     : ", which is not a finite point",
                           made_by.empty() ? "" : fmt::format(" (made by {})", made_by),
                           is_finite ? " (ASCII STL, OBJ and PLY hold it)" : ""));
  }
  return ok;
}

bool write_stl_binary(std::span<const OutputMesh> meshes, const std::function<bool(std::string_view)>& sink) {
  if (!all_writable(meshes, kMaxStlBinaryCoordinate)) return false;
  std::vector<char> bufs[2];
  return write_stl_pieces(meshes, bufs, 1, sink);
}

bool write_stl_binary_overlapped(std::span<const OutputMesh> meshes,
                                 const std::function<bool(std::string_view)>& sink) {
  if (!all_writable(meshes, kMaxStlBinaryCoordinate)) return false;
  std::vector<char> bufs[2];  // outlives the second thread's writes (declared first)
  OverlappedSink overlapped(sink);
  const bool is_made =
      write_stl_pieces(meshes, bufs, 2, [&](std::string_view piece) { return overlapped.submit(piece); });
  return overlapped.finish() && is_made;
}

std::string to_stl_binary(std::span<const OutputMesh> meshes) {
  std::string out;
  write_stl_binary(meshes, [&](std::string_view piece) {
    if (out.empty()) {  // the first piece holds the count: size the string once
      uint32_t count = 0;
      std::memcpy(&count, piece.data() + 80, 4);
      if constexpr (std::endian::native == std::endian::little) out.reserve(84 + 50 * static_cast<size_t>(count));
    }
    out.append(piece);
    return true;
  });
  return out;
}

namespace {

char* put_text(char* p, std::string_view t) {
  std::memcpy(p, t.data(), t.size());
  return p + t.size();
}

// A buffer of about a megabyte that the text writers fill by pointer: `room` makes space
// for a line (handing the text so far to the sink when the buffer is full), `done` keeps
// what was written. The whole text is never in memory (a large ASCII STL is hundreds of
// megabytes, whose fresh pages cost more than formatting them). Numbers go through
// number_text.h (fmt's characters, faster).
class TextOut {
 public:
  static constexpr size_t kPiece = size_t{1} << 20;
  explicit TextOut(const std::function<bool(std::string_view)>& sink)
      : buf_(static_cast<char*>(std::malloc(kPiece))), cap_(kPiece), sink_(sink) {
    if (buf_ == nullptr) throw std::bad_alloc();
  }
  TextOut(const TextOut&) = delete;
  TextOut& operator=(const TextOut&) = delete;
  ~TextOut() { std::free(buf_); }
  /// Space for at least `n` more characters (not initialised), at the end of the text.
  char* room(size_t n) {
    if (size_ + n > cap_) {
      flush();
      if (n > cap_) {  // a line longer than a piece (a long name)
        std::free(buf_);
        buf_ = static_cast<char*>(std::malloc(n));
        if (buf_ == nullptr) throw std::bad_alloc();
        cap_ = n;
      }
    }
    return buf_ + size_;
  }
  /// Keeps what was written into `room` up to `end`.
  void done(const char* end) { size_ = static_cast<size_t>(end - buf_); }
  void add(std::string_view text) { done(put_text(room(text.size()), text)); }
  /// False once the sink has failed (later text is then dropped).
  bool is_ok() const { return is_ok_; }
  /// Hands the rest to the sink; false if the sink failed for some piece.
  bool finish() {
    flush();
    return is_ok_;
  }

 private:
  void flush() {
    if (size_ > 0 && is_ok_) is_ok_ = sink_(std::string_view(buf_, size_));
    size_ = 0;
  }

  char* buf_;
  size_t cap_;
  size_t size_ = 0;
  const std::function<bool(std::string_view)>& sink_;
  bool is_ok_ = true;
};

// The pieces of a writer appended to one string (reserved at `estimate` bytes).
template <typename Write>
std::string collect(size_t estimate, Write&& write) {
  std::string out;
  out.reserve(estimate);
  write([&](std::string_view piece) {
    out.append(piece);
    return true;
  });
  return out;
}


// `a b c` for a point: each coordinate as `put`, -0 written as 0 (`+ 0.0`), so goldens do
// not depend on the sign of zero.
template <char* (*Put)(char*, double)>
char* put_xyz(char* p, const glm::dvec3& v) {
  p = Put(p, v.x + 0.0);
  *p++ = ' ';
  p = Put(p, v.y + 0.0);
  *p++ = ' ';
  return Put(p, v.z + 0.0);
}

}  // namespace

bool write_stl_ascii(std::span<const OutputMesh> meshes, const std::function<bool(std::string_view)>& sink) {
  if (!all_writable(meshes, kMaxTextCoordinate)) return false;
  TextOut out(sink);
  for (const OutputMesh& m : meshes) {
    if (!out.is_ok()) break;
    const std::string name = m.name.empty() ? "nomec" : m.name;
    out.add(fmt::format("solid {}\n", name));
    const kernel::PolygonSoup& s = m.soup;
    // Each point's text once (a point is a corner of about six triangles).
    std::vector<size_t> point_at(s.positions.size() + 1, 0);
    const std::unique_ptr<char[]> points(new char[s.positions.size() * (3 * kNumberTextMax + 2) + 1]);
    char* w = points.get();
    for (size_t i = 0; i < s.positions.size(); ++i) {
      w = put_xyz<put_e6>(w, s.positions[i]);
      point_at[i + 1] = static_cast<size_t>(w - points.get());
    }
    const std::vector<int32_t> t = triangulate(s);
    for (size_t k = 0; k + 2 < t.size(); k += 3) {
      char* p = out.room(3 * kNumberTextMax + 3 * (3 * kNumberTextMax + 16) + 80);
      p = put_text(p, "  facet normal ");
      p = put_xyz<put_e6>(p, tri_normal(s.positions.data(), t[k], t[k + 1], t[k + 2]));
      p = put_text(p, "\n    outer loop\n");
      for (int j = 0; j < 3; ++j) {
        const int32_t v = t[k + j];
        p = put_text(p, "      vertex ");
        p = put_text(p, std::string_view(points.get() + point_at[v], point_at[v + 1] - point_at[v]));
        *p++ = '\n';
      }
      p = put_text(p, "    endloop\n  endfacet\n");
      out.done(p);
    }
    out.add(fmt::format("endsolid {}\n", name));
  }
  return out.finish();
}

std::string to_stl_ascii(std::span<const OutputMesh> meshes) {
  size_t triangles = 0;
  for (const OutputMesh& m : meshes) triangles += static_cast<size_t>(m.soup.face_count()) * 2;
  return collect(triangles * 250 + 64, [&](const auto& sink) { return write_stl_ascii(meshes, sink); });
}

bool write_obj(std::span<const OutputMesh> meshes, std::string_view mtl_file,
               const std::function<bool(std::string_view)>& sink) {
  if (!all_writable(meshes, kMaxTextCoordinate)) return false;
  TextOut out(sink);
  out.add("# written by nomec\n");
  if (!mtl_file.empty()) out.add(fmt::format("mtllib {}\n", mtl_file));
  int64_t base = 1;
  for (const OutputMesh& m : meshes) {
    if (!out.is_ok()) break;
    const kernel::PolygonSoup& s = m.soup;
    out.add(fmt::format("o {}\n", m.name.empty() ? "nomec" : m.name));
    for (const glm::dvec3& v : s.positions) {
      char* p = out.room(3 * kNumberTextMax + 8);
      p = put_text(p, "v ");
      p = put_xyz<put_shortest>(p, v);
      *p++ = '\n';
      out.done(p);
    }
    std::string current;
    size_t at = 0;
    for (int32_t f = 0; f < s.face_count(); ++f) {
      if (!mtl_file.empty() && !s.face_colors.empty()) {
        std::string c = color_name(s.face_colors[f]);
        if (c != current) {
          out.add(fmt::format("usemtl {}\n", c));
          current = c;
        }
      }
      const int32_t n = s.face_sizes[f];
      char* p = out.room(static_cast<size_t>(n) * 24 + 4);
      *p++ = 'f';
      for (int32_t i = 0; i < n; ++i) {
        *p++ = ' ';
        p = put_int(p, base + s.face_vertices[at + i]);
      }
      *p++ = '\n';
      out.done(p);
      at += static_cast<size_t>(n);
    }
    base += s.vertex_count();
  }
  return out.finish();
}

std::string to_obj(std::span<const OutputMesh> meshes, std::string_view mtl_file) {
  size_t points = 0, corners = 0;
  for (const OutputMesh& m : meshes) {
    points += m.soup.positions.size();
    corners += m.soup.face_vertices.size();
  }
  return collect(points * 60 + corners * 8 + 64, [&](const auto& sink) { return write_obj(meshes, mtl_file, sink); });
}

std::string to_mtl(std::span<const OutputMesh> meshes) {
  std::map<std::string, glm::vec3> colors;
  for (const OutputMesh& m : meshes) {
    for (const glm::vec3& c : m.soup.face_colors) colors.emplace(color_name(c), c);
  }
  std::string out;
  for (const auto& [name, c] : colors) {
    fmt::format_to(std::back_inserter(out), "newmtl {}\nKd {} {} {}\n\n", name, c.r, c.g, c.b);
  }
  return out;
}

std::string to_ply(std::span<const OutputMesh> meshes) {
  if (!all_writable(meshes, kMaxTextCoordinate)) return {};
  size_t vcount = 0, fcount = 0;
  bool colored = false;
  for (const OutputMesh& m : meshes) {
    vcount += m.soup.positions.size();
    fcount += static_cast<size_t>(m.soup.face_count());
    colored = colored || !m.soup.face_colors.empty();
  }
  std::string out = fmt::format(
      "ply\nformat ascii 1.0\ncomment written by nomec\nelement vertex {}\nproperty double x\n"
      "property double y\nproperty double z\nelement face {}\nproperty list uchar int "
      "vertex_indices\n",
      vcount, fcount);
  if (colored) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  out += "end_header\n";
  for (const OutputMesh& m : meshes) {
    for (const glm::dvec3& p : m.soup.positions) {
      char line[3 * kNumberTextMax + 4];
      char* e = put_xyz<put_shortest>(line, p);
      *e++ = '\n';
      out.append(line, e);
    }
  }
  size_t base = 0;
  for (const OutputMesh& m : meshes) {
    const kernel::PolygonSoup& s = m.soup;
    size_t at = 0;
    for (int32_t f = 0; f < s.face_count(); ++f) {
      fmt::format_to(std::back_inserter(out), "{}", s.face_sizes[f]);
      for (int32_t i = 0; i < s.face_sizes[f]; ++i) fmt::format_to(std::back_inserter(out), " {}", base + s.face_vertices[at + i]);
      at += s.face_sizes[f];
      if (colored) {
        glm::vec3 c = s.face_colors.empty() ? glm::vec3(0.8f) : s.face_colors[f];
        auto q = [](float x) { return static_cast<int>(std::lround(std::clamp(x, 0.0f, 1.0f) * 255)); };
        fmt::format_to(std::back_inserter(out), " {} {} {}", q(c.r), q(c.g), q(c.b));
      }
      out += "\n";
    }
    base += s.positions.size();
  }
  return out;
}

}  // namespace nomec::backend
