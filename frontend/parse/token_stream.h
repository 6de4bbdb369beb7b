// Internal to frontend/parse: the generated parser's view of a token list. The parser reads
// only default-channel tokens, so only those become ANTLR tokens: small objects (a type,
// a byte range, a line and an index) held in one array, instead of one heap-allocated
// CommonToken with its own text per token, whitespace included. Include after the ANTLR
// headers.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "frontend/parse/tokens.h"

namespace nomec::parse_detail {

class ArenaTokenSource;

/// One token of the parser's stream. Its text is a view of the text lexed (comments
/// blanked, as the lexer saw it); its offsets are bytes.
class ArenaToken final : public antlr4::Token {
 public:
  // Rationale: 32 bytes (the index is this token's place in the stream's array, which the
  // source knows): a 1 MiB scene has about 300 000 of them.
  ArenaToken(const ArenaTokenSource* source, const Tok& t)
      : source_(source), begin_(t.begin), end_(t.end), line_(t.line), type_(t.type) {}

  std::string getText() const override;
  size_t getType() const override { return type_ == kEof ? antlr4::Token::EOF : type_; }
  size_t getLine() const override { return line_; }
  size_t getCharPositionInLine() const override { return 0; }  // not used by nomec
  size_t getChannel() const override { return antlr4::Token::DEFAULT_CHANNEL; }
  size_t getTokenIndex() const override;
  size_t getStartIndex() const override { return begin_; }
  // ANTLR's stop index is inclusive: a zero-width token stops before it starts.
  size_t getStopIndex() const override { return static_cast<size_t>(end_) - 1; }
  antlr4::TokenSource* getTokenSource() const override;
  antlr4::CharStream* getInputStream() const override { return nullptr; }
  std::string toString() const override { return getText(); }

 private:
  const ArenaTokenSource* source_;
  uint32_t begin_, end_, line_;
  uint16_t type_;
};

/// The tokens' source, which ANTLR's error recovery asks for a token factory when it
/// conjures a missing token.
class ArenaTokenSource final : public antlr4::TokenSource {
 public:
  explicit ArenaTokenSource(std::string_view lexed) : lexed_(lexed) {}
  std::unique_ptr<antlr4::Token> nextToken() override { return nullptr; }  // never read: the stream holds the tokens
  size_t getLine() const override { return 0; }
  size_t getCharPositionInLine() override { return 0; }
  antlr4::CharStream* getInputStream() override { return nullptr; }
  std::string getSourceName() override { return {}; }
  antlr4::TokenFactory<antlr4::CommonToken>* getTokenFactory() override {
    return antlr4::CommonTokenFactory::DEFAULT.get();
  }
  std::string_view lexed() const { return lexed_; }
  /// The stream's first token: a token's index is its distance from it.
  const ArenaToken* first_token = nullptr;

 private:
  std::string_view lexed_;
};

inline size_t ArenaToken::getTokenIndex() const { return static_cast<size_t>(this - source_->first_token); }

/// The parser's token stream: every default-channel token of `tokens` (which ends with a
/// kEof token), in one array. Like nomec's old watched stream, it records whether the parser
/// looked at the end before it had consumed every token (inside a statement, or further
/// ahead than the next token), or while recovering from an error: a piece of a file parsed
/// on its own is only equivalent to the same text inside the file when it did not. The
/// generated parser reads the current token's type directly (TokenArrayStream).
class ArenaTokenStream final : public nomec_antlr::TokenArrayStream {
 public:
  ArenaTokenStream(const std::vector<Tok>& tokens, std::string_view lexed);

  antlr4::Token* LT(ssize_t k) override;
  antlr4::Token* get(size_t index) const override { return const_cast<ArenaToken*>(&tokens_[index]); }
  antlr4::TokenSource* getTokenSource() const override { return const_cast<ArenaTokenSource*>(&source_); }
  std::string getText(const antlr4::misc::Interval& interval) override;
  std::string getText() override { return getText(antlr4::misc::Interval(size_t{0}, tokens_.size() - 1)); }
  std::string getText(antlr4::RuleContext* ctx) override { return getText(ctx->getSourceInterval()); }
  std::string getText(antlr4::Token* start, antlr4::Token* stop) override;

  void consume() override;
  size_t LA(ssize_t i) override;
  ssize_t mark() override { return 0; }
  void release(ssize_t) override {}
  size_t index() override { return p_; }
  void seek(size_t index) override { p_ = std::min(index, tokens_.size() - 1); }
  size_t size() override { return tokens_.size(); }
  std::string getSourceName() const override { return {}; }

  /// The last token before EOF, or null when there is none.
  const antlr4::Token* last_real() const { return tokens_.size() >= 2 ? &tokens_[tokens_.size() - 2] : nullptr; }
  /// The type of the first token (EOF when there is none).
  size_t first_type() const { return tokens_.front().getType(); }

  antlr4::Parser* parser_ = nullptr;
  bool eof_seen_early_ = false;

 private:
  bool all_consumed() const;

  ArenaTokenSource source_;
  std::vector<ArenaToken> tokens_;
  std::vector<uint16_t> codes_storage_;  // each token's type for the parser's direct reads (codes_)
};

/// The grammar's token vocabulary (literal and symbolic names by token type), read from a
/// parser, which is cheap to make: a NomeLexer would build the lexer's ATN, which nomec
/// needs only for the lexer's reference (grammar/lazy_lexer.cmake). The lexer's vocabulary
/// is the same (one grammar; the lexer diff tests compare their tokens).
const antlr4::dfa::Vocabulary& grammar_vocabulary();

}  // namespace nomec::parse_detail
