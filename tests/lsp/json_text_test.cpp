// Outgoing JSON text (lsp/json_text.h): exactly nlohmann-json's text, with long base64
// strings copied in rather than escaped; base64 encoding of the geometry.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <random>
#include <string>

#include "lsp/json_text.h"
#include "lsp/preview.h"

namespace nomec::lsp {
namespace {

using json = nlohmann::json;

std::string dumped(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

std::string random_base64(size_t bytes, uint32_t seed) {
  std::mt19937 rng(seed);
  std::string raw(bytes, '\0');
  for (char& c : raw) c = static_cast<char>(rng());
  return base64(raw.data(), raw.size());
}

TEST(JsonText, SameTextAsNlohmannWithLongBase64Strings) {
  json m = json::object();
  m["jsonrpc"] = "2.0";
  m["id"] = 7;
  json out = json::object();
  out["name"] = "klein \"bottle\"\n\x01nomec-raw-0000000000000000-0";  // escapes and a look-alike marker
  out["geometry"] = {{"positions", random_base64(30000, 1)}, {"triangles", random_base64(5000, 2)},
                     {"short", random_base64(30, 3)}};
  json other = out;
  other["geometry"]["positions"] = random_base64(20000, 4);  // the order of the strings matters
  m["result"] = {{"outputs", json::array({out, other})},
                 {"meshes", json::array({{{"euler", 0}, {"orientable", false}}})},
                 {"long_text", std::string(5000, 'x') + " not base64"},
                 {"bad_utf8", std::string("\xff\xfe ok")}};
  const std::string want = dumped(m);
  const std::string got = json_text(m);
  EXPECT_EQ(got, want);
  EXPECT_TRUE(json::parse(got) == json::parse(want));  // (invalid UTF-8 is replaced in both)
}

TEST(JsonText, MessagesWithoutLongStringsAreUntouched) {
  const json m = {{"jsonrpc", "2.0"}, {"method", "textDocument/publishDiagnostics"},
                  {"params", {{"uri", "file:///a.nome"}, {"diagnostics", json::array({{{"message", "é ∞ \t"}}})}}}};
  EXPECT_EQ(json_text(m), dumped(m));
}

TEST(JsonText, Base64MatchesTheStandardAlphabetAndPadding) {
  EXPECT_EQ(base64("", 0), "");
  EXPECT_EQ(base64("f", 1), "Zg==");
  EXPECT_EQ(base64("fo", 2), "Zm8=");
  EXPECT_EQ(base64("foo", 3), "Zm9v");
  EXPECT_EQ(base64("foob", 4), "Zm9vYg==");
  EXPECT_EQ(base64("fooba", 5), "Zm9vYmE=");
  EXPECT_EQ(base64("foobar", 6), "Zm9vYmFy");
  const unsigned char all[] = {0x00, 0xff, 0xfe, 0x10, 0x83};
  EXPECT_EQ(base64(all, sizeof all), "AP/+EIM=");
}

}  // namespace
}  // namespace nomec::lsp
