// In-process transcript of the custom request nome/setParameter: moving `fp.z` of the
// funnel cube answers the new summary (the same as a fresh build with -D) with the work
// done (six instances re-transformed, no generator), a second move at the same version is
// incremental, the 2016 `fp_n` spelling runs the funnel once, and unknown sliders, values
// out of range, documents with errors and malformed parameters are InvalidParams errors.
#include <gtest/gtest.h>


#include <fmt/format.h>

#include "base/file_io.h"
#include "frontend/source/source_manager.h"
#include "backend/session.h"
#include "frontend/check/check.h"
#include "lsp_client.h"

namespace nomec::lsp::test {
namespace {

const char* kUri = "file:///tmp/lsp-test/funnel_cube.nome";

std::string funnel_cube() {
  return nomec::read_file_bytes(std::string(NOMEC_SOURCE_DIR) + "/examples/funnel_cube.nome").value();
}

json set(Client& c, const std::string& uri, const std::string& parameter, json value) {
  return c.request("nome/setParameter", {{"uri", uri}, {"parameter", parameter}, {"value", value}});
}

TEST(LspSetParameter, MovesASliderAndAnswersTheSummary) {
  Client c;
  c.initialize();
  c.open(kUri, funnel_cube(), 1);
  EXPECT_TRUE(c.diagnostics(kUri, 1)["diagnostics"].empty());

  json r = set(c, kUri, "fp.z", -0.5);
  ASSERT_TRUE(r.contains("result")) << r.dump(2);
  const json& res = r["result"];
  EXPECT_EQ(res["parameter"], "fp.z");
  EXPECT_EQ(res["version"], 1);
  EXPECT_EQ(res["nodesInGraph"], 24);
  EXPECT_EQ(res["nodesReevaluated"], 14);
  EXPECT_EQ(res["generatorsRerun"], 0);
  EXPECT_EQ(res["instancesRetransformed"], 6);
  EXPECT_EQ(res["changedOutputs"], json::array({"cf"}));
  ASSERT_EQ(res["meshes"].size(), 1u);
  const json& mesh = res["meshes"][0];
  EXPECT_EQ(mesh["name"], "cf");
  EXPECT_EQ(mesh["faces"], 48);
  EXPECT_EQ(mesh["bounding_box"]["max"][2], 0.5);  // the funnels' rims moved to z = ±0.5

  // A fresh build with fp.z = -0.5 has the same summary, position hash included.
  {
    SourceManager sources;
    DiagnosticEngine diags;
    CheckOptions o;
    o.overrides = {{"fp.z", -0.5}};
    CheckResult fresh = check_source(sources, "f.nome", funnel_cube(), o, diags);
    backend::Session s(std::move(fresh.module));
    s.build(diags);
    EXPECT_EQ(mesh["position_hash"], fmt::format("{:016x}", s.summary()[0].position_hash));
  }

  // The next move at the same version reuses the session: the 2016 spelling of fp.n
  // re-runs the funnel once.
  json n = set(c, kUri, "fp_n", 5);
  ASSERT_TRUE(n.contains("result")) << n.dump(2);
  EXPECT_EQ(n["result"]["parameter"], "fp.n");
  EXPECT_EQ(n["result"]["generatorsRerun"], 1);
  EXPECT_EQ(n["result"]["meshes"][0]["faces"], 30);
  EXPECT_EQ(n["result"]["meshes"][0]["bounding_box"]["max"][2], 0.5);  // fp.z stays moved
}

// A SLIDE slider that only Tcl reads (`lod {if …}`, as in spiral.slf) switches instances
// on and off through nome/setParameter; the Tcl runs on the evaluator's thread while the
// server's threads ask for the values.
TEST(LspSetParameter, TclLodFollowsASlideSlider) {
  const char* uri = "file:///tmp/lsp-test/bands.slf";
  const std::string text = R"(tclinit {
  package require slideui
  set par_numS 2
  scale .n -from 0 -to 3 -resolution 1 -variable par_numS
}
point p0 (0 0 0) endpoint
point p1 (1 0 0) endpoint
point p2 (0 1 0) endpoint
face f (p0 p1 p2) endface
object band (f) endobject
group shell
  instance band id b1 lod {if {$par_numS >= 1} {expr $SLF_FULL} else {expr $SLF_OFF}} endinstance
  instance band id b2 lod {if {$par_numS >= 2} {expr $SLF_FULL} else {expr $SLF_OFF}} translate (2 0 0) endinstance
  instance band id b3 lod {if {$par_numS >= 3} {expr $SLF_FULL} else {expr $SLF_OFF}} translate (4 0 0) endinstance
endgroup
instance shell endinstance
)";
  Client c;
  c.initialize();
  c.open(uri, text, 1);
  c.diagnostics(uri, 1);
  for (auto [value, faces] : {std::pair{3, 3}, std::pair{1, 1}, std::pair{2, 2}}) {
    json r = set(c, uri, "par.numS", value);
    ASSERT_TRUE(r.contains("result")) << r.dump(2);
    ASSERT_EQ(r["result"]["meshes"].size(), 1u) << r.dump(2);
    EXPECT_EQ(r["result"]["meshes"][0]["faces"], faces) << "numS = " << value;
  }
}

TEST(LspSetParameter, RefusesBadRequests) {
  Client c;
  c.initialize();
  c.open(kUri, funnel_cube(), 1);
  c.diagnostics(kUri, 1);
  json unknown = set(c, kUri, "fp.nope", 1);
  ASSERT_TRUE(unknown.contains("error")) << unknown.dump();
  EXPECT_EQ(unknown["error"]["code"], -32602);
  EXPECT_NE(unknown["error"]["message"].get<std::string>().find("no slider `fp.nope`"), std::string::npos);
  json range = set(c, kUri, "fp.n", 42);
  ASSERT_TRUE(range.contains("error")) << range.dump();
  EXPECT_NE(range["error"]["message"].get<std::string>().find("outside the range [3, 10]"), std::string::npos);
  json malformed = c.request("nome/setParameter", {{"uri", kUri}, {"parameter", "fp.n"}, {"value", "five"}});
  ASSERT_TRUE(malformed.contains("error")) << malformed.dump();
  EXPECT_EQ(malformed["error"]["code"], -32602);

  const char* broken = "file:///tmp/lsp-test/broken.nome";
  c.open(broken, "bank fp\n  set n 8 3 10 1\nendbank\nfunnel f ({expr $fp_q} 1 0.2 0.5) endfunnel\n", 1);
  c.diagnostics(broken, 1);
  json err = set(c, broken, "fp.n", 4);
  ASSERT_TRUE(err.contains("error")) << err.dump();
  EXPECT_NE(err["error"]["message"].get<std::string>().find("the document has errors"), std::string::npos);
}

}  // namespace
}  // namespace nomec::lsp::test
