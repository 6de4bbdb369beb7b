// In-process JSON-RPC transcripts for the protocol core: lifecycle and error codes,
// diagnostics on open and after full and incremental changes (UTF-16 ranges, CRLF),
// stale versions, close, cancellation, and background geometry diagnostics.
#include <gtest/gtest.h>

#include "lsp_client.h"

namespace nomec::lsp::test {
namespace {

const char* kUri = "file:///tmp/lsp-test/funnel_cube.nome";

TEST(LspProtocol, LifecycleAndErrorCodes) {
  Client c;
  json early = c.request("textDocument/hover", {{"textDocument", {{"uri", kUri}}}, {"position", pos(0, 0)}});
  EXPECT_EQ(early["error"]["code"], -32002);

  json init = c.initialize();
  ASSERT_TRUE(init.contains("result")) << init.dump();
  const json& caps = init["result"]["capabilities"];
  EXPECT_EQ(caps["textDocumentSync"]["change"], 2);
  EXPECT_EQ(caps["positionEncoding"], "utf-16");
  EXPECT_EQ(init["result"]["serverInfo"]["name"], "nomec");

  EXPECT_EQ(c.request("initialize", {{"capabilities", json::object()}})["error"]["code"], -32600);
  EXPECT_EQ(c.request("nome/noSuchMethod")["error"]["code"], -32601);
  size_t before = c.messages().size();
  c.notify("nome/noSuchNotification");
  c.notify("$/setTrace", {{"value", "off"}});
  c.server().wait_idle();
  EXPECT_EQ(c.messages().size(), before) << "notifications are never answered";

  c.send_raw("{\"jsonrpc\": \"2.0\", \"id\": 77, \"method\": ");
  c.send_raw("[1, 2]");
  c.send_raw("{\"jsonrpc\": \"2.0\", \"id\": 78, \"method\": 5}");
  c.send_raw("{\"jsonrpc\": \"2.0\", \"id\": [1], \"method\": \"shutdown\"}");
  c.server().wait_idle();
  EXPECT_EQ(c.count_errors(-32700), 1u);
  EXPECT_EQ(c.count_errors(-32600), 4u);  // 2nd initialize, array, method type, id type
  EXPECT_EQ(c.wait_response(78)["error"]["code"], -32600);

  // Wrong parameter types are InvalidParams, not a crash.
  json bad = c.request("textDocument/codeAction", {{"textDocument", {{"uri", 5}}}});
  EXPECT_EQ(bad["error"]["code"], -32602);

  json sd = c.request("shutdown");
  EXPECT_TRUE(sd.contains("result") && sd["result"].is_null()) << sd.dump();
  EXPECT_EQ(c.request("textDocument/codeAction", json::object())["error"]["code"], -32600);
  EXPECT_FALSE(c.server().exit_requested());
  c.notify("exit");
  c.server().wait_idle();
  EXPECT_TRUE(c.server().exit_requested());
  EXPECT_EQ(c.server().exit_code(), 0);
}

TEST(LspProtocol, ExitWithoutShutdownIsExitCodeOne) {
  Client c;
  c.initialize();
  c.notify("exit");
  c.server().wait_idle();
  EXPECT_TRUE(c.server().exit_requested());
  EXPECT_EQ(c.server().exit_code(), 1);
}

TEST(LspProtocol, DiagnosticsOnOpenAndAfterChanges) {
  Client c;
  c.initialize();
  std::string text = funnel_cube();
  c.open(kUri, text, 1);
  json d1 = c.diagnostics(kUri, 1);
  EXPECT_EQ(d1["version"], 1);
  EXPECT_TRUE(d1["diagnostics"].empty()) << d1.dump(2);

  // Line 30 (0-based) is `funnel fun ({expr $fp_n} {expr $fp_ro} …`; misspell `$fp_ro`.
  size_t at = text.find("{expr $fp_ro}");
  ASSERT_NE(at, std::string::npos);
  int line = static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
  int col = static_cast<int>(at - text.rfind('\n', at) - 1) + 6;  // start of `$fp_ro`
  c.change(kUri, 2, json::array({{{"range", range(line, col + 5, line, col + 5)}, {"text", "h"}}}));
  json d2 = c.diagnostics(kUri, 2);
  ASSERT_EQ(d2["diagnostics"].size(), 1u) << d2.dump(2);
  const json& diag = d2["diagnostics"][0];
  EXPECT_EQ(diag["code"], "UnknownParameter");
  EXPECT_EQ(diag["severity"], 1);
  EXPECT_EQ(diag["source"], "nomec");
  EXPECT_EQ(diag["range"], range(line, col, line, col + 7));
  EXPECT_NE(diag["message"].get<std::string>().find("$fp_ro"), std::string::npos);

  // Fix it again with an incremental deletion of the `h`.
  c.change(kUri, 3, json::array({{{"range", range(line, col + 5, line, col + 6)}, {"text", ""}}}));
  EXPECT_TRUE(c.diagnostics(kUri, 3)["diagnostics"].empty());
  EXPECT_EQ(c.server().document_text(kUri), text);

  // A full-text change (no range) replaces everything.
  c.change(kUri, 4, json::array({{{"text", "instance x nosuch endinstance\n"}}}));
  json d4 = c.diagnostics(kUri, 4);
  ASSERT_EQ(d4["diagnostics"].size(), 1u) << d4.dump(2);
  EXPECT_EQ(d4["diagnostics"][0]["code"], "UnknownName");
  EXPECT_EQ(d4["diagnostics"][0]["range"], range(0, 11, 0, 17));
}

// `initializationOptions.dialect` (the editor's `nome.dialect` setting) checks every file as
// that dialect; "auto" keeps detection from content. `2^3^2` reads differently only in NOME3.
TEST(LspProtocol, DialectFromInitializationOptions) {
  const std::string text = "point p ({2^3^2} 0 0) endpoint\n";
  auto codes = [&](const json& init) {
    Client c;
    c.initialize(init);
    c.open(kUri, text, 1);
    std::vector<std::string> out;
    const json published = c.diagnostics(kUri, 1);
    for (const json& d : published["diagnostics"]) out.push_back(d["code"].get<std::string>());
    if (out.empty()) out.push_back(published.dump());
    return out;
  };
  EXPECT_EQ(codes({{"dialect", "nome3"}}), std::vector<std::string>{"PowerAssociativity"});
  const std::vector<std::string> none{R"({"diagnostics":[],"uri":"file:///tmp/lsp-test/funnel_cube.nome","version":1})"};
  EXPECT_EQ(codes({{"dialect", "auto"}}), none);  // a `.nome` file with no signal: nome
  EXPECT_EQ(codes(json::object()), none);
}

TEST(LspProtocol, StaleAndOutOfOrderVersionsAreIgnored) {
  Client c;
  c.initialize();
  c.open(kUri, "bank b\n  set n 1 0 2 1\nendbank\n", 5);
  c.diagnostics(kUri, 5);
  // Versions 5 (same) and 3 (older) were made against other texts: ignored.
  c.change(kUri, 5, json::array({{{"range", range(0, 0, 0, 0)}, {"text", "garbage ("}}}));
  c.change(kUri, 3, json::array({{{"range", range(0, 0, 0, 0)}, {"text", "garbage ("}}}));
  c.server().wait_idle();
  EXPECT_EQ(c.server().document_text(kUri), "bank b\n  set n 1 0 2 1\nendbank\n");
  c.change(kUri, 6, json::array({{{"range", range(1, 8, 1, 9)}, {"text", "5"}}}));
  json d = c.diagnostics(kUri, 6);
  EXPECT_EQ(c.server().document_text(kUri), "bank b\n  set n 5 0 2 1\nendbank\n");
  ASSERT_EQ(d["version"], 6);
  ASSERT_FALSE(d["diagnostics"].empty());
  EXPECT_EQ(d["diagnostics"][0]["code"], "ValueOutOfRange") << d.dump(2);
}

TEST(LspProtocol, Utf16RangesAndCrLf) {
  Client c;
  c.initialize();
  // A comment with non-BMP and accented characters before the error on the same line,
  // CRLF line ends throughout.
  std::string text = "# ok\r\n(* é😀 *) instance x nosuch endinstance\r\n";
  c.open(kUri, text, 1);
  json d = c.diagnostics(kUri, 1);
  ASSERT_EQ(d["diagnostics"].size(), 1u) << d.dump(2);
  // `(* é😀 *) instance x ` is 3 + 1 + 2 + 4 + 11 units: `nosuch` starts at character 21.
  EXPECT_EQ(d["diagnostics"][0]["range"], range(1, 21, 1, 27));
  // Edit the identifier through UTF-16 positions: replace `nosuch` with `y`.
  c.change(kUri, 2, json::array({{{"range", range(1, 21, 1, 27)}, {"text", "y"}}}));
  c.diagnostics(kUri, 2);
  EXPECT_EQ(c.server().document_text(kUri), "# ok\r\n(* é😀 *) instance x y endinstance\r\n");
}

// A byte order mark is skipped by the check (it was an unexpected character). VS Code hides
// the mark of a file it opens ("UTF-8 with BOM") and sends the text without it, so its
// positions start after it; a client that sends the mark (U+FEFF) counts it as one UTF-16
// unit of line 0, and so does the server: positions are always in the text as received.
TEST(LspProtocol, ByteOrderMarkIsSkippedAndPositionsFollowTheText) {
  Client c;
  c.initialize();
  c.open(kUri, "instance x nosuch endinstance\n", 1);  // as VS Code sends a file with a mark
  json without = c.diagnostics(kUri, 1);
  ASSERT_EQ(without["diagnostics"].size(), 1u) << without.dump(2);
  EXPECT_EQ(without["diagnostics"][0]["range"], range(0, 11, 0, 17));
  const std::string other = "file:///tmp/lsp-test/bom.nome";
  c.open(other, "\xEF\xBB\xBFinstance x nosuch endinstance\npoint p (1 2 3) endpoint\n", 1);
  json with = c.diagnostics(other, 1);
  ASSERT_EQ(with["diagnostics"].size(), 1u) << with.dump(2);  // only the unknown name
  EXPECT_EQ(with["diagnostics"][0]["code"], "UnknownName");
  EXPECT_EQ(with["diagnostics"][0]["range"], range(0, 12, 0, 18));
  // An edit at those positions lands on `nosuch`.
  c.change(other, 2, json::array({{{"range", range(0, 12, 0, 18)}, {"text", "y"}}}));
  c.diagnostics(other, 2);
  EXPECT_EQ(c.server().document_text(other), "\xEF\xBB\xBFinstance x y endinstance\npoint p (1 2 3) endpoint\n");
}

TEST(LspProtocol, CloseClearsDiagnosticsAndForgetsTheDocument) {
  Client c;
  c.initialize();
  c.open(kUri, "instance x nosuch endinstance\n", 1);
  EXPECT_EQ(c.diagnostics(kUri, 1)["diagnostics"].size(), 1u);
  c.notify("textDocument/didClose", {{"textDocument", {{"uri", kUri}}}});
  c.server().wait_idle();
  EXPECT_FALSE(c.server().document_text(kUri).has_value());
  json last = c.messages().back();
  EXPECT_EQ(last["method"], "textDocument/publishDiagnostics");
  EXPECT_TRUE(last["params"]["diagnostics"].empty());
  json r = c.request("textDocument/codeAction",
                     {{"textDocument", {{"uri", kUri}}}, {"range", range(0, 0, 0, 0)}, {"context", json::object()}});
  EXPECT_EQ(r["error"]["code"], -32602);
}

// A scene big enough that checking it takes a while, so requests wait on it.
std::string big_scene(int banks) {
  std::string s;
  for (int i = 0; i < banks; ++i) {
    std::string b = "b" + std::to_string(i);
    s += "bank " + b + "\n  set n 4 3 10 1\n  set r 1.5 0.5 3 0.1\nendbank\n";
    s += "funnel f" + std::to_string(i) + " ({expr $" + b + "_n} {expr $" + b + "_r} 0.2 0.5) endfunnel\n";
    s += "instance i" + std::to_string(i) + " f" + std::to_string(i) + " translate (" + std::to_string(i) +
         " 0 0) endinstance\n";
  }
  return s;
}

TEST(LspProtocol, CancelledRequestsStop) {
  Client c;
  c.initialize();
  c.open(kUri, big_scene(2500), 1);  // ~400 KB: the check takes much longer than the messages below
  json params = {{"textDocument", {{"uri", kUri}}}, {"range", range(0, 0, 0, 0)}, {"context", json::object()}};
  int running = c.send_request("textDocument/codeAction", params);  // waits for the check
  int queued = c.send_request("textDocument/codeAction", params);
  c.notify("$/cancelRequest", {{"id", queued}});
  c.notify("$/cancelRequest", {{"id", running}});
  c.notify("$/cancelRequest", {{"id", 12345}});  // unknown ids are ignored
  json r1 = c.wait_response(running);
  json r2 = c.wait_response(queued);
  EXPECT_EQ(r1["error"]["code"], -32800) << r1.dump();
  EXPECT_EQ(r2["error"]["code"], -32800) << r2.dump();
  // Both answers came before the check finished (it publishes when done).
  std::vector<json> ms = c.messages();
  size_t answered = 0, published = ms.size();
  for (size_t i = 0; i < ms.size(); ++i) {
    if (ms[i].value("id", json()) == running) answered = i;
    if (ms[i].value("method", "") == "textDocument/publishDiagnostics" && published == ms.size()) published = i;
  }
  EXPECT_LT(answered, published);
  // The cancelled request did not wait for the analysis: nothing was published yet,
  // and the server still answers afterwards.
  json r3 = c.request("textDocument/codeAction", params);
  EXPECT_TRUE(r3["result"].is_array()) << r3.dump();
}

TEST(LspProtocol, GeometryDiagnosticsFromTheBackgroundEvaluation) {
  ServerOptions o = Client::test_options();
  o.geometry = true;
  Client c(o);
  c.initialize();
  std::string text =
      "mesh fan\n"
      "    point a (0 0 0) endpoint\n    point b (1 0 0) endpoint\n    point c (0 1 0) endpoint\n"
      "    point d (0 -1 0) endpoint\n    point e (0 0 1) endpoint\n"
      "    face f1 (a b c) endface\n    face f2 (b a d) endface\n    face f3 (a b e) endface\n"
      "endmesh\n"
      "instance outer fan endinstance\n";
  c.open(kUri, text, 1);
  json d = c.diagnostics(kUri, 1, /*with_geometry=*/true);
  ASSERT_EQ(d["diagnostics"].size(), 1u) << d.dump(2);
  const json& g = d["diagnostics"][0];
  EXPECT_EQ(g["code"], "NonManifoldGeometry");
  EXPECT_EQ(g["range"], range(6, 4, 6, 27));
  ASSERT_EQ(g["relatedInformation"].size(), 2u);
  EXPECT_EQ(g["relatedInformation"][0]["location"]["range"], range(7, 4, 7, 27));
  EXPECT_EQ(g["relatedInformation"][0]["location"]["uri"], kUri);

  // Removing the third face fixes the geometry; the next publication drops the error.
  c.change(kUri, 2, json::array({{{"range", range(8, 0, 9, 0)}, {"text", ""}}}));
  json d2 = c.diagnostics(kUri, 2, true);
  EXPECT_TRUE(d2["diagnostics"].empty()) << d2.dump(2);
}

}  // namespace
}  // namespace nomec::lsp::test
