// The language server survives the unbounded inputs of issue 45 and answers the next
// request: a document that includes a FIFO, `/dev/zero` and a file past the cap (once a hang
// and a 2 GB string), one that includes itself four times (once 3.6 GB and an abort), and
// one that nests 10^12 instances (once placed one by one in the background geometry). Each
// gets its diagnostics, and a hover after it is answered.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "lsp/handler.h"
#include "lsp_client.h"

namespace nomec::lsp::test {
namespace {

namespace fs = std::filesystem;

class LspBoundedInputs : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("nomec_lsp_bounded_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    ServerOptions o = Client::test_options();
    o.geometry = true;
    client_ = std::make_unique<Client>(o);
    client_->initialize();
  }
  void TearDown() override {
    client_.reset();
    fs::remove_all(dir_);
  }

  // Writes `text` as `name` in the folder, opens it and returns the codes of its diagnostics
  // (geometry's included).
  std::vector<std::string> open(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << text;
    uri_ = path_to_uri(path);
    client_->open(uri_, text, 1);
    json d = client_->diagnostics(uri_, 1, /*with_geometry=*/true);
    std::vector<std::string> codes;
    for (const json& x : d["diagnostics"]) codes.push_back(x["code"].get<std::string>());
    return codes;
  }
  // A hover on the first line is answered (a result or null, not silence).
  void expect_answered_hover() {
    json r = client_->request("textDocument/hover", {{"textDocument", {{"uri", uri_}}}, {"position", pos(0, 3)}});
    EXPECT_TRUE(r.contains("result")) << r.dump();
  }

  fs::path dir_;
  std::unique_ptr<Client> client_;
  std::string uri_;
};

TEST_F(LspBoundedInputs, IncludesOfAFifoADeviceAndAHugeFileAreRefusedAndTheServerAnswers) {
  ASSERT_EQ(::mkfifo((dir_ / "pipe.slf").c_str(), 0600), 0);
  std::ofstream(dir_ / "huge.slf") << "x";
  fs::resize_file(dir_ / "huge.slf", std::uintmax_t{3} << 30);
  const auto codes = open("scene.nome", "point a (0 0 0) endpoint\ninclude \"pipe.slf\"\ninclude \"/dev/zero\"\n"
                                        "include \"huge.slf\"\n");
  EXPECT_EQ(codes, (std::vector<std::string>{"IncludeFailed", "IncludeFailed", "IncludeFailed"}));
  expect_answered_hover();
}

TEST_F(LspBoundedInputs, AFileThatIncludesItselfIsOneErrorAndTheServerAnswers) {
  std::string bomb;
  for (int i = 0; i < 4; ++i) bomb += "include \"bomb.nome\"\n";
  EXPECT_EQ(open("bomb.nome", bomb), std::vector<std::string>{"IncludeLimit"});
  expect_answered_hover();
}

TEST_F(LspBoundedInputs, NestedInstancesPastTheBudgetAreRefusedAndTheServerAnswers) {
  std::string text =
      "mesh tri\n  point a (0 0 0) endpoint\n  point b (1 0 0) endpoint\n  point c (0 1 0) endpoint\n"
      "  face f (a b c) endface\nendmesh\n";
  std::string below = "tri";
  for (int level = 1; level <= 12; ++level) {
    const std::string name = "g" + std::to_string(level);
    text += "group " + name + "\n";
    for (int k = 0; k < 10; ++k) text += "  instance i" + std::to_string(k) + " " + below + " endinstance\n";
    text += "endgroup\n";
    below = name;
  }
  text += "instance top " + below + " endinstance\n";
  EXPECT_EQ(open("nested.nome", text), std::vector<std::string>{"SceneTooLarge"});
  expect_answered_hover();
  json preview = client_->request("nome/preview", {{"uri", uri_}});
  EXPECT_TRUE(preview.contains("result")) << preview.dump();
}

}  // namespace
}  // namespace nomec::lsp::test
