// Byte codecs and frame I/O of the Tcl worker protocol (see protocol.h). Fields are written
// in order: integers little-endian, doubles as their 8 bytes, strings and lists as a 32-bit
// count then their items. A reader that runs past the end or finds a count larger than
// what is left marks the frame malformed.
#include "frontend/tcl/protocol.h"

#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace nomec::tcl::protocol {

namespace {

class Writer {
 public:
  explicit Writer(Op op) { out_.push_back(static_cast<char>(op)); }
  void u8(uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) out_.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  }
  void i64(int64_t v) {
    const auto u = static_cast<uint64_t>(v);
    for (int i = 0; i < 8; ++i) out_.push_back(static_cast<char>((u >> (8 * i)) & 0xff));
  }
  void f64(double v) {
    uint64_t u = 0;
    std::memcpy(&u, &v, sizeof u);
    i64(static_cast<int64_t>(u));
  }
  void str(std::string_view s) {
    u32(static_cast<uint32_t>(s.size()));
    out_.append(s);
  }
  void strings(const std::vector<std::string>& v) {
    u32(static_cast<uint32_t>(v.size()));
    for (const std::string& s : v) str(s);
  }
  void problems(const std::vector<Problem>& v) {
    u32(static_cast<uint32_t>(v.size()));
    for (const Problem& p : v) {
      u8(static_cast<uint8_t>(p.kind));
      str(p.message);
      i64(p.line);
      str(p.trace);
    }
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

class Reader {
 public:
  Reader(std::string_view frame, Op op) : in_(frame) {
    if (in_.empty() || static_cast<Op>(in_[0]) != op) ok_ = false;
    at_ = in_.empty() ? 0 : 1;
  }
  bool ok() const { return ok_ && at_ == in_.size(); }
  uint8_t u8() { return need(1) ? static_cast<uint8_t>(in_[at_++]) : 0; }
  uint32_t u32() {
    if (!need(4)) return 0;
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(static_cast<uint8_t>(in_[at_++])) << (8 * i);
    return v;
  }
  int64_t i64() {
    if (!need(8)) return 0;
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<uint64_t>(static_cast<uint8_t>(in_[at_++])) << (8 * i);
    return static_cast<int64_t>(v);
  }
  double f64() {
    const auto u = static_cast<uint64_t>(i64());
    double v = 0;
    std::memcpy(&v, &u, sizeof v);
    return v;
  }
  bool flag() { return u8() != 0; }
  std::string str() {
    const uint32_t n = u32();
    if (!need(n)) return {};
    std::string s(in_.substr(at_, n));
    at_ += n;
    return s;
  }
  // A count of items each at least `min_bytes` long: refused when the frame cannot hold them.
  uint32_t count(size_t min_bytes) {
    const uint32_t n = u32();
    if (!ok_ || static_cast<uint64_t>(n) * min_bytes > in_.size() - at_) {
      ok_ = false;
      return 0;
    }
    return n;
  }
  std::vector<std::string> strings() {
    std::vector<std::string> v(count(4));
    for (std::string& s : v) s = str();
    return v;
  }
  std::vector<Problem> problems() {
    std::vector<Problem> v(count(17));
    for (Problem& p : v) {
      const uint8_t kind = u8();
      if (kind > static_cast<uint8_t>(ProblemKind::Stopped)) ok_ = false;
      p.kind = static_cast<ProblemKind>(kind);
      p.message = str();
      p.line = static_cast<int>(i64());
      p.trace = str();
    }
    return v;
  }

 private:
  bool need(size_t n) {
    if (!ok_ || n > in_.size() - at_) {
      ok_ = false;
      return false;
    }
    return true;
  }
  std::string_view in_;
  size_t at_ = 0;
  bool ok_ = true;
};

bool is_request(Op op) { return op >= Op::Start && op <= Op::Watch; }

}  // namespace

std::string encode(const Request& r) {
  Writer w(r.op);
  w.str(r.text);
  w.str(r.value);
  w.i64(r.milliseconds);
  w.i64(r.commands);
  w.u8(r.has_preset ? 1 : 0);
  return w.take();
}

std::string encode(const Callback& c) {
  Writer w(c.op);
  w.str(c.text);
  w.f64(c.from);
  w.f64(c.to);
  return w.take();
}

std::string encode(const CallbackReply& r) {
  Writer w(Op::CallbackReply);
  w.u8(r.text ? 1 : 0);
  w.str(r.text.value_or(""));
  w.u8(r.yes ? 1 : 0);
  w.u8(r.number ? 1 : 0);
  w.f64(r.number.value_or(0));
  return w.take();
}

std::string encode(const Reply& r) {
  Writer w(Op::Reply);
  const Outcome& o = r.outcome;
  w.u8(o.ok ? 1 : 0);
  w.str(o.result);
  w.f64(o.number);
  w.problems(o.problems);
  w.strings(o.reads);
  w.strings(o.writes);
  w.u8(r.got ? 1 : 0);
  w.str(r.got.value_or(""));
  w.u8(r.sliders ? 1 : 0);
  const std::vector<Slider> none;
  const std::vector<Slider>& sliders = r.sliders ? *r.sliders : none;
  w.u32(static_cast<uint32_t>(sliders.size()));
  for (const Slider& s : sliders) {
    w.str(s.variable);
    w.f64(s.value);
    w.f64(s.from);
    w.f64(s.to);
    w.f64(s.resolution);
    w.u8(s.rounded ? 1 : 0);
    w.f64(s.written);
  }
  w.u32(static_cast<uint32_t>(r.calls.size()));
  for (const SlideCall& c : r.calls) w.strings(c.words);
  w.problems(r.notes);
  return w.take();
}

std::optional<Op> op_of(std::string_view frame) {
  if (frame.empty()) return std::nullopt;
  const auto op = static_cast<Op>(frame[0]);
  if (op < Op::Start || op > Op::Reply) return std::nullopt;
  return op;
}

std::optional<Request> decode_request(std::string_view frame) {
  std::optional<Op> op = op_of(frame);
  if (!op || !is_request(*op)) return std::nullopt;
  Reader in(frame, *op);
  Request r;
  r.op = *op;
  r.text = in.str();
  r.value = in.str();
  r.milliseconds = in.i64();
  r.commands = in.i64();
  r.has_preset = in.flag();
  if (!in.ok()) return std::nullopt;
  return r;
}

std::optional<Callback> decode_callback(std::string_view frame) {
  std::optional<Op> op = op_of(frame);
  if (!op || (*op != Op::ReadFile && *op != Op::HasFile && *op != Op::Preset)) return std::nullopt;
  Reader in(frame, *op);
  Callback c;
  c.op = *op;
  c.text = in.str();
  c.from = in.f64();
  c.to = in.f64();
  if (!in.ok()) return std::nullopt;
  return c;
}

std::optional<CallbackReply> decode_callback_reply(std::string_view frame) {
  Reader in(frame, Op::CallbackReply);
  CallbackReply r;
  const bool has_text = in.flag();
  std::string text = in.str();
  if (has_text) r.text = std::move(text);
  r.yes = in.flag();
  const bool has_number = in.flag();
  const double number = in.f64();
  if (has_number) r.number = number;
  if (!in.ok()) return std::nullopt;
  return r;
}

std::optional<Reply> decode_reply(std::string_view frame) {
  Reader in(frame, Op::Reply);
  Reply r;
  Outcome& o = r.outcome;
  o.ok = in.flag();
  o.result = in.str();
  o.number = in.f64();
  o.problems = in.problems();
  o.reads = in.strings();
  o.writes = in.strings();
  const bool has_got = in.flag();
  std::string got = in.str();
  if (has_got) r.got = std::move(got);
  const bool has_sliders = in.flag();
  std::vector<Slider> sliders(in.count(45));
  for (Slider& s : sliders) {
    s.variable = in.str();
    s.value = in.f64();
    s.from = in.f64();
    s.to = in.f64();
    s.resolution = in.f64();
    s.rounded = in.flag();
    s.written = in.f64();
  }
  if (has_sliders) r.sliders = std::move(sliders);
  r.calls.resize(in.count(4));
  for (SlideCall& c : r.calls) c.words = in.strings();
  r.notes = in.problems();
  if (!in.ok()) return std::nullopt;
  return r;
}

bool write_frame(int fd, std::string_view payload) {
  if (payload.size() > kMaxFrame) return false;
  const auto n = static_cast<uint32_t>(payload.size());
  char head[4];
  for (int i = 0; i < 4; ++i) head[i] = static_cast<char>((n >> (8 * i)) & 0xff);
  for (std::string_view part : {std::string_view(head, 4), payload}) {
    while (!part.empty()) {
      const ssize_t w = ::send(fd, part.data(), part.size(), MSG_NOSIGNAL);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) return false;
      part.remove_prefix(static_cast<size_t>(w));
    }
  }
  return true;
}

namespace {

bool read_exactly(int fd, char* at, size_t n) {
  while (n > 0) {
    const ssize_t r = ::read(fd, at, n);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    at += r;
    n -= static_cast<size_t>(r);
  }
  return true;
}

}  // namespace

std::optional<std::string> read_frame(int fd) {
  unsigned char head[4];
  if (!read_exactly(fd, reinterpret_cast<char*>(head), 4)) return std::nullopt;
  const uint32_t n = head[0] | (head[1] << 8) | (head[2] << 16) | (static_cast<uint32_t>(head[3]) << 24);
  if (n > kMaxFrame) return std::nullopt;
  std::string frame(n, '\0');
  if (!read_exactly(fd, frame.data(), n)) return std::nullopt;
  return frame;
}

}  // namespace nomec::tcl::protocol
