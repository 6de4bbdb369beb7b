// Parse layer implementation. Stages: lex with the generated NomeLexer; a token pass that
// reports stray characters and unclosed comments/blocks, assigns the list-sign token types
// (SPLUS/SMINUS, language.md §3) and retypes generator keywords (K_GEN/E_GEN); parse with
// SLL prediction that bails on the first error, then again with error recovery if it did;
// then convert the parse tree into the ANTLR-free AST of frontend/ast.
#include "frontend/parse/parse.h"
#include "frontend/parse/piece.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fmt/format.h>
#include <memory>
#include <optional>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "ir/generator_catalogue.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#pragma GCC diagnostic ignored "-Wattributes"
#pragma GCC diagnostic ignored "-Woverloaded-virtual"
#include "NomeLexer.h"
#include "NomeParser.h"
#include "antlr4-runtime.h"
#pragma GCC diagnostic pop

namespace nomec {

namespace {

using nomec_antlr::NomeLexer;
using nomec_antlr::NomeParser;

// ANTLR indexes code points; diagnostics use byte offsets. The input is decoded here (not by
// ANTLR, whose decoder throws on invalid UTF-8): every invalid byte becomes one U+FFFD, so
// any byte sequence lexes, and `byte_of` maps a code-point index back to its byte offset.
// A text parsed on its own but lying inside a file (the function of `funcX [ … ]`) has the
// offset of its first byte in `base`, so ranges are file offsets.
struct Offsets {
  std::vector<uint32_t> cp_to_byte;  // empty when the text is ASCII (identity)
  uint32_t text_size = 0;
  uint32_t base = 0;
  // Clamped to the text: tokens the parser conjures during recovery have no real position.
  uint32_t local_of(size_t cp) const {
    if (cp_to_byte.empty()) return static_cast<uint32_t>(std::min<size_t>(cp, text_size));
    return cp < cp_to_byte.size() ? cp_to_byte[cp] : cp_to_byte.back();
  }
  uint32_t byte_of(size_t cp) const { return base + local_of(cp); }
};

std::u32string decode_utf8(std::string_view text, Offsets& offsets) {
  std::u32string out;
  out.reserve(text.size());
  bool ascii = std::all_of(text.begin(), text.end(), [](char c) { return (c & 0x80) == 0; });
  for (size_t i = 0; i < text.size();) {
    auto b = static_cast<unsigned char>(text[i]);
    char32_t cp = 0xFFFD;
    size_t len = 1;
    if (b < 0x80) {
      cp = b;
    } else {
      size_t need = (b & 0xE0) == 0xC0 ? 2 : (b & 0xF0) == 0xE0 ? 3 : (b & 0xF8) == 0xF0 ? 4 : 0;
      if (need > 0 && i + need <= text.size()) {
        char32_t v = b & (0x7F >> need);
        bool ok = true;
        for (size_t k = 1; k < need; ++k) {
          auto c = static_cast<unsigned char>(text[i + k]);
          if ((c & 0xC0) != 0x80) { ok = false; break; }
          v = (v << 6) | (c & 0x3F);
        }
        if (ok && v <= 0x10FFFF && !(v >= 0xD800 && v <= 0xDFFF)) {
          cp = v;
          len = need;
        }
      }
    }
    if (!ascii) offsets.cp_to_byte.push_back(static_cast<uint32_t>(i));
    out.push_back(cp);
    i += len;
  }
  if (!ascii) offsets.cp_to_byte.push_back(static_cast<uint32_t>(text.size()));
  return out;
}

// Nested `(* … *)` comments are removed before ANTLR sees the text: each comment character
// (except newlines) becomes a space, so offsets do not move. An iterative scan handles any
// nesting depth (ANTLR's recursive comment rule does not) and finds an unclosed comment at
// its opening. `#` line comments and `"…"` strings are skipped so a `(*` inside them stays.
bool blank_block_comments(std::u32string& text, const Offsets& offsets, FileId file,
                          DiagnosticEngine& diags) {
  size_t depth = 0;
  size_t outer_open = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    char32_t c = text[i];
    char32_t next = i + 1 < text.size() ? text[i + 1] : 0;
    if (depth == 0) {
      if (c == '#') {
        while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
      } else if (c == '"') {
        while (i + 1 < text.size() && text[i + 1] != '"' && text[i + 1] != '\n') ++i;
        ++i;
      } else if (c == '(' && next == '*') {
        depth = 1;
        outer_open = i;
        text[i] = text[i + 1] = ' ';
        ++i;
      }
      continue;
    }
    if (c == '(' && next == '*') {
      ++depth;
      text[i] = text[i + 1] = ' ';
      ++i;
    } else if (c == '*' && next == ')') {
      --depth;
      text[i] = text[i + 1] = ' ';
      ++i;
    } else if (c != '\n') {
      text[i] = ' ';
    }
  }
  if (depth > 0) {
    uint32_t at = offsets.byte_of(outer_open);
    diags.emit(DiagKind::UnclosedBlockComment, SourceRange{file, at, at + 2},
               "block comment `(*` is never closed by a matching `*)`");
  }
  return depth > 0;
}

// The decoded text as ANTLR's character stream. It also records the start of the earliest
// token whose lexing looked at the end of the input: when a piece of a file is parsed on its
// own (ParseCache), only its trailing whitespace may do that, or the lexer might have
// produced different tokens with the rest of the file behind the piece.
class DecodedInput : public antlr4::ANTLRInputStream {
 public:
  explicit DecodedInput(std::u32string data) {
    _data = std::move(data);
    p = 0;
  }
  size_t LA(ssize_t i) override {
    size_t c = antlr4::ANTLRInputStream::LA(i);
    if (c == antlr4::IntStream::EOF && i > 0 && lexer_ != nullptr) {
      eof_touch_start_ = std::min(eof_touch_start_, lexer_->tokenStartCharIndex);
    }
    return c;
  }
  antlr4::Lexer* lexer_ = nullptr;
  size_t eof_touch_start_ = static_cast<size_t>(-1);
};

// The parser's token stream. It records whether the parser looked at the end of the input
// before it had consumed every token (inside a statement, or further ahead than the next
// token): a piece parsed on its own is only equivalent to the same text inside the whole
// file when the end was seen at the top level with nothing left to read.
class WatchedTokenStream : public antlr4::CommonTokenStream {
 public:
  using antlr4::CommonTokenStream::CommonTokenStream;
  antlr4::Token* LT(ssize_t k) override {
    antlr4::Token* t = antlr4::CommonTokenStream::LT(k);
    if (k > 0 && t != nullptr && t->getType() == antlr4::Token::EOF && parser_ != nullptr &&
        !eof_seen_early_ &&
        (!all_consumed() || parser_->getErrorHandler()->inErrorRecoveryMode(parser_))) {
      eof_seen_early_ = true;
    }
    return t;
  }
  NomeParser* parser_ = nullptr;
  antlr4::Token* last_real_ = nullptr;  // the last default-channel token before EOF
  // Set when the end was seen too early, or at the top level while the error strategy was
  // still recovering from an error (it would then stay quiet about an error that follows).
  bool eof_seen_early_ = false;

 private:
  bool all_consumed() const {
    antlr4::ParserRuleContext* ctx = parser_->getContext();
    if (ctx == nullptr || ctx->getRuleIndex() != NomeParser::RuleFile) return false;
    if (last_real_ == nullptr) return true;
    if (ctx->children.empty()) return false;
    antlr4::tree::ParseTree* child = ctx->children.back();
    if (auto* term = dynamic_cast<antlr4::tree::TerminalNode*>(child);
        term != nullptr && term->getSymbol()->getType() == antlr4::Token::EOF) {
      return true;  // `file` matched EOF: nothing is left
    }
    if (auto* rule = dynamic_cast<antlr4::ParserRuleContext*>(child)) {
      return rule->stop == last_real_;
    }
    if (auto* term = dynamic_cast<antlr4::tree::TerminalNode*>(child)) {
      return term->getSymbol() == last_real_;
    }
    return false;
  }
};

// Maps keyword token types to block kinds, derived from the lexer's literal names so the
// grammar and block_kinds.def cannot drift apart silently (a missing keyword fails a test).
// Every generator keyword is the one token type K_GEN (its end keyword E_GEN), assigned by
// the token pass from the generator catalogue.
struct KeywordTable {
  std::unordered_map<size_t, ast::BlockKind> open;
  std::unordered_map<size_t, ast::BlockKind> close;
};

const KeywordTable& keyword_table() {
  static const KeywordTable table = [] {
    KeywordTable t;
    antlr4::ANTLRInputStream empty(std::string{});
    NomeLexer lexer(&empty);
    const antlr4::dfa::Vocabulary& vocab = lexer.getVocabulary();
    for (size_t type = 1; type <= vocab.getMaxTokenType(); ++type) {
      std::string lit = vocab.getLiteralName(type);
      if (lit.size() <= 2) continue;
      std::string word = lit.substr(1, lit.size() - 2);
      if (auto kind = ast::block_of_keyword(word)) t.open[type] = *kind;
      if (auto kind = ast::block_of_end_keyword(word)) t.close[type] = *kind;
    }
    t.open[NomeParser::K_GEN] = ast::BlockKind::Generator;
    t.close[NomeParser::E_GEN] = ast::BlockKind::Generator;
    return t;
  }();
  return table;
}

// The generator token type a name takes (K_GEN, E_GEN), or 0 when it is no generator keyword.
size_t generator_token_type(std::string_view word) {
  if (word.size() < 4) return 0;  // shorter than any generator keyword
  if (ast::block_of_keyword(word) == ast::BlockKind::Generator) return NomeParser::K_GEN;
  if (word.starts_with("end") && ast::block_of_end_keyword(word) == ast::BlockKind::Generator) return NomeParser::E_GEN;
  return 0;
}

std::string token_display(const antlr4::dfa::Vocabulary& vocab, size_t type) {
  if (type == antlr4::Token::EOF) {
    return "end of file";
  }
  std::string lit = vocab.getLiteralName(type);
  if (lit.size() > 2) {
    return fmt::format("`{}`", lit.substr(1, lit.size() - 2));
  }
  if (type == NomeParser::K_GEN) {
    return "a generator keyword";
  }
  if (type == NomeParser::E_GEN) {
    return "a generator's end keyword";
  }
  std::string sym = vocab.getSymbolicName(type);
  if (sym == "IDENT") {
    return "a name";
  }
  if (sym == "NUMBER") {
    return "a number";
  }
  if (sym == "DOLLAR_REF") {
    return "a `$` reference";
  }
  return sym;
}

bool is_end_token(size_t type) { return keyword_table().close.contains(type); }

// An arithmetic operator or sign token.
bool is_operator(size_t type) {
  switch (type) {
    case NomeParser::PLUS: case NomeParser::MINUS: case NomeParser::SPLUS: case NomeParser::SMINUS:
    case NomeParser::STAR: case NomeParser::SLASH: case NomeParser::DSLASH: case NomeParser::PERCENT:
    case NomeParser::CARET: return true;
    default: return false;
  }
}

// Converts ANTLR syntax errors into diagnostics, phrased in terms of NOME statements.
class SyntaxErrorListener : public antlr4::BaseErrorListener {
 public:
  SyntaxErrorListener(FileId file, const Offsets& offsets, DiagnosticEngine& diags)
      : file_(file), offsets_(offsets), diags_(diags) {}

  /// For a function text parsed on its own (`funcX [ … ]`): its end is the closing `]`.
  void in_function() {
    end_ = "the `]` that ends the function";
    in_function_ = true;
  }

  void syntaxError(antlr4::Recognizer* recognizer, antlr4::Token* offending, size_t, size_t,
                   const std::string&, std::exception_ptr) override {
    ++error_count_;
    auto* parser = dynamic_cast<NomeParser*>(recognizer);
    if (parser == nullptr || offending == nullptr) {
      return;
    }
    const auto& vocab = parser->getVocabulary();
    SourceRange at = range_of(offending);
    // The innermost open block, if any: its opening keyword explains most errors.
    antlr4::ParserRuleContext* ctx = parser->getContext();
    antlr4::Token* opener = nullptr;
    for (auto* c = ctx; c != nullptr; c = dynamic_cast<antlr4::ParserRuleContext*>(c->parent)) {
      const std::string& rule = parser->getRuleNames()[c->getRuleIndex()];
      bool is_block_rule = rule.size() > 4 && rule.ends_with("Stmt") && rule != "topStmt" &&
                           rule != "includeStmt";
      if (is_block_rule && c->start != nullptr &&
          keyword_table().open.contains(c->start->getType())) {
        opener = c->start;
        break;
      }
    }
    antlr4::misc::IntervalSet expected = parser->getExpectedTokens();
    size_t type = offending->getType();
    std::string shown = type == antlr4::Token::EOF ? end_ : fmt::format("`{}`", offending->getText());
    // An unclosed `(` or `{`: name the bracket, not the statement around it.
    for (auto [open_type, close_type, open_text, close_text] :
         {std::tuple{NomeParser::LPAREN, NomeParser::RPAREN, "(", ")"},
          std::tuple{NomeParser::LBRACE, NomeParser::RBRACE, "{", "}"}}) {
      if (!expected.contains(static_cast<size_t>(close_type)) || type == static_cast<size_t>(close_type)) {
        continue;
      }
      antlr4::Token* bracket = innermost_start(ctx, static_cast<size_t>(open_type));
      if (bracket == nullptr) {
        continue;
      }
      auto d = diags_.emit(DiagKind::SyntaxError, at,
                           fmt::format("`{}` is never closed: expected `{}` before {}", open_text,
                                       close_text, shown));
      d.note(range_of(bracket), fmt::format("`{}` opened here", open_text));
      return;
    }
    if (opener != nullptr) {
      std::string open = opener->getText();
      std::string close = ast::end_keyword(open);
      if (type == antlr4::Token::EOF) {
        diags_
            .emit(DiagKind::MissingEndKeyword, range_of(opener),
                  fmt::format("`{}` is never closed: expected `{}` before the end of the file",
                              open, close))
            .fixit(SourceRange{file_, at.begin, at.begin}, fmt::format("{}\n", close),
                   fmt::format("insert `{}`", close));
        return;
      }
      if (is_end_token(type) && offending->getText() != close) {
        diags_
            .emit(DiagKind::MismatchedEndKeyword, at,
                  fmt::format("`{}` does not close the open `{}`; expected `{}`",
                              offending->getText(), open, close))
            .note(range_of(opener), fmt::format("`{}` opened here", open));
        return;
      }
    }
    if (opener == nullptr && is_end_token(type)) {
      diags_.emit(DiagKind::UnmatchedEndKeyword, at,
                  fmt::format("`{}` closes nothing: no `{}` statement is open here",
                              offending->getText(), offending->getText().substr(3)))
          .fixit(at, "", fmt::format("remove `{}`", offending->getText()));
      return;
    }
    if (in_function_) {
      // A function is one expression: name what ended it early or what follows it.
      antlr4::Token* before = previous_token(parser);
      if (type == antlr4::Token::EOF && before != nullptr && is_operator(before->getType())) {
        diags_.emit(DiagKind::SyntaxError, range_of(before),
                    fmt::format("the function ends after `{}`: the value after it is missing", before->getText()));
        return;
      }
      antlr4::Token* after = parser->getTokenStream()->LT(2);
      if (is_operator(type) && after != nullptr && after->getType() == antlr4::Token::EOF) {
        diags_.emit(DiagKind::SyntaxError, at,
                    fmt::format("the function ends after `{}`: the value after it is missing", offending->getText()));
        return;
      }
      if (type == NomeParser::LPAREN && !closes_before_end(parser)) {
        diags_.emit(DiagKind::SyntaxError, at, fmt::format("`(` is never closed: expected `)` before {}", end_));
        return;
      }
      if (type != antlr4::Token::EOF && expected.contains(static_cast<size_t>(antlr4::Token::EOF))) {
        diags_.emit(DiagKind::SyntaxError, at,
                    fmt::format("unexpected {} in the function; a function is one expression, e.g. `cos(u)*v`", shown));
        return;
      }
    }
    std::vector<std::string> names;
    for (size_t t : expected.toList()) {
      if (t == NomeParser::SPLUS || t == NomeParser::SMINUS) {
        continue;
      }
      std::string d = token_display(vocab, t);
      if (std::find(names.begin(), names.end(), d) == names.end()) {
        names.push_back(d);
      }
    }
    std::string expect;
    if (!names.empty() && names.size() <= 6) {
      expect = "; expected " + fmt::format("{}", fmt::join(names, ", "));
    }
    diags_.emit(DiagKind::SyntaxError, at,
                type == antlr4::Token::EOF ? fmt::format("{} comes too early{}", end_, expect)
                                           : fmt::format("unexpected {}{}", shown, expect));
  }

  int error_count() const { return error_count_; }

 private:
  // The start token of the innermost enclosing rule that begins with `type` (e.g. the `(`
  // of an unclosed list).
  static antlr4::Token* innermost_start(antlr4::ParserRuleContext* ctx, size_t type) {
    for (auto* c = ctx; c != nullptr; c = dynamic_cast<antlr4::ParserRuleContext*>(c->parent)) {
      if (c->start != nullptr && c->start->getType() == type) {
        return c->start;
      }
      if (c->getRuleIndex() == NomeParser::RuleTopStmt) {
        break;
      }
    }
    return nullptr;
  }

  SourceRange range_of(antlr4::Token* token) const {
    if (token->getType() == antlr4::Token::EOF) {
      uint32_t at = offsets_.byte_of(token->getStartIndex());
      return SourceRange{file_, at, at};
    }
    return SourceRange{file_, offsets_.byte_of(token->getStartIndex()),
                       offsets_.byte_of(token->getStopIndex() + 1)};
  }

  FileId file_;
  const Offsets& offsets_;
  DiagnosticEngine& diags_;
  int error_count_ = 0;
  std::string end_ = "the end of the file";
  bool in_function_ = false;

  // True when the `(` at the parser's current token has its `)` before the end.
  static bool closes_before_end(NomeParser* parser) {
    int depth = 0;
    for (ssize_t k = 1;; ++k) {
      antlr4::Token* t = parser->getTokenStream()->LT(k);
      if (t == nullptr || t->getType() == antlr4::Token::EOF) return false;
      if (t->getType() == NomeParser::LPAREN) ++depth;
      if (t->getType() == NomeParser::RPAREN && --depth == 0) return true;
    }
  }
  // The last default-channel token before the parser's current one.
  static antlr4::Token* previous_token(NomeParser* parser) {
    auto* stream = dynamic_cast<antlr4::BufferedTokenStream*>(parser->getTokenStream());
    if (stream == nullptr) return nullptr;
    for (ssize_t i = static_cast<ssize_t>(stream->index()) - 1; i >= 0; --i) {
      antlr4::Token* t = stream->get(static_cast<size_t>(i));
      if (t->getChannel() == antlr4::Token::DEFAULT_CHANNEL) return t;
    }
    return nullptr;
  }
};

// ANTLR's recovery with the same decisions, but without composing its English error
// messages (nomec's listener words its own): each report goes to the listeners with an
// empty message. Building those strings was most of the cost of a file with errors.
class QuietErrorStrategy : public antlr4::DefaultErrorStrategy {
 protected:
  void reportNoViableAlternative(antlr4::Parser* parser, const antlr4::NoViableAltException& e) override {
    parser->notifyErrorListeners(e.getOffendingToken(), std::string(), nullptr);
  }
  void reportInputMismatch(antlr4::Parser* parser, const antlr4::InputMismatchException& e) override {
    parser->notifyErrorListeners(e.getOffendingToken(), std::string(), nullptr);
  }
  void reportFailedPredicate(antlr4::Parser* parser, const antlr4::FailedPredicateException& e) override {
    parser->notifyErrorListeners(e.getOffendingToken(), std::string(), nullptr);
  }
  void reportUnwantedToken(antlr4::Parser* parser) override {
    if (inErrorRecoveryMode(parser)) return;
    beginErrorCondition(parser);
    parser->notifyErrorListeners(parser->getCurrentToken(), std::string(), nullptr);
  }
  void reportMissingToken(antlr4::Parser* parser) override {
    if (inErrorRecoveryMode(parser)) return;
    beginErrorCondition(parser);
    parser->notifyErrorListeners(parser->getCurrentToken(), std::string(), nullptr);
  }
};

// Silences ANTLR's console output from the lexer (all characters are tokens, so the lexer
// itself has nothing to report).
class SilentListener : public antlr4::BaseErrorListener {};

// NOME2 (2018) names a top-level instance inside `subdivision`, `offset` and `merge` blocks
// with `instance X`, without `endinstance` (`subdivision s instance c type T subdivisions 2
// endsubdivision`). Such an `instance` becomes a name, which the block reads as its
// `instance` option (frontend/check/blocks.cpp): it is inside one of those blocks and the
// word after its name continues the block (`type`, `min`, …, another `instance`, or the
// block's end keyword), where an instance statement would have its target.
void retype_block_instance_names(std::vector<std::unique_ptr<antlr4::Token>>& toks) {
  auto next = [&](size_t i) {
    while (++i < toks.size() && toks[i]->getChannel() != antlr4::Token::DEFAULT_CHANNEL) {
    }
    return i;
  };
  int depth = 0;  // open subdivision, offset and merge blocks
  for (size_t i = 0; i < toks.size(); ++i) {
    if (toks[i]->getChannel() != antlr4::Token::DEFAULT_CHANNEL) continue;
    const size_t type = toks[i]->getType();
    if (type == NomeLexer::K_SUBDIVISION || type == NomeLexer::K_OFFSET || type == NomeLexer::K_MERGE) ++depth;
    if ((type == NomeLexer::E_SUBDIVISION || type == NomeLexer::E_OFFSET || type == NomeLexer::E_MERGE) && depth > 0) --depth;
    if (type != NomeLexer::K_INSTANCE || depth == 0) continue;
    const size_t name = next(i);
    const size_t after = next(name);
    if (after >= toks.size() || toks[name]->getType() != NomeLexer::IDENT) continue;
    const size_t t = toks[after]->getType();
    const bool is_word = t == NomeLexer::IDENT || t == NomeLexer::K_INSTANCE || t == NomeLexer::E_SUBDIVISION ||
                         t == NomeLexer::E_OFFSET || t == NomeLexer::E_MERGE;
    if (!is_word || !continues_block_after_instance_name(toks[after]->getText())) continue;
    if (auto* common = dynamic_cast<antlr4::CommonToken*>(toks[i].get())) common->setType(NomeLexer::IDENT);
  }
}

// Token pass: diagnostics for stray characters and unclosed constructs, and the list-sign
// rule. Returns the tokens the parser should see.
// `stopped` is set when a limit made the pass stop reading the text; `what` names the text
// in messages (`file`, or `function` for a function text parsed on its own).
std::vector<std::unique_ptr<antlr4::Token>> prepare_tokens(
    std::vector<std::unique_ptr<antlr4::Token>> tokens, std::string_view text,
    const Offsets& offsets, FileId file, DiagnosticEngine& diags, bool& stopped,
    std::string_view what = "file") {
  std::vector<std::unique_ptr<antlr4::Token>> out;
  out.reserve(tokens.size());
  int brace_depth = 0;
  constexpr int kMaxNesting = 200;
  int nesting = 0;
  int sign_run = 0;
  int caret_run = 0;
  auto range = [&](const antlr4::Token& t) {
    return SourceRange{file, offsets.byte_of(t.getStartIndex()),
                       offsets.byte_of(t.getStopIndex() + 1)};
  };
  for (size_t i = 0; i < tokens.size(); ++i) {
    auto& tok = tokens[i];
    size_t type = tok->getType();
    if (type == antlr4::Token::EOF) {
      out.push_back(std::move(tok));
      break;
    }
    size_t start = offsets.local_of(tok->getStartIndex());  // index into `text`
    // The parser is recursive: bound how deep brackets, signs and `^` chains nest, and stop
    // reading the file where a limit is crossed (one error, no stack overflow).
    if (type == NomeLexer::LPAREN || type == NomeLexer::LBRACE) {
      ++nesting;
    } else if ((type == NomeLexer::RPAREN || type == NomeLexer::RBRACE) && nesting > 0) {
      --nesting;
    }
    bool is_sign = type == NomeLexer::PLUS || type == NomeLexer::MINUS;
    sign_run = is_sign ? sign_run + 1 : 0;
    if (type == NomeLexer::CARET) {
      ++caret_run;
    } else if (type != NomeLexer::NUMBER && type != NomeLexer::IDENT &&
               type != NomeLexer::DOLLAR_REF && !is_sign) {
      caret_run = 0;
    }
    if (nesting > kMaxNesting || sign_run > kMaxNesting || caret_run > kMaxNesting) {
      diags.emit(DiagKind::NestingTooDeep, range(*tok),
                 fmt::format("brackets, signs or `^` nest more than {} levels deep here; nomec "
                             "stops reading the {} at this point",
                             kMaxNesting, what));
      stopped = true;
      while (i + 1 < tokens.size() && tokens[i + 1]->getType() != antlr4::Token::EOF) {
        ++i;
      }
      continue;
    }
    if (type == NomeLexer::IDENT) {
      if (size_t gen = generator_token_type(text.substr(start, offsets.local_of(tok->getStopIndex() + 1) - start))) {
        if (auto* common = dynamic_cast<antlr4::CommonToken*>(tok.get())) common->setType(gen);
        out.push_back(std::move(tok));
        continue;
      }
    }
    if (type == NomeLexer::IDENT && (tok->getText() == "tclinit" || tok->getText() == "tclupdate")) {
      diags.emit(DiagKind::UnclosedTclBlock, range(*tok),
                 fmt::format("`{}` block is not enclosed in balanced braces `{{ … }}`", tok->getText()));
      stopped = true;
      while (i + 1 < tokens.size() && tokens[i + 1]->getType() != antlr4::Token::EOF) {
        ++i;
      }
      continue;
    }
    if (type == NomeLexer::LBRACE) {
      ++brace_depth;
    } else if (type == NomeLexer::RBRACE && brace_depth > 0) {
      --brace_depth;
    }
    if (type == NomeLexer::UNEXPECTED_CHAR && brace_depth > 0 && text[start] != '"') {
      // Inside braces any character may belong to a Tcl script (`{if {$n >= 2} …}`); the
      // parser keeps such a value raw and the checker explains it.
      out.push_back(std::move(tok));
      continue;
    }
    if (type == NomeLexer::UNEXPECTED_CHAR) {
      char c = text[start];
      if (c == '"') {
        diags.emit(DiagKind::UnexpectedCharacter, range(*tok),
                   "string is not closed: `\"` has no matching `\"` on this line");
      } else if (c == '[') {
        diags.emit(DiagKind::UnexpectedCharacter, range(*tok),
                   "`[` is not closed by a matching `]`");
      } else if (c == ';') {
        diags.emit(DiagKind::UnexpectedCharacter, range(*tok),
                   "unexpected `;`: NOME statements end with their `end…` keyword")
            .fixit(range(*tok), "", "remove `;`");
      } else {
        unsigned char uc = static_cast<unsigned char>(c);
        std::string shown = std::isprint(uc) ? std::string(1, c) : fmt::format("\\x{:02x}", uc);
        diags.emit(DiagKind::UnexpectedCharacter, range(*tok),
                   fmt::format("unexpected character `{}`", shown));
      }
      continue;
    }
    if (type == NomeLexer::NBSP) {
      const SourceRange r = range(*tok);
      diags
          .emit(DiagKind::NonBreakingSpace, r,
                "a no-break space (U+00A0) here is read as a space; it is invisible in most editors and other "
                "tools may read it as part of a name or number")
          .fixit(r, std::string((r.end - r.begin) / 2, ' '), "replace with a plain space");
      out.push_back(std::move(tok));
      continue;
    }
    if ((type == NomeLexer::PLUS || type == NomeLexer::MINUS) &&
        tok->getChannel() == antlr4::Token::DEFAULT_CHANNEL) {
      // U+00A0 is C2 A0 in UTF-8 and separates like a space.
      auto nbsp_at = [&](size_t i) { return i + 1 < text.size() && text[i] == '\xC2' && text[i + 1] == '\xA0'; };
      bool before = start == 0 || std::isspace(static_cast<unsigned char>(text[start - 1])) ||
                    text[start - 1] == '(' || (start >= 2 && nbsp_at(start - 2));
      bool after = start + 1 < text.size() &&
                   !std::isspace(static_cast<unsigned char>(text[start + 1])) && !nbsp_at(start + 1);  // ASCII sign
      if (before && after) {
        auto* common = dynamic_cast<antlr4::CommonToken*>(tok.get());
        if (common != nullptr) {
          common->setType(type == NomeLexer::PLUS ? NomeParser::SPLUS : NomeParser::SMINUS);
        }
      }
    }
    out.push_back(std::move(tok));
  }
  retype_block_instance_names(out);
  return out;
}

// A zero-width token of `type` at code point `at` (a repair the parser reads as written).
std::unique_ptr<antlr4::Token> conjured_token(size_t type, const antlr4::Token& near, size_t at) {
  // With the lexer and input as its source, like every other token: ANTLR's recovery copies
  // them into the tokens it conjures.
  auto t = std::make_unique<antlr4::CommonToken>(
      std::pair<antlr4::TokenSource*, antlr4::CharStream*>{near.getTokenSource(), near.getInputStream()}, type,
      antlr4::Token::DEFAULT_CHANNEL, at, at - 1);
  t->setLine(near.getLine());
  t->setCharPositionInLine(near.getCharPositionInLine());
  return t;
}

// NOME3 evaluated function texts with exprtk, which reads a product without its `*` (`5x`,
// `10(x^2+y^2)`, `(u+1)v`, `u v`; generators-original.md §11.2): between a number and a name
// or `(`, a name and a number, `)` and a number or name, and two names. The same pairs
// are never valid otherwise, so a `*` is put between them and the text is read as exprtk
// read it.
void insert_implicit_multiplication(std::vector<std::unique_ptr<antlr4::Token>>& tokens) {
  auto product_pair = [](size_t a, size_t b) {
    const bool number = a == NomeParser::NUMBER, name = a == NomeParser::IDENT, close = a == NomeParser::RPAREN;
    if (number) return b == NomeParser::IDENT || b == NomeParser::LPAREN;
    if (name) return b == NomeParser::NUMBER || b == NomeParser::IDENT;
    if (close) return b == NomeParser::NUMBER || b == NomeParser::IDENT;
    return false;
  };
  std::vector<std::unique_ptr<antlr4::Token>> out;
  out.reserve(tokens.size());
  const antlr4::Token* last = nullptr;  // the previous default-channel token
  for (std::unique_ptr<antlr4::Token>& t : tokens) {
    if (t->getChannel() == antlr4::Token::DEFAULT_CHANNEL && t->getType() != antlr4::Token::EOF) {
      if (last != nullptr && product_pair(last->getType(), t->getType())) {
        out.push_back(conjured_token(NomeParser::STAR, *t, t->getStartIndex()));
      }
      last = t.get();
    }
    out.push_back(std::move(t));
  }
  tokens = std::move(out);
}

// `point p 0 0 0) endpoint`: a `)` that closes nothing, after a run of values (or of names
// after a statement's own name) on its line, is missing its `(`. One error with the fix-it,
// and a `(` is put before the run so the statement is read as meant.
void insert_missing_open_parens(std::vector<std::unique_ptr<antlr4::Token>>& tokens, const Offsets& offsets,
                                FileId file, DiagnosticEngine& diags) {
  auto real = [&](size_t i) {
    return tokens[i]->getChannel() == antlr4::Token::DEFAULT_CHANNEL && tokens[i]->getType() != antlr4::Token::EOF;
  };
  auto is_value = [](size_t t) {
    return t == NomeParser::NUMBER || t == NomeParser::DOLLAR_REF || t == NomeParser::TCL_ARRAY_REF || is_operator(t);
  };
  std::vector<std::pair<size_t, size_t>> inserts;  // (position in `tokens` to insert before, code point)
  int depth = 0;
  for (size_t i = 0; i < tokens.size(); ++i) {
    if (!real(i)) continue;
    const size_t type = tokens[i]->getType();
    if (type == NomeParser::LPAREN) ++depth;
    if (type != NomeParser::RPAREN) continue;
    if (depth > 0) {
      --depth;
      continue;
    }
    // Walk back over the values on the `)`'s line (a `{…}` group counts as one value).
    const size_t line = tokens[i]->getLine();
    size_t first = i;
    int braces = 0;
    for (size_t k = i; k-- > 0;) {
      if (!real(k)) continue;
      const antlr4::Token& t = *tokens[k];
      if (t.getLine() != line && braces == 0) break;
      if (t.getType() == NomeParser::RBRACE) ++braces;
      else if (t.getType() == NomeParser::LBRACE && braces > 0) --braces;
      else if (braces == 0 && !is_value(t.getType())) break;
      if (braces == 0) first = k;
    }
    if (first == i) {
      // Names: `face f a b c)`; the run starts after the statement's keyword and name.
      size_t names = i, keyword = i;
      for (size_t k = i; k-- > 0;) {
        if (!real(k)) continue;
        const antlr4::Token& t = *tokens[k];
        if (t.getLine() != line) break;
        if (keyword_table().open.contains(t.getType())) {
          keyword = k;
          break;
        }
        if (t.getType() != NomeParser::IDENT) break;
        names = k;
      }
      if (keyword == i) continue;
      size_t after_name = keyword + 1;
      while (after_name < i && !real(after_name)) ++after_name;
      ++after_name;  // past the statement's own name
      while (after_name < i && !real(after_name)) ++after_name;
      if (after_name >= i || names > after_name) continue;
      first = after_name;
    }
    const size_t at = tokens[first]->getStartIndex();
    const uint32_t byte = offsets.byte_of(at);
    const uint32_t close_at = offsets.byte_of(tokens[i]->getStartIndex());
    diags
        .emit(DiagKind::SyntaxError, SourceRange{file, close_at, close_at + 1},
              fmt::format("`)` closes nothing here: the list it ends is missing its `(`"))
        .note(SourceRange{file, byte, byte}, "the list would start here")
        .fixit(SourceRange{file, byte, byte}, "(", "insert `(`");
    inserts.emplace_back(first, at);
  }
  if (inserts.empty()) return;
  std::vector<std::unique_ptr<antlr4::Token>> out;
  out.reserve(tokens.size() + inserts.size());
  size_t next = 0;
  for (size_t i = 0; i < tokens.size(); ++i) {
    while (next < inserts.size() && inserts[next].first == i) {
      out.push_back(conjured_token(NomeParser::LPAREN, *tokens[i], inserts[next].second));
      ++next;
    }
    out.push_back(std::move(tokens[i]));
  }
  tokens = std::move(out);
}

// NOME 2016 read `point`, `face`, `polyline`, `instance`, `funnel` and `tunnel` statements a
// line at a time: the statement ended at its end keyword or at the end of its line, and a
// wrong or misspelt end keyword there went unnoticed (compat.md §B2). So that such a file
// parses as its author saw it, a statement of these kinds that is not closed on its first
// line gets its end at the end of that line, in every dialect: a wrong end keyword
// or a misspelt one (`endinstnace`) that ends the line is taken as its end, and where none
// is there and the statement does not go on to its end keyword on later lines (the next
// line starts another statement, or ends an enclosing one), an end is inserted. The parser
// then reads the rest of the file as it is; the checker warns in `nome` files and reports
// an error in the others (ast::CloseRepair says which repair was made).
struct LineEndRepairs {
  // By the start (code point) of the end token: those inserted (zero width) and those retyped.
  std::unordered_set<size_t> inserted, replaced;
};

bool is_open_type(size_t type) { return keyword_table().open.contains(type); }

// The end token type of a single-line statement opened by `type` (with its text `word`),
// or 0 when the statement is not one of them.
size_t line_statement_end(size_t type, std::string_view word) {
  switch (type) {
    case NomeParser::K_POINT: return NomeParser::E_POINT;
    case NomeParser::K_FACE: return NomeParser::E_FACE;
    case NomeParser::K_POLYLINE: return NomeParser::E_POLYLINE;
    case NomeParser::K_INSTANCE: return NomeParser::E_INSTANCE;
    case NomeParser::K_GEN: return word == "funnel" || word == "tunnel" ? NomeParser::E_GEN : 0;
    default: return 0;
  }
}

// A block the statement may contain on later lines (`instance … lookat … endlookat …`).
bool nests_in(size_t open, size_t inner) {
  return (open == NomeParser::K_INSTANCE && inner == NomeParser::K_LOOKAT) ||
         (open == NomeParser::K_FACE && inner == NomeParser::K_VERTEX);
}

// A keyword that is also an option word of these statements (`surface RED`, the 2016
// instance transform `mirror (…)`), so a line it starts may continue the statement.
bool is_option_keyword(size_t type) { return type == NomeParser::K_SURFACE || type == NomeParser::K_MIRROR; }

void end_line_statements(std::vector<std::unique_ptr<antlr4::Token>>& tokens, std::string_view text,
                         const Offsets& offsets, LineEndRepairs& repairs) {
  // The default-channel tokens, by position in `tokens`.
  std::vector<size_t> real;
  for (size_t i = 0; i < tokens.size(); ++i) {
    if (tokens[i]->getChannel() == antlr4::Token::DEFAULT_CHANNEL && tokens[i]->getType() != antlr4::Token::EOF) {
      real.push_back(i);
    }
  }
  auto tok = [&](size_t r) -> antlr4::Token& { return *tokens[real[r]]; };
  auto word = [&](size_t r) {
    const size_t b = offsets.local_of(tok(r).getStartIndex()), e = offsets.local_of(tok(r).getStopIndex() + 1);
    return text.substr(b, e - b);
  };
  auto line = [&](size_t r) { return tok(r).getLine(); };
  auto first_on_line = [&](size_t r) { return r == 0 || line(r - 1) != line(r); };
  struct Insert {
    size_t after;  // position in `tokens` of the token the end follows
    size_t type;
  };
  std::vector<Insert> inserts;
  // Where a statement may start, judged from the tokens before it, never from line breaks
  // (the formatter moves statements onto lines of their own and must not change how they
  // are read): at the start of the text, after an end keyword (or an end inserted here),
  // after a `tclinit` block or an `include "…"`, or first in the body of a block that holds
  // statements (`group g instance …`, `mesh m face …`).
  std::unordered_set<size_t> ended;  // real positions an end was inserted after
  auto holds_statements = [](size_t t) {
    switch (t) {
      case NomeParser::K_MESH: case NomeParser::K_GROUP: case NomeParser::K_DELETE: case NomeParser::K_CONSOLIDATE:
      case NomeParser::K_CONSOLIDATEFACE: case NomeParser::K_SAVEDWORKINGMESH: case NomeParser::K_MERGE:
      case NomeParser::K_SUBDIVISION: case NomeParser::K_OFFSET: case NomeParser::K_HANDLE: case NomeParser::K_RIND:
      case NomeParser::K_SIERPINSKI: case NomeParser::K_MENGER: case NomeParser::K_MIRROR: case NomeParser::K_SWEEP:
        return true;
      default: return false;
    }
  };
  auto may_start = [&](size_t r) {
    if (r == 0) return true;
    const size_t prev = tok(r - 1).getType();
    if (is_end_token(prev) || ended.contains(r - 1) || prev == NomeParser::TCLINIT || prev == NomeParser::STRING ||
        holds_statements(prev)) {
      return true;
    }
    return r >= 2 && holds_statements(tok(r - 2).getType()) &&
           (prev == NomeParser::IDENT || is_open_type(prev) || prev == NomeParser::K_GEN);
  };
  // Each statement looks at its own line and then jumps between the places where a scan
  // for its end could stop, so the pass stays linear in the text (a long line of
  // statements, or many unclosed ones, must not make it quadratic).
  const size_t n = real.size();
  std::vector<size_t> line_last(n);
  for (size_t k = n; k-- > 0;) line_last[k] = k + 1 < n && line(k + 1) == line(k) ? line_last[k + 1] : k;
  std::vector<int> depth_at(n);  // `(` and `{` open before token k
  for (size_t k = 0, d = 0; k < n; ++k) {
    depth_at[k] = static_cast<int>(d);
    const size_t t = tok(k).getType();
    if (t == NomeParser::LPAREN || t == NomeParser::LBRACE) ++d;
    if ((t == NomeParser::RPAREN || t == NomeParser::RBRACE) && d > 0) --d;
  }
  // The next token, from k on, outside brackets, where a scan for an end may stop: an end
  // keyword, a block nested in an instance or face, or a statement keyword opening a line.
  std::vector<size_t> next_stop(n + 1, n);
  for (size_t k = n; k-- > 0;) {
    const size_t t = tok(k).getType();
    const bool stop = depth_at[k] == 0 &&
                      (is_end_token(t) || t == NomeParser::K_LOOKAT || t == NomeParser::K_VERTEX ||
                       (first_on_line(k) && (is_open_type(t) || t == NomeParser::K_GEN) && !is_option_keyword(t)));
    next_stop[k] = stop ? k : next_stop[k + 1];
  }
  constexpr size_t kMaxStops = 4096;  // beyond this many nested blocks, leave the statement as written
  for (size_t r = 0; r < n; ++r) {
    const size_t type = tok(r).getType();
    const bool at_start = depth_at[r] == 0 && may_start(r);
    const size_t end_type = at_start ? line_statement_end(type, word(r)) : 0;
    if (end_type == 0) continue;
    // The rest of its line, at its own bracket depth, up to its end or an enclosing one's.
    const size_t last = line_last[r];
    bool closed = false;
    int d = 0;
    size_t foreign = 0;  // a token on the line that ends an enclosing statement
    for (size_t k = r + 1; k <= last; ++k) {
      const size_t t = tok(k).getType();
      if (t == NomeParser::LPAREN || t == NomeParser::LBRACE) ++d;
      if ((t == NomeParser::RPAREN || t == NomeParser::RBRACE) && d > 0) --d;
      if (d != 0) continue;
      if (t == end_type) {
        closed = true;
        // `funnel … endtunnel`: one token type closes every generator; the checker decides.
        const std::optional<ir::GenKind> gen = ir::generator_by_keyword(word(r));
        if (t == NomeParser::E_GEN && gen && !ir::generator(*gen).closes_with(word(r), word(k))) {
          repairs.replaced.insert(tok(k).getStartIndex());
        }
        break;
      }
      if (is_end_token(t)) {
        foreign = k;
        break;
      }
    }
    // Closed on its line, or a bracket left open there (another error, reported as such).
    if (closed || d != 0) continue;
    const std::string expected = ast::end_keyword(word(r));
    if (foreign != 0) {
      // A wrong end keyword of this family that ends the line is this statement's end; any
      // other (`endmesh`) closes an enclosing block, and this statement ends before it.
      const std::string_view w = word(foreign);
      const bool family = w == "endpoint" || w == "endface" || w == "endpolyline" || w == "endinstance" ||
                          tok(foreign).getType() == NomeParser::E_GEN;
      if (family && foreign == last) {
        static_cast<antlr4::CommonToken&>(tok(foreign)).setType(end_type);
        repairs.replaced.insert(tok(foreign).getStartIndex());
      } else {
        inserts.push_back({real[foreign - 1], end_type});
        ended.insert(foreign - 1);
      }
      continue;
    }
    if (last != r && tok(last).getType() == NomeParser::IDENT && word(last).starts_with("end") &&
        !closest_match(word(last), std::vector<std::string>{expected}).empty()) {
      static_cast<antlr4::CommonToken&>(tok(last)).setType(end_type);  // `endinstnace`
      repairs.replaced.insert(tok(last).getStartIndex());
      continue;
    }
    // Not closed on its line: does it go on to its end keyword before the next statement?
    bool continues = false;
    size_t inner = 0;
    size_t stops = 0;
    for (size_t k = next_stop[last + 1]; k < n; k = next_stop[k + 1]) {
      if (++stops > kMaxStops) {
        continues = true;
        break;
      }
      const size_t t = tok(k).getType();
      if (t == end_type && inner == 0) {
        continues = true;
        break;
      }
      if (nests_in(type, t)) {  // `face` … `vertex v endvertex` …
        ++inner;
        continue;
      }
      if (is_end_token(t)) {
        if (inner == 0) break;
        --inner;
        continue;
      }
      if (first_on_line(k) && (is_open_type(t) || t == NomeParser::K_GEN) && !is_option_keyword(t)) break;
    }
    if (!continues) {
      inserts.push_back({real[last], end_type});
      ended.insert(last);
    }
  }
  if (inserts.empty()) return;
  std::vector<std::unique_ptr<antlr4::Token>> out;
  out.reserve(tokens.size() + inserts.size());
  size_t next = 0;
  for (size_t i = 0; i < tokens.size(); ++i) {
    out.push_back(std::move(tokens[i]));
    while (next < inserts.size() && inserts[next].after == i) {
      const antlr4::Token& before = *out.back();
      // A zero-width token right after the last token of the line.
      const size_t at = before.getStopIndex() + 1;
      repairs.inserted.insert(at);
      out.push_back(conjured_token(inserts[next].type, before, at));
      ++next;
    }
  }
  tokens = std::move(out);
}

// One child of a parse-tree node: a rule context or a token (an error node is a token the
// parser conjured or skipped). Told apart with one virtual call instead of dynamic_cast:
// a failed dynamic_cast compares type names, which dominated the builder's time.
struct Child {
  antlr4::ParserRuleContext* rule = nullptr;
  antlr4::tree::TerminalNode* terminal = nullptr;
  bool is_error = false;
  size_t rule_index() const { return rule != nullptr ? rule->getRuleIndex() : static_cast<size_t>(-1); }
  size_t token_type() const {
    return terminal != nullptr && !is_error ? terminal->getSymbol()->getType() : antlr4::Token::INVALID_TYPE;
  }
};

class ChildProbe final : public antlr4::tree::ParseTreeVisitor {
 public:
  Child child;
  antlrcpp::Any visit(antlr4::tree::ParseTree* tree) override { return tree->accept(this); }
  // Generated contexts do not override `accept` (no visitor is generated), so every rule
  // context arrives here.
  antlrcpp::Any visitChildren(antlr4::tree::ParseTree* node) override {
    child.rule = static_cast<antlr4::ParserRuleContext*>(node);
    return {};
  }
  antlrcpp::Any visitTerminal(antlr4::tree::TerminalNode* node) override {
    child.terminal = node;
    return {};
  }
  antlrcpp::Any visitErrorNode(antlr4::tree::ErrorNode* node) override {
    child.terminal = node;
    child.is_error = true;
    return {};
  }
};

Child classify(antlr4::tree::ParseTree* tree) {
  ChildProbe probe;
  if (tree != nullptr) tree->accept(&probe);
  return probe.child;
}

// Child `i` of `ctx`, classified (an empty Child when there is none).
Child child(antlr4::ParserRuleContext* ctx, size_t i) {
  return ctx != nullptr && i < ctx->children.size() ? classify(ctx->children[i]) : Child{};
}

// The first child of `ctx` that is a rule context with index `rule`.
antlr4::ParserRuleContext* rule_child(antlr4::ParserRuleContext* ctx, size_t rule) {
  for (antlr4::tree::ParseTree* t : ctx->children) {
    Child c = classify(t);
    if (c.rule != nullptr && c.rule_index() == rule) return c.rule;
  }
  return nullptr;
}

// The first token of type `type` among the children of `ctx`.
antlr4::Token* token_child(antlr4::ParserRuleContext* ctx, size_t type) {
  for (antlr4::tree::ParseTree* t : ctx->children) {
    Child c = classify(t);
    if (c.token_type() == type) return c.terminal->getSymbol();
  }
  return nullptr;
}

// Converts the parse tree into the AST.
class AstBuilder {
 public:
  AstBuilder(FileId file, std::string_view text, const Offsets& offsets, ast::Ast& out,
             std::vector<int32_t>* unanchored, DiagnosticEngine* diags)
      : file_(file), text_(text), offsets_(offsets), ast_(out), unanchored_(unanchored), diags_(diags) {}

  /// The expression of a parse-tree context (a function text parsed with the `expr` rule).
  ast::ExprId build_expr(antlr4::ParserRuleContext* ctx) { return convert_expr(ctx); }

  void build_file(NomeParser::FileContext* file) {
    for (antlr4::tree::ParseTree* t : file->children) {
      Child top = classify(t);
      if (top.rule == nullptr || top.rule_index() != NomeParser::RuleTopStmt) continue;
      Child inner = child(top.rule, 0);
      if (inner.token_type() == NomeParser::TCLINIT) {
        ast::Item item;
        item.kind = ast::ItemKind::Tcl;
        item.range = token_range(inner.terminal->getSymbol());
        item.text = view(item.range);
        ast_.top.push_back(item);
        continue;
      }
      if (inner.rule == nullptr) continue;
      switch (inner.rule_index()) {
        case NomeParser::RuleIncludeStmt: {
          ast::Item item;
          item.kind = ast::ItemKind::Include;
          item.range = ctx_range(inner.rule);
          if (antlr4::Token* str = token_child(inner.rule, NomeParser::STRING)) {
            SourceRange r = token_range(str);
            if (r.end >= r.begin + 2) {  // a conjured (missing) string has no text
              item.text = view(SourceRange{file_, r.begin + 1, r.end - 1});
            }
          }
          ast_.top.push_back(item);
          break;
        }
        case NomeParser::RuleBlock:
          if (auto item = block_item(inner.rule)) ast_.top.push_back(*item);
          break;
        case NomeParser::RuleStrayItem: {
          ast::Item item;
          item.range = ctx_range(inner.rule);
          Child what = child(inner.rule, 0);
          if (what.rule_index() == NomeParser::RuleParenList) {
            item.kind = ast::ItemKind::List;
            item.list = convert_list(what.rule);
          } else if (what.rule_index() == NomeParser::RuleItemExpr) {
            item.kind = ast::ItemKind::Value;
            item.expr = convert_expr(what.rule);
          } else {
            item.kind = ast::ItemKind::Word;
            item.text = view(item.range);
          }
          ast_.top.push_back(item);
          break;
        }
        default:
          break;
      }
    }
  }

 private:
  SourceRange token_range(antlr4::Token* t) const {
    return SourceRange{file_, offsets_.byte_of(t->getStartIndex()),
                       offsets_.byte_of(t->getStopIndex() + 1)};
  }
  SourceRange ctx_range(antlr4::ParserRuleContext* ctx) const {
    size_t begin_cp = ctx->start != nullptr ? ctx->start->getStartIndex() : 0;
    uint32_t begin = offsets_.byte_of(begin_cp);
    uint32_t end = begin;
    if (ctx->stop != nullptr && ctx->stop->getType() != antlr4::Token::EOF &&
        ctx->stop->getStopIndex() + 1 >= begin_cp) {
      end = offsets_.byte_of(ctx->stop->getStopIndex() + 1);
    }
    return SourceRange{file_, begin, end};
  }
  std::string_view view(SourceRange r) const {
    size_t begin = std::min<size_t>(r.begin - std::min(r.begin, offsets_.base), text_.size());
    size_t end = std::clamp<size_t>(r.end - std::min(r.end, offsets_.base), begin, text_.size());
    return text_.substr(begin, end - begin);
  }

  // A `block` wrapper or a concrete `xxxStmt` context -> Block item.
  std::optional<ast::Item> block_item(antlr4::ParserRuleContext* ctx) {
    if (ctx->getRuleIndex() == NomeParser::RuleBlock) {
      Child inner = child(ctx, 0);
      return inner.rule != nullptr ? block_item(inner.rule) : std::nullopt;
    }
    if (ctx->start == nullptr) {
      return std::nullopt;
    }
    auto open_it = keyword_table().open.find(ctx->start->getType());
    if (open_it == keyword_table().open.end()) {
      return std::nullopt;
    }
    ast::Stmt stmt;
    stmt.kind = open_it->second;
    stmt.range = ctx_range(ctx);
    stmt.open_kw = token_range(ctx->start);
    stmt.keyword = view(stmt.open_kw);
    decltype(ast::Stmt::items) items;
    for (size_t i = 1; i < ctx->children.size(); ++i) {
      Child c = classify(ctx->children[i]);
      if (c.terminal != nullptr) {
        if (c.is_error) {
          continue;
        }
        antlr4::Token* t = c.terminal->getSymbol();
        if (is_end_token(t->getType()) && t->getTokenIndex() != static_cast<size_t>(-1) &&
            t->getStartIndex() != static_cast<size_t>(-1)) {
          const size_t start = t->getStartIndex();
          if (t->getStopIndex() + 1 == start) {  // zero width: inserted, or conjured by recovery
            if (repairs_ != nullptr && repairs_->inserted.contains(start)) {
              const uint32_t at = offsets_.byte_of(start);
              stmt.close_kw = SourceRange{file_, at, at};
              stmt.close_repair = ast::CloseRepair::Inserted;
            }
          } else if (t->getStopIndex() >= start) {
            stmt.close_kw = token_range(t);
            stmt.close_text = view(stmt.close_kw);
            if (repairs_ != nullptr && repairs_->replaced.contains(start)) stmt.close_repair = ast::CloseRepair::Replaced;
          }
        }
        continue;
      }
      antlr4::ParserRuleContext* rule = c.rule;
      if (rule == nullptr) {
        continue;
      }
      if (rule->getRuleIndex() == NomeParser::RuleItem) {
        if (auto item = convert_item(rule)) {
          items.push_back(*item);
        }
      } else if (auto item = block_item(rule)) {
        items.push_back(*item);
      }
    }
    stmt.items = std::move(items);
    if (stmt.kind == ast::BlockKind::Generator) check_generator_end(stmt);
    ast_.stmts.push_back(std::move(stmt));
    ast::Item item;
    item.kind = ast::ItemKind::Block;
    item.range = ast_.stmts.back().range;
    item.block = ast::StmtId{static_cast<int32_t>(ast_.stmts.size() - 1)};
    return item;
  }

  // The grammar closes any generator with any generator's end keyword (they are one token
  // type); the end keyword must close the generator that was opened, or be one the catalogue
  // lists as another spelling (2016's `tunnel … endfunnel`).
  void check_generator_end(const ast::Stmt& stmt) {
    if (diags_ == nullptr || !stmt.close_kw.is_valid() || stmt.close_text == ast::end_keyword(stmt.keyword)) return;
    if (stmt.close_repair != ast::CloseRepair::None) return;  // the checker explains it, by dialect
    const std::optional<ir::GenKind> gen = ir::generator_by_keyword(stmt.keyword);
    if (gen && ir::generator(*gen).closes_with(stmt.keyword, stmt.close_text)) return;
    const std::string close = ast::end_keyword(stmt.keyword);
    diags_->emit(DiagKind::MismatchedEndKeyword, stmt.close_kw,
                 fmt::format("`{}` does not close the open `{}`; expected `{}`", stmt.close_text, stmt.keyword, close))
        .note(stmt.open_kw, fmt::format("`{}` opened here", stmt.keyword))
        .fixit(stmt.close_kw, close, fmt::format("replace with `{}`", close));
  }

  // `item`: a word, a parenthesised list or a value (its one child says which).
  std::optional<ast::Item> convert_item(antlr4::ParserRuleContext* ctx) {
    ast::Item item;
    item.range = ctx_range(ctx);
    Child what = child(ctx, 0);
    switch (what.rule_index()) {
      case NomeParser::RuleWord:
        item.kind = ast::ItemKind::Word;
        item.range = ctx_range(what.rule);
        item.text = view(item.range);
        return item;
      case NomeParser::RuleParenList:
        item.kind = ast::ItemKind::List;
        item.list = convert_list(what.rule);
        return item;
      case NomeParser::RuleItemExpr:
        item.kind = ast::ItemKind::Value;
        item.expr = convert_expr(what.rule);
        return item;
      default:
        return std::nullopt;
    }
  }

  ast::ListId convert_list(antlr4::ParserRuleContext* ctx) {
    ast::ParenList list;
    list.range = ctx_range(ctx);
    for (antlr4::tree::ParseTree* t : ctx->children) {
      Child c = classify(t);
      if (c.rule_index() == NomeParser::RuleListExpr) {
        list.elems.push_back(convert_expr(c.rule));
      } else if (c.token_type() == NomeParser::COMMA) {
        list.commas.push_back(token_range(c.terminal->getSymbol()));
      }
    }
    ast_.lists.push_back(std::move(list));
    return ast::ListId{static_cast<int32_t>(ast_.lists.size() - 1)};
  }

  ast::ExprId add(ast::Expr e) {
    ast_.exprs.push_back(std::move(e));
    return ast::ExprId{static_cast<int32_t>(ast_.exprs.size() - 1)};
  }

  ast::ExprId error_expr(antlr4::ParserRuleContext* ctx) {
    ast::Expr e;
    e.kind = ast::ExprKind::Error;
    const bool anchored = ctx != nullptr && ctx->start != nullptr;
    e.range = anchored ? ctx_range(ctx) : SourceRange{file_, 0, 0};
    ast::ExprId id = add(e);
    if (!anchored && unanchored_ != nullptr) unanchored_->push_back(id.index);
    return id;
  }

  static char op_of(antlr4::Token* t) {
    switch (t->getType()) {
      case NomeParser::PLUS:
      case NomeParser::SPLUS:
        return '+';
      case NomeParser::MINUS:
      case NomeParser::SMINUS:
        return '-';
      case NomeParser::STAR:
        return '*';
      case NomeParser::SLASH:
        return '/';
      case NomeParser::DSLASH:
        return 'i';
      case NomeParser::PERCENT:
        return '%';
      case NomeParser::CARET:
        return '^';
      default:
        return '?';
    }
  }

  // The expression rules (`expr`, `listExpr`, `itemExpr`) are flat runs
  // `sign* atom (op sign* atom)*`; this applies the precedence, loosest to tightest:
  // `+ -`; `* / % //`; unary signs; `^` (right-associative; its right operand may carry
  // signs). An atom (`atom`, `itemAtom`) converts directly.
  ast::ExprId convert_expr(antlr4::ParserRuleContext* ctx) {
    if (ctx == nullptr || ctx->children.empty() || ctx->exception != nullptr) {
      return error_expr(ctx);
    }
    switch (ctx->getRuleIndex()) {
      case NomeParser::RuleExpr:
      case NomeParser::RuleListExpr:
      case NomeParser::RuleItemExpr: {
        Run run{ctx, {}, 0};
        run.items.reserve(ctx->children.size());
        for (antlr4::tree::ParseTree* t : ctx->children) {
          Child c = classify(t);
          if (c.is_error) return error_expr(ctx);
          run.items.push_back(c);
        }
        ast::ExprId e = binary(run, 1);
        return run.pos == run.items.size() ? e : error_expr(ctx);
      }
      default:
        return convert_atom(ctx);
    }
  }

  // A flat expression being read (see convert_expr).
  struct Run {
    antlr4::ParserRuleContext* ctx;
    std::vector<Child> items;
    size_t pos;
    const Child* peek() const { return pos < items.size() ? &items[pos] : nullptr; }
  };

  static int binary_level(size_t type) {
    switch (type) {
      case NomeParser::PLUS: case NomeParser::MINUS: case NomeParser::SPLUS: case NomeParser::SMINUS: return 1;
      case NomeParser::STAR: case NomeParser::SLASH: case NomeParser::DSLASH: case NomeParser::PERCENT: return 2;
      default: return 0;
    }
  }

  ast::ExprId binary_expr(antlr4::Token* op, ast::ExprId lhs, ast::ExprId rhs) {
    ast::Expr e;
    e.kind = ast::ExprKind::Binary;
    e.op = op_of(op);
    e.lhs = lhs;
    e.rhs = rhs;
    // An operand the parser could not read may have no position (offset 0): the range
    // never ends before it begins.
    const SourceRange& l = ast_.exprs[lhs.index].range;
    const SourceRange& r = ast_.exprs[rhs.index].range;
    e.range = SourceRange{file_, l.begin, std::max(l.end, r.end)};
    return add(e);
  }

  // Operators of level `min` and looser-binding ones' operands: left-associative.
  ast::ExprId binary(Run& run, int min) {
    ast::ExprId lhs = unary(run);
    while (const Child* op = run.peek()) {
      const int level = op->terminal != nullptr ? binary_level(op->token_type()) : 0;
      if (level == 0 || level < min) break;
      ++run.pos;
      ast::ExprId rhs = binary(run, level + 1);
      lhs = binary_expr(op->terminal->getSymbol(), lhs, rhs);
    }
    return lhs;
  }

  // Signs, then a power.
  ast::ExprId unary(Run& run) {
    const Child* sign = run.peek();
    if (sign == nullptr || sign->terminal == nullptr) return power(run);
    const size_t type = sign->token_type();
    if (type != NomeParser::PLUS && type != NomeParser::MINUS && type != NomeParser::SPLUS &&
        type != NomeParser::SMINUS) {
      return error_expr(run.ctx);
    }
    ++run.pos;
    ast::Expr e;
    e.kind = ast::ExprKind::Unary;
    e.op = op_of(sign->terminal->getSymbol());
    e.lhs = unary(run);
    e.range = SourceRange{file_, token_range(sign->terminal->getSymbol()).begin, ast_.exprs[e.lhs.index].range.end};
    if (e.range.end < e.range.begin) e.range.end = e.range.begin;
    return add(e);
  }

  // An atom, and `^` with its (signed) right operand.
  ast::ExprId power(Run& run) {
    const Child* operand = run.peek();
    if (operand == nullptr || operand->rule == nullptr) return error_expr(run.ctx);
    ++run.pos;
    ast::ExprId base = convert_expr(operand->rule);
    const Child* caret = run.peek();
    if (caret == nullptr || caret->token_type() != NomeParser::CARET) return base;
    ++run.pos;
    ast::ExprId exponent = unary(run);
    return binary_expr(caret->terminal->getSymbol(), base, exponent);
  }

  ast::ExprId token_expr(ast::ExprKind kind, antlr4::Token* t) {
    ast::Expr e;
    e.kind = kind;
    e.range = token_range(t);
    e.text = view(e.range);
    if (kind == ast::ExprKind::Number) {
      e.number = std::strtod(std::string(e.text).c_str(), nullptr);
    }
    return add(e);
  }

  // `braceExpr`: `{expr …}` / `{…}` around an expression, or raw Tcl braces.
  ast::ExprId convert_brace(antlr4::ParserRuleContext* b) {
    if (antlr4::ParserRuleContext* tcl = rule_child(b, NomeParser::RuleTclBraces)) {
      ast::Expr e;
      e.kind = ast::ExprKind::Raw;
      e.in_braces = true;
      e.range = ctx_range(tcl);
      e.text = view(e.range);
      return add(e);
    }
    ast::ExprId inner = convert_expr(rule_child(b, NomeParser::RuleExpr));
    ast_.exprs[inner.index].in_braces = true;
    return inner;
  }

  // `atom` and `itemAtom`: each alternative starts with a different token or rule.
  ast::ExprId convert_atom(antlr4::ParserRuleContext* ctx) {
    Child first = child(ctx, 0);
    switch (first.token_type()) {
      case NomeParser::NUMBER: return token_expr(ast::ExprKind::Number, first.terminal->getSymbol());
      case NomeParser::DOLLAR_REF: return token_expr(ast::ExprKind::DollarRef, first.terminal->getSymbol());
      case NomeParser::TCL_ARRAY_REF: return token_expr(ast::ExprKind::TclArrayRef, first.terminal->getSymbol());
      case NomeParser::BRACKET_RAW:
      case NomeParser::PCT_RAW: return token_expr(ast::ExprKind::Raw, first.terminal->getSymbol());
      case NomeParser::STRING: return token_expr(ast::ExprKind::String, first.terminal->getSymbol());
      case NomeParser::LPAREN: {  // `( expr )`
        ast::ExprId inner = convert_expr(rule_child(ctx, NomeParser::RuleExpr));
        ast_.exprs[inner.index].parenthesized = true;
        return inner;
      }
      default: break;
    }
    if (first.rule_index() == NomeParser::RuleBraceExpr) return convert_brace(first.rule);
    if (first.rule_index() == NomeParser::RuleWord) {
      ast::Expr e;
      e.text = view(ctx_range(first.rule));
      if (child(ctx, 1).token_type() != NomeParser::LPAREN) {  // a name
        e.kind = ast::ExprKind::Name;
        e.range = ctx_range(first.rule);
        return add(e);
      }
      e.kind = ast::ExprKind::Call;  // `word ( expr (, expr)* )`
      e.range = ctx_range(ctx);
      for (antlr4::tree::ParseTree* t : ctx->children) {
        Child arg = classify(t);
        if (arg.rule_index() == NomeParser::RuleExpr) e.args.push_back(convert_expr(arg.rule));
      }
      return add(e);
    }
    return error_expr(ctx);
  }

  FileId file_;
  std::string_view text_;
  const Offsets& offsets_;
  ast::Ast& ast_;
  std::vector<int32_t>* unanchored_;  // ids of error expressions placed at offset 0
  DiagnosticEngine* diags_;           // syntax errors the grammar leaves to the builder

 public:
  const LineEndRepairs* repairs_ = nullptr;  // ends found for single-line statements
};

}  // namespace

ast::Ast parse_piece(std::string_view text, FileId file, const PieceSinks& sinks,
                     PieceInfo* info) {
  ast::Ast result;
  result.file = file;

  Offsets offsets;
  offsets.text_size = static_cast<uint32_t>(text.size());
  std::u32string decoded = decode_utf8(text, offsets);
  bool comment_open = blank_block_comments(decoded, offsets, file, sinks.comments);
  DecodedInput input(std::move(decoded));
  NomeLexer lexer(&input);
  input.lexer_ = &lexer;
  lexer.removeErrorListeners();
  SilentListener silent;
  lexer.addErrorListener(&silent);
  std::vector<std::unique_ptr<antlr4::Token>> raw = lexer.getAllTokens();
  input.lexer_ = nullptr;
  // Only the trailing whitespace may have looked at the end of the text (see DecodedInput).
  bool lexer_contained = raw.empty() ? input.eof_touch_start_ == static_cast<size_t>(-1)
                                     : (raw.back()->getType() == NomeLexer::WS || raw.back()->getType() == NomeLexer::NBSP) &&
                                           input.eof_touch_start_ >= raw.back()->getStartIndex();
  // getAllTokens() stops before EOF; add it so the parser sees a proper end.
  raw.push_back(lexer.getTokenFactory()->create(
      {&lexer, &input}, antlr4::Token::EOF, "<EOF>", antlr4::Token::DEFAULT_CHANNEL,
      input.size(), input.size() - 1, 0, 0));
  bool stopped = false;
  DiagnosticEngine token_diags;
  std::vector<std::unique_ptr<antlr4::Token>> tokens =
      prepare_tokens(std::move(raw), text, offsets, file, token_diags, stopped);
  // Repairs only where the whole text was read (a limit may have cut it short). Their
  // diagnostics join the token pass's in position order, as a piece of the file reports them.
  LineEndRepairs repairs;
  if (!stopped) {
    DiagnosticEngine repair_diags;
    insert_missing_open_parens(tokens, offsets, file, repair_diags);
    token_diags.merge_in_order(std::move(repair_diags));
    end_line_statements(tokens, text, offsets, repairs);
  }
  sinks.tokens.append(std::move(token_diags));
  antlr4::Token* last_real = nullptr;
  size_t first_type = antlr4::Token::EOF;
  for (const auto& t : tokens) {
    if (t->getType() != antlr4::Token::EOF && t->getChannel() == antlr4::Token::DEFAULT_CHANNEL) {
      if (last_real == nullptr) first_type = t->getType();
      last_real = t.get();
    }
  }

  antlr4::ListTokenSource source(std::move(tokens));
  WatchedTokenStream stream(&source);
  NomeParser parser(&stream);
  stream.parser_ = &parser;
  stream.last_real_ = last_real;
  parser.removeErrorListeners();

  // Stage 1: fast SLL prediction that bails on the first error.
  parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(
      antlr4::atn::PredictionMode::SLL);
  parser.setErrorHandler(std::make_shared<antlr4::BailErrorStrategy>());
  NomeParser::FileContext* tree = nullptr;
  try {
    tree = parser.file();
  } catch (const antlr4::ParseCancellationException&) {
    tree = nullptr;
  }
  SyntaxErrorListener listener(file, offsets, sinks.syntax);
  if (tree == nullptr) {
    // Stage 2: error reporting and recovery. Still SLL prediction: the grammar needs no
    // more (stage 1 would fail on a valid file that did), and full LL costs four times as
    // much on the files that reach this stage, those with syntax errors.
    stream.seek(0);
    parser.reset();
    parser.addErrorListener(&listener);
    parser.setErrorHandler(std::make_shared<QuietErrorStrategy>());
    parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(
        antlr4::atn::PredictionMode::SLL);
    try {
      tree = parser.file();
    } catch (const std::exception&) {
      tree = nullptr;  // recovery gave up; diagnostics were emitted
      stream.eof_seen_early_ = true;
    }
  }
  if (info != nullptr) {
    // At the start of a file the parser enters `topStmt*`; inside a file it loops back to
    // it. The two recover differently from a token that cannot start a statement.
    const antlr4::atn::ATN& atn = parser.getATN();
    info->starts_cleanly =
        first_type == antlr4::Token::EOF ||
        atn.nextTokens(atn.ruleToStartState[NomeParser::RuleTopStmt]).contains(first_type);
    info->self_contained = !comment_open && !stopped && lexer_contained && !stream.eof_seen_early_;
  }
  if (tree != nullptr) {
    AstBuilder builder(file, text, offsets, result,
                       info != nullptr ? &info->unanchored_exprs : nullptr, &sinks.syntax);
    builder.repairs_ = &repairs;
    builder.build_file(tree);
  }
  return result;
}

ast::Ast parse_file(const SourceManager& sources, FileId file, DiagnosticEngine& diags) {
  return parse_piece(sources.text(file), file, PieceSinks{diags, diags, diags}, nullptr);
}

ast::ExprId parse_function_text(std::string_view file_text, FileId file, SourceRange raw, ast::Ast& out,
                                DiagnosticEngine& diags) {
  uint32_t b = std::min<uint32_t>(raw.begin, static_cast<uint32_t>(file_text.size()));
  uint32_t e = std::clamp<uint32_t>(raw.end, b, static_cast<uint32_t>(file_text.size()));
  if (e > b && file_text[b] == '[') ++b;
  if (e > b && file_text[e - 1] == ']') --e;
  const std::string_view text = file_text.substr(b, e - b);
  if (std::all_of(text.begin(), text.end(), [](char ch) { return std::isspace(static_cast<unsigned char>(ch)) != 0; })) {
    diags.emit(DiagKind::SyntaxError, raw, "the function is empty; write one expression of its variables, e.g. `cos(u)*v`");
    ast::Expr x;
    x.kind = ast::ExprKind::Error;
    x.range = raw;
    out.exprs.push_back(x);
    return ast::ExprId(static_cast<int32_t>(out.exprs.size() - 1));
  }
  Offsets offsets;
  offsets.text_size = static_cast<uint32_t>(text.size());
  offsets.base = b;
  DecodedInput input(decode_utf8(text, offsets));
  NomeLexer lexer(&input);
  lexer.removeErrorListeners();
  SilentListener silent;
  lexer.addErrorListener(&silent);
  std::vector<std::unique_ptr<antlr4::Token>> raw_tokens = lexer.getAllTokens();
  raw_tokens.push_back(lexer.getTokenFactory()->create({&lexer, &input}, antlr4::Token::EOF, "<EOF>",
                                                       antlr4::Token::DEFAULT_CHANNEL, input.size(), input.size() - 1, 0, 0));
  bool stopped = false;
  DiagnosticEngine token_diags;
  std::vector<std::unique_ptr<antlr4::Token>> tokens =
      prepare_tokens(std::move(raw_tokens), text, offsets, file, token_diags, stopped, "function");
  const bool token_errors = token_diags.error_count() > 0;
  diags.append(std::move(token_diags));
  auto error = [&](SourceRange at) {
    ast::Expr x;
    x.kind = ast::ExprKind::Error;
    x.range = at;
    out.exprs.push_back(x);
    return ast::ExprId(static_cast<int32_t>(out.exprs.size() - 1));
  };
  if (token_errors || stopped) return error(raw);  // one message: the parser would only echo it
  insert_implicit_multiplication(tokens);
  antlr4::ListTokenSource source(std::move(tokens));
  antlr4::CommonTokenStream stream(&source);
  NomeParser parser(&stream);
  parser.removeErrorListeners();
  SyntaxErrorListener listener(file, offsets, diags);
  listener.in_function();
  // As for files: SLL prediction that bails on the first error, then again with error
  // reporting and recovery only when that fails.
  parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(antlr4::atn::PredictionMode::SLL);
  parser.setErrorHandler(std::make_shared<antlr4::BailErrorStrategy>());
  NomeParser::FunctionTextContext* tree = nullptr;
  try {
    tree = parser.functionText();
  } catch (const std::exception&) {
    tree = nullptr;
  }
  if (tree == nullptr) {
    stream.seek(0);
    parser.reset();
    parser.addErrorListener(&listener);
    parser.setErrorHandler(std::make_shared<QuietErrorStrategy>());
    parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(antlr4::atn::PredictionMode::SLL);
    try {
      tree = parser.functionText();
    } catch (const std::exception&) {
      tree = nullptr;
    }
  }
  antlr4::ParserRuleContext* expr = tree != nullptr ? rule_child(tree, NomeParser::RuleExpr) : nullptr;
  if (expr == nullptr || listener.error_count() > 0) {
    return error(raw);
  }
  AstBuilder builder(file, text, offsets, out, nullptr, &diags);
  return builder.build_expr(expr);
}

}  // namespace nomec

// ---- Token stream for text tools (the formatter): the parse layer's lexer, comments kept.
namespace nomec {

std::vector<LexToken> lex_file(std::string_view text) {
  Offsets offsets;
  offsets.text_size = static_cast<uint32_t>(text.size());
  std::u32string original = decode_utf8(text, offsets);
  std::u32string blanked = original;
  DiagnosticEngine ignored;
  blank_block_comments(blanked, offsets, FileId{}, ignored);
  DecodedInput input(std::move(blanked));
  NomeLexer lexer(&input);
  lexer.removeErrorListeners();
  SilentListener silent;
  lexer.addErrorListener(&silent);
  std::vector<LexToken> out;
  auto push = [&](LexKind kind, size_t first_cp, size_t end_cp) {
    out.push_back(LexToken{kind, offsets.byte_of(first_cp), offsets.byte_of(end_cp)});
  };
  // An unclosed string, `[` or `%{` is one token to the end of its line or of the text;
  // the lexer's tokens inside it are skipped.
  size_t skip_to = 0;
  int brace_depth = 0;
  auto forgive = [&](LexKind kind, size_t begin, size_t end) {
    push(kind, begin, end);
    skip_to = end;
  };
  for (const auto& tok : lexer.getAllTokens()) {
    size_t begin = tok->getStartIndex();
    size_t end = tok->getStopIndex() + 1;
    if (begin < skip_to) continue;
    switch (tok->getType()) {
      case NomeLexer::WS:
        // Blanked block comments are whitespace here: find them in the original text.
        for (size_t i = begin; i < end; ++i) {
          if (original[i] != '(' || i + 1 >= end || original[i + 1] != '*') continue;
          size_t depth = 0;
          size_t j = i;
          for (; j < end; ++j) {
            if (original[j] == '(' && j + 1 < end && original[j + 1] == '*') {
              ++depth;
              ++j;
            } else if (original[j] == '*' && j + 1 < end && original[j + 1] == ')') {
              ++j;
              if (--depth == 0) break;
            }
          }
          size_t stop = std::min(j + 1, end);
          push(LexKind::BlockComment, i, stop);
          i = stop - 1;
        }
        continue;
      case NomeLexer::NBSP: continue;  // whitespace (the checker warns)
      case NomeLexer::LINE_COMMENT: push(LexKind::LineComment, begin, end); continue;
      // Not blanked when it follows a `#` comment ended by a lone `\r`; ANTLR lexes it whole.
      case NomeLexer::BLOCK_COMMENT: push(LexKind::BlockComment, begin, end); continue;
      case NomeLexer::TCLINIT: push(LexKind::TclInit, begin, end); continue;
      case NomeLexer::NUMBER: push(LexKind::Number, begin, end); continue;
      case NomeLexer::DOLLAR_REF:
      case NomeLexer::TCL_ARRAY_REF: push(LexKind::DollarRef, begin, end); continue;
      case NomeLexer::STRING: push(LexKind::String, begin, end); continue;
      case NomeLexer::BRACKET_RAW:
      case NomeLexer::PCT_RAW: push(LexKind::Raw, begin, end); continue;
      case NomeLexer::LPAREN: push(LexKind::LParen, begin, end); continue;
      case NomeLexer::RPAREN: push(LexKind::RParen, begin, end); continue;
      case NomeLexer::LBRACE:
        ++brace_depth;
        push(LexKind::LBrace, begin, end);
        continue;
      case NomeLexer::RBRACE:
        if (brace_depth > 0) --brace_depth;
        push(LexKind::RBrace, begin, end);
        continue;
      case NomeLexer::COMMA: push(LexKind::Comma, begin, end); continue;
      case NomeLexer::PLUS:
      case NomeLexer::MINUS:
      case NomeLexer::STAR:
      case NomeLexer::SLASH:
      case NomeLexer::DSLASH:
      case NomeLexer::CARET: push(LexKind::Operator, begin, end); continue;
      case NomeLexer::UNEXPECTED_CHAR:
        if (original[begin] == '"') {
          size_t e = begin + 1;
          while (e < original.size() && original[e] != '\n' && original[e] != '\r') ++e;
          forgive(LexKind::String, begin, e);
        } else if (original[begin] == '[' && brace_depth == 0) {
          // A balanced `[ … ]` would be BRACKET_RAW. Inside braces (Tcl text) the parser reads
          // a lone `[` as one character, and so does this lexer (the formatter relies on it).
          forgive(LexKind::Raw, begin, original.size());
        } else {
          push(LexKind::Other, begin, end);
        }
        continue;
      case NomeLexer::PERCENT:
        if (begin + 1 < original.size() && original[begin + 1] == '{') {  // `%{` with no `}%`
          forgive(LexKind::Raw, begin, original.size());
        } else {
          push(LexKind::Operator, begin, end);
        }
        continue;
      default: push(LexKind::Word, begin, end); continue;  // IDENT and every keyword
    }
  }
  return out;
}

}  // namespace nomec
