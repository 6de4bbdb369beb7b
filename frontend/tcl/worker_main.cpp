// `nomec-tcl-worker`: the process that runs one SLIDE scene's Tcl for nomec (interp.h). nomec
// starts it with the socket it talks over as descriptor 3; the worker walls itself in
// (sandbox.h), makes the engine when asked (`Start`), installs its system-call filter and
// then answers one request at a time until the socket closes. The engine runs on a thread
// of its own whose stack is large enough for Tcl's recursion limit, whatever stack limit
// the worker inherited. Nothing here decides what a scene may do: the engine and its guards
// do, and this process is the wall behind them.
#include <pthread.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "frontend/tcl/engine.h"
#include "frontend/tcl/protocol.h"
#include "frontend/tcl/sandbox.h"

// The worker ends by being killed or by the socket closing; a leak check at exit would need
// a thread and ptrace, which the filter refuses. And its crashes are the scene's, as in a
// release build: a signal ends it (the client reports `TclCrashed` with the signal), instead
// of the sanitizer catching it and writing a report (which its file-size limit of 0 turns
// into a SIGXFSZ, or an exit status).
extern "C" const char* __asan_default_options() {  // NOLINT
  return "detect_leaks=0:handle_segv=0:handle_sigbus=0:handle_abort=0:handle_sigfpe=0:handle_sigill=0";
}

namespace nomec::tcl {
namespace {

namespace proto = protocol;

constexpr int kSocket = 3;

[[noreturn]] void gone() { _exit(0); }  // nomec closed the socket: nothing left to do

proto::CallbackReply ask(const proto::Callback& c) {
  if (!proto::write_frame(kSocket, proto::encode(c))) gone();
  std::optional<std::string> frame = proto::read_frame(kSocket);
  if (!frame) gone();
  std::optional<proto::CallbackReply> r = proto::decode_callback_reply(*frame);
  if (!r) _exit(4);
  return std::move(*r);
}

// What the engine reports, remembered so each reply carries only what changed.
struct Sent {
  std::vector<Slider> sliders;
  size_t calls = 0;
};

void reply(Engine* engine, Sent& sent, proto::Reply r) {
  if (engine != nullptr) {
    if (engine->sliders() != sent.sliders) {
      sent.sliders = engine->sliders();
      r.sliders = sent.sliders;
    }
    const std::vector<SlideCall>& calls = engine->slide_calls();
    r.calls.assign(calls.begin() + static_cast<std::ptrdiff_t>(sent.calls), calls.end());
    sent.calls = calls.size();
    std::vector<Problem> notes = engine->take_notes();
    r.notes.insert(r.notes.end(), notes.begin(), notes.end());
  }
  if (!proto::write_frame(kSocket, proto::encode(r))) gone();
}

int clamp_ms(int64_t ms) { return static_cast<int>(std::clamp<int64_t>(ms, 1, 24 * 3600 * 1000)); }

void serve() {
  std::optional<std::string> frame = proto::read_frame(kSocket);
  if (!frame) gone();
  std::optional<proto::Request> start = proto::decode_request(*frame);
  if (!start || start->op != proto::Op::Start) _exit(4);
  ReadFile read_file = [](const std::string& path) { return ask({proto::Op::ReadFile, path, 0, 0}).text; };
  HasFile has_file = [](const std::string& path) { return ask({proto::Op::HasFile, path, 0, 0}).yes; };
  Preset preset;
  if (start->has_preset) {
    preset = [](const std::string& var, double from, double to) { return ask({proto::Op::Preset, var, from, to}).number; };
  }
  Limits limits;
  limits.commands = start->commands > 0 ? start->commands : limits.commands;
  limits.milliseconds = clamp_ms(start->milliseconds);
  auto engine = std::make_unique<Engine>(start->text, read_file, limits, preset, has_file);
  Sent sent;
  if (std::string error = sandbox::install_filter(); !error.empty()) {
    proto::Reply r;
    r.outcome.problems.push_back({ProblemKind::Unavailable, "nomec could not wall in its Tcl worker: " + error, 0, ""});
    reply(nullptr, sent, std::move(r));
    _exit(5);
  }
  proto::Reply ready;
  ready.outcome.ok = true;
  reply(engine.get(), sent, std::move(ready));
  for (;;) {
    frame = proto::read_frame(kSocket);
    if (!frame) gone();
    std::optional<proto::Request> q = proto::decode_request(*frame);
    if (!q || q->op == proto::Op::Start) _exit(4);
    engine->set_time_limit(clamp_ms(q->milliseconds));
    proto::Reply r;
    switch (q->op) {
      case proto::Op::Run: r.outcome = engine->run(q->text); break;
      case proto::Op::RunTrackingWrites: r.outcome = engine->run_tracking_writes(q->text); break;
      case proto::Op::Value: r.outcome = engine->value(q->text); break;
      case proto::Op::Get:
        r.got = engine->get(q->text);
        r.outcome.ok = true;
        break;
      case proto::Op::Set:
        engine->set(q->text, q->value);
        r.outcome.ok = true;
        break;
      case proto::Op::Watch:
        engine->watch(q->text);
        r.outcome.ok = true;
        break;
      default: _exit(4);
    }
    reply(engine.get(), sent, std::move(r));
  }
}

void* serve_thread(void*) {
  serve();
  return nullptr;
}

}  // namespace
}  // namespace nomec::tcl

int main(int argc, char** argv) {
  // nomec-tcl-worker --parent PID (descriptor 3 is the socket to nomec)
  pid_t parent = 0;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--parent") == 0) parent = static_cast<pid_t>(std::atol(argv[i + 1]));
  }
  if (parent <= 0) {
    std::fprintf(stderr, "nomec-tcl-worker: runs SLIDE's Tcl for nomec, which starts it; it is not run by hand\n");
    return 2;
  }
  std::signal(SIGPIPE, SIG_IGN);
  if (std::string error = nomec::tcl::sandbox::prepare(nomec::tcl::kSocket, parent); !error.empty()) {
    std::fprintf(stderr, "nomec-tcl-worker: %s\n", error.c_str());
    return 3;
  }
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  pthread_attr_setstacksize(&attr, nomec::tcl::sandbox::kEngineStack);
  pthread_t thread;
  if (pthread_create(&thread, &attr, nomec::tcl::serve_thread, nullptr) != 0) {
    std::fprintf(stderr, "nomec-tcl-worker: cannot start the interpreter's thread\n");
    return 3;
  }
  pthread_join(thread, nullptr);
  return 0;
}
