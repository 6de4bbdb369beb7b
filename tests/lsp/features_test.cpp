// In-process JSON-RPC transcripts for the language features: quick fixes from fix-its
// (and, as the index lands, hover, definition, references, symbols, completion, …).
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

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

// The funnel cube: line 21 is `bank fp`, line 30 `funnel fun ({expr $fp_n} {expr $fp_ro} …`,
// line 43 `instance cf cubeMadeByFunnel endinstance` (0-based).
json at(int line, int character) {
  return {{"textDocument", {{"uri", kUri}}}, {"position", pos(line, character)}};
}

class FunnelCube : public ::testing::Test {
 protected:
  void SetUp() override {
    ServerOptions o = Client::test_options();
    o.geometry = true;
    client = std::make_unique<Client>(o);
    client->initialize();
    client->open(kUri, funnel_cube(), 1);
    json d = client->diagnostics(kUri, 1, /*with_geometry=*/true);
    ASSERT_TRUE(d["diagnostics"].empty()) << d.dump(2);
  }
  std::unique_ptr<Client> client;
};

TEST_F(FunnelCube, HoverOnBankUseShowsSliders) {
  json r = client->request("textDocument/hover", at(30, 20));
  const json& h = r["result"];
  ASSERT_TRUE(h.is_object()) << r.dump();
  EXPECT_EQ(h["contents"]["kind"], "markdown");
  std::string md = h["contents"]["value"];
  EXPECT_NE(md.find("bank `fp`"), std::string::npos) << md;
  EXPECT_NE(md.find("| `n` | 8 | 3 | 10 | 1 |"), std::string::npos) << md;
  EXPECT_EQ(h["range"], range(30, 19, 30, 21));
  // On blank space: no hover.
  EXPECT_TRUE(client->request("textDocument/hover", at(20, 0))["result"].is_null());
}

TEST_F(FunnelCube, HoverOnInstanceShowsGeometryFacts) {
  json r = client->request("textDocument/hover", at(43, 10));
  std::string md = r["result"]["contents"]["value"];
  EXPECT_NE(md.find("instance `cf`"), std::string::npos) << md;
  // Six funnels of n = 8 quads each, 16 vertices each; the cube spans about ±1.
  EXPECT_NE(md.find("**Geometry** (placed by this instance): 96 vertices, 48 faces"), std::string::npos) << md;
  EXPECT_NE(md.find("bounding box ("), std::string::npos) << md;
}

TEST_F(FunnelCube, DefinitionAndReferences) {
  json def = client->request("textDocument/definition", at(30, 20));
  EXPECT_EQ(def["result"]["uri"], kUri);
  EXPECT_EQ(def["result"]["range"], range(21, 5, 21, 7));
  json refs = client->request("textDocument/references",
                              {{"textDocument", {{"uri", kUri}}}, {"position", pos(30, 20)},
                               {"context", {{"includeDeclaration", true}}}});
  const json& list = refs["result"];
  ASSERT_EQ(list.size(), 11u) << list.dump();  // the bank, 4 uses in the funnel, 6 `$fp_z`
  EXPECT_EQ(list[0]["range"], range(21, 5, 21, 7));
  EXPECT_EQ(list[1]["range"], range(30, 19, 30, 21));
  EXPECT_EQ(list[2]["range"], range(30, 32, 30, 34));
  json without = client->request("textDocument/references",
                                 {{"textDocument", {{"uri", kUri}}}, {"position", pos(30, 20)},
                                  {"context", {{"includeDeclaration", false}}}});
  EXPECT_EQ(without["result"].size(), 10u);
}

TEST_F(FunnelCube, DocumentSymbolsAreHierarchical) {
  json r = client->request("textDocument/documentSymbol", {{"textDocument", {{"uri", kUri}}}});
  const json& top = r["result"];
  ASSERT_TRUE(top.is_array() && top.size() >= 4) << r.dump(2);
  EXPECT_EQ(top[0]["name"], "fp");
  EXPECT_EQ(top[0]["kind"], 3);
  ASSERT_EQ(top[0]["children"].size(), 5u);
  EXPECT_EQ(top[0]["children"][0]["name"], "n");
  EXPECT_EQ(top[0]["children"][0]["selectionRange"], range(22, 12, 22, 13));
  std::vector<std::string> names;
  for (const json& s : top) names.push_back(s["name"]);
  EXPECT_EQ(names, (std::vector<std::string>{"fp", "fun", "cubeMadeByFunnel", "cf"}));
  EXPECT_EQ(top[2]["children"].size(), 6u);  // fun1 … fun6
}

TEST_F(FunnelCube, CompletionAndSignatureHelp) {
  json r = client->request("textDocument/completion", at(30, 19));  // just after `$`
  std::vector<std::string> labels;
  for (const json& i : r["result"]["items"]) labels.push_back(i["label"]);
  EXPECT_NE(std::find(labels.begin(), labels.end(), "$fp_n"), labels.end());
  EXPECT_NE(std::find(labels.begin(), labels.end(), "$fp_ratio"), labels.end());
  json sig = client->request("textDocument/signatureHelp", at(30, 26));  // in the 2nd argument
  const json& s = sig["result"];
  EXPECT_EQ(s["signatures"][0]["label"], "funnel NAME (n ro ratio h)");
  EXPECT_EQ(s["activeParameter"], 1);
  EXPECT_EQ(s["signatures"][0]["parameters"][1]["label"], json::array({15, 17}));
}

TEST_F(FunnelCube, SemanticTokensAndFolding) {
  json r = client->request("textDocument/semanticTokens/full", {{"textDocument", {{"uri", kUri}}}});
  const json& data = r["result"]["data"];
  ASSERT_EQ(data.size() % 5, 0u);
  ASSERT_GT(data.size(), 100u);
  // Decode and find the token at line 21 `bank fp`: keyword then the bank's definition.
  uint32_t line = 0, ch = 0;
  bool saw_bank_keyword = false, saw_fp_definition = false;
  for (size_t i = 0; i < data.size(); i += 5) {
    uint32_t dl = data[i], dc = data[i + 1];
    ch = dl == 0 ? ch + dc : dc;
    line += dl;
    if (line == 21 && ch == 0 && data[i + 2] == 4 && data[i + 3] == 0) saw_bank_keyword = true;
    if (line == 21 && ch == 5 && data[i + 2] == 2 && data[i + 4] == 1) saw_fp_definition = true;
  }
  EXPECT_TRUE(saw_bank_keyword);
  EXPECT_TRUE(saw_fp_definition);
  json f = client->request("textDocument/foldingRange", {{"textDocument", {{"uri", kUri}}}});
  EXPECT_EQ(f["result"], json::parse(R"([{"startLine": 21, "endLine": 27}, {"startLine": 33, "endLine": 40}])"));
}

TEST_F(FunnelCube, RenameAndPrepareRename) {
  json p = client->request("textDocument/prepareRename", at(30, 20));
  EXPECT_EQ(p["result"]["range"], range(30, 19, 30, 21));
  EXPECT_EQ(p["result"]["placeholder"], "fp");
  json r = client->request("textDocument/rename",
                           {{"textDocument", {{"uri", kUri}}}, {"position", pos(30, 20)}, {"newName", "params"}});
  const json& change = r["result"]["documentChanges"][0];
  EXPECT_EQ(change["textDocument"]["version"], 1);
  ASSERT_EQ(change["edits"].size(), 11u) << r.dump();
  EXPECT_EQ(change["edits"][0], json({{"range", range(21, 5, 21, 7)}, {"newText", "params"}}));
  // Applying the edits (last first) leaves a file that still checks cleanly.
  json edits = change["edits"];
  json changes = json::array();
  for (auto it = edits.rbegin(); it != edits.rend(); ++it) changes.push_back({{"range", (*it)["range"]}, {"text", "params"}});
  client->change(kUri, 2, changes);
  EXPECT_TRUE(client->diagnostics(kUri, 2)["diagnostics"].empty());
  EXPECT_NE(client->server().document_text(kUri)->find("{expr $params_n}"), std::string::npos);
  // A name that is not an identifier is refused with a reason.
  json bad = client->request("textDocument/rename",
                             {{"textDocument", {{"uri", kUri}}}, {"position", pos(30, 20)}, {"newName", "1 2"}});
  EXPECT_EQ(bad["error"]["code"], -32803) << bad.dump();
}

TEST(LspFeatures, FormattingUsesTheFormatterAndSkipsUnparsableFiles) {
  Client c;
  c.initialize();
  c.open(kUri, "bank b\nset n 1 0 2 1\nendbank\n", 1);
  json r = c.request("textDocument/formatting",
                     {{"textDocument", {{"uri", kUri}}}, {"options", {{"tabSize", 4}, {"insertSpaces", true}}}});
  ASSERT_EQ(r["result"].size(), 1u) << r.dump();
  EXPECT_EQ(r["result"][0]["range"], range(0, 0, 3, 0));
  std::string formatted = r["result"][0]["newText"];
  EXPECT_NE(formatted.find("\n    set n"), std::string::npos) << formatted;
  // Already formatted: no edits.
  c.change(kUri, 2, json::array({{{"text", formatted}}}));
  json again = c.request("textDocument/formatting", {{"textDocument", {{"uri", kUri}}}, {"options", json::object()}});
  EXPECT_TRUE(again["result"].empty()) << again.dump();
  // Does not parse: no edits either.
  c.change(kUri, 3, json::array({{{"text", "bank b\n set n 1 0 2 1\n"}}}));
  json broken = c.request("textDocument/formatting", {{"textDocument", {{"uri", kUri}}}, {"options", json::object()}});
  EXPECT_TRUE(broken["result"].is_array() && broken["result"].empty()) << broken.dump();
}

}  // namespace
}  // namespace nomec::lsp::test
