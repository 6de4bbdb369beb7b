// Topology summary of one output mesh (V, E, F, χ, orientability, borders, genus, closed,
// bounding box, a position hash): the data behind `nomec --emit summary`, the session's
// summaries and the language server's `nome/setParameter` answer; and the geometry each IR
// node contributed (vertex and face counts, bounding box), which the language server shows
// in hover. JSON-free; tools/ and lsp/ turn it into JSON.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <map>
#include <optional>
#include <span>
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

/// What one IR node contributed to the output meshes: for a scene entry, its whole mesh;
/// for an instance, the faces it placed (innermost instance only); for a mesh or generator,
/// the faces made from it over all its placements.
struct NodeFacts {
  int64_t vertices = 0;
  int64_t faces = 0;
  int32_t placements = 0;  // definitions: how many placed copies contributed
  double min[3] = {0, 0, 0};
  double max[3] = {0, 0, 0};
};

/// The facts of every node that contributed to `meshes` (the result of evaluating
/// `module`), by node index.
std::map<int32_t, NodeFacts> node_facts(const ir::Module& module, std::span<const OutputMesh> meshes);

}  // namespace nomec::backend
