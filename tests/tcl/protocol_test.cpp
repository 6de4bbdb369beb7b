// The Tcl worker protocol (frontend/tcl/protocol.h): every message survives encoding, and
// every malformed frame — each valid frame cut short or grown, each byte flipped — is
// refused or read as some message, never read out of bounds (run under AddressSanitizer).
#include <gtest/gtest.h>

#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <limits>
#include <thread>

#include "frontend/tcl/protocol.h"

namespace nomec::tcl::protocol {
namespace {

Reply sample_reply() {
  Reply r;
  r.outcome.ok = false;
  r.outcome.result = "boom\nwith a newline and \xff bytes";
  r.outcome.number = -0.25;
  r.outcome.problems = {{ProblemKind::Error, "divide by zero", 3, "trace\n(procedure \"f\" line 2)"},
                        {ProblemKind::Fallback, "SLIDEUI.tcl", 0, ""}};
  r.outcome.reads = {"par_a", "oOffset(height)"};
  r.outcome.writes = {"r"};
  r.got = std::string("1.5");
  r.sliders = std::vector<Slider>{{"par_x", 0.5, 0, 2, 0.1, true, 0.55}, {"b", 3, 1, 9, 1, false, 0}};
  r.calls = {{{"create", "point", "p1", "{1 2 3}"}}, {{"delete", "face", "f"}}};
  r.notes = {{ProblemKind::MissingSource, "couldn't read", 0, "x.tcl"}};
  return r;
}

TEST(TclProtocol, EveryMessageRoundTrips) {
  Request q;
  q.op = Op::Set;
  q.text = "par_x";
  q.value = std::string("0.3\0x", 5);
  q.milliseconds = 9876;
  q.commands = int64_t{1} << 40;
  q.has_preset = true;
  std::optional<Request> q2 = decode_request(encode(q));
  ASSERT_TRUE(q2);
  EXPECT_EQ(q2->op, Op::Set);
  EXPECT_EQ(q2->text, q.text);
  EXPECT_EQ(q2->value, q.value);
  EXPECT_EQ(q2->milliseconds, 9876);
  EXPECT_EQ(q2->commands, q.commands);
  EXPECT_TRUE(q2->has_preset);

  Callback c{Op::Preset, "swp_q0x", -1.5, std::numeric_limits<double>::infinity()};
  std::optional<Callback> c2 = decode_callback(encode(c));
  ASSERT_TRUE(c2);
  EXPECT_EQ(c2->op, Op::Preset);
  EXPECT_EQ(c2->text, "swp_q0x");
  EXPECT_EQ(c2->from, -1.5);
  EXPECT_TRUE(std::isinf(c2->to));

  CallbackReply a;
  a.text = std::string("proc f {} {}\n");
  a.yes = true;
  a.number = 0.1;
  std::optional<CallbackReply> a2 = decode_callback_reply(encode(a));
  ASSERT_TRUE(a2);
  EXPECT_EQ(a2->text, a.text);
  EXPECT_TRUE(a2->yes);
  EXPECT_EQ(a2->number, 0.1);
  std::optional<CallbackReply> none = decode_callback_reply(encode(CallbackReply{}));
  ASSERT_TRUE(none);
  EXPECT_FALSE(none->text);
  EXPECT_FALSE(none->number);

  const Reply r = sample_reply();
  std::optional<Reply> r2 = decode_reply(encode(r));
  ASSERT_TRUE(r2);
  EXPECT_EQ(r2->outcome.result, r.outcome.result);
  EXPECT_EQ(r2->outcome.number, -0.25);
  ASSERT_EQ(r2->outcome.problems.size(), 2u);
  EXPECT_EQ(r2->outcome.problems[0].kind, ProblemKind::Error);
  EXPECT_EQ(r2->outcome.problems[0].line, 3);
  EXPECT_EQ(r2->outcome.problems[0].trace, r.outcome.problems[0].trace);
  EXPECT_EQ(r2->outcome.reads, r.outcome.reads);
  EXPECT_EQ(r2->outcome.writes, r.outcome.writes);
  EXPECT_EQ(r2->got, r.got);
  ASSERT_TRUE(r2->sliders);
  EXPECT_EQ(*r2->sliders, *r.sliders);
  ASSERT_EQ(r2->calls.size(), 2u);
  EXPECT_EQ(r2->calls[0].words, r.calls[0].words);
  ASSERT_EQ(r2->notes.size(), 1u);
  EXPECT_EQ(r2->notes[0].kind, ProblemKind::MissingSource);
}

bool decodes(std::string_view f) {
  return decode_reply(f) || decode_request(f) || decode_callback(f) || decode_callback_reply(f);
}

TEST(TclProtocol, MalformedFramesAreRefusedNotOverread) {
  const std::string frames[] = {encode(sample_reply()), encode(Request{Op::Run, "set x 1", "", 5, 0, false}),
                                encode(Callback{Op::ReadFile, "a.tcl", 0, 0}), encode(CallbackReply{})};
  for (const std::string& f : frames) {
    ASSERT_TRUE(decodes(f));
    // Cut short anywhere, or grown by a byte (nothing may follow a message): refused.
    for (size_t n = 0; n < f.size(); ++n) EXPECT_FALSE(decodes(std::string_view(f.data(), n))) << n;
    EXPECT_FALSE(decodes(f + "x"));
    // Any byte changed: whatever is read, nothing is read past the frame (AddressSanitizer).
    for (size_t i = 0; i < f.size(); ++i) {
      for (unsigned char b : {0x00, 0x7f, 0xff}) {
        std::string g = f;
        g[i] = static_cast<char>(b);
        (void)decodes(g);
      }
    }
  }
  // A count of items larger than the frame could hold is refused before anything is made.
  std::string huge = encode(Reply{});
  huge[huge.size() - 1] = '\x7f';  // the notes' count, the last field
  EXPECT_FALSE(decode_reply(huge));
  EXPECT_FALSE(op_of(""));
  EXPECT_FALSE(op_of(std::string(1, '\x63')));
}

TEST(TclProtocol, FramesCrossASocket) {
  int sv[2];
  ASSERT_EQ(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
  const std::string big(3 << 20, 'x');  // larger than the socket's buffer: written while read
  std::string got;
  std::thread reader([&] { got = read_frame(sv[1]).value_or(""); });
  ASSERT_TRUE(write_frame(sv[0], big));
  reader.join();
  EXPECT_EQ(got, big);
  // A length past the largest frame ends the reading, as does the other side closing.
  const char too_long[4] = {'\xff', '\xff', '\xff', '\x7f'};
  ASSERT_EQ(write(sv[0], too_long, 4), 4);
  EXPECT_FALSE(read_frame(sv[1]));
  close(sv[1]);
  EXPECT_FALSE(write_frame(sv[0], "after the reader left"));  // no SIGPIPE
  close(sv[0]);
}

}  // namespace
}  // namespace nomec::tcl::protocol
