// The language server re-parses only what an edit touched: each open document keeps a
// ParseCache, so a one-character edit in a large document re-parses one top-level piece,
// and the diagnostics it publishes equal those of a fresh check of the same text.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>

#include "lsp_client.h"

namespace nomec::lsp::test {
namespace {

// `count` independent top-level statements: a mesh with points and a face per module.
std::string large_document(int count) {
  std::string out;
  for (int k = 0; k < count; ++k) {
    std::string n = std::to_string(k);
    out += "mesh m" + n + "\n";
    out += "  point a (0 0 " + n + ") endpoint\n";
    out += "  point b (1 0 " + n + ") endpoint\n";
    out += "  point c (0 1 " + n + ") endpoint\n";
    out += "  face f (a b c) endface\n";
    out += "endmesh\n";
  }
  return out;
}

// Waits until the server's background threads (the cache fill, the index) are done.
void wait_background(const Server& server) {
  auto deadline = std::chrono::steady_clock::now() + Client::kHungServer;
  while (server.background_busy() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// Replaces the character at (line, character) with `c`, as an editor's incremental change.
json replace_char(int line, int character, const std::string& c) {
  return json::array({{{"range", range(line, character, line, character + 1)}, {"text", c}}});
}

TEST(LspIncremental, OneCharacterEditReparsesOnePieceAndMatchesAFreshCheck) {
  Client c;
  c.initialize();
  const std::string uri = "file:///tmp/lsp-test/large.nome";
  const int modules = 400;
  std::string text = large_document(modules);
  c.open(uri, text, 1);
  EXPECT_TRUE(c.diagnostics(uri, 1)["diagnostics"].empty());
  // didOpen parses the text in one piece; the after thread fills the cache once it is parsed.
  std::optional<ParseStats> first = c.server().parse_stats(uri);
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->pieces, 1u);
  EXPECT_EQ(first->parsed_bytes, text.size());
  wait_background(c.server());

  // Line 6*200+1 is `  point a (0 0 200) endpoint`: change the value 200 to 900.
  const int line = 6 * 200 + 1;
  c.change(uri, 2, replace_char(line, 15, "9"));
  EXPECT_TRUE(c.diagnostics(uri, 2)["diagnostics"].empty());
  std::optional<ParseStats> s = c.server().parse_stats(uri);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->parsed, 1u);
  EXPECT_GE(s->pieces, static_cast<size_t>(modules));
  EXPECT_LT(s->parsed_bytes, 200u);

  // A name edit that makes an error: face f (a b c) -> (a x c) in module 300.
  const int face_line = 6 * 300 + 4;
  c.change(uri, 3, replace_char(face_line, 12, "x"));
  json edited = c.diagnostics(uri, 3)["diagnostics"];
  s = c.server().parse_stats(uri);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->parsed, 1u);
  ASSERT_FALSE(edited.empty());

  // The same text opened fresh (its own, empty cache) gets the same diagnostics.
  std::optional<std::string> now = c.server().document_text(uri);
  ASSERT_TRUE(now.has_value());
  EXPECT_NE(now->find("point a (0 0 900) endpoint"), std::string::npos);
  const std::string fresh_uri = "file:///tmp/lsp-test/large.nome";  // same path: same messages
  c.notify("textDocument/didClose", {{"textDocument", {{"uri", uri}}}});
  c.open(fresh_uri, *now, 10);
  json fresh = c.diagnostics(fresh_uri, 10)["diagnostics"];
  std::optional<ParseStats> f = c.server().parse_stats(fresh_uri);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->parsed, f->pieces);  // the reopened document is parsed afresh, in one piece
  EXPECT_EQ(f->pieces, 1u);
  EXPECT_EQ(edited, fresh);
}

// Polls `releases` until it reaches `want` (false after two minutes).
bool wait_releases(const Server& server, size_t want) {
  auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  while (server.memory_releases() < want) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

// Freed memory is kept while the user types (tools/allocator.h) and returned once no
// document was re-checked for `idle_release_ms`: once per pause, not on a timer.
TEST(LspMemory, FreedMemoryIsReturnedOnceAfterEachPause) {
  ServerOptions o = Client::test_options();
  o.idle_release_ms = 40;
  Client c(o);
  c.initialize();
  EXPECT_EQ(c.server().memory_releases(), 0u);  // nothing analysed, nothing freed yet
  const std::string uri = "file:///tmp/lsp-test/memory.nome";
  c.open(uri, large_document(50), 1);
  c.diagnostics(uri, 1);
  ASSERT_TRUE(wait_releases(c.server(), 1));
  // No new work, no new release, however long the pause.
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(c.server().memory_releases(), 1u);
  // An edit frees the previous analysis: one more release after the next pause.
  c.change(uri, 2, replace_char(1, 18, "7"));
  c.diagnostics(uri, 2);
  ASSERT_TRUE(wait_releases(c.server(), 2));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(c.server().memory_releases(), 2u);
}

TEST(LspMemory, ZeroIdleTimeNeverReleases) {
  ServerOptions o = Client::test_options();
  o.idle_release_ms = 0;
  Client c(o);
  c.initialize();
  const std::string uri = "file:///tmp/lsp-test/memory.nome";
  c.open(uri, large_document(10), 1);
  c.diagnostics(uri, 1);
  c.change(uri, 2, replace_char(1, 18, "7"));
  c.diagnostics(uri, 2);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(c.server().memory_releases(), 0u);
}

// The nice value of each of this process's threads, by thread name (/proc/self/task).
std::map<std::string, int> thread_nice_by_name() {
  std::map<std::string, int> out;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream comm(task.path() / "comm"), stat(task.path() / "stat");
    std::string name, line;
    std::getline(comm, name);
    std::getline(stat, line);
    const size_t close = line.rfind(')');
    if (name.empty() || close == std::string::npos) continue;
    std::istringstream fields(line.substr(close + 2));  // from field 3, the state
    std::string field;
    for (int i = 3; i <= 19 && fields >> field; ++i) {
      if (i == 19) out[name] = std::stoi(field);  // field 19: nice
    }
  }
  return out;
}

// The background threads yield the processor to the analysis thread, whose diagnostics the
// sculptor waits for: they run `kBackgroundNice` lower; the others keep the process's own.
TEST(LspThreads, BackgroundThreadsRunBelowTheAnalysisThread) {
  Client c;
  c.initialize();
  const std::string uri = "file:///tmp/lsp-test/threads.nome";
  c.open(uri, large_document(20), 1);
  c.diagnostics(uri, 1);
  const int base = thread_nice_by_name().at("nomec-analysis");
  const int want = std::min(19, base + kBackgroundNice);  // nice values stop at 19
  std::map<std::string, int> nice;
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  do {  // each thread sets its own name and priority when it starts
    nice = thread_nice_by_name();
  } while ((nice["nomec-after"] != want || nice["nomec-geometry"] != want) && std::chrono::steady_clock::now() < deadline);
  EXPECT_EQ(nice["nomec-after"], want);
  EXPECT_EQ(nice["nomec-geometry"], want);
  EXPECT_EQ(nice["nomec-request"], base);
  EXPECT_EQ(nice["nomec-analysis"], base);
}

}  // namespace
}  // namespace nomec::lsp::test
