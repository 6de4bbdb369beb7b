// JSON text of an outgoing message (see json_text.h).
#include "lsp/json_text.h"

#include <array>
#include <chrono>
#include <string_view>
#include <functional>
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

// Replaces each long base64 string by the marker and its number, in the order nlohmann-json
// writes values (object members by key, array elements in order), moving it into `lifted`.
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
  std::string out;
  out.reserve(total);
  // The marker's control character is written `\u0001`; the rest of it is plain text.
  const std::string written = "\"\\u0001" + marker().substr(1);
  size_t at = 0;
  for (size_t k = 0; k < lifted.size(); ++k) {
    const std::string placeholder = written + std::to_string(k) + "\"";
    const size_t p = text.find(placeholder, at);
    if (p == std::string::npos) {
      // Not where the order says (cannot happen with nlohmann-json's writer): put the strings
      // back and write the message the slow way.
      std::vector<std::string>::size_type i = 0;
      std::function<void(json&)> restore = [&](json& v) {
        if (v.is_string() && v.get_ref<std::string&>().rfind(marker(), 0) == 0) {
          v = std::move(lifted[i++]);
        } else if (v.is_structured()) {
          for (json& c : v) restore(c);
        }
      };
      restore(message);
      return message.dump(-1, ' ', false, json::error_handler_t::replace);
    }
    out.append(text, at, p - at);
    out += '"';
    out += lifted[k];
    out += '"';
    at = p + placeholder.size();
  }
  out.append(text, at, std::string::npos);
  return out;
}

}  // namespace nomec::lsp
