// JSON form of backend::MeshSummary, shared by the language server's `nome/setParameter`
// and the CLI's `nomec --emit summary` and `nomec --what-if` (nlohmann-json lives only in
// lsp/ and tools/, and tools/ builds on lsp/, so the one conversion lives here).
#pragma once

#include <cmath>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "backend/summary.h"

namespace nomec::lsp {

inline double round6(double x) { return std::round(x * 1e6) / 1e6; }

inline nlohmann::json mesh_summary_json(const backend::MeshSummary& s) {
  nlohmann::json bbox = nullptr;
  if (s.bounding_box) {
    const auto& b = *s.bounding_box;
    bbox = {{"min", {round6(b.min.x), round6(b.min.y), round6(b.min.z)}},
            {"max", {round6(b.max.x), round6(b.max.y), round6(b.max.z)}}};
  }
  return {{"name", s.name},
          {"vertices", s.vertices},
          {"edges", s.edges},
          {"faces", s.faces},
          {"euler", s.euler},
          {"orientable", s.is_orientable},
          {"border_loops", s.border_loops},
          {"genus", s.genus},
          {"components", s.components},
          {"closed", s.is_closed},
          {"curves", s.curves},
          {"bounding_box", bbox},
          {"position_hash", fmt::format("{:016x}", s.position_hash)}};
}

/// `{"file": path, "meshes": [...]}`, one summary per output mesh.
inline nlohmann::json summary_json(const std::string& path, const std::vector<backend::MeshSummary>& meshes) {
  nlohmann::json out = {{"file", path}, {"meshes", nlohmann::json::array()}};
  for (const auto& m : meshes) out["meshes"].push_back(mesh_summary_json(m));
  return out;
}

}  // namespace nomec::lsp
