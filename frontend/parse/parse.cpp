// Parse layer implementation. Stages: lex with the hand-written lexer (lexer.cpp; ANTLR's
// generated NomeLexer is its reference and fallback); the token passes (token_passes.cpp)
// that report stray characters and unclosed comments/blocks, assign the list-sign token
// types (SPLUS/SMINUS, language.md §3), retype generator keywords (K_GEN/E_GEN) and insert
// repairs; parse the default-channel tokens (token_stream.h) with the generated parser,
// SLL prediction that bails on the first error, then again with error recovery if it did;
// then convert the parse tree into the ANTLR-free AST of frontend/ast.
#include "frontend/parse/parse.h"
#include "frontend/parse/piece.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cctype>
#include <cstring>
#include <cstdlib>
#include <fmt/format.h>
#include <memory>
#include <optional>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "ir/generator_catalogue.h"

#include "frontend/parse/generated.h"
#include "frontend/parse/prediction_seed.h"

#include "frontend/parse/recovery.h"
#include "frontend/parse/token_passes.h"
#include "frontend/parse/token_stream.h"
#include "frontend/parse/tokens.h"

namespace nomec {

namespace {

using nomec_antlr::NomeLexer;
using nomec_antlr::NomeParser;
using namespace parse_detail;

// Token offsets are bytes of the text parsed. A text parsed on its own but lying inside a
// file (the function of `funcX [ … ]`) has the offset of its first byte in `base`, so
// ranges are file offsets.
struct Offsets {
  uint32_t text_size = 0;
  uint32_t base = 0;
  // Clamped to the text: tokens the parser conjures during recovery have no real position.
  uint32_t local_of(size_t at) const { return static_cast<uint32_t>(std::min<size_t>(at, text_size)); }
  uint32_t byte_of(size_t at) const { return base + local_of(at); }
};

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
          is_open_type(c->start->getType())) {
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
    antlr4::TokenStream* stream = parser->getTokenStream();
    const size_t at = stream->index();
    return at > 0 ? stream->get(at - 1) : nullptr;  // the stream holds default-channel tokens only
  }
};

// Whether a token of type `type` can start a top-level statement (`topStmt`).
bool starts_statement(const antlr4::atn::ATN& atn, size_t type) {
  return atn.nextTokens(atn.ruleToStartState[NomeParser::RuleTopStmt]).contains(type);
}

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


// Stage 2's strategy: QuietErrorStrategy's recovery, which (when `stops`) stops the parse
// at the first statement boundary after an error where a recovering parse of the whole text
// would read on exactly as a fresh parse from there: at the `topStmt*` loop of `file`,
// facing a token that starts a statement (so the loop's `sync` has nothing to do and the
// loop goes on into `topStmt`, with `file` the only rule above it, as in a parse started
// there), and out of error recovery (which also clears the strategy's record of where the
// last error was, its guard against looping; the grammar matches every statement's first
// token before it can report an error, so no parse reaches this loop in error recovery
// with a difference to show, but a grammar change could). It throws `Stop` from the loop's
// `sync`, before which nothing was built for that statement, and stage 1 reads on.
class RecoveringStrategy final : public QuietErrorStrategy {
 public:
  struct Stop {
    NomeParser::FileContext* file;
    size_t token;  // the next statement's first token
  };
  /// Stops only after `after`, the token the parse starts at (so each stop makes progress).
  RecoveringStrategy(bool stops, size_t after) : stops_(stops), after_(after) {}

  void reportError(antlr4::Parser* parser, const antlr4::RecognitionException& e) override {
    had_error_ = true;
    QuietErrorStrategy::reportError(parser, e);
  }
  void sync(antlr4::Parser* parser) override {
    if (stops_ && had_error_ && !inErrorRecoveryMode(parser) && parser->getContext() != nullptr &&
        parser->getContext()->getRuleIndex() == NomeParser::RuleFile) {
      const size_t at = parser->getTokenStream()->index();
      const size_t type = parser->getTokenStream()->LA(1);
      if (at > after_ && type != antlr4::Token::EOF && starts_statement(parser->getATN(), type)) {
        throw Stop{static_cast<NomeParser::FileContext*>(parser->getContext()), at};
      }
    }
    QuietErrorStrategy::sync(parser);
  }

 protected:
  void reportUnwantedToken(antlr4::Parser* parser) override {
    had_error_ = true;
    QuietErrorStrategy::reportUnwantedToken(parser);
  }
  void reportMissingToken(antlr4::Parser* parser) override {
    had_error_ = true;
    QuietErrorStrategy::reportMissingToken(parser);
  }

 private:
  bool stops_;
  size_t after_;
  bool had_error_ = false;
};

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
      if (top.rule != nullptr && top.rule_index() == NomeParser::RuleTopStmt) build_top(top.rule);
    }
  }

  /// One `topStmt`: its item is appended to the AST's top level.
  void build_top(antlr4::ParserRuleContext* top) {
    {
      Child inner = child(top, 0);
      if (inner.token_type() == NomeParser::TCLINIT) {
        ast::Item item;
        item.kind = ast::ItemKind::Tcl;
        item.range = token_range(inner.terminal->getSymbol());
        item.text = view(item.range);
        ast_.top.push_back(item);
        return;
      }
      if (inner.rule == nullptr) return;
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

 protected:
  // The end keyword `t` of a block statement (a `Stmt`, or the event builder's frame): its
  // range and text, or, for a zero-width token a line-end repair inserted, an empty range
  // there. A token recovery conjured (no index or no place) and other zero-width tokens leave
  // the block without a close keyword. `Token` is antlr4::Token or, without virtual calls,
  // the final ArenaToken.
  template <typename Block, typename Token>
  void close(Block& block, const Token* t) const {
    if (t->getTokenIndex() == static_cast<size_t>(-1) || t->getStartIndex() == static_cast<size_t>(-1)) return;
    const size_t start = t->getStartIndex();
    if (t->getStopIndex() + 1 == start) {  // zero width: inserted, or conjured by recovery
      if (repairs_ != nullptr && repairs_->inserted.contains(static_cast<uint32_t>(start))) {
        const uint32_t at = offsets_.byte_of(start);
        block.close_kw = SourceRange{file_, at, at};
        block.close_repair = ast::CloseRepair::Inserted;
      }
    } else if (t->getStopIndex() >= start) {
      block.close_kw = SourceRange{file_, offsets_.byte_of(start), offsets_.byte_of(t->getStopIndex() + 1)};
      block.close_text = spelled(start, view(block.close_kw));
      if (repairs_ != nullptr && repairs_->replaced.contains(static_cast<uint32_t>(start))) {
        block.close_repair = ast::CloseRepair::Replaced;
      }
    }
  }

  // A keyword as meant: the token starting at `start` as written, or the keyword the
  // structure pass read it as (`faec` as `face`: frontend/parse/recovery.h).
  std::string_view spelled(size_t start, std::string_view written) const {
    if (repairs_ == nullptr || repairs_->respelled.empty()) return written;
    auto it = repairs_->respelled.find(static_cast<uint32_t>(start));
    return it == repairs_->respelled.end() ? written : it->second;
  }

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
    const std::optional<ast::BlockKind> open = open_kind(ctx->start->getType());
    if (!open) {
      return std::nullopt;
    }
    ast::Stmt stmt;
    stmt.kind = *open;
    stmt.range = ctx_range(ctx);
    stmt.open_kw = token_range(ctx->start);
    stmt.keyword = spelled(ctx->start->getStartIndex(), view(stmt.open_kw));
    decltype(ast::Stmt::items) items;
    for (size_t i = 1; i < ctx->children.size(); ++i) {
      Child c = classify(ctx->children[i]);
      if (c.terminal != nullptr) {
        if (c.is_error) {
          continue;
        }
        antlr4::Token* t = c.terminal->getSymbol();
        if (is_end_token(t->getType())) close(stmt, t);
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

  // The range of a name: an IDENT token or a `keywordName` context; none for anything else.
  std::optional<SourceRange> name_range(const Child& c) const {
    if (c.token_type() == NomeParser::IDENT) return token_range(c.terminal->getSymbol());
    if (c.rule_index() == NomeParser::RuleKeywordName) return ctx_range(c.rule);
    return std::nullopt;
  }

  // `item`: a word, a parenthesised list or a value (its one child says which).
  std::optional<ast::Item> convert_item(antlr4::ParserRuleContext* ctx) {
    ast::Item item;
    item.range = ctx_range(ctx);
    Child what = child(ctx, 0);
    if (std::optional<SourceRange> name = name_range(what)) {
      item.kind = ast::ItemKind::Word;
      item.range = *name;
      item.text = view(item.range);
      return item;
    }
    switch (what.rule_index()) {
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
    std::vector<SourceRange> commas;
    for (antlr4::tree::ParseTree* t : ctx->children) {
      Child c = classify(t);
      if (c.rule_index() == NomeParser::RuleListExpr) {
        list.elems.push_back(convert_expr(c.rule));
      } else if (c.token_type() == NomeParser::COMMA) {
        commas.push_back(token_range(c.terminal->getSymbol()));
      }
    }
    // Ids are given as lists end, so a nested list's commas come before its parent's.
    ast_.lists.push_back(std::move(list));
    const ast::ListId id{static_cast<int32_t>(ast_.lists.size() - 1)};
    for (SourceRange r : commas) ast_.commas.push_back({id, r});
    return id;
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
  // `sign* operand (op sign* operand)*`, an operand being a NUMBER or DOLLAR_REF token or
  // an atom; this applies the precedence, loosest to tightest: `+ -`; `* / % //`; unary
  // signs; `^` (right-associative; its right operand may carry signs). An atom (`atom`,
  // `itemAtom`) converts directly.
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
    e.set_operands(lhs, rhs);
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
    if (sign == nullptr || sign->terminal == nullptr || is_token_operand(sign->token_type())) return power(run);
    const size_t type = sign->token_type();
    if (type != NomeParser::PLUS && type != NomeParser::MINUS && type != NomeParser::SPLUS &&
        type != NomeParser::SMINUS) {
      return error_expr(run.ctx);
    }
    ++run.pos;
    ast::Expr e;
    e.kind = ast::ExprKind::Unary;
    e.op = op_of(sign->terminal->getSymbol());
    const ast::ExprId operand = unary(run);
    e.set_operands(operand);
    e.range = SourceRange{file_, token_range(sign->terminal->getSymbol()).begin, ast_.exprs[operand.index].range.end};
    if (e.range.end < e.range.begin) e.range.end = e.range.begin;
    return add(e);
  }

  // An operand the expression rules read as a token (not through `atom`).
  static bool is_token_operand(size_t type) { return type == NomeParser::NUMBER || type == NomeParser::DOLLAR_REF; }

  // An operand (a NUMBER or DOLLAR_REF token, or an atom), and `^` with its (signed) right
  // operand.
  ast::ExprId power(Run& run) {
    const Child* operand = run.peek();
    if (operand == nullptr) return error_expr(run.ctx);
    const size_t type = operand->token_type();
    if (operand->rule == nullptr && !is_token_operand(type)) return error_expr(run.ctx);
    ++run.pos;
    ast::ExprId base = operand->rule != nullptr ? convert_expr(operand->rule)
                       : token_expr(type == NomeParser::NUMBER ? ast::ExprKind::Number : ast::ExprKind::DollarRef,
                                    operand->terminal->getSymbol());
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
      e.set_number(std::strtod(std::string(e.text).c_str(), nullptr));
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
    if (std::optional<SourceRange> name = name_range(first)) {
      ast::Expr e;
      e.text = view(*name);
      if (child(ctx, 1).token_type() != NomeParser::LPAREN) {  // a name
        e.kind = ast::ExprKind::Name;
        e.range = *name;
        return add(e);
      }
      e.kind = ast::ExprKind::Call;  // `name ( expr (, expr)* )`
      e.range = ctx_range(ctx);
      SmallVec<ast::ExprId, 4> args;  // an argument's own calls add theirs to `Ast::args` first
      for (antlr4::tree::ParseTree* t : ctx->children) {
        Child arg = classify(t);
        if (arg.rule_index() == NomeParser::RuleExpr) args.push_back(convert_expr(arg.rule));
      }
      e.set_args(static_cast<uint32_t>(ast_.args.size()), args.size());
      ast_.args.insert(ast_.args.end(), args.begin(), args.end());
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


// Builds the AST from the generated parser's events while it builds no parse tree (stage 1,
// which bails on the first syntax error): exactly what AstBuilder makes of the parse tree
// of an error-free parse, node for node and in the same order. Every rule invocation is a
// frame; a frame hands its result (an item, an expression, a list, a name) to the frame
// below when its rule exits. The flat expression rules apply the precedence as their
// tokens arrive (operator precedence with two stacks), which creates the nodes in the order
// AstBuilder's recursive descent over the finished run does: every operand's nodes when
// the operand is read, every operator's node when the next operator or the end shows it
// complete. Items, list elements, call arguments and operators wait on stacks shared by
// all frames, so the parse allocates nothing per rule.
class StreamBuilder final : public AstBuilder, public nomec_antlr::ParseEvents {
 public:
  using AstBuilder::AstBuilder;

  /// Stops reading events: the parse is bailing out on a syntax error.
  void abandon() { dead_ = true; }
  bool dead() const { return dead_; }

  void enter_rule(antlr4::ParserRuleContext*, size_t rule) override {
    if (dead_) return;
    Frame f;
    f.kind = kind_of(rule);
    f.items_at = static_cast<uint32_t>(items_.size());
    f.operands_at = static_cast<uint32_t>(operands_.size());
    f.ops_at = static_cast<uint32_t>(ops_.size());
    f.commas_at = static_cast<uint32_t>(commas_.size());
    frames_.push_back(f);
  }

  void token(antlr4::Token* token) override {
    if (dead_ || frames_.empty()) return;
    const auto* t = static_cast<const ArenaToken*>(token);
    Frame& f = frames_.back();
    const size_t type = t->getType();
    switch (f.kind) {
      case Kind::Top:
        if (type == NomeParser::TCLINIT) {
          ast::Item item;
          item.kind = ast::ItemKind::Tcl;
          item.range = range_of(t);
          item.text = view(item.range);
          ast_.top.push_back(item);
        }
        break;
      case Kind::Include:
        if (type == NomeParser::STRING && !f.has_name) {
          f.name = range_of(t);
          f.has_name = true;
        }
        break;
      case Kind::Item:
      case Kind::Stray:
        if (type == NomeParser::IDENT) {
          f.name = range_of(t);
          f.what = What::Word;
        }
        break;
      case Kind::Stmt:
        if (!f.opened) {
          f.opened = true;  // the opening keyword: the context's start token
        } else if (is_end_token(type)) {
          close(f, t);
        }
        break;
      case Kind::ParenList:
        if (type == NomeParser::COMMA) commas_.push_back(range_of(t));
        break;
      case Kind::Expr:
        expr_token(f, t, type);
        break;
      case Kind::Atom:
        switch (type) {
          case NomeParser::TCL_ARRAY_REF: f.result = leaf(ast::ExprKind::TclArrayRef, t); break;
          case NomeParser::BRACKET_RAW:
          case NomeParser::PCT_RAW: f.result = leaf(ast::ExprKind::Raw, t); break;
          case NomeParser::STRING: f.result = leaf(ast::ExprKind::String, t); break;
          case NomeParser::IDENT:
            f.name = range_of(t);
            f.has_name = true;
            break;
          case NomeParser::LPAREN:
            if (f.atom == AtomForm::Plain) f.atom = f.has_name ? AtomForm::Call : AtomForm::Paren;
            break;
          default: break;
        }
        break;
      default:
        break;
    }
  }

  void exit_rule(antlr4::ParserRuleContext* ctx) override {
    if (dead_ || frames_.empty()) return;
    const Frame f = frames_.back();
    frames_.pop_back();
    switch (f.kind) {
      case Kind::Include: {
        ast::Item item;
        item.kind = ast::ItemKind::Include;
        item.range = range_of(ctx);
        if (f.has_name && f.name.end >= f.name.begin + 2) {  // a conjured (missing) string has no text
          item.text = view(SourceRange{file_, f.name.begin + 1, f.name.end - 1});
        }
        deliver_item(item);
        break;
      }
      case Kind::Stray: {
        ast::Item item;
        item.range = range_of(ctx);
        if (f.what == What::List) {
          item.kind = ast::ItemKind::List;
          item.list = ast::ListId{f.result};
        } else if (f.what == What::Value) {
          item.kind = ast::ItemKind::Value;
          item.expr = ast::ExprId{f.result};
        } else {
          item.kind = ast::ItemKind::Word;
          item.text = view(item.range);
        }
        deliver_item(item);
        break;
      }
      case Kind::Item: {
        ast::Item item;
        item.range = range_of(ctx);
        switch (f.what) {
          case What::Word:
            item.kind = ast::ItemKind::Word;
            item.range = f.name;
            item.text = view(item.range);
            break;
          case What::List:
            item.kind = ast::ItemKind::List;
            item.list = ast::ListId{f.result};
            break;
          case What::Value:
            item.kind = ast::ItemKind::Value;
            item.expr = ast::ExprId{f.result};
            break;
          case What::None: return;
        }
        deliver_item(item);
        break;
      }
      case Kind::Stmt:
        finish_stmt(f, ctx);
        break;
      case Kind::ParenList: {
        ast::ParenList list;
        list.range = range_of(ctx);
        list.elems.reserve(static_cast<uint32_t>(operands_.size() - f.operands_at));
        for (size_t i = f.operands_at; i < operands_.size(); ++i) list.elems.push_back(operands_[i]);
        operands_.resize(f.operands_at);
        ast_.lists.push_back(std::move(list));
        const ast::ListId id{static_cast<int32_t>(ast_.lists.size() - 1)};
        for (size_t i = f.commas_at; i < commas_.size(); ++i) ast_.commas.push_back({id, commas_[i]});
        commas_.resize(f.commas_at);
        deliver_list(id.index);
        break;
      }
      case Kind::Expr: {
        if (!reduce(f, 0) || operands_.size() != f.operands_at + 1u) {
          dead_ = true;
          return;
        }
        const int32_t id = operands_.back().index;
        operands_.pop_back();
        deliver_expr(id);
        break;
      }
      case Kind::Atom:
        switch (f.atom) {
          case AtomForm::Call: {
            ast::Expr e;
            e.kind = ast::ExprKind::Call;
            e.text = view(f.name);
            e.range = range_of(ctx);
            e.set_args(static_cast<uint32_t>(ast_.args.size()), static_cast<uint32_t>(operands_.size() - f.operands_at));
            ast_.args.insert(ast_.args.end(), operands_.begin() + static_cast<ptrdiff_t>(f.operands_at), operands_.end());
            operands_.resize(f.operands_at);
            deliver_expr(add(e).index);
            break;
          }
          case AtomForm::Paren:
            if (f.result < 0) {
              dead_ = true;
              return;
            }
            ast_.exprs[static_cast<size_t>(f.result)].parenthesized = true;
            deliver_expr(f.result);
            break;
          case AtomForm::Plain:
            if (f.has_name) {
              ast::Expr e;
              e.kind = ast::ExprKind::Name;
              e.range = f.name;
              e.text = view(f.name);
              deliver_expr(add(e).index);
            } else if (f.result >= 0) {
              deliver_expr(f.result);
            } else {
              dead_ = true;
            }
            break;
        }
        break;
      case Kind::BraceExpr:
        if (f.has_name) {  // raw Tcl braces (their range is in `name`)
          ast::Expr e;
          e.kind = ast::ExprKind::Raw;
          e.in_braces = true;
          e.range = f.name;
          e.text = view(e.range);
          deliver_expr(add(e).index);
        } else if (f.result >= 0) {
          ast_.exprs[static_cast<size_t>(f.result)].in_braces = true;
          deliver_expr(f.result);
        } else {
          dead_ = true;
        }
        break;
      case Kind::TclBraces:
        if (!frames_.empty() && frames_.back().kind == Kind::BraceExpr && !frames_.back().has_name) {
          frames_.back().name = range_of(ctx);
          frames_.back().has_name = true;
        }
        break;
      case Kind::KeywordName:
        deliver_name(range_of(ctx));
        break;
      default:
        break;
    }
  }

 private:
  enum class Kind : uint8_t { Top, Include, Stray, Block, Stmt, Item, ParenList, Expr, Atom, BraceExpr, TclBraces, KeywordName, Other };
  enum class What : uint8_t { None, Word, List, Value };
  enum class AtomForm : uint8_t { Plain, Call, Paren };

  struct Frame {
    Kind kind = Kind::Other;
    What what = What::None;          // Item, Stray: what the item is
    AtomForm atom = AtomForm::Plain;  // Atom: a call (name then `(`) or `( expr )`
    bool has_name = false;           // Atom: a name was read; Include: its string; BraceExpr: Tcl braces
    bool want_operand = true;        // Expr: an operand comes next (else an operator)
    bool opened = false;             // Stmt: its opening keyword was read
    ast::CloseRepair close_repair = ast::CloseRepair::None;
    int32_t result = -1;             // an expression or list id
    uint32_t items_at = 0, operands_at = 0, ops_at = 0, commas_at = 0;  // bases on the shared stacks
    SourceRange name;
    SourceRange close_kw;
    std::string_view close_text;
  };

  // An operator waiting for its right operand.
  struct PendingOp {
    enum Form : uint8_t { Sign, Caret, Binary } form;
    char op;
    int level;       // Binary: 1 for `+ -`, 2 for `* / % //`
    uint32_t begin;  // Sign: where the sign starts
  };

  static Kind kind_of(size_t rule) {
    switch (rule) {
      case NomeParser::RuleFile:
      case NomeParser::RuleFunctionText: return Kind::Other;
      case NomeParser::RuleTopStmt: return Kind::Top;
      case NomeParser::RuleIncludeStmt: return Kind::Include;
      case NomeParser::RuleStrayItem: return Kind::Stray;
      case NomeParser::RuleBlock: return Kind::Block;
      case NomeParser::RuleItem: return Kind::Item;
      case NomeParser::RuleParenList: return Kind::ParenList;
      case NomeParser::RuleExpr:
      case NomeParser::RuleListExpr:
      case NomeParser::RuleItemExpr: return Kind::Expr;
      case NomeParser::RuleAtom:
      case NomeParser::RuleItemAtom: return Kind::Atom;
      case NomeParser::RuleBraceExpr: return Kind::BraceExpr;
      case NomeParser::RuleTclBraces: return Kind::TclBraces;
      case NomeParser::RuleKeywordName: return Kind::KeywordName;
      default: return Kind::Stmt;  // every block statement rule
    }
  }

  SourceRange range_of(const ArenaToken* t) const {
    return SourceRange{file_, offsets_.byte_of(t->getStartIndex()), offsets_.byte_of(t->getStopIndex() + 1)};
  }
  // AstBuilder::ctx_range, reading the arena tokens directly.
  SourceRange range_of(const antlr4::ParserRuleContext* ctx) const {
    const auto* start = static_cast<const ArenaToken*>(ctx->start);
    const auto* stop = static_cast<const ArenaToken*>(ctx->stop);
    const size_t begin_cp = start != nullptr ? start->getStartIndex() : 0;
    const uint32_t begin = offsets_.byte_of(begin_cp);
    uint32_t end = begin;
    if (stop != nullptr && stop->getType() != antlr4::Token::EOF && stop->getStopIndex() + 1 >= begin_cp) {
      end = offsets_.byte_of(stop->getStopIndex() + 1);
    }
    return SourceRange{file_, begin, end};
  }

  int32_t leaf(ast::ExprKind kind, const ArenaToken* t) {
    ast::Expr e;
    e.kind = kind;
    e.range = range_of(t);
    e.text = view(e.range);
    if (kind == ast::ExprKind::Number) e.set_number(parse_number(e.text));
    return add(e).index;
  }

  // What std::strtod reads from the token's text (a NUMBER token is a plain decimal):
  // std::from_chars rounds as correctly; strtod where it does not read the whole text or
  // the value is out of range (strtod's infinity or zero then).
  static double parse_number(std::string_view text) {
    double value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error == std::errc{} && end == text.data() + text.size()) return value;
    char buffer[64];
    if (text.size() < sizeof buffer) {
      std::memcpy(buffer, text.data(), text.size());
      buffer[text.size()] = '\0';
      return std::strtod(buffer, nullptr);
    }
    return std::strtod(std::string(text).c_str(), nullptr);
  }

  static char op_char(size_t type) {
    switch (type) {
      case NomeParser::PLUS:
      case NomeParser::SPLUS: return '+';
      case NomeParser::MINUS:
      case NomeParser::SMINUS: return '-';
      case NomeParser::STAR: return '*';
      case NomeParser::SLASH: return '/';
      case NomeParser::DSLASH: return 'i';
      case NomeParser::PERCENT: return '%';
      case NomeParser::CARET: return '^';
      default: return '?';
    }
  }


  void finish_stmt(const Frame& f, antlr4::ParserRuleContext* ctx) {
    const auto* start = static_cast<const ArenaToken*>(ctx->start);
    const std::optional<ast::BlockKind> open = start != nullptr ? open_kind(start->getType()) : std::nullopt;
    if (!open) {
      items_.resize(f.items_at);
      return;
    }
    ast::Stmt stmt;
    stmt.kind = *open;
    stmt.range = range_of(ctx);
    stmt.open_kw = range_of(start);
    stmt.keyword = spelled(start->getStartIndex(), view(stmt.open_kw));
    stmt.close_kw = f.close_kw;
    stmt.close_text = f.close_text;
    stmt.close_repair = f.close_repair;
    stmt.items.reserve(static_cast<uint32_t>(items_.size() - f.items_at));
    for (size_t i = f.items_at; i < items_.size(); ++i) stmt.items.push_back(items_[i]);
    items_.resize(f.items_at);
    if (stmt.kind == ast::BlockKind::Generator) check_generator_end(stmt);
    ast_.stmts.push_back(std::move(stmt));
    ast::Item item;
    item.kind = ast::ItemKind::Block;
    item.range = ast_.stmts.back().range;
    item.block = ast::StmtId{static_cast<int32_t>(ast_.stmts.size() - 1)};
    deliver_item(item);
  }

  // A token of `expr`, `listExpr` or `itemExpr`: `sign* operand (op sign* operand)*`.
  void expr_token(Frame& f, const ArenaToken* t, size_t type) {
    if (f.want_operand) {
      if (type == NomeParser::NUMBER || type == NomeParser::DOLLAR_REF) {
        operands_.push_back(ast::ExprId{leaf(type == NomeParser::NUMBER ? ast::ExprKind::Number : ast::ExprKind::DollarRef, t)});
        f.want_operand = false;
      } else {
        ops_.push_back(PendingOp{PendingOp::Sign, op_char(type), 0, offsets_.byte_of(t->getStartIndex())});
      }
      return;
    }
    f.want_operand = true;
    if (type == NomeParser::CARET) {  // binds tightest, right-associative: waits for its operand
      ops_.push_back(PendingOp{PendingOp::Caret, '^', 0, 0});
      return;
    }
    const int level = binary_level(type);
    if (!reduce(f, level)) return;
    ops_.push_back(PendingOp{PendingOp::Binary, op_char(type), level, 0});
  }

  // Applies the waiting operators that bind at least as tightly as a binary operator of
  // `level` (0: all of them): signs and `^`, and binary operators of `level` or tighter.
  bool reduce(const Frame& f, int level) {
    while (ops_.size() > f.ops_at) {
      const PendingOp op = ops_.back();
      if (op.form == PendingOp::Binary && op.level < level) break;
      ops_.pop_back();
      if (op.form == PendingOp::Sign) {
        if (operands_.size() < f.operands_at + 1u) {
          dead_ = true;
          return false;
        }
        ast::Expr e;
        e.kind = ast::ExprKind::Unary;
        e.op = op.op;
        e.set_operands(operands_.back());
        e.range = SourceRange{file_, op.begin, ast_.exprs[e.lhs().index].range.end};
        if (e.range.end < e.range.begin) e.range.end = e.range.begin;
        operands_.back() = add(e);
      } else {
        if (operands_.size() < f.operands_at + 2u) {
          dead_ = true;
          return false;
        }
        ast::Expr e;
        e.kind = ast::ExprKind::Binary;
        e.op = op.op;
        const ast::ExprId rhs = operands_.back();
        operands_.pop_back();
        const ast::ExprId lhs = operands_.back();
        e.set_operands(lhs, rhs);
        const SourceRange& l = ast_.exprs[lhs.index].range;
        const SourceRange& r = ast_.exprs[rhs.index].range;
        e.range = SourceRange{file_, l.begin, std::max(l.end, r.end)};
        operands_.back() = add(e);
      }
    }
    return true;
  }

  // The frame a result goes to: the one below, through `block` wrappers for items.
  void deliver_item(const ast::Item& item) {
    size_t at = frames_.size();
    while (at > 0 && frames_[at - 1].kind == Kind::Block) --at;
    if (at == 0) return;
    switch (frames_[at - 1].kind) {
      case Kind::Top: ast_.top.push_back(item); break;
      case Kind::Stmt: items_.push_back(item); break;
      default: break;
    }
  }

  void deliver_expr(int32_t id) {
    if (frames_.empty()) return;
    Frame& f = frames_.back();
    switch (f.kind) {
      case Kind::Expr:
        operands_.push_back(ast::ExprId{id});
        f.want_operand = false;
        break;
      case Kind::ParenList: operands_.push_back(ast::ExprId{id}); break;
      case Kind::Atom:
        if (f.atom == AtomForm::Call) {
          operands_.push_back(ast::ExprId{id});
        } else {
          f.result = id;
        }
        break;
      case Kind::BraceExpr: f.result = id; break;
      case Kind::Item:
      case Kind::Stray:
        f.result = id;
        f.what = What::Value;
        break;
      default: break;
    }
  }

  void deliver_list(int32_t id) {
    if (frames_.empty()) return;
    Frame& f = frames_.back();
    if (f.kind == Kind::Item || f.kind == Kind::Stray) {
      f.result = id;
      f.what = What::List;
    }
  }

  void deliver_name(SourceRange range) {
    if (frames_.empty()) return;
    Frame& f = frames_.back();
    if (f.kind == Kind::Item || f.kind == Kind::Stray) {
      f.name = range;
      f.what = What::Word;
    } else if (f.kind == Kind::Atom) {
      f.name = range;
      f.has_name = true;
    }
  }

  std::vector<Frame> frames_;
  std::vector<ast::Item> items_;
  std::vector<ast::ExprId> operands_;
  std::vector<PendingOp> ops_;
  std::vector<SourceRange> commas_;
  bool dead_ = false;
};

// Stage 1's strategy: BailErrorStrategy, which first tells the event-driven builder to stop
// (the rules that unwind still exit), and composes no error report nobody would read.
class BailOut final : public antlr4::BailErrorStrategy {
 public:
  explicit BailOut(StreamBuilder* builder) : builder_(builder) {}
  void reportError(antlr4::Parser*, const antlr4::RecognitionException&) override {}
  void recover(antlr4::Parser* recognizer, std::exception_ptr e) override {
    if (builder_ != nullptr) builder_->abandon();
    antlr4::BailErrorStrategy::recover(recognizer, e);
  }
  antlr4::Token* recoverInline(antlr4::Parser* recognizer) override {
    if (builder_ != nullptr) builder_->abandon();
    return antlr4::BailErrorStrategy::recoverInline(recognizer);
  }

 private:
  StreamBuilder* builder_;
};

thread_local bool tls_tree_builder = false;
thread_local bool tls_remembered_predictions = true;
thread_local bool tls_resume_recovery = true;
std::atomic<size_t> g_resumed_recoveries{0};
std::atomic<size_t> g_recoveries{0};

// A parser as every parse makes one: the remembered walks known, and used unless a test
// switched them off.
void prepare_parser(NomeParser& parser) {
  parse_detail::remember_seeded_predictions();
  parser.remember_predictions(tls_remembered_predictions);
}

}  // namespace

namespace parse_detail {
void use_tree_builder(bool on) { tls_tree_builder = on; }

void use_remembered_predictions(bool on) { tls_remembered_predictions = on; }

void resume_recovery(bool on) { tls_resume_recovery = on; }

RecoveryCounts recovery_counts() {
  return {g_recoveries.load(std::memory_order_relaxed), g_resumed_recoveries.load(std::memory_order_relaxed)};
}

void remember_seeded_predictions() {
  // Thread-safe once (a static's initialisation); the records are the build's own, so a
  // malformed one (never written) would only stop the remembering there.
  static const bool remembered = remember_walks(prediction_seed());
  (void)remembered;
}

std::vector<uint16_t> remembered_walks() { return nomec_antlr::Predictor::remembered_walks(); }
bool remember_walks(std::span<const uint16_t> records) {
  return nomec_antlr::Predictor::remember_walks(records.data(), records.size());
}

ParseSwitches ParseSwitches::current() {
  return {reference_lexer_in_use(), tls_tree_builder, tls_remembered_predictions, tls_resume_recovery};
}

void ParseSwitches::apply() const {
  use_reference_lexer(reference_lexer);
  use_tree_builder(tree_builder);
  use_remembered_predictions(remembered_predictions);
  resume_recovery(resumed_recovery);
}
}  // namespace parse_detail

namespace {

// The state of a parse at the start of a top-level statement in stage 1: the statement's
// first token, and how much the AST, its unplaced error expressions and the builder's
// diagnostics held.
struct StatementMark {
  size_t token = 0;
  size_t top = 0, stmts = 0, exprs = 0, args = 0, lists = 0, commas = 0, unanchored = 0, diags = 0;

  /// Drops what was built after the mark.
  void truncate(ast::Ast& a, std::vector<int32_t>& unplaced, DiagnosticEngine& diags) const {
    a.top.resize(top);
    a.stmts.resize(stmts);
    a.exprs.resize(exprs);
    a.args.resize(args);
    a.lists.resize(lists);
    a.commas.resize(commas);
    unplaced.resize(unanchored);
    std::vector<Diagnostic> kept = diags.take();
    kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(this->diags), kept.end());
    for (Diagnostic& d : kept) diags.push(std::move(d));
  }
};

StatementMark mark_statement(size_t token, const ast::Ast& a, const std::vector<int32_t>& unplaced,
                             const DiagnosticEngine& diags) {
  return {token,       a.top.size(),   a.stmts.size(),    a.exprs.size(),
          a.args.size(), a.lists.size(), a.commas.size(), unplaced.size(), diags.diagnostics().size()};
}

// Whether the recovering pass (stage 2) may start at the statement beginning with token
// `first` instead of at the start of the text, when stage 1 failed in that statement: the
// statements before it parsed without error, so a recovering parse from the start reads
// them as stage 1 did and reaches that token in the `topStmt*` loop, in no error recovery,
// with the same rules above it (`file`). A `file` rule started at the token behaves the
// same when the token can start a statement (the loop's entry and its loop-back differ
// only for one that cannot). tests/unit/recovery_resume_test.cpp compares both passes on
// damaged texts.
bool resumes_at(const NomeParser& parser, ArenaTokenStream& stream, size_t first) {
  if (first == 0) return false;
  const antlr4::Token* t = stream.get(first);
  return t->getType() != antlr4::Token::EOF && starts_statement(parser.getATN(), t->getType());
}

// Where stage 2 starts when stage 1 failed in the statement marked `failing`: at that
// statement, or, when its first token cannot start a statement (a stray `)`), at the one
// before (`previous`), which then reaches the token in the loop as a parse from the start
// does. Null when neither can: stage 2 starts at the start of the text.
const StatementMark* resume_point(const NomeParser& parser, ArenaTokenStream& stream, const StatementMark& failing,
                                  const StatementMark& previous) {
  if (resumes_at(parser, stream, failing.token)) return &failing;
  if (failing.token > previous.token && resumes_at(parser, stream, previous.token)) return &previous;
  return nullptr;
}

}  // namespace

ast::Ast parse_piece(std::string_view text, FileId file, const PieceSinks& sinks,
                     PieceInfo* info, double reserve_scale) {
  ast::Ast result;
  result.file = file;

  Offsets offsets;
  offsets.text_size = static_cast<uint32_t>(text.size());
  std::string blanked_storage;
  Lexed lexed = lex_text(text, file, sinks.comments, blanked_storage, /*drop_whitespace=*/true);
  const std::string_view lexed_text = blanked_storage.empty() ? text : std::string_view(blanked_storage);
  std::vector<Tok>& raw = lexed.tokens;
  // Only the trailing whitespace may have looked at the end of the text (see Lexed).
  const Tok& last = lexed.last;
  const bool lexer_contained =
      last.type == kEof ? lexed.eof_touch_start == static_cast<size_t>(-1)
                        : (last.type == NomeLexer::WS || last.type == NomeLexer::NBSP) &&
                              lexed.eof_touch_start >= last.begin;
  // The parser needs a proper end.
  const auto size = static_cast<uint32_t>(text.size());
  raw.push_back(Tok{size, size, 0, kEof, false});
  bool stopped = false;
  DiagnosticEngine token_diags;
  std::vector<Tok> tokens = prepare_tokens(std::move(raw), text, 0, file, token_diags, stopped);
  // Repairs only where the whole text was read (a limit may have cut it short). Their
  // diagnostics join the token pass's in position order, as a piece of the file reports them.
  LineEndRepairs repairs;
  StructureOutcome structure;
  if (!stopped) {
    DiagnosticEngine repair_diags;
    insert_missing_open_parens(tokens, 0, file, repair_diags);
    recover_brackets(tokens, text, 0, file, repair_diags, repairs, structure);
    end_line_statements(tokens, text, repairs);
    recover_structure(tokens, text, 0, file, repair_diags, repairs, structure);
    repair_diags.sort_by_position();  // the passes report in their own order
    token_diags.merge_in_order(std::move(repair_diags));
  }
  sinks.tokens.append(std::move(token_diags));

  ArenaTokenStream stream(tokens, lexed_text);
  AstSizes sizes = ast_sizes(tokens);
  for (size_t* n : {&sizes.stmts, &sizes.lists, &sizes.exprs}) *n = static_cast<size_t>(double(*n) * reserve_scale);
  std::vector<Tok>().swap(tokens);
  reserve_ast(sizes, result);  // where the tokens were, if it fits
  NomeParser parser(&stream);
  prepare_parser(parser);
  stream.parser_ = &parser;
  parser.removeErrorListeners();

  // Stage 1: fast SLL prediction that bails on the first error, one top-level statement at
  // a time: each statement's AST is built and its parse tree freed before the next is read,
  // so the parse tree never holds more than one statement. (SLL prediction does not look at
  // the rules around the statement, so the statement parses as inside `file`; the loop
  // reads the end of the text without the stream's lookahead watch, as `file` would see it
  // with every statement consumed.)
  parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(
      antlr4::atn::PredictionMode::SLL);
  std::vector<int32_t> unanchored;
  DiagnosticEngine builder_diags;  // the AST builders' diagnostics, in statement order
  bool parsed = false;
  bool gave_up = false;
  // Where the statement the fast pass was reading when it failed starts, and the one
  // before it (token 0 when none): the recovering pass resumes there (see resume_point).
  StatementMark failing, previous;
  // Stage 1 from token `from` (a statement's first token) to the end; false when it fails.
  auto fast_pass = [&](size_t from) {
    stream.seek(from);
    failing = previous = StatementMark{};
    bool clean = false;
    if (!tls_tree_builder) {
      // The AST is built from the parser's events; no parse tree is made.
      StreamBuilder builder(file, text, offsets, result, &unanchored, &builder_diags);
      builder.repairs_ = &repairs;
      parser.setErrorHandler(std::make_shared<BailOut>(&builder));
      parser.set_events(&builder);
      try {
        while (stream.get(stream.index())->getType() != antlr4::Token::EOF) {
          previous = failing;
          failing = mark_statement(stream.index(), result, unanchored, builder_diags);
          parser.topStmt();
          parser.reset_contexts();
          if (builder.dead()) break;
        }
        clean = !builder.dead();
      } catch (const antlr4::ParseCancellationException&) {
        clean = false;
      }
      parser.set_events(nullptr);
    } else {
      // The reference (tests): each statement's parse tree, converted by AstBuilder.
      AstBuilder builder(file, text, offsets, result, &unanchored, &builder_diags);
      builder.repairs_ = &repairs;
      parser.setErrorHandler(std::make_shared<BailOut>(nullptr));
      try {
        while (stream.get(stream.index())->getType() != antlr4::Token::EOF) {
          previous = failing;
          failing = mark_statement(stream.index(), result, unanchored, builder_diags);
          builder.build_top(parser.topStmt());
          parser.getTreeTracker().reset();
          parser.reset_contexts();
        }
        clean = true;
      } catch (const antlr4::ParseCancellationException&) {
        clean = false;
      }
    }
    return clean;
  };
  // Drops the AST and the builders' diagnostics (a recovering pass from the start, or one
  // that gave up, which keeps neither).
  auto discard_ast = [&] {
    result = ast::Ast{};
    result.file = file;
    unanchored.clear();
    builder_diags = DiagnosticEngine{};
  };
  // Stage 2's syntax errors, reported with the builders' diagnostics in position order, so
  // that a file cut into pieces reports them as the whole file does.
  DiagnosticEngine recovery_diags;
  SyntaxErrorListener listener(file, offsets, recovery_diags);
  parsed = fast_pass(0);
  if (!parsed) {
    // Stage 2: error reporting and recovery. Still SLL prediction: the grammar needs no
    // more (stage 1 would fail on a valid file that did), and full LL costs four times as
    // much on the files that reach this stage, those with syntax errors.
    //
    // The statements before the failing one parsed without error, so a recovering pass from
    // the start would build them again exactly as stage 1 did: they are kept, what the
    // failing statement had begun is dropped, and the recovering pass starts at that
    // statement (resume_point). It stops again at the first statement after its errors
    // where a pass from the start would be back to a clean state (RecoveringStrategy), and
    // stage 1 takes over from there; and so on to the end. Without a resume point the
    // recovering pass reads the whole text.
    g_recoveries.fetch_add(1, std::memory_order_relaxed);
    parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(
        antlr4::atn::PredictionMode::SLL);
    bool partial = false;  // some recovering pass did not read the whole text
    for (bool first = true;; first = false) {
      const StatementMark* from = tls_resume_recovery ? resume_point(parser, stream, failing, previous) : nullptr;
      if (from != nullptr) {
        partial = true;
        from->truncate(result, unanchored, builder_diags);
      } else {
        discard_ast();
        recovery_diags = DiagnosticEngine{};  // the listener's, which reports into it again
      }
      const size_t start = from != nullptr ? from->token : 0;
      parser.reset();  // which also rewinds the stream to its first token
      stream.seek(start);
      // A pass from the start after a stop (never expected: a stop faces a statement's first
      // token, where the next failure can resume) reads to the end, so the loop ends.
      const bool stops = tls_resume_recovery && (from != nullptr || first);
      parser.setErrorHandler(std::make_shared<RecoveringStrategy>(stops, start));
      parser.addErrorListener(&listener);
      NomeParser::FileContext* tree = nullptr;
      size_t stopped_at = 0;
      try {
        tree = parser.file();
      } catch (const RecoveringStrategy::Stop& stop) {
        tree = stop.file;
        stopped_at = stop.token;
      } catch (const std::exception&) {
        tree = nullptr;  // recovery gave up; diagnostics were emitted
        stream.eof_seen_early_ = true;
        gave_up = true;
      }
      if (tree != nullptr) {
        AstBuilder builder(file, text, offsets, result, &unanchored, &builder_diags);
        builder.repairs_ = &repairs;
        builder.build_file(tree);
      }
      parser.removeErrorListener(&listener);
      partial = partial || stopped_at != 0;
      if (stopped_at == 0 || gave_up) break;
      parser.reset();
      if (fast_pass(stopped_at)) break;
    }
    if (partial) g_resumed_recoveries.fetch_add(1, std::memory_order_relaxed);
    // A parse that gives up keeps no AST (PieceInfo::gave_up), nor any builder diagnostic:
    // a pass from the start converts no tree.
    if (gave_up) discard_ast();
    // After the parser's errors, as a pass from the start emits the builder's diagnostics
    // when it converts the parse tree.
    recovery_diags.append(std::move(builder_diags));
  } else {
    sinks.syntax.append(std::move(builder_diags));
  }
  if (info != nullptr) {
    // At the start of a file the parser enters `topStmt*`; inside a file it loops back to
    // it. The two recover differently from a token that cannot start a statement.
    const size_t first_type = stream.first_type();
    info->starts_cleanly = first_type == antlr4::Token::EOF || starts_statement(parser.getATN(), first_type);
    info->self_contained = !lexed.comment_open && !stopped && lexer_contained && !stream.eof_seen_early_ &&
                           !structure.depends_on_what_follows && !repairs.scanned_to_end;
    info->gave_up = gave_up;
    info->stopped = stopped;
  }
  recovery_diags.sort_by_position();
  sinks.syntax.append(std::move(recovery_diags));
  if (info != nullptr) info->unanchored_exprs = std::move(unanchored);
  return result;
}

ast::Ast parse_file(const SourceManager& sources, FileId file, DiagnosticEngine& diags, ParseThreads threads) {
  const std::string_view text = sources.text(file);
  if (parse_detail::uses_two_threads(threads, text.size())) {
    if (std::optional<ast::Ast> halves = parse_detail::parse_in_two_pieces(text, file, diags)) return std::move(*halves);
  }
  return parse_piece(text, file, PieceSinks{diags, diags, diags}, nullptr);
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
  Lexed lexed = lex_unblanked(text);
  const auto size = static_cast<uint32_t>(text.size());
  lexed.tokens.push_back(Tok{size, size, 0, kEof, false});
  bool stopped = false;
  DiagnosticEngine token_diags;
  std::vector<Tok> tokens = prepare_tokens(std::move(lexed.tokens), text, b, file, token_diags, stopped, "function");
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
  ArenaTokenStream stream(tokens, text);
  NomeParser parser(&stream);
  prepare_parser(parser);
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
  using namespace parse_detail;
  DiagnosticEngine ignored;
  std::string blanked_storage;
  const Lexed lexed = lex_text(text, FileId{}, ignored, blanked_storage);
  const std::string_view original = text;
  std::vector<LexToken> out;
  auto push = [&](LexKind kind, size_t begin, size_t end) {
    out.push_back(LexToken{kind, static_cast<uint32_t>(begin), static_cast<uint32_t>(end)});
  };
  // An unclosed string, `[` or `%{` is one token to the end of its line or of the text;
  // the lexer's tokens inside it are skipped.
  size_t skip_to = 0;
  int brace_depth = 0;
  auto forgive = [&](LexKind kind, size_t begin, size_t end) {
    push(kind, begin, end);
    skip_to = end;
  };
  for (const Tok& tok : lexed.tokens) {
    size_t begin = tok.begin;
    size_t end = tok.end;
    if (begin < skip_to) continue;
    switch (tok.type) {
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
