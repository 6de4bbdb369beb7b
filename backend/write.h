// Output writers: STL (binary and ASCII), OBJ with an MTL of face colours, and ASCII PLY
// with face colours, e.g. `nomec --emit stl funnel_cube.nome -o funnel_cube.stl`. Writers
// render to a string, and STL and OBJ also in pieces to a sink; the CLI streams STL and OBJ
// through an `AtomicFileWriter` and writes the rest with `write_file_atomically`
// (base/file_io.h), so a failed compile never touches an existing output.
#pragma once

#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "backend/evaluate.h"

namespace nomec::backend {

/// Splits every face into triangles (indices into `soup.positions`), three per triangle.
/// Triangles and convex faces are fanned from their first vertex; other faces are ear
/// clipped in the plane of their Newell normal (falling back to a fan if clipping fails).
std::vector<int32_t> triangulate(const kernel::PolygonSoup& soup);

namespace write_detail {
/// The Newell normal (unnormalised) of the face whose corners are `positions[v[0..n)]`.
glm::dvec3 newell(const glm::dvec3* positions, const int32_t* v, int32_t n);
/// Whether the face turns the same way as `nrm` at every corner (`triangulate` fans it).
bool is_convex(const glm::dvec3* positions, const int32_t* v, int32_t n, glm::dvec3 nrm);
/// `is_convex(positions, v, 4, newell(positions, v, 4))` for a quad, to the bit (the
/// writers' test for the faces most meshes are made of; tests/backend compares the two).
bool is_convex_quad(const glm::dvec3* positions, const int32_t* v);
}  // namespace write_detail

/// The largest coordinate each format holds: binary STL stores 32-bit floats (about
/// ±3.4e38); the text formats (ASCII STL, OBJ, PLY) any finite double.
inline constexpr double kMaxStlBinaryCoordinate = 3.4028234663852886e38;  // FLT_MAX
inline constexpr double kMaxTextCoordinate = 1.7976931348623157e308;     // DBL_MAX

/// The last check before an output is written: every vertex position of `meshes` is a
/// finite number within ±`limit` (one of the two above). When one is not (an overflow no
/// earlier check caught, e.g. `scale (1e300 1e300 1e300)` of a point at 1e10), reports
/// `NonFiniteCoordinate` at what made it (the face statement or generator of a face that
/// uses the vertex, and the instance that placed it; else the output's scene entry) and
/// returns false. The writers below refuse such meshes too: they write nothing and return
/// false (or an empty string), so infinity or NaN never reaches a file.
bool check_coordinates(std::span<const OutputMesh> meshes, const ir::Module& module, double limit,
                       DiagnosticEngine& diags);

/// Binary STL: 80-byte header, triangle count, 50 bytes per triangle (little endian).
std::string to_stl_binary(std::span<const OutputMesh> meshes);
/// The same bytes as `to_stl_binary`, handed to `sink` in consecutive pieces of about a
/// megabyte (so a large model is never held in memory whole, e.g. `nomec --emit stl`
/// writes each piece to the file as it is made). Stops and returns false when `sink` does,
/// and returns false at once, calling `sink` never, when a coordinate is beyond
/// `kMaxStlBinaryCoordinate` or not finite (`check_coordinates` says which).
bool write_stl_binary(std::span<const OutputMesh> meshes, const std::function<bool(std::string_view)>& sink);
/// `write_stl_binary` with the sink called on a second thread (one piece at a time, in
/// order) while the next piece is formatted, so formatting and writing overlap on two
/// cores; the same pieces and bytes. Returns false when `sink` failed for some piece (later
/// pieces are then not made).
bool write_stl_binary_overlapped(std::span<const OutputMesh> meshes,
                                 const std::function<bool(std::string_view)>& sink);
/// ASCII STL, one `solid` per mesh. The text writers (this one, OBJ and PLY, whole or in
/// pieces) write nothing when a coordinate is not finite (see `check_coordinates`).
std::string to_stl_ascii(std::span<const OutputMesh> meshes);
/// The same bytes as `to_stl_ascii`, handed to `sink` in consecutive pieces of about a
/// megabyte from one reused buffer (e.g. `nomec --emit stl --stl-ascii` writes each piece to
/// the file as it is made). Returns false when `sink` failed for some piece (the rest is
/// then not handed on).
bool write_stl_ascii(std::span<const OutputMesh> meshes, const std::function<bool(std::string_view)>& sink);
/// OBJ (`o` per mesh, polygons kept as written). When `mtl_file` is not empty, a
/// `mtllib` line is written and `usemtl` switches per face colour.
std::string to_obj(std::span<const OutputMesh> meshes, std::string_view mtl_file);
/// The same bytes as `to_obj`, handed to `sink` in pieces as `write_stl_ascii` does.
bool write_obj(std::span<const OutputMesh> meshes, std::string_view mtl_file,
               const std::function<bool(std::string_view)>& sink);
/// The MTL matching `to_obj` (one `newmtl` per distinct colour; empty if uncoloured).
std::string to_mtl(std::span<const OutputMesh> meshes);
/// ASCII PLY with `red green blue` face properties when any mesh has face colours.
std::string to_ply(std::span<const OutputMesh> meshes);


}  // namespace nomec::backend
