// Topology summary of one output mesh (V, E, F, χ, orientability, borders, genus, closed,
// bounding box, a position hash): the data behind `nomec --emit summary`, the session's
// summaries and the language server's `nome/setParameter` answer. JSON-free; tools/ and
// lsp/ turn it into JSON.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <optional>
#include <string>

#include "backend/evaluate.h"

namespace nomec::backend {

struct MeshSummary {
  struct Box {
    glm::dvec3 min;
    glm::dvec3 max;
  };
  std::string name;
  int32_t vertices = 0;
  int32_t edges = 0;
  int32_t faces = 0;
  int32_t euler = 0;
  bool is_orientable = true;
  int32_t border_loops = 0;
  int32_t genus = 0;
  int32_t components = 0;
  bool is_closed = true;
  int32_t curves = 0;
  std::optional<Box> bounding_box;  // none for a mesh without vertices
  uint64_t position_hash = 0;       // kernel::position_hash with quantum 1e-3
};

MeshSummary summarize(const OutputMesh& mesh);

}  // namespace nomec::backend
