// The generated parser's base class (ANTLR's `superClass` option, given to the parser's
// generation only: see CMakeLists.txt). It keeps every rule of the generated NomeParser as
// generated and changes how the recognizer's bookkeeping is done, with members of the same
// names as those of antlr4::Parser that the generated code calls:
//  * `_tracker`: rule contexts come from one arena that a reset rewinds (destructors run,
//    memory kept), instead of one heap allocation each;
//  * `exitRule`, `getInterpreter`: a static_cast where antlr4::Parser does a dynamic_cast
//    (the parent of a rule context and the interpreter have one known type);
//  * `finally`: the scope guard that calls `exitRule` holds the lambda itself, not a
//    std::function.
// And, when an event sink is set (`set_events`), no parse tree is built: `enterRule`,
// `consume` and `exitRule` report the parse to the sink as it happens, and tokens become no
// tree nodes. Without a sink every hook does exactly what antlr4::Parser does.
// Included (before NomeParser.h) by the generated parser's sources and by
// frontend/parse/generated.h; nothing here knows NOME.
#pragma once

#include <cstddef>
#include <cstdint>
#include <atomic>
#include <memory>
#include <mutex>
#include <type_traits>
#include <new>
#include <utility>
#include <vector>

#include "antlr4-runtime.h"

namespace nomec_antlr {

/// Receives a parse as it happens, when the parser builds no tree. `exit_rule` sees the
/// context with its start and stop tokens set.
class ParseEvents {
 public:
  virtual ~ParseEvents() = default;
  virtual void enter_rule(antlr4::ParserRuleContext* ctx, size_t rule) = 0;
  virtual void token(antlr4::Token* token) = 0;
  virtual void exit_rule(antlr4::ParserRuleContext* ctx) = 0;
};

/// Rule contexts in chunks of memory kept across resets.
class ContextArena {
 public:
  ContextArena() = default;
  ContextArena(const ContextArena&) = delete;
  ContextArena& operator=(const ContextArena&) = delete;
  ~ContextArena() {
    reset();
    for (char* chunk : chunks_) ::operator delete(chunk);
  }

  template <typename T, typename... Args>
  T* createInstance(Args&&... args) {
    void* memory = allocate(sizeof(T));
    T* node = new (memory) T(std::forward<Args>(args)...);
    live_.push_back(node);
    return node;
  }

  /// Destroys every context made since the last reset; their memory is reused.
  void reset() {
    for (antlr4::tree::ParseTree* node : live_) node->~ParseTree();
    live_.clear();
    chunk_ = 0;
    used_ = 0;
  }

 private:
  static constexpr size_t kChunk = 64 * 1024;
  static constexpr size_t kAlign = alignof(std::max_align_t);

  void* allocate(size_t size) {
    size = (size + kAlign - 1) & ~(kAlign - 1);
    if (chunks_.empty() || used_ + size > kChunk) {
      if (!chunks_.empty()) ++chunk_;
      if (chunk_ == chunks_.size()) chunks_.push_back(static_cast<char*>(::operator new(kChunk)));
      used_ = 0;
    }
    void* at = chunks_[chunk_] + used_;
    used_ += size;
    return at;
  }

  std::vector<char*> chunks_;
  std::vector<antlr4::tree::ParseTree*> live_;
  size_t chunk_ = 0;  // the chunk being filled
  size_t used_ = 0;   // bytes used in it
};

/// A token stream over an array that lets the parser read the current token's type without
/// a virtual call and count what prediction consumed: a stream that derives from this keeps
/// `codes_[p_]` the type of the token at its position (kEnd at the end) and counts every
/// `consume()` in `consumed_`.
class TokenArrayStream : public antlr4::TokenStream {
 public:
  static constexpr uint16_t kEnd = 0xFFFF;
  uint16_t current_code() const { return codes_[p_]; }
  size_t consumed() const { return consumed_; }
  /// The token at the current position (the same as LT(1) when it is not the end token).
  antlr4::Token* current_token() const { return token_at(p_); }
  /// The token before the current position (LT(-1)), or null at the start.
  antlr4::Token* previous_token() const { return p_ > 0 ? token_at(p_ - 1) : nullptr; }

 protected:
  friend class Predictor;
  antlr4::Token* token_at(size_t i) const { return reinterpret_cast<antlr4::Token*>(token_bytes_ + i * stride_); }

  char* token_bytes_ = nullptr;  // the tokens, `stride_` bytes apart
  size_t stride_ = 0;
  const uint16_t* codes_ = nullptr;
  size_t p_ = 0;
  size_t consumed_ = 0;
};

class NomeParserBase;

/// What the generated rules see as `_input`: the parser's token stream, with `LA(1)` read
/// directly from a TokenArrayStream (the end token still goes through the stream, which
/// may watch for it).
class FastInput {
 public:
  FastInput* operator->() { return this; }
  operator antlr4::TokenStream*() const { return stream_; }
  size_t LA(ssize_t i) {
    if (array_ != nullptr && i == 1) {
      const uint16_t code = array_->current_code();
      if (code != TokenArrayStream::kEnd) return code;
    }
    return stream_->LA(i);
  }

 private:
  friend class NomeParserBase;
  antlr4::TokenStream* stream_ = nullptr;
  TokenArrayStream* array_ = nullptr;
};

/// What the generated rules see as the interpreter: ANTLR's ParserATNSimulator, with the
/// answers of its SLL predictions remembered per decision in a trie of token types (shared by
/// every parser of the grammar). SLL prediction without predicates is a deterministic walk
/// of the decision's DFA over the next token types, independent of the rule invocation
/// stack: the same decision and the same token types give the same walk, which stops after
/// the same number of tokens with the same alternative. The trie holds the walks seen
/// (recognised by how many tokens the simulator consumed to answer); a walk it knows
/// replaces the call, which would only have read those tokens and seeked back. Walks that
/// reach the end token are left to the simulator (the stream may watch for that token).
class Predictor {
 public:
  size_t adaptivePredict(antlr4::TokenStream* input, size_t decision, antlr4::ParserRuleContext* outer) {
    auto* sim = static_cast<antlr4::atn::ParserATNSimulator*>(*interpreter_);
    if (array_ == nullptr || !sll_ || !remembers_ || input != static_cast<antlr4::TokenStream*>(array_) ||
        decision >= kDecisions) {
      return sim->adaptivePredict(input, decision, outer);
    }
    Memo& memo = shared_memo();
    const uint16_t* codes = array_->codes_ + array_->p_;
    if (const int32_t alt = memo.find(decision, codes); alt > 0) return static_cast<size_t>(alt);
    const size_t before = array_->consumed();
    const size_t predicted = sim->adaptivePredict(input, decision, outer);
    memo.insert(decision, codes, array_->consumed() - before + 1, predicted);
    return predicted;
  }
  void setPredictionMode(antlr4::atn::PredictionMode mode) {
    sll_ = mode == antlr4::atn::PredictionMode::SLL;
    static_cast<antlr4::atn::ParserATNSimulator*>(*interpreter_)->setPredictionMode(mode);
  }
  antlr4::atn::PredictionMode getPredictionMode() {
    return static_cast<antlr4::atn::ParserATNSimulator*>(*interpreter_)->getPredictionMode();
  }

  // Remembered walks as one array of records `decision, alternative, length, token types…`
  // (what `remembered_walks` writes and `remember_walks` reads): a build step parses
  // training texts, writes the walks the trie then holds into a source file, and every
  // program remembers them before its first parse (frontend/parse/prediction_seed.h), so no
  // program pays the simulator's first predictions (building its DFA states) for walks a
  // build already saw. A walk is a fact about the grammar, not about the text it was seen
  // in, so remembering it is the same as having seen it.
  static std::vector<uint16_t> remembered_walks() {
    std::vector<uint16_t> out;
    shared_memo().walks(out);
    return out;
  }
  /// Remembers the walks of `records`; false (and stops) at a malformed record.
  static bool remember_walks(const uint16_t* records, size_t size) {
    Memo& memo = shared_memo();
    for (size_t i = 0; i < size;) {
      if (size - i < 3) return false;
      const size_t decision = records[i], alt = records[i + 1], length = records[i + 2];
      if (decision >= kDecisions || length == 0 || size - i - 3 < length) return false;
      memo.insert(decision, records + i + 3, length, alt);
      i += 3 + length;
    }
    return true;
  }

 private:
  friend class NomeParserBase;
  static constexpr size_t kDecisions = 512;
  static constexpr size_t kTypes = 128;  // token types the trie covers
  static constexpr size_t kChunkNodes = 64;
  static constexpr size_t kChunks = 64;  // at most 4096 nodes (2 MiB)

  // Entries: 0 unknown, > 0 the alternative (the walk stops here), < 0 -(the next node).
  class Memo {
   public:
    int32_t find(size_t decision, const uint16_t* codes) const {
      int32_t node = roots_[decision].load(std::memory_order_acquire);
      for (size_t k = 0; node > 0; ++k) {
        if (codes[k] >= kTypes) return 0;  // the end token, or a type the trie does not cover
        const int32_t e = entry(node, codes[k]).load(std::memory_order_acquire);
        if (e >= 0) return e;
        node = -e;
      }
      return 0;
    }
    void insert(size_t decision, const uint16_t* codes, size_t length, size_t alt) {
      if (alt == 0 || alt > 0x7FFFFFFF || length == 0) return;
      for (size_t k = 0; k < length; ++k) {
        if (codes[k] >= kTypes) return;
      }
      std::lock_guard<std::mutex> lock(mutex_);
      int32_t node = roots_[decision].load(std::memory_order_relaxed);
      if (node == 0) {
        node = make_node();
        if (node == 0) return;
        roots_[decision].store(node, std::memory_order_release);
      }
      for (size_t k = 0; k + 1 < length; ++k) {
        std::atomic<int32_t>& e = entry(node, codes[k]);
        int32_t next = e.load(std::memory_order_relaxed);
        if (next > 0) return;  // cannot happen: a walk that stopped here does not go on
        if (next == 0) {
          const int32_t fresh = make_node();
          if (fresh == 0) return;
          e.store(-fresh, std::memory_order_release);
          next = -fresh;
        }
        node = -next;
      }
      std::atomic<int32_t>& last = entry(node, codes[length - 1]);
      if (last.load(std::memory_order_relaxed) == 0) last.store(static_cast<int32_t>(alt), std::memory_order_release);
    }

    // Every walk, decision by decision and in order of token types (see remembered_walks).
    void walks(std::vector<uint16_t>& out) const {
      std::vector<uint16_t> path;
      for (size_t d = 0; d < kDecisions; ++d) {
        if (const int32_t root = roots_[d].load(std::memory_order_acquire); root > 0) walks_from(d, root, path, out);
      }
    }

   private:
    void walks_from(size_t decision, int32_t node, std::vector<uint16_t>& path, std::vector<uint16_t>& out) const {
      for (size_t t = 0; t < kTypes; ++t) {
        const int32_t e = entry(node, t).load(std::memory_order_acquire);
        if (e == 0) continue;
        path.push_back(static_cast<uint16_t>(t));
        if (e > 0 && e <= 0xFFFF) {
          out.push_back(static_cast<uint16_t>(decision));
          out.push_back(static_cast<uint16_t>(e));
          out.push_back(static_cast<uint16_t>(path.size()));
          out.insert(out.end(), path.begin(), path.end());
        } else if (e < 0) {
          walks_from(decision, -e, path, out);
        }
        path.pop_back();
      }
    }
    std::atomic<int32_t>& entry(int32_t node, size_t type) const {
      const size_t n = static_cast<size_t>(node);  // nodes count from 1
      return chunks_[n / kChunkNodes].load(std::memory_order_acquire)[(n % kChunkNodes) * kTypes + type];
    }
    int32_t make_node() {  // under mutex_; 0 when the trie is full
      const size_t n = next_node_;
      if (n / kChunkNodes >= kChunks) return 0;
      if (chunks_[n / kChunkNodes].load(std::memory_order_relaxed) == nullptr) {
        auto* chunk = new std::atomic<int32_t>[kChunkNodes * kTypes];
        for (size_t i = 0; i < kChunkNodes * kTypes; ++i) chunk[i].store(0, std::memory_order_relaxed);
        chunks_[n / kChunkNodes].store(chunk, std::memory_order_release);
      }
      ++next_node_;
      return static_cast<int32_t>(n);
    }

    std::atomic<int32_t> roots_[kDecisions] = {};
    mutable std::atomic<std::atomic<int32_t>*> chunks_[kChunks] = {};
    size_t next_node_ = 1;
    std::mutex mutex_;
  };
  static Memo& shared_memo() {
    static Memo* const memo = new Memo();  // never freed: parsers on any thread may use it
    return *memo;
  }

  antlr4::atn::ATNSimulator* const* interpreter_ = nullptr;
  TokenArrayStream* array_ = nullptr;
  bool sll_ = false;
  bool remembers_ = true;  // false: every prediction asks the simulator (differential tests)
};

template <class T>
struct InterpreterView {
  using type = T;
};
template <>
struct InterpreterView<antlr4::atn::ParserATNSimulator> {
  using type = Predictor;
};

class NomeParserBase : public antlr4::Parser {
 public:
  explicit NomeParserBase(antlr4::TokenStream* input) : antlr4::Parser(input) {
    _input.stream_ = input;
    _input.array_ = dynamic_cast<TokenArrayStream*>(input);
    predictor_.interpreter_ = &_interpreter;
    predictor_.array_ = _input.array_;
  }

  void setTokenStream(antlr4::TokenStream* input) override {
    antlr4::Parser::setTokenStream(input);
    _input.stream_ = input;
    _input.array_ = dynamic_cast<TokenArrayStream*>(input);
    predictor_.array_ = _input.array_;
  }

  /// With a sink, the parse is reported to it and no parse tree is built; with none
  /// (the default), a parse tree is built as by antlr4::Parser.
  void set_events(ParseEvents* events) {
    events_ = events;
    setBuildParseTree(events == nullptr);
  }

  /// Off: every prediction goes to ANTLR's simulator, none to the remembered walks (for the
  /// tests that hold the walks to the simulator's answers).
  void remember_predictions(bool on) { predictor_.remembers_ = on; }

  /// Frees the rule contexts of what was parsed so far (nothing may point to them).
  void reset_contexts() { _tracker.reset(); }

  void reset() override {
    antlr4::Parser::reset();
    _tracker.reset();
  }

  void enterRule(antlr4::ParserRuleContext* localctx, size_t state, size_t ruleIndex) final {
    if (events_ == nullptr) {
      antlr4::Parser::enterRule(localctx, state, ruleIndex);
      return;
    }
    setState(state);
    _ctx = localctx;
    _ctx->start = lt1();
    events_->enter_rule(localctx, ruleIndex);
  }

  void enterOuterAlt(antlr4::ParserRuleContext* localctx, size_t altNum) final {
    if (events_ == nullptr) {
      antlr4::Parser::enterOuterAlt(localctx, altNum);
      return;
    }
    _ctx = localctx;
  }

  // Hides antlr4::Parser::exitRule (not virtual) for the generated rules.
  void exitRule() {
    if (events_ == nullptr) {
      _ctx->stop = _matchedEOF ? stream()->LT(1) : stream()->LT(-1);
      if (!_parseListeners.empty()) triggerExitRuleEvent();
    } else {
      _ctx->stop = _matchedEOF ? stream()->LT(1) : (_input.array_ != nullptr ? _input.array_->previous_token() : stream()->LT(-1));
      events_->exit_rule(_ctx);
    }
    setState(_ctx->invokingState);
    _ctx = static_cast<antlr4::ParserRuleContext*>(_ctx->parent);
  }

  antlr4::Token* consume() final {
    if (events_ == nullptr) return antlr4::Parser::consume();
    antlr4::Token* token = lt1();
    if (token->getType() != antlr4::Token::EOF) stream()->consume();
    events_->token(token);
    return token;
  }

  antlr4::Token* match(size_t ttype) final {
    if (events_ != nullptr) {
      antlr4::Token* token = lt1();
      if (token->getType() == ttype) {
        if (ttype == antlr4::Token::EOF) _matchedEOF = true;
        _errHandler->reportMatch(this);
        consume();
        return token;
      }
    }
    return antlr4::Parser::match(ttype);
  }

  // Hides Recognizer::getInterpreter (a dynamic_cast) for the generated rules and for
  // nomec: the ParserATNSimulator is seen through the Predictor.
  template <class T>
  typename InterpreterView<T>::type* getInterpreter() {
    if constexpr (std::is_same_v<T, antlr4::atn::ParserATNSimulator>) {
      return &predictor_;
    } else {
      return static_cast<T*>(_interpreter);
    }
  }

 protected:
  template <class F>
  struct ScopeExit {
    F f;
    ~ScopeExit() { f(); }
  };
  // Hides antlrcpp::finally for the generated rules.
  template <class F>
  static ScopeExit<F> finally(F f) {
    return ScopeExit<F>{std::move(f)};
  }

  // Hides antlr4::Parser::_tracker for the generated rules.
  ContextArena _tracker;
  // Hides antlr4::Parser::_input for the generated rules.
  FastInput _input;

 private:
  antlr4::TokenStream* stream() const { return antlr4::Parser::_input; }
  // LT(1): read from the array unless it is the end token (which the stream may watch for).
  antlr4::Token* lt1() const {
    if (_input.array_ != nullptr && _input.array_->current_code() != TokenArrayStream::kEnd) {
      return _input.array_->current_token();
    }
    return stream()->LT(1);
  }

  ParseEvents* events_ = nullptr;
  Predictor predictor_;
};

}  // namespace nomec_antlr
