// JSON text of an outgoing message. The preview's replies carry geometry as long base64
// strings (hundreds of kilobytes for a subdivided, offset Klein bottle); nlohmann-json's
// writer checks and escapes such a string character by character, which took more of a
// slider move than evaluating the scene. Here long base64 strings are lifted out, the rest is
// written by nlohmann-json, and the strings are copied in whole: the same text, faster.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace nomec::lsp {

/// `message.dump(-1, ' ', false, error_handler_t::replace)`, with strings of 4096 or more
/// base64 characters copied in instead of escaped (they need no escaping).
std::string json_text(nlohmann::json message);

}  // namespace nomec::lsp
