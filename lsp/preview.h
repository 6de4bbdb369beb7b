// What the live preview's requests share (`nome/preview`, `nome/setParameter`,
// `nome/saveScene`; see lsp/README.md): the editing session held per document, and the
// compact JSON of geometry — typed arrays as base64 text (little-endian float32 positions,
// uint32 indices, uint8 colours) instead of JSON number arrays, e.g. the 98 vertices of the
// funnel cube's `cf` are one 1568-character `positions` string.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "backend/evaluate.h"
#include "backend/summary.h"
#include "lsp/handler.h"

namespace nomec::lsp {

/// Standard base64 (RFC 4648, with padding) of `size` bytes.
std::string base64(const void* data, size_t size);

/// `{merge, subdivide, rule, offset}` of a request, or InvalidParams. Absent: no pipeline.
backend::PipelineOptions pipeline_from_json(const json& p);
json pipeline_json(const backend::PipelineOptions& p);

/// The sliders of `module`: one entry per parameter, banks in declaration order, within a
/// bank the NOME3 `list (…)` names first in list order (`listed: true`), then the rest in
/// declaration order.
json sliders_json(const ir::Module& module);

/// One output: name, summary and, unless `positions_only`, the triangles, face colours,
/// edges, border edges and Möbius edges (see backend/preview.h). `summary`, when given, is
/// the mesh's summary already computed (it is not computed again).
json output_json(const backend::OutputMesh& mesh, bool positions_only, const backend::MeshSummary* summary = nullptr);

/// The session of `a`'s document (made or rebuilt when its version or `pipeline` differ,
/// or when `pipeline` is nullopt and none is held); geometry diagnostics of a build go to
/// `diags`. `rebuilt` says whether it was (re)built. Caller holds `sessions.mu`.
SliderSessions::Held& session_for(SliderSessions& sessions, const std::shared_ptr<const Analysis>& a,
                                  const std::optional<backend::PipelineOptions>& pipeline,
                                  const json& values, DiagnosticEngine& diags, bool& rebuilt);

/// Outputs of `held`'s session as JSON: every output when `all`, else those named in
/// `changed`; positions only when an output's topology equals what was last sent under its
/// name. Updates `held.sent`. `summaries`, when given, are the session's output summaries
/// in output order, already computed.
json outputs_json(SliderSessions::Held& held, bool all, const std::vector<std::string>& changed,
                  const std::vector<backend::MeshSummary>* summaries = nullptr);

/// The viewing set-up of `module` (`backend::scene_view`) as the `view` object of
/// `nome/preview`, or null when the scene has none: `{camera?: {name, position, direction,
/// up, projection: "parallel"|"perspective", frustum: {min, max}}, lights: [{name, type:
/// "ambient"|"directional"|"point"|"spot", color, position, direction, on}], background?}`.
json view_json(const ir::Module& module);

/// The first error among `a`'s diagnostics, if any.
const Diagnostic* first_error(const Analysis& a);

}  // namespace nomec::lsp
