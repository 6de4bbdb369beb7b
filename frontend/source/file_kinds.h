// What an input file is, from its name: a scene the checker reads (`.nome`, `.nom`, `.slf`,
// saved work `.anom`/`.amom`), or something else that may sit beside scenes (a Tcl helper
// that SLIDE files `source`, a `.sif` mesh, a README). One list, used by the checker (saved
// work, base scenes) and by every test and benchmark that walks a folder of real files.
#pragma once

#include <string_view>

namespace nomec {

/// The extension of a path (`.slf` for `a/b.slf`), or "" when the file name has none.
constexpr std::string_view path_extension(std::string_view path) {
  const size_t slash = path.find_last_of('/');
  const std::string_view name = slash == std::string_view::npos ? path : path.substr(slash + 1);
  const size_t dot = name.rfind('.');
  if (dot == std::string_view::npos || dot == 0) return {};
  return name.substr(dot);
}

/// Saved work of NOME 2016 (`.anom`, and `.amom` as some users spelt it): checked on top of
/// its base scene.
constexpr bool is_saved_work_path(std::string_view path) {
  const std::string_view ext = path_extension(path);
  return ext == ".anom" || ext == ".amom";
}

/// A base scene of saved work (`.nom`, `.nome`).
constexpr bool is_base_scene_path(std::string_view path) {
  const std::string_view ext = path_extension(path);
  return ext == ".nom" || ext == ".nome";
}

/// Any scene file nomec checks: NOME 2016, NOME2, NOME3 and SLIDE scenes and saved work.
/// Not `.tcl` (SLIDE's helper scripts), `.sif` (a mesh), `.md`.
constexpr bool is_scene_path(std::string_view path) {
  return is_base_scene_path(path) || is_saved_work_path(path) || path_extension(path) == ".slf";
}

}  // namespace nomec
