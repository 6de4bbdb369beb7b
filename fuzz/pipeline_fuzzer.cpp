// libFuzzer target for the whole pipeline: bytes → check → evaluate → merge → subdivide one
// level → offset, the way `nomec --emit stl --merge --subdivide 1 --offset 0.05` runs a
// scene. Fails on a crash, a sanitizer report, an exception, a diagnostic range outside its
// file, an output mesh that breaks a winged-edge invariant (kernel::mesh_problem), or binary
// STL from the output meshes alone that differs from the STL from their polygon lists. Size
// limits keep every input fast: at most 2 KiB of text and a budget of 20 000 vertices for
// the evaluation and each subdivision (beyond it the backend reports SceneTooLarge).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "backend/evaluate.h"
#include "backend/write.h"
#include "frontend/check/check.h"
#include "fuzz/ranges.h"
#include "kernel/topology.h"

namespace {

constexpr size_t kMaxInput = 2048;
constexpr int64_t kMaxVertices = 20000;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > kMaxInput) return -1;  // not added to the corpus
  static const char* const kPaths[] = {"fuzz.nome", "fuzz.nom", "fuzz.slf"};
  const char* path = kPaths[size > 0 ? data[0] % 3 : 0];
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  nomec::CheckOptions options;
  options.read_file = [](const std::string&) -> std::optional<std::string> { return std::nullopt; };
  try {
    nomec::CheckResult checked =
        nomec::check_source(sources, path, std::string(reinterpret_cast<const char*>(data), size), options, diags);
    nomec::fuzz::abort_unless_inside(sources, diags);
    if (diags.error_count() > 0) return 0;
    nomec::backend::PipelineOptions pipeline;
    pipeline.is_merge = true;
    pipeline.subdivide_levels = 1;
    pipeline.offset_height = 0.05;
    pipeline.max_vertices = kMaxVertices;
    nomec::DiagnosticEngine geo;
    std::vector<nomec::backend::OutputMesh> meshes =
        nomec::backend::evaluate_scene(checked.module, geo, nullptr, kMaxVertices);
    if (geo.error_count() == 0 && !meshes.empty()) {
      meshes = nomec::backend::run_pipeline(std::move(meshes), pipeline, "fuzz", nomec::SourceRange{}, geo);
      if (geo.error_count() == 0) {
        // `nomec --emit stl` writes a pipeline's outputs from their meshes, without the
        // polygon lists: the same bytes as from the lists.
        // (The lists are not read after this.)
        const std::string listed = nomec::backend::to_stl_binary(meshes);
        for (nomec::backend::OutputMesh& m : meshes) m.soup = {};
        if (nomec::backend::to_stl_binary(meshes) != listed) std::abort();
      }
    }
    nomec::fuzz::abort_unless_inside(sources, geo);
    for (const nomec::backend::OutputMesh& m : meshes) {
      if (!nomec::kernel::mesh_problem(m.mesh).empty()) std::abort();
    }
  } catch (...) {
    std::abort();  // "No stage throws" (ARCHITECTURE.md)
  }
  return 0;
}
