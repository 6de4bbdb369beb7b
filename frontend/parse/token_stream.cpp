// The generated parser's token stream over the token list (token_stream.h).
#include "frontend/parse/generated.h"

#include "frontend/parse/token_stream.h"

namespace nomec::parse_detail {

std::string ArenaToken::getText() const {
  const std::string_view text = source_->lexed();
  if (type_ == kEof) return "<EOF>";
  if (end_ > begin_) return std::string(text.substr(begin_, end_ - begin_));
  // A zero-width token a pass inserted: as ANTLR's CommonToken over the input reads it.
  return begin_ >= 1 && begin_ < text.size() ? std::string() : std::string("<EOF>");
}

antlr4::TokenSource* ArenaToken::getTokenSource() const { return const_cast<ArenaTokenSource*>(source_); }

ArenaTokenStream::ArenaTokenStream(const std::vector<Tok>& tokens, std::string_view lexed) : source_(lexed) {
  size_t count = 0;
  for (const Tok& t : tokens) count += t.hidden ? 0 : 1;
  tokens_.reserve(count);
  source_.first_token = tokens_.data();  // the array is not moved once filled
  for (const Tok& t : tokens) {
    if (!t.hidden) tokens_.emplace_back(&source_, t);
  }
  codes_storage_.reserve(tokens_.size());
  for (const ArenaToken& t : tokens_) {
    codes_storage_.push_back(t.getType() == antlr4::Token::EOF ? kEnd : static_cast<uint16_t>(t.getType()));
  }
  codes_ = codes_storage_.data();
  token_bytes_ = reinterpret_cast<char*>(static_cast<antlr4::Token*>(tokens_.data()));
  stride_ = sizeof(ArenaToken);
}

antlr4::Token* ArenaTokenStream::LT(ssize_t k) {
  if (k == 0) return nullptr;
  if (k < 0) {
    const auto back = static_cast<size_t>(-k);
    return back > p_ ? nullptr : &tokens_[p_ - back];
  }
  const size_t i = std::min(p_ + static_cast<size_t>(k) - 1, tokens_.size() - 1);
  ArenaToken* t = &tokens_[i];
  if (t->getType() == antlr4::Token::EOF && parser_ != nullptr && !eof_seen_early_ &&
      (!all_consumed() || parser_->getErrorHandler()->inErrorRecoveryMode(parser_))) {
    eof_seen_early_ = true;
  }
  return t;
}

size_t ArenaTokenStream::LA(ssize_t i) {
  antlr4::Token* t = LT(i);
  return t != nullptr ? t->getType() : antlr4::Token::INVALID_TYPE;
}

void ArenaTokenStream::consume() {
  if (tokens_[p_].getType() == antlr4::Token::EOF) {
    (void)LT(1);  // the lookahead watch sees the attempt
    throw antlr4::IllegalStateException("cannot consume EOF");
  }
  ++p_;
  ++consumed_;
}

std::string ArenaTokenStream::getText(const antlr4::misc::Interval& interval) {
  if (interval.a < 0 || interval.b < 0) return {};
  std::string out;
  const size_t last = std::min(static_cast<size_t>(interval.b), tokens_.size() - 1);
  for (size_t i = static_cast<size_t>(interval.a); i <= last; ++i) {
    if (tokens_[i].getType() == antlr4::Token::EOF) break;
    out += tokens_[i].getText();
  }
  return out;
}

std::string ArenaTokenStream::getText(antlr4::Token* start, antlr4::Token* stop) {
  if (start == nullptr || stop == nullptr) return {};
  return getText(antlr4::misc::Interval(start->getTokenIndex(), stop->getTokenIndex()));
}

// The end was seen at the top level with nothing left to read: `file` matched EOF, or its
// last statement ends with the last token.
bool ArenaTokenStream::all_consumed() const {
  antlr4::ParserRuleContext* ctx = parser_->getContext();
  if (ctx == nullptr || ctx->getRuleIndex() != nomec_antlr::NomeParser::RuleFile) return false;
  const antlr4::Token* last = last_real();
  if (last == nullptr) return true;
  if (ctx->children.empty()) return false;
  antlr4::tree::ParseTree* child = ctx->children.back();
  if (auto* term = dynamic_cast<antlr4::tree::TerminalNode*>(child);
      term != nullptr && term->getSymbol()->getType() == antlr4::Token::EOF) {
    return true;
  }
  if (auto* rule = dynamic_cast<antlr4::ParserRuleContext*>(child)) return rule->stop == last;
  if (auto* term = dynamic_cast<antlr4::tree::TerminalNode*>(child)) return term->getSymbol() == last;
  return false;
}

const antlr4::dfa::Vocabulary& grammar_vocabulary() {
  static const antlr4::dfa::Vocabulary* const vocabulary = [] {
    const std::vector<Tok> no_tokens;
    ArenaTokenStream empty(no_tokens, "");
    nomec_antlr::NomeParser parser(&empty);
    return &parser.getVocabulary();  // the generated parser's static vocabulary
  }();
  return *vocabulary;
}

}  // namespace nomec::parse_detail
