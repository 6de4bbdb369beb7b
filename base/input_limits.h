// The limits on what nomec reads, as plain numbers (and their text for messages) shared by the file reader (base/file_io.h),
// the checker (includes and base scenes, through CheckOptions) and the clients that set
// them (`--max-file-size`): no input a user can name makes nomec read without end or hold
// more than a bounded amount of text.
#pragma once

#include <cstdint>
#include <cstdio>
#include <iterator>
#include <string>
#include <string_view>

namespace nomec {

/// The most bytes nomec reads for one scene by default (`--max-file-size`): one file, and
/// a file together with everything it includes (each time it is included) and its base
/// scene. Real scenes and meshes are far smaller (the largest file of the corpus is 23 KB).
/// The bound is memory: checking costs about 17 bytes per byte of ordinary scene text, but
/// up to some 300 bytes per byte of the densest (one statement of a million vertex names,
/// parsed whole), so 2 MiB keeps a check under about 620 MiB whatever the text holds.
inline constexpr int64_t kDefaultMaxFileBytes = int64_t{2} << 20;

/// The most bytes of flat mesh files (`.stl`, `.obj`, `.sif`) nomec reads for one scene
/// by default (`--max-mesh-size`): a mesh file named on the command line, and the mesh files
/// a scene includes or saved work is based on, together. Meshes exported for 3D printing
/// are megabytes to tens of megabytes, and reading one costs about 6 bytes per byte (a
/// binary STL of 25 MB: 157 MB) to 7 (an OBJ whose one face has 3 million corners: 426 MB
/// for 60 MB), so 64 MiB keeps a check under about 450 MiB; what a mesh builds is bounded
/// by `--max-vertices`.
inline constexpr int64_t kDefaultMaxMeshFileBytes = int64_t{64} << 20;

/// Is `path` a flat mesh file by its extension (`.stl`, `.obj`, `.sif`, any case)? Those
/// are read under the mesh cap (kDefaultMaxMeshFileBytes), other files under the text cap.
inline bool is_mesh_file_path(std::string_view path) {
  const size_t dot = path.rfind('.');
  if (dot == std::string_view::npos || path.find('/', dot) != std::string_view::npos) return false;
  std::string ext(path.substr(dot + 1));
  for (char& ch : ext) ch = static_cast<char>(ch >= 'A' && ch <= 'Z' ? ch - 'A' + 'a' : ch);
  return ext == "stl" || ext == "obj" || ext == "sif";
}

/// Files nested deeper than this in `include`s are refused (a file that includes itself).
inline constexpr int kMaxIncludeDepth = 16;

/// The most `include`s one check reads, repeats counted: each costs a parse and a syntax
/// tree however small the file is, so this bounds an include bomb of tiny files.
inline constexpr int kMaxIncludes = 4096;

/// A size for messages: "512 bytes", "16.0 KiB", "32.0 MiB", "3.0 GiB".
inline std::string byte_size_text(int64_t bytes) {
  if (bytes < 1024) return std::to_string(bytes) + (bytes == 1 ? " byte" : " bytes");
  static const char* const kUnits[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  double v = static_cast<double>(bytes) / 1024;
  size_t unit = 0;
  while (v >= 1024 && unit + 1 < std::size(kUnits)) {
    v /= 1024;
    ++unit;
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.1f %s", v, kUnits[unit]);
  return text;
}

}  // namespace nomec
