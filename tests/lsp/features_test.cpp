// In-process JSON-RPC transcripts for the language features: quick fixes from fix-its
// (and, as the index lands, hover, definition, references, symbols, completion, …).
#include <gtest/gtest.h>

#include "lsp_client.h"

namespace nomec::lsp::test {
namespace {

const char* kUri = "file:///tmp/lsp-test/features.nome";

TEST(LspFeatures, CodeActionAppliesTheFixIt) {
  Client c;
  c.initialize();
  std::string text = "bank fp\n  set ro 0.4 0.1 1.0 0.1\nendbank\nfunnel fun (4 {expr $fp_rho} 0.2 0.5) endfunnel\n";
  c.open(kUri, text, 1);
  json d = c.diagnostics(kUri, 1);
  ASSERT_EQ(d["diagnostics"].size(), 1u) << d.dump(2);
  EXPECT_EQ(d["diagnostics"][0]["range"], range(3, 20, 3, 27));

  json r = c.request("textDocument/codeAction", {{"textDocument", {{"uri", kUri}}},
                                                 {"range", range(3, 22, 3, 22)},
                                                 {"context", {{"diagnostics", d["diagnostics"]}}}});
  ASSERT_TRUE(r["result"].is_array()) << r.dump();
  ASSERT_EQ(r["result"].size(), 1u) << r.dump(2);
  const json& action = r["result"][0];
  EXPECT_EQ(action["kind"], "quickfix");
  EXPECT_EQ(action["isPreferred"], true);
  EXPECT_EQ(action["diagnostics"][0]["code"], "UnknownParameter");
  const json& change = action["edit"]["documentChanges"][0];
  EXPECT_EQ(change["textDocument"]["version"], 1);
  EXPECT_EQ(change["edits"][0]["range"], range(3, 20, 3, 27));
  EXPECT_EQ(change["edits"][0]["newText"], "$fp_ro");

  // Elsewhere in the file, or when only refactorings are wanted: no quick fix.
  json none = c.request("textDocument/codeAction", {{"textDocument", {{"uri", kUri}}},
                                                    {"range", range(0, 0, 1, 0)},
                                                    {"context", {{"diagnostics", json::array()}}}});
  EXPECT_TRUE(none["result"].empty()) << none.dump();
  json only = c.request("textDocument/codeAction", {{"textDocument", {{"uri", kUri}}},
                                                    {"range", range(3, 22, 3, 22)},
                                                    {"context", {{"diagnostics", json::array()}, {"only", {"refactor"}}}}});
  EXPECT_TRUE(only["result"].empty()) << only.dump();

  // Applying the edit the client would apply fixes the file.
  c.change(kUri, 2, json::array({{{"range", change["edits"][0]["range"]}, {"text", "$fp_ro"}}}));
  EXPECT_TRUE(c.diagnostics(kUri, 2)["diagnostics"].empty());
}

}  // namespace
}  // namespace nomec::lsp::test
