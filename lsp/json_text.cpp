// JSON text of an outgoing message (see json_text.h).
#include "lsp/json_text.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <string_view>
#include <fmt/format.h>
#include <random>

namespace nomec::lsp {

namespace {

using json = nlohmann::json;

constexpr size_t kLong = 4096;

bool is_base64(const std::string& s) {
  static const auto kTable = [] {
    std::array<bool, 256> t{};
    for (const char ch : std::string_view("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/=")) {
      t[static_cast<unsigned char>(ch)] = true;
    }
    return t;
  }();
  bool ok = true;
  for (const char ch : s) ok &= kTable[static_cast<unsigned char>(ch)];  // no branch per character
  return ok;
}

// A marker no message text can contain by chance: a control character (written escaped as
// `\u0001`) and a random number drawn once per process.
const std::string& marker() {
  static const std::string m = [] {
    std::random_device rd;
    const uint64_t nonce = (uint64_t{rd()} << 32) ^ rd() ^
                           static_cast<uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
    return fmt::format("\x01nomec-raw-{:016x}-", nonce);
  }();
  return m;
}

// Replaces each long base64 string by the marker and its number, moving it into `lifted`.
void lift(json& j, std::vector<std::string>& lifted) {
  if (j.is_string()) {
    std::string& s = j.get_ref<std::string&>();
    if (s.size() >= kLong && is_base64(s)) {
      lifted.push_back(std::move(s));
      j = marker() + std::to_string(lifted.size() - 1);
    }
  } else if (j.is_structured()) {
    for (json& v : j) lift(v, lifted);
  }
}

}  // namespace

std::string json_text(json message) {
  std::vector<std::string> lifted;
  lift(message, lifted);
  std::string text = message.dump(-1, ' ', false, json::error_handler_t::replace);
  if (lifted.empty()) return text;
  size_t total = text.size();
  for (const std::string& s : lifted) total += s.size();
  // Each placeholder is written once, as `"\u0001nomec-raw-<nonce>-<k>"` (the marker's
  // control character escaped, the closing quote ending the number): find each, then copy
  // the text between them and the strings in their place.
  const std::string written = "\"\\u0001" + marker().substr(1);
  std::vector<std::pair<size_t, size_t>> at;  // (position, string number)
  for (size_t k = 0; k < lifted.size(); ++k) at.emplace_back(text.find(written + std::to_string(k) + "\""), k);
  std::sort(at.begin(), at.end());
  std::string out;
  out.reserve(total);
  size_t from = 0;
  for (const auto& [p, k] : at) {
    out.append(text, from, p - from);
    out += '"';
    out += lifted[k];
    out += '"';
    from = p + written.size() + std::to_string(k).size() + 1;
  }
  out.append(text, from, std::string::npos);
  return out;
}

}  // namespace nomec::lsp
