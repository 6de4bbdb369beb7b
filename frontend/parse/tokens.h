// Internal to frontend/parse: the token list between the lexer and the parser. Both lexers
// (the hand-written one in lexer.cpp, and ANTLR's generated NomeLexer kept as the reference
// and the fallback) produce it; the token passes (token_passes.cpp) retype and insert tokens
// in it; token_stream.h hands its default-channel tokens to the generated parser.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "frontend/diagnostics/diagnostic.h"

namespace nomec::parse_detail {

/// The type of the end-of-text token (ANTLR's EOF in the parser's stream).
inline constexpr uint16_t kEof = 0xFFFF;

/// One token: its type (the generated lexer's token types), its byte range in the text
/// parsed and its line. Whitespace and comments are hidden-channel tokens.
struct Tok {
  uint32_t begin = 0;  // byte offset of the first byte
  uint32_t end = 0;    // byte offset past the last byte (== begin for a token inserted by a pass)
  uint32_t line = 1;   // 1-based, counted in `\n`s like the generated lexer
  uint16_t type = 0;
  bool hidden = false;  // whitespace, comments, no-break spaces
  bool operator==(const Tok&) const = default;
};

/// What a lexer made of a text.
struct Lexed {
  std::vector<Tok> tokens;  // in text order, without an EOF token
  /// The start of the first token whose lexing looked at the end of the text (a piece of a
  /// file lexed on its own is only equivalent to the same text inside the file when nothing
  /// but its trailing whitespace did); SIZE_MAX when none did.
  size_t eof_touch_start = static_cast<size_t>(-1);
  /// An unclosed `(*` comment was reported.
  bool comment_open = false;
  /// The last token lexed, even when not kept in `tokens` (type kEof when there is none).
  Tok last{0, 0, 0, kEof, false};
  /// Set by the caller before lexing: whitespace and line comments are not kept in `tokens`
  /// (the parser and the token passes skip them; no-break spaces are kept, the token pass
  /// reports them). A 1 MiB scene has about 200 000 of them.
  bool drop_whitespace = false;
};

/// Nested `(* … *)` comments are blanked before lexing (each byte but `\n` becomes a space,
/// so offsets do not move); an unclosed one is reported at its opening into `diags`.
/// Returns the text to lex: `text` itself when it has no `(*`, else `storage`.
std::string_view blank_block_comments(std::string_view text, std::string& storage, FileId file,
                                      DiagnosticEngine& diags, bool& comment_open);

/// The hand-written lexer: the tokens of `text` (already blanked), exactly those ANTLR's
/// NomeLexer gives for it (tests/unit/lexer_diff_test.cpp compares them on every corpus
/// file, example, golden input, fuzzer corpus input and generated input). Returns false,
/// leaving `out` unspecified, for the two things it leaves to NomeLexer, which no real file
/// holds: a `(*` that blanking did not remove (behind a `#` comment ended by a lone `\r`,
/// or inside a string with an escaped quote), and overlong UTF-8 forms (which the input
/// decoder reads as the ASCII characters they encode).
bool lex_fast(std::string_view blanked, Lexed& out);

/// The reference lexer: ANTLR's NomeLexer over `blanked`, its code-point offsets mapped to
/// byte offsets.
void lex_antlr(std::string_view blanked, Lexed& out);

/// Blanks comments and lexes `text` with the fast lexer, falling back to NomeLexer. The
/// blanked text is put in `blanked_storage` when it differs from `text` (tokens' texts are
/// read from it).
Lexed lex_text(std::string_view text, FileId file, DiagnosticEngine& comment_diags, std::string& blanked_storage,
               bool drop_whitespace = false);

/// Lexes `text` as it is (a function text: no comment blanking), fast lexer first.
Lexed lex_unblanked(std::string_view text);

/// For the differential tests: while set (on this thread), every parse lexes with NomeLexer
/// instead of the hand-written lexer.
void use_reference_lexer(bool on);
/// Whether `use_reference_lexer` is set on this thread.
bool reference_lexer_in_use();

}  // namespace nomec::parse_detail
