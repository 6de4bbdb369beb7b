// The language server and SLIDE's Tcl in its worker process: a scene whose Tcl crashes is a
// diagnostic, and the server answers the next request; a slider whose variable has a trace
// that never ends makes each move an error within the move's budget, and the server goes on
// answering (the preview and `nomec view` speak this same request).
#include <gtest/gtest.h>

#include "lsp_client.h"
#include "tests/common/tcl_scenes.h"

namespace nomec::lsp::test {
namespace {

bool has_code(const json& published, const std::string& code) {
  for (const json& d : published["diagnostics"]) {
    if (d.value("code", "") == code) return true;
  }
  return false;
}

TEST(LspTclWorker, ACrashingSceneIsADiagnosticAndTheServerGoesOn) {
  const char* crash = "file:///tmp/lsp-test/crash.slf";
  const char* fine = "file:///tmp/lsp-test/fine.slf";
  Client c;
  c.initialize();
  c.open(crash, "tclinit {\n  set r 1\n  eval \"set x [string repeat {[} 1000000]\"\n}\npoint p (1 2 3) endpoint\n", 1);
  json d = c.diagnostics(crash, 1);
  EXPECT_TRUE(has_code(d, "TclCrashed")) << d.dump(2);
  json hover = c.request("textDocument/hover", {{"textDocument", {{"uri", crash}}}, {"position", pos(4, 7)}});
  EXPECT_TRUE(hover.contains("result")) << hover.dump(2);
  // The next check gets a new worker.
  c.open(fine, "tclinit {\n  set r 1.5\n}\npoint p ({expr $r * 2} 0 0) endpoint\n", 1);
  json ok = c.diagnostics(fine, 1);
  EXPECT_TRUE(ok["diagnostics"].empty()) << ok.dump(2);
}

TEST(LspTclWorker, ASliderMoveThatNeverEndsIsStoppedAndTheNextIsAnswered) {
  const char* uri = "file:///tmp/lsp-test/trace.slf";
  const std::string text = nomec::testing_scenes::kSliderTraceNeverEnds;
  Client c;
  c.initialize();
  c.open(uri, text, 1);
  c.diagnostics(uri, 1);
  for (double value : {0.7, 0.1}) {
    json r = c.request("nome/setParameter", {{"uri", uri}, {"parameter", "par.x"}, {"value", value}});
    ASSERT_TRUE(r.contains("result") || r.contains("error")) << r.dump(2);
    EXPECT_NE(r.dump().find("slider move"), std::string::npos) << r.dump(2);
  }
  json symbols = c.request("textDocument/documentSymbol", {{"textDocument", {{"uri", uri}}}});
  EXPECT_TRUE(symbols.contains("result")) << symbols.dump(2);
}

}  // namespace
}  // namespace nomec::lsp::test
