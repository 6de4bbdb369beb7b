// In-process transcripts of the live preview's requests (lsp/README.md): nome/preview
// answers every output's geometry as base64 typed arrays that decode to the summary's
// counts, the sliders (NOME3 `list` order first), and the pipeline used; a slider move with
// `geometry: true` answers the changed outputs only, positions alone when the topology
// stayed; a document with errors answers `ok: false` and no geometry; nome/saveScene saves
// the moved values, each in place (SLIDE's `CreateScale` arguments, a NOME 2016 file's one
// `savedparameter` block), and refuses a save that would lose a moved value.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <set>

#include "lsp/preview.h"
#include "lsp_client.h"

namespace nomec::lsp::test {
namespace {

std::string example(const char* name) { return read_text(std::string(NOMEC_SOURCE_DIR) + "/examples/" + name); }

std::vector<uint8_t> unbase64(const std::string& s) {
  auto val = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
  };
  std::vector<uint8_t> out;
  uint32_t acc = 0;
  int bits = 0;
  for (char c : s) {
    if (c == '=') break;
    acc = (acc << 6) | static_cast<uint32_t>(val(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<uint8_t>((acc >> bits) & 0xff));
    }
  }
  return out;
}

template <typename T>
std::vector<T> decode(const json& field) {
  std::vector<uint8_t> bytes = unbase64(field.get<std::string>());
  EXPECT_EQ(bytes.size() % sizeof(T), 0u);
  std::vector<T> v(bytes.size() / sizeof(T));
  if (!v.empty()) std::memcpy(v.data(), bytes.data(), v.size() * sizeof(T));  // never with null pointers
  return v;
}

TEST(LspPreview, Base64IsRfc4648) {
  EXPECT_EQ(base64("Man", 3), "TWFu");
  EXPECT_EQ(base64("Ma", 2), "TWE=");
  EXPECT_EQ(base64("M", 1), "TQ==");
  EXPECT_EQ(base64("", 0), "");
  const unsigned char high[] = {0xfb, 0xff, 0xbf};
  EXPECT_EQ(base64(high, 3), "+/+/");
}

TEST(LspPreview, AnswersGeometrySlidersAndTopology) {
  Client c;
  c.initialize();
  const char* uri = "file:///tmp/lsp-test/funnel_cube.nome";
  c.open(uri, example("funnel_cube.nome"), 1);
  json r = c.request("nome/preview", {{"uri", uri}});
  ASSERT_TRUE(r.contains("result")) << r.dump(2);
  const json& res = r["result"];
  EXPECT_EQ(res["ok"], true);
  EXPECT_EQ(res["version"], 1);
  EXPECT_EQ(res["pipeline"]["merge"], false);
  EXPECT_EQ(res["files"][0], "/tmp/lsp-test/funnel_cube.nome");
  // The sliders of bank fp with their ranges.
  ASSERT_FALSE(res["sliders"].empty());
  const json& n = res["sliders"][0];
  EXPECT_EQ(n["id"], "fp.n");
  EXPECT_EQ(n["bank"], "fp");
  EXPECT_EQ(n["name"], "n");
  EXPECT_EQ(n["min"], 3);
  EXPECT_EQ(n["max"], 10);
  EXPECT_EQ(n["step"], 1);
  ASSERT_EQ(res["outputs"].size(), 1u);
  const json& cf = res["outputs"][0];
  EXPECT_EQ(cf["name"], "cf");
  EXPECT_EQ(cf["positionsOnly"], false);
  const json& s = cf["summary"];
  const json& g = cf["geometry"];
  const auto positions = decode<float>(g["positions"]);
  const auto triangles = decode<uint32_t>(g["triangles"]);
  const auto tri_faces = decode<uint32_t>(g["triangleFaces"]);
  const auto edges = decode<uint32_t>(g["edges"]);
  const auto borders = decode<uint32_t>(g["borderEdges"]);
  EXPECT_EQ(positions.size(), 3u * s["vertices"].get<size_t>());
  EXPECT_EQ(edges.size(), 2u * s["edges"].get<size_t>());
  EXPECT_EQ(triangles.size(), 3u * tri_faces.size());
  std::set<uint32_t> faces(tri_faces.begin(), tri_faces.end());
  EXPECT_EQ(faces.size(), s["faces"].get<size_t>());  // every face has triangles
  for (uint32_t v : triangles) ASSERT_LT(v, s["vertices"].get<uint32_t>());
  // Six funnels, unmerged: every rim is a border, and borders are edges of the mesh.
  EXPECT_GT(s["border_loops"].get<int>(), 0);
  EXPECT_FALSE(borders.empty());
  EXPECT_TRUE(decode<uint32_t>(g["mobiusEdges"]).empty());
  EXPECT_TRUE(g["faceColors"].is_null());
  float zmax = -1e9f;
  for (size_t i = 2; i < positions.size(); i += 3) zmax = std::max(zmax, positions[i]);
  EXPECT_NEAR(zmax, s["bounding_box"]["max"][2].get<double>(), 1e-5);

  // A move of fp.z re-places the funnels: the changed output, positions only.
  json z = c.request("nome/setParameter", {{"uri", uri}, {"parameter", "fp.z"}, {"value", -0.5}, {"geometry", true}});
  ASSERT_TRUE(z.contains("result")) << z.dump(2);
  EXPECT_EQ(z["result"]["outputNames"], json::array({"cf"}));
  ASSERT_EQ(z["result"]["outputs"].size(), 1u);
  const json& moved = z["result"]["outputs"][0];
  EXPECT_EQ(moved["positionsOnly"], true);
  EXPECT_FALSE(moved["geometry"].contains("triangles"));
  EXPECT_EQ(decode<float>(moved["geometry"]["positions"]).size(), positions.size());
  EXPECT_NE(moved["geometry"]["positions"], g["positions"]);
  // fp.n changes the topology: everything again.
  json nn = c.request("nome/setParameter", {{"uri", uri}, {"parameter", "fp.n"}, {"value", 5}, {"geometry", true}});
  ASSERT_TRUE(nn.contains("result")) << nn.dump(2);
  ASSERT_EQ(nn["result"]["outputs"].size(), 1u);
  EXPECT_EQ(nn["result"]["outputs"][0]["positionsOnly"], false);
  EXPECT_EQ(nn["result"]["outputs"][0]["summary"]["faces"], 30);
  // Without `geometry` the reply is as before.
  json plain = c.request("nome/setParameter", {{"uri", uri}, {"parameter", "fp.n"}, {"value", 6}});
  EXPECT_FALSE(plain["result"].contains("outputs"));

  // The saved scene carries the moved values.
  json saved = c.request("nome/saveScene", {{"uri", uri}});
  ASSERT_TRUE(saved.contains("result")) << saved.dump(2);
  const std::string text = saved["result"]["text"].get<std::string>();
  EXPECT_NE(text.find("-0.5"), std::string::npos) << text;
}

TEST(LspPreview, PipelineValuesAndKleinBottleTopology) {
  Client c;
  c.initialize();
  const char* uri = "file:///tmp/lsp-test/klein_bottle_zipped.nome";
  c.open(uri, example("klein_bottle_zipped.nome"), 1);
  json r = c.request("nome/preview", {{"uri", uri}, {"pipeline", {{"merge", true}, {"subdivide", 1}}}});
  ASSERT_TRUE(r.contains("result")) << r.dump(2);
  const json& res = r["result"];
  EXPECT_EQ(res["ok"], true) << res["diagnostics"].dump(2);
  EXPECT_EQ(res["pipeline"]["subdivide"], 1);
  ASSERT_EQ(res["outputs"].size(), 1u);
  const json& s = res["outputs"][0]["summary"];
  EXPECT_EQ(res["outputs"][0]["name"], "klein_bottle_zipped");
  EXPECT_EQ(s["euler"], 0);
  EXPECT_EQ(s["orientable"], false);
  EXPECT_EQ(s["closed"], true);
  EXPECT_TRUE(decode<uint32_t>(res["outputs"][0]["geometry"]["borderEdges"]).empty());
  // Non-orientable: where the faces' orientations meet reversed, Möbius edges.
  EXPECT_FALSE(decode<uint32_t>(res["outputs"][0]["geometry"]["mobiusEdges"]).empty());

  // Values a client moved before are applied to a rebuilt session: the same summary as
  // moving the slider afterwards.
  json v = c.request("nome/preview", {{"uri", uri}, {"values", {{"tp1.h", 1.0}}}});
  ASSERT_TRUE(v.contains("result")) << v.dump(2);
  EXPECT_EQ(v["result"]["rebuilt"], true);
  const json h = v["result"]["sliders"];
  auto it = std::find_if(h.begin(), h.end(), [](const json& x) { return x["id"] == "tp1.h"; });
  ASSERT_NE(it, h.end());
  EXPECT_EQ((*it)["value"], 1.0);
  json again = c.request("nome/preview", {{"uri", uri}, {"values", {{"tp1.h", 1.0}}}});
  EXPECT_EQ(again["result"]["rebuilt"], false);  // same version and pipeline: the held session

  json bad = c.request("nome/preview", {{"uri", uri}, {"pipeline", {{"subdivide", "two"}}}});
  ASSERT_TRUE(bad.contains("error"));
  EXPECT_EQ(bad["error"]["code"], -32602);
}

TEST(LspPreview, ListOrderAndDocumentsWithErrors) {
  Client c;
  c.initialize();
  const char* uri = "file:///tmp/lsp-test/listed.nome";
  c.open(uri,
         "bank b\n  set a 1 0 2 0.1\n  set z 1 0 2 0.1\n  set m 1 0 2 0.1\n  list (m a)\nendbank\n"
         "funnel f ({expr $b.a} 0.5 0.2 8) endfunnel\ninstance i f endinstance\n",
         1);
  json r = c.request("nome/preview", {{"uri", uri}});
  ASSERT_TRUE(r.contains("result")) << r.dump(2);
  EXPECT_EQ(r["result"]["ok"], true) << r["result"]["diagnostics"].dump(2);
  const json& sl = r["result"]["sliders"];
  ASSERT_EQ(sl.size(), 3u) << sl.dump(2);
  EXPECT_EQ(sl[0]["id"], "b.m");
  EXPECT_EQ(sl[1]["id"], "b.a");
  EXPECT_EQ(sl[2]["id"], "b.z");
  EXPECT_EQ(sl[0]["listed"], true);
  EXPECT_EQ(sl[2]["listed"], false);

  const char* broken = "file:///tmp/lsp-test/broken.nome";
  c.open(broken, "bank fp\n  set n 8 3 10 1\nendbank\nfunnel f ({expr $fp_q} 1 0.2 0.5) endfunnel\n", 1);
  json e = c.request("nome/preview", {{"uri", broken}});
  ASSERT_TRUE(e.contains("result")) << e.dump(2);
  EXPECT_EQ(e["result"]["ok"], false);
  EXPECT_FALSE(e["result"].contains("outputs"));
  ASSERT_FALSE(e["result"]["diagnostics"].empty());
  EXPECT_NE(e["result"]["diagnostics"][0]["message"].get<std::string>().find("fp_q"), std::string::npos);
  json save = c.request("nome/saveScene", {{"uri", broken}});
  EXPECT_TRUE(save.contains("error"));
}

// The preview's "Save scene with these values" and "Write slider values into the file"
// (issue 45): a SLIDE file keeps its `CreateScale` calls, the moved value is their default
// argument, nothing else changes; a NOME 2016 file's savedparameter block is updated, not
// repeated; a slider whose value the file cannot carry makes the save an error.
TEST(LspPreview, SaveSceneWritesEachMovedValueInPlace) {
  Client c;
  c.initialize();
  const std::string path = std::string(NOMEC_CORPUS_DIR) + "/slide/BellShape.slf";
  const std::string uri = "file://" + path;
  const std::string original = read_text(path);
  c.open(uri.c_str(), original, 1);
  ASSERT_EQ(c.request("nome/preview", {{"uri", uri}})["result"]["ok"], true);
  json moved = c.request("nome/setParameter", {{"uri", uri}, {"parameter", "swp.q0x"}, {"value", 0.9 + 0.1 + 0.1}});
  ASSERT_TRUE(moved.contains("result")) << moved.dump(2);
  json saved = c.request("nome/saveScene", {{"uri", uri}});
  ASSERT_TRUE(saved.contains("result")) << saved.dump(2);
  std::string text = saved["result"]["text"].get<std::string>();
  text = text.substr(text.find('\n') + 1);  // past the `# Saved by nomec` line
  std::string expected = original;
  const std::string q0x = "\"q0x\"                              0.9";
  expected.replace(expected.find(q0x), q0x.size(), "\"q0x\"                              1.1");
  EXPECT_EQ(text, expected);

  std::string scene =
      "bank fp\n    set n 8 3 10 1\nendbank\nfunnel fun ({expr $fp_n} 0.4 0 0.2) endfunnel\ninstance f fun endinstance\n"
      "savedparameter\n    fp_n 6.000000\nendsavedparameter\n";
  for (int round = 0; round < 2; ++round) {
    const std::string nome = "file:///tmp/lsp-test/saved" + std::to_string(round) + ".nom";
    c.open(nome, scene, 1);
    ASSERT_EQ(c.request("nome/preview", {{"uri", nome}})["result"]["ok"], true);
    c.request("nome/setParameter", {{"uri", nome}, {"parameter", "fp.n"}, {"value", 4 + round}});
    json r = c.request("nome/saveScene", {{"uri", nome}});
    ASSERT_TRUE(r.contains("result")) << r.dump(2);
    const std::string t = r["result"]["text"].get<std::string>();
    EXPECT_EQ(t.find("\nsavedparameter"), t.rfind("\nsavedparameter")) << "one block: " << t;
    EXPECT_NE(t.find("    fp_n " + std::to_string(4 + round) + "\n"), std::string::npos) << t;
    EXPECT_NE(t.find("    set n 8 3 10 1\n"), std::string::npos) << t;
    scene = t.substr(t.find('\n') + 1);  // "Write slider values into the file"
  }

  const char* off = "file:///tmp/lsp-test/off.slf";
  c.open(off, "tclinit {\n  package require slideui\n  CreateSLIDEOffsetObject oOff\n  CreateSLIDEOffsetUI .ui oOff\n}\n"
              "point p (0 0 0) endpoint\n", 1);
  ASSERT_EQ(c.request("nome/preview", {{"uri", off}})["result"]["ok"], true);
  c.request("nome/setParameter", {{"uri", off}, {"parameter", "oOff.height"}, {"value", 0.5}});
  json refused = c.request("nome/saveScene", {{"uri", off}});
  ASSERT_TRUE(refused.contains("error")) << refused.dump(2);
  EXPECT_NE(refused["error"]["message"].get<std::string>().find("slider `oOff.height` = 0.5 cannot be saved"),
            std::string::npos)
      << refused.dump(2);
}

TEST(LspPreview, CurvesAreLines) {
  Client c;
  c.initialize();
  const char* uri = "file:///tmp/lsp-test/curve.nome";
  c.open(uri,
         "bank s\n  set z 2 0 3 0.5\nendbank\n"
         "point a (0 0 0) endpoint\npoint b (1 0 0) endpoint\npoint c (1 1 0) endpoint\n"
         "polyline l (a b c) closed endpolyline\ninstance il l translate (0 0 {expr $s_z}) endinstance\n",
         1);
  json r = c.request("nome/preview", {{"uri", uri}});
  ASSERT_TRUE(r.contains("result")) << r.dump(2);
  ASSERT_EQ(r["result"]["ok"], true) << r["result"]["diagnostics"].dump(2);
  ASSERT_EQ(r["result"]["outputs"].size(), 1u);
  const json& o = r["result"]["outputs"][0];
  EXPECT_EQ(o["summary"]["curves"], 1);
  const auto points = decode<float>(o["geometry"]["curvePoints"]);
  const auto segments = decode<uint32_t>(o["geometry"]["curveSegments"]);
  ASSERT_EQ(points.size(), 9u);  // a b c, placed at z = 2
  EXPECT_EQ(points[3], 1.0f);
  EXPECT_EQ(points[8], 2.0f);
  EXPECT_EQ(segments, (std::vector<uint32_t>{0, 1, 1, 2, 2, 0}));  // closed: back to a

  // Moving the slider moves the curve (it travels whole, not as positions only).
  json m = c.request("nome/setParameter", {{"uri", uri}, {"parameter", "s.z"}, {"value", 0.5}, {"geometry", true}});
  ASSERT_TRUE(m.contains("result")) << m.dump(2);
  ASSERT_EQ(m["result"]["outputs"].size(), 1u);
  EXPECT_EQ(m["result"]["outputs"][0]["positionsOnly"], false);
  EXPECT_EQ(decode<float>(m["result"]["outputs"][0]["geometry"]["curvePoints"])[8], 0.5f);
}

// A polyline placed inside a subdivision block is still drawn: the block steps the faces
// and passes the curves through, in place.
TEST(LspPreview, CurvesInsideBlocksAreLines) {
  Client c;
  c.initialize();
  const char* uri = "file:///tmp/lsp-test/block_curve.nom";
  c.open(uri,
         "point a (0 0 0) endpoint\npoint b (1 0 0) endpoint\npoint c (1 1 0) endpoint\npoint d (0 1 0) endpoint\n"
         "mesh sq\n  face f (a b c d) endface\nendmesh\n"
         "polyline l (a b c) endpolyline\n"
         "subdivision sub0\n  instance s sq endinstance\n  instance il l translate (0 0 2) endinstance\nendsubdivision\n",
         1);
  json r = c.request("nome/preview", {{"uri", uri}});
  ASSERT_TRUE(r.contains("result")) << r.dump(2);
  ASSERT_EQ(r["result"]["ok"], true) << r["result"]["diagnostics"].dump(2);
  ASSERT_EQ(r["result"]["outputs"].size(), 1u) << r.dump(2);
  const json& o = r["result"]["outputs"][0];
  EXPECT_EQ(o["summary"]["curves"], 1);
  EXPECT_GT(o["summary"]["faces"].get<int>(), 1);  // the square was subdivided
  const auto points = decode<float>(o["geometry"]["curvePoints"]);
  const auto segments = decode<uint32_t>(o["geometry"]["curveSegments"]);
  ASSERT_EQ(points.size(), 9u);  // a b c, placed at z = 2
  EXPECT_EQ(points[3], 1.0f);
  EXPECT_EQ(points[8], 2.0f);
  EXPECT_EQ(segments, (std::vector<uint32_t>{0, 1, 1, 2}));  // open
}

void expect_vec(const json& v, double x, double y, double z, const std::string& what) {
  ASSERT_TRUE(v.is_array() && v.size() == 3) << what << ": " << v.dump();
  EXPECT_NEAR(v[0].get<double>(), x, 1e-9) << what;
  EXPECT_NEAR(v[1].get<double>(), y, 1e-9) << what;
  EXPECT_NEAR(v[2].get<double>(), z, 1e-9) << what;
}

// A SLIDE scene's `render` gives the preview its camera, placed by the instances along the
// camera path, its lights (a `lookat` aims one) and the window's background.
TEST(LspPreview, SlideRenderGivesTheView) {
  Client c;
  c.initialize();
  const char* uri = "file:///tmp/lsp-test/view.slf";
  c.open(uri,
         "point a (0 0 0) endpoint\npoint b (1 0 0) endpoint\npoint d (0 1 0) endpoint\n"
         "face f (a b d) endface\nobject tri (f) endobject\n"
         "render vp gCam.iCam.cam world\n  light world.front_sun.sun\n  light world.main_amb.amb SLF_OFF\nendrender\n"
         "camera cam projection SLF_PERSPECTIVE frustum (-0.1 -0.1 -2) (0.1 0.1 -0.01) endcamera\n"
         "light sun type SLF_DIRECTIONAL color (0.8 0.8 0.8) endlight\n"
         "light amb type SLF_AMBIENT color (0.2 0.2 0.2) endlight\n"
         "group gCam\n  instance cam id iCam translate (0 0 1) endinstance\nendgroup\n"
         "group world\n  instance tri endinstance\n"
         "  instance sun id front_sun\n    lookat eye (0 0 0) target (-1 -1 -1) up (0 1 0) endlookat\n"
         "    translate (1 1 1)\n  endinstance\n  instance amb id main_amb endinstance\nendgroup\n"
         "window Window background (0.3 0.6 0.3) endwindow\nviewport vp Window endviewport\ninstance world endinstance\n",
         1);
  json r = c.request("nome/preview", {{"uri", uri}});
  ASSERT_TRUE(r.contains("result")) << r.dump(2);
  ASSERT_EQ(r["result"]["ok"], true) << r["result"]["diagnostics"].dump(2);
  ASSERT_TRUE(r["result"].contains("view")) << r["result"].dump(2);
  const json& view = r["result"]["view"];
  const json& cam = view["camera"];
  EXPECT_EQ(cam["name"], "cam");
  expect_vec(cam["position"], 0, 0, 1, "camera position: iCam's translate");
  expect_vec(cam["direction"], 0, 0, -1, "looks down -z");
  expect_vec(cam["up"], 0, 1, 0, "up");
  EXPECT_EQ(cam["projection"], "perspective");
  expect_vec(cam["frustum"]["min"], -0.1, -0.1, -2, "frustum min");
  expect_vec(cam["frustum"]["max"], 0.1, 0.1, -0.01, "frustum max");
  ASSERT_EQ(view["lights"].size(), 2u) << view.dump(2);
  const json& sun = view["lights"][0];
  EXPECT_EQ(sun["type"], "directional");
  expect_vec(sun["color"], 0.8, 0.8, 0.8, "sun colour");
  // lookat … endlookat translate (1 1 1): a light at (1, 1, 1) aimed at the origin.
  expect_vec(sun["position"], 1, 1, 1, "sun position");
  const double k = -1 / std::sqrt(3.0);
  expect_vec(sun["direction"], k, k, k, "sun direction");
  EXPECT_EQ(sun["on"], true);
  EXPECT_EQ(view["lights"][1]["type"], "ambient");
  EXPECT_EQ(view["lights"][1]["on"], false);
  expect_vec(view["background"], 0.3, 0.6, 0.3, "the window's background");
}

// Instance transforms compose parent · child along the path: the group instance's rotation
// acts after the camera instance's translate, so (0 0 1) turns to (1 0 0), looking down -x.
// Without `render`, a JIPCAD `backgroundcolor` and the first camera instance make the view.
TEST(LspPreview, ViewComposesNestedInstancesAndNome3Cameras) {
  Client c;
  c.initialize();
  const char* uri = "file:///tmp/lsp-test/nested.slf";
  c.open(uri,
         "camera cam endcamera\nwindow w endwindow\nviewport vp w endviewport\n"
         "group gCam\n  instance cam id iCam translate (0 0 1) endinstance\nendgroup\n"
         "group gOuter\n  instance gCam id iG rotate (0 1 0) (90) endinstance\nendgroup\n"
         "render vp gOuter.iG.iCam.cam gOuter endrender\n",
         1);
  json r = c.request("nome/preview", {{"uri", uri}});
  ASSERT_EQ(r["result"]["ok"], true) << r.dump(2);
  const json& cam = r["result"]["view"]["camera"];
  expect_vec(cam["position"], 1, 0, 0, "rotated camera position");
  expect_vec(cam["direction"], -1, 0, 0, "rotated direction");
  EXPECT_EQ(cam["projection"], "parallel");  // SLIDE's default
  expect_vec(cam["frustum"]["min"], -1, -1, -100, "default frustum");
  expect_vec(r["result"]["view"]["background"], 0, 0, 0, "the default background");
  EXPECT_TRUE(r["result"]["view"]["lights"].empty());

  const char* nome3 = "file:///tmp/lsp-test/viewer.nom";
  c.open(nome3,
         "backgroundcolor (1 1 1) endbackgroundcolor\n"
         "camera c1 projection NOME_ORTHOGONAL frustum (-2 2 -1 1 0.5 20) endcamera\n"
         "light l1 type NOME_DIRECTIONAL color (1 0 0) endlight\n"
         "instance ic c1 translate (0 0 5) endinstance\ninstance il l1 rotate (1 0 0) (90) endinstance\n",
         1);
  json n = c.request("nome/preview", {{"uri", nome3}});
  ASSERT_EQ(n["result"]["ok"], true) << n.dump(2);
  const json& v = n["result"]["view"];
  expect_vec(v["camera"]["position"], 0, 0, 5, "NOME3 camera instance");
  EXPECT_EQ(v["camera"]["projection"], "parallel");
  // (left right bottom top near far) in SLIDE's order: x, y, then z in front of the camera.
  expect_vec(v["camera"]["frustum"]["min"], -2, -1, -20, "NOME3 frustum min");
  expect_vec(v["camera"]["frustum"]["max"], 2, 1, -0.5, "NOME3 frustum max");
  ASSERT_EQ(v["lights"].size(), 1u);
  expect_vec(v["lights"][0]["direction"], 0, 1, 0, "-z turned 90° about x");
  expect_vec(v["background"], 1, 1, 1, "JIPCAD backgroundcolor");

  // A scene with no viewing set-up has no `view`.
  const char* plain = "file:///tmp/lsp-test/plain.nome";
  c.open(plain, example("funnel_cube.nome"), 1);
  json p = c.request("nome/preview", {{"uri", plain}});
  EXPECT_FALSE(p["result"].contains("view")) << p["result"]["view"].dump();
}

}  // namespace
}  // namespace nomec::lsp::test
