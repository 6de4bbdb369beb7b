// The live preview's shared pieces (see preview.h): base64 geometry, sliders, pipeline
// options and the editing session held per document.
#include "lsp/preview.h"

#include <algorithm>
#include <cmath>

#include "backend/preview.h"
#include "backend/session.h"
#include "backend/view.h"
#include "lsp/summary_json.h"

namespace nomec::lsp {

namespace {

template <typename T>
std::string b64(const std::vector<T>& v) {
  return base64(v.data(), v.size() * sizeof(T));
}

bool same_pipeline(const backend::PipelineOptions& a, const backend::PipelineOptions& b) {
  return a.is_merge == b.is_merge && a.merge_tolerance == b.merge_tolerance &&
         a.subdivide_levels == b.subdivide_levels && a.rule == b.rule && a.offset_height == b.offset_height &&
         a.subdivide_after_levels == b.subdivide_after_levels;
}

// The parameter `bank.param` (or 2016 `bank_param`) of `m`, or None.
ir::NodeId find_param(const ir::Module& m, std::string_view name) {
  if (size_t dot = name.find('.'); dot != std::string_view::npos) return m.find_param(name.substr(0, dot), name.substr(dot + 1));
  for (size_t us = name.find('_'); us != std::string_view::npos; us = name.find('_', us + 1)) {
    if (ir::NodeId p = m.find_param(name.substr(0, us), name.substr(us + 1)); p.is_valid()) return p;
  }
  return ir::NodeId::None();
}

// "dir/klein.nome" -> "klein" (the name `nomec --emit` gives the pipeline's output).
std::string file_stem(const Analysis& a) {
  std::string_view name = a.sources().name(a.file);
  if (size_t slash = name.rfind('/'); slash != std::string_view::npos) name = name.substr(slash + 1);
  if (size_t dot = name.rfind('.'); dot != std::string_view::npos && dot > 0) name = name.substr(0, dot);
  return std::string(name);
}

json vec_json(const backend::Vec3& v) { return json::array({v[0], v[1], v[2]}); }

}  // namespace

json view_json(const ir::Module& module) {
  const backend::SceneView v = backend::scene_view(module);
  if (v.empty()) return nullptr;
  json out = json::object();
  if (v.camera) {
    const backend::ViewCamera& c = *v.camera;
    out["camera"] = {{"name", c.name},
                     {"position", vec_json(c.position)},
                     {"direction", vec_json(c.direction)},
                     {"up", vec_json(c.up)},
                     {"projection", std::string(ir::projection_name(c.projection))},
                     {"frustum",
                      {{"min", json::array({c.frustum[0], c.frustum[1], c.frustum[2]})},
                       {"max", json::array({c.frustum[3], c.frustum[4], c.frustum[5]})}}}};
  }
  json lights = json::array();
  for (const backend::ViewLight& l : v.lights) {
    lights.push_back({{"name", l.name},
                      {"type", std::string(ir::light_type_name(l.type))},
                      {"color", vec_json(l.color)},
                      {"position", vec_json(l.position)},
                      {"direction", vec_json(l.direction)},
                      {"on", l.on}});
  }
  out["lights"] = std::move(lights);
  if (v.background) out["background"] = vec_json(*v.background);
  return out;
}

std::string base64(const void* data, size_t size) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out((size + 2) / 3 * 4, '=');
  char* w = out.data();
  size_t i = 0;
  for (; i + 2 < size; i += 3, w += 4) {
    const uint32_t n = (uint32_t{p[i]} << 16) | (uint32_t{p[i + 1]} << 8) | p[i + 2];
    w[0] = kAlphabet[n >> 18];
    w[1] = kAlphabet[(n >> 12) & 63];
    w[2] = kAlphabet[(n >> 6) & 63];
    w[3] = kAlphabet[n & 63];
  }
  if (i < size) {  // one or two bytes left: the rest of `out` is already '=' padding
    const uint32_t n = (uint32_t{p[i]} << 16) | (i + 1 < size ? uint32_t{p[i + 1]} << 8 : 0);
    w[0] = kAlphabet[n >> 18];
    w[1] = kAlphabet[(n >> 12) & 63];
    if (i + 1 < size) w[2] = kAlphabet[(n >> 6) & 63];
  }
  return out;
}

backend::PipelineOptions pipeline_from_json(const json& p) {
  backend::PipelineOptions o;
  if (p.is_null()) return o;
  const auto bad = [] {
    return LspError(error_code::InvalidParams,
                    "pipeline expects {merge: bool, subdivide: 0..12, rule: \"catmull-clark\"|\"derose\", offset: number >= 0}");
  };
  if (!p.is_object()) throw bad();
  if (p.contains("merge")) {
    if (!p["merge"].is_boolean()) throw bad();
    o.is_merge = p["merge"].get<bool>();
  }
  if (p.contains("subdivide")) {
    if (!p["subdivide"].is_number_integer() || p["subdivide"].get<int>() < 0 || p["subdivide"].get<int>() > 12) throw bad();
    o.subdivide_levels = p["subdivide"].get<int>();
  }
  if (p.contains("rule")) {
    if (!p["rule"].is_string() || (p["rule"] != "catmull-clark" && p["rule"] != "derose")) throw bad();
    o.rule = p["rule"] == "derose" ? kernel::VertexRule::DeRose : kernel::VertexRule::CatmullClark;
  }
  if (p.contains("offset")) {
    // JSON's `1e999` reads as infinity: refused like a negative offset.
    if (!p["offset"].is_number() || !(p["offset"].get<double>() >= 0) || !std::isfinite(p["offset"].get<double>())) {
      throw bad();
    }
    o.offset_height = p["offset"].get<double>();
  }
  return o;
}

json pipeline_json(const backend::PipelineOptions& p) {
  return {{"merge", p.is_merge},
          {"subdivide", p.subdivide_levels},
          {"rule", p.rule == kernel::VertexRule::DeRose ? "derose" : "catmull-clark"},
          {"offset", p.offset_height}};
}

json sliders_json(const ir::Module& m) {
  std::vector<std::string> banks;
  for (ir::NodeId p : m.params()) {
    const std::string& bank = m.param(p).bank;
    if (std::find(banks.begin(), banks.end(), bank) == banks.end()) banks.push_back(bank);
  }
  json out = json::array();
  for (const std::string& bank : banks) {
    std::vector<ir::NodeId> in_bank;
    for (ir::NodeId p : m.params()) {
      if (m.param(p).bank == bank) in_bank.push_back(p);
    }
    std::stable_sort(in_bank.begin(), in_bank.end(), [&](ir::NodeId a, ir::NodeId b) {
      const int32_t la = m.param(a).list_index, lb = m.param(b).list_index;
      if ((la < 0) != (lb < 0)) return la >= 0;
      return la >= 0 && la < lb;
    });
    for (ir::NodeId p : in_bank) {
      const ir::ParamData& d = m.param(p);
      const std::string& full = m.node(p).name;
      out.push_back({{"id", full},
                     {"bank", bank},
                     {"name", full.substr(bank.size() + 1)},
                     {"value", d.value},
                     {"min", d.min},
                     {"max", d.max},
                     {"step", d.step},
                     {"listed", d.list_index >= 0}});
    }
  }
  return out;
}

json output_json(const backend::OutputMesh& mesh, bool positions_only, const backend::MeshSummary* summary) {
  json o = {{"name", mesh.name},
            {"summary", mesh_summary_json(summary != nullptr ? *summary : backend::summarize(mesh))}};
  if (positions_only) {
    o["positionsOnly"] = true;
    o["geometry"] = {{"positions", b64(backend::preview_positions(mesh))}};
    return o;
  }
  const backend::PreviewGeometry g = backend::preview_geometry(mesh);
  o["positionsOnly"] = false;
  o["geometry"] = {{"positions", b64(g.positions)},
                   {"triangles", b64(g.triangles)},
                   {"triangleFaces", b64(g.triangle_faces)},
                   {"faceColors", g.face_colors.empty() ? json(nullptr) : json(b64(g.face_colors))},
                   {"edges", b64(g.edges)},
                   {"borderEdges", b64(g.border_edges)},
                   {"mobiusEdges", b64(g.mobius_edges)},
                   {"curvePoints", b64(g.curve_points)},
                   {"curveSegments", b64(g.curve_segments)}};
  return o;
}

SliderSessions::Held& session_for(SliderSessions& sessions, const std::shared_ptr<const Analysis>& a,
                                  const std::optional<backend::PipelineOptions>& pipeline,
                                  const json& values, DiagnosticEngine& diags, bool& rebuilt) {
  auto it = std::find_if(sessions.held.begin(), sessions.held.end(),
                         [&](const SliderSessions::Held& h) { return h.uri == a->uri; });
  if (it != sessions.held.end() &&
      (it->version != a->version || (pipeline && !same_pipeline(*pipeline, it->pipeline)))) {
    sessions.held.erase(it);
    it = sessions.held.end();
  }
  rebuilt = it == sessions.held.end();
  if (rebuilt) {
    ir::Module module = a->module();
    if (values.is_object()) {  // the values a client moved before this version of the text
      for (const auto& [name, v] : values.items()) {
        ir::NodeId p = find_param(module, name);
        if (!p.is_valid() || !v.is_number()) continue;
        ir::ParamData& d = module.param(p);
        if (v.get<double>() >= d.min && v.get<double>() <= d.max) d.value = v.get<double>();
      }
    }
    backend::SessionOptions options;
    if (pipeline) options.pipeline = *pipeline;
    options.pipeline_name = file_stem(*a);
    if (!module.scene.empty()) options.pipeline_where = module.node(module.scene.front()).range;
    SliderSessions::Held h{a->uri, a->version, a, std::make_unique<backend::Session>(std::move(module), options),
                           options.pipeline, {}};
    h.session->build(diags);
    sessions.held.insert(sessions.held.begin(), std::move(h));
    if (sessions.held.size() > SliderSessions::kMax) sessions.held.pop_back();
    return sessions.held.front();
  }
  if (values.is_object()) {
    for (const auto& [name, v] : values.items()) {
      ir::NodeId p = it->session->find_parameter(name);
      if (!p.is_valid() || !v.is_number() || it->session->module().param(p).value == v.get<double>()) continue;
      DiagnosticEngine ignored;  // a refused value leaves the session as it was
      it->session->set_parameter(name, v.get<double>(), ignored);
    }
  }
  return *it;
}

json outputs_json(SliderSessions::Held& held, bool all, const std::vector<std::string>& changed,
                  const std::vector<backend::MeshSummary>* summaries) {
  json out = json::array();
  std::map<std::string, uint64_t> sent;
  const auto& outputs = held.session->outputs();
  if (summaries != nullptr && summaries->size() != outputs.size()) summaries = nullptr;
  for (size_t i = 0; i < outputs.size(); ++i) {
    const auto& m = outputs[i];
    auto prev = held.sent.find(m->name);
    if (!all && std::find(changed.begin(), changed.end(), m->name) == changed.end()) {
      sent[m->name] = prev != held.sent.end() ? prev->second : backend::preview_topology_key(*m);
      continue;
    }
    const uint64_t key = backend::preview_topology_key(*m);
    sent[m->name] = key;
    // Curves travel whole (their points are not in `positions`).
    const bool positions_only = !all && prev != held.sent.end() && prev->second == key && m->curves.empty();
    out.push_back(output_json(*m, positions_only, summaries != nullptr ? &(*summaries)[i] : nullptr));
  }
  held.sent = std::move(sent);
  return out;
}

const Diagnostic* first_error(const Analysis& a) {
  for (const Diagnostic& d : a.diagnostics) {
    if (d.severity == Severity::Error) return &d;
  }
  return nullptr;
}

}  // namespace nomec::lsp
