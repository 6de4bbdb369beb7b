// The framed protocol between nomec (`Interp`, interp.h) and its Tcl worker process
// (worker_main.cpp) over a Unix stream socket. A frame is a 4-byte little-endian length and
// that many bytes; the first byte says what the frame is. nomec sends one `Request` per
// operation and reads frames until the worker's `Reply`; while the scene's Tcl runs, the
// worker may ask for a file (`source`), whether a file exists (`slide import`) or a `-D`
// value (`scale`), each a `Callback` that nomec answers with a `CallbackReply`. The worker
// reads nothing else and writes nothing else, so a worker that sends anything malformed is
// ended. Plain data and byte codecs; no Tcl, no processes.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "frontend/tcl/types.h"

namespace nomec::tcl::protocol {

/// The largest frame either side accepts (a value the engine may build is at most 4 M
/// characters, guard.h; a sourced file at most the reader's cap).
constexpr uint32_t kMaxFrame = 256u << 20;

enum class Op : uint8_t {
  // nomec → worker
  Start = 1,          // make the engine: `text` = the scene's folder, `commands`, `has_preset`
  Run,                // run a script (`text`)
  RunTrackingWrites,  // run a script, recording the globals it writes
  Value,              // evaluate a value's script
  Get,                // read a global (`text`)
  Set,                // set a global (`text` = name, `value`)
  Watch,              // trace reads of a global (`text`)
  // worker → nomec, in the middle of an operation
  ReadFile,  // `source FILE`: the file's text, please
  HasFile,   // `slide import NAME FILE`: does it exist?
  Preset,    // a `scale` binds `text` with range `from`..`to`: a `-D` value for it?
  // nomec → worker: the answer to a callback
  CallbackReply,
  // worker → nomec: the end of an operation
  Reply,
};

/// One operation nomec asks of the worker.
struct Request {
  Op op = Op::Run;
  std::string text;          // the script, the variable's name, or (Start) the scene's folder
  std::string value;         // Set: the value
  int64_t milliseconds = 0;  // how long Tcl may run (the caller's budget left)
  int64_t commands = 0;      // Start: Tcl commands per script
  bool has_preset = false;   // Start: ask nomec for `-D` values when a `scale` binds a variable
};

/// What the worker asks nomec while an operation runs.
struct Callback {
  Op op = Op::ReadFile;  // ReadFile, HasFile or Preset
  std::string text;      // the path, or the variable
  double from = 0, to = 0;
};

/// nomec's answer to a `Callback`.
struct CallbackReply {
  std::optional<std::string> text;  // ReadFile: the file's text
  bool yes = false;                 // HasFile
  std::optional<double> number;     // Preset
};

/// The end of one operation: its outcome, and what changed in the engine's records.
struct Reply {
  Outcome outcome;
  std::optional<std::string> got;              // Get: the variable's value, when set
  std::optional<std::vector<Slider>> sliders;  // every slider, when they changed
  std::vector<SlideCall> calls;                // `slide` calls made since the last reply
  std::vector<Problem> notes;                  // notes made since the last reply
};

std::string encode(const Request& r);
std::string encode(const Callback& c);
std::string encode(const CallbackReply& r);
std::string encode(const Reply& r);

/// The operation a frame carries (its first byte); nullopt for an empty or unknown frame.
std::optional<Op> op_of(std::string_view frame);
/// Decoders: nullopt when the frame is malformed (nomec then ends the worker).
std::optional<Request> decode_request(std::string_view frame);
std::optional<Callback> decode_callback(std::string_view frame);
std::optional<CallbackReply> decode_callback_reply(std::string_view frame);
std::optional<Reply> decode_reply(std::string_view frame);

/// Writes one frame (length and bytes) to `fd`, a socket: never raises SIGPIPE. False when
/// the other side is gone.
bool write_frame(int fd, std::string_view payload);
/// Reads one frame from `fd`, blocking; nullopt at end of input or on a malformed length.
std::optional<std::string> read_frame(int fd);

}  // namespace nomec::tcl::protocol
