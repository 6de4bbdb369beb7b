// The language server and SLIDE's Tcl in its worker process: a scene whose Tcl crashes is a
// diagnostic, and the server answers the next request; a slider whose variable has a trace
// that never ends makes each move an error within the move's budget, and the server goes on
// answering (the preview and `nomec view` speak this same request).
#include <gtest/gtest.h>

#include "lsp_client.h"

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
  const std::string text = R"(tclinit {
  set par_x 0.5
  scale .x -from 0 -to 1 -resolution 0.1 -variable par_x
  trace add variable par_x write {apply {args { while 1 {} }}}
}
point p0 (0 0 0) endpoint
point p1 ({if {$par_x > 0.2} {expr 1} else {expr 2}} 0 0) endpoint
point p2 (0 1 0) endpoint
face f (p0 p1 p2) endface
object o (f) endobject
instance o endinstance
)";
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
