// The handle on a scene's Tcl worker (see interp.h): finding and starting the worker, one
// request at a time with a deadline, the worker's callbacks answered meanwhile, and a dead
// or overdue worker turned into one problem.
#include "frontend/tcl/interp.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "frontend/tcl/protocol.h"

extern char** environ;

namespace nomec::tcl {

namespace proto = protocol;
using Clock = std::chrono::steady_clock;

namespace {

// How long past its budget a worker may take to answer: the engine's own time limit stops
// an interruptible script at the budget and the answer needs a moment to arrive; a command
// Tcl cannot interrupt is ended here.
constexpr auto kGrace = std::chrono::milliseconds(300);

bool executable(const std::string& path) { return !path.empty() && access(path.c_str(), X_OK) == 0; }

std::string find_worker() {
  if (const char* env = std::getenv("NOMEC_TCL_WORKER"); env != nullptr && *env != '\0') return env;
  char self[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n > 0) {
    std::string dir(self, static_cast<size_t>(n));
    dir.erase(dir.rfind('/') + 1);
    for (const char* rel : {"nomec-tcl-worker", "../libexec/nomec/nomec-tcl-worker", "../lib/nomec/nomec-tcl-worker"}) {
      if (executable(dir + rel)) return dir + rel;
    }
  }
#ifdef NOMEC_TCL_WORKER_BUILD_PATH
  if (executable(NOMEC_TCL_WORKER_BUILD_PATH)) return NOMEC_TCL_WORKER_BUILD_PATH;
#endif
  return "";
}

std::string signal_name(int sig) {
  switch (sig) {
    case SIGSEGV: return "SIGSEGV";
    case SIGBUS: return "SIGBUS";
    case SIGABRT: return "SIGABRT";
    case SIGKILL: return "SIGKILL";
    case SIGSYS: return "SIGSYS";
    case SIGXCPU: return "SIGXCPU";
    case SIGXFSZ: return "SIGXFSZ";
    case SIGILL: return "SIGILL";
    case SIGFPE: return "SIGFPE";
    default: return "signal " + std::to_string(sig);
  }
}

// What a worker's end (its wait status) means for the scene.
Problem describe_end(int status) {
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const std::string name = signal_name(sig);
    switch (sig) {
      case SIGSEGV:
      case SIGBUS:
        return {ProblemKind::Crashed,
                "Tcl crashed (" + name + "): a command nested too deeply for its stack, such as a deep `regexp`, "
                "`string match` or `eval`, or Tcl itself failed",
                0, ""};
      case SIGSYS:
        return {ProblemKind::Crashed, "the scene's Tcl tried a system call nomec forbids (" + name + ")", 0, ""};
      case SIGXCPU:
        return {ProblemKind::Limit, "the scene's Tcl used up the CPU time nomec allows (" + name + ")", 0, ""};
      case SIGKILL:
        return {ProblemKind::Crashed, "the system ended the scene's Tcl (" + name + "; out of memory?)", 0, ""};
      default: return {ProblemKind::Crashed, "Tcl crashed (" + name + ")", 0, ""};
    }
  }
  if (WIFEXITED(status)) {
    return {ProblemKind::Crashed,
            "nomec's Tcl worker ended unexpectedly (exit status " + std::to_string(WEXITSTATUS(status)) + ")", 0, ""};
  }
  return {ProblemKind::Crashed, "nomec's Tcl worker ended unexpectedly", 0, ""};
}

std::string seconds_text(int ms) {
  if (ms % 1000 == 0) return std::to_string(ms / 1000) + " s";
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", ms / 1000.0);
  return text;
}

}  // namespace

const std::string& worker_path() {
  static const std::string path = find_worker();
  return path;
}

struct Interp::State {
  std::string dir;
  ReadFile read_file;
  Limits limits;
  Preset preset;
  std::shared_ptr<Budget> budget;

  std::mutex call;  // one operation at a time
  pid_t pid = -1;
  int fd = -1;
  bool started = false;
  std::optional<Problem> stop;  // why nothing more runs
  std::string pending;          // bytes read past the last frame

  std::vector<Slider> sliders;
  std::vector<SlideCall> calls;
  std::vector<Problem> notes;

  ~State() { end_worker(); }

  void end_worker() {
    if (fd >= 0) close(fd);
    fd = -1;
    if (pid > 0) {
      kill(pid, SIGKILL);
      while (waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
      }
    }
    pid = -1;
  }

  // Stops the worker for `why`; returns the problem the current operation reports.
  Problem stop_with(Problem why, bool reap_status = false) {
    if (reap_status && pid > 0) {
      if (fd >= 0) close(fd);
      fd = -1;
      int status = 0;
      // The worker closed its socket: it is ending (or already ended); wait for it briefly.
      pid_t got = 0;
      for (int i = 0; i < 200 && (got = waitpid(pid, &status, WNOHANG)) == 0; ++i) usleep(1000);
      if (got == 0) {
        kill(pid, SIGKILL);
        while ((got = waitpid(pid, &status, 0)) < 0 && errno == EINTR) {
        }
      }
      if (got == pid) why = describe_end(status);
      pid = -1;
    }
    end_worker();
    stop = why;
    return why;
  }

  // Reads one frame before `deadline`: true with `out`; false on end, timeout (`*late`) or garbage.
  bool read_frame(std::string& out, Clock::time_point deadline, bool* late) {
    for (;;) {
      if (pending.size() >= 4) {
        const auto* b = reinterpret_cast<const unsigned char*>(pending.data());
        const uint32_t n = b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<uint32_t>(b[3]) << 24);
        if (n > proto::kMaxFrame) return false;
        if (pending.size() >= 4 + size_t{n}) {
          out.assign(pending, 4, n);
          pending.erase(0, 4 + size_t{n});
          return true;
        }
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0) {
        *late = true;
        return false;
      }
      pollfd p{fd, POLLIN, 0};
      const int ready = poll(&p, 1, static_cast<int>(std::min<int64_t>(left, INT_MAX)));
      if (ready < 0 && errno == EINTR) continue;
      if (ready < 0) return false;
      if (ready == 0) continue;  // the deadline is checked above
      char chunk[65536];
      const ssize_t got = ::read(fd, chunk, sizeof chunk);
      if (got < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (got <= 0) return false;
      pending.append(chunk, static_cast<size_t>(got));
    }
  }

  bool spawn(std::string* why) {
    const std::string& path = worker_path();
    if (path.empty()) {
      *why = "nomec cannot run this scene's Tcl: its Tcl worker `nomec-tcl-worker` is not installed beside nomec "
             "(or set NOMEC_TCL_WORKER to its path)";
      return false;
    }
    int sv[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) {
      *why = std::string("nomec cannot start its Tcl worker: ") + std::strerror(errno);
      return false;
    }
    // The worker's end becomes its descriptor 3 (dup2 clears close-on-exec; a descriptor
    // already numbered 3 is moved first, since dup2 onto itself would keep the flag).
    int child = sv[1];
    if (child == 3) {
      child = fcntl(sv[1], F_DUPFD_CLOEXEC, 4);
      close(sv[1]);
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, child, 3);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t none, defaults;
    sigemptyset(&none);
    sigemptyset(&defaults);
    for (int sig : {SIGPIPE, SIGINT, SIGTERM, SIGHUP, SIGCHLD}) sigaddset(&defaults, sig);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setsigdefault(&attr, &defaults);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    const std::string parent = std::to_string(getpid());
    char* argv[] = {const_cast<char*>(path.c_str()), const_cast<char*>("--parent"), const_cast<char*>(parent.c_str()),
                    nullptr};
    pid_t child_pid = -1;
    const int rc = posix_spawn(&child_pid, path.c_str(), &actions, &attr, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
    close(child);
    if (rc != 0) {
      close(sv[0]);
      *why = "nomec cannot start its Tcl worker `" + path + "`: " + std::strerror(rc);
      return false;
    }
    pid = child_pid;
    fd = sv[0];
    return true;
  }

  // Answers one callback of the worker.
  bool answer(const std::string& frame) {
    std::optional<proto::Callback> c = proto::decode_callback(frame);
    if (!c) return false;
    proto::CallbackReply r;
    switch (c->op) {
      case proto::Op::ReadFile: r.text = read_file ? read_file(c->text) : std::nullopt; break;
      case proto::Op::HasFile: r.yes = read_file && read_file(c->text).has_value(); break;
      case proto::Op::Preset:
        if (preset) r.number = preset(c->text, c->from, c->to);
        break;
      default: return false;
    }
    if (r.text && r.text->size() > proto::kMaxFrame - 64) r.text.reset();
    return proto::write_frame(fd, proto::encode(r));
  }

  // The budget's message, when it is used up.
  Problem out_of_budget() const {
    return {ProblemKind::Limit,
            "the scene's Tcl has run for the whole " + seconds_text(budget->total_ms()) + " nomec gives it" +
                (budget->scope().empty() ? "" : " " + budget->scope()) + ", and nomec runs no more of it",
            0, ""};
  }

  // Sends `q` and waits for the reply, answering callbacks; a problem when the worker
  // failed (it is stopped then) or was stopped before.
  std::optional<proto::Reply> exchange(proto::Request q, Problem* failure) {
    if (stop) {
      *failure = Problem{ProblemKind::Stopped, stop->message, 0, ""};
      return std::nullopt;
    }
    if (budget->left_us() <= 0) {
      *failure = stop_with(out_of_budget());
      return std::nullopt;
    }
    const auto start = Clock::now();
    if (!started) {
      std::string why;
      if (!spawn(&why)) {
        *failure = stop_with({ProblemKind::Unavailable, why, 0, ""});
        return std::nullopt;
      }
      started = true;
      proto::Request s;
      s.op = proto::Op::Start;
      s.text = dir;
      s.commands = limits.commands;
      s.milliseconds = limits.milliseconds;
      s.has_preset = static_cast<bool>(preset);
      std::optional<proto::Reply> ready = round_trip(s, start, failure);
      if (!ready) return std::nullopt;
      if (!ready->outcome.ok) {
        Problem why = ready->outcome.problems.empty() ? Problem{ProblemKind::Unavailable, "nomec's Tcl worker did not start", 0, ""}
                                                      : ready->outcome.problems.front();
        *failure = stop_with(why);
        return std::nullopt;
      }
    }
    q.milliseconds = std::max<int64_t>(1, (budget->left_us() + 999) / 1000);
    std::optional<proto::Reply> r = round_trip(q, start, failure);
    if (r) {
      if (r->sliders) sliders = std::move(*r->sliders);
      calls.insert(calls.end(), r->calls.begin(), r->calls.end());
      notes.insert(notes.end(), r->notes.begin(), r->notes.end());
      // Tcl's own time limit stopped this operation at the end of the budget: that is the
      // budget's one problem, and what comes after is not run (nor reported again).
      const bool limited = std::any_of(r->outcome.problems.begin(), r->outcome.problems.end(),
                                       [](const Problem& p) { return p.kind == ProblemKind::Limit; });
      if (limited && budget->left_us() <= 0) stop_with(out_of_budget());
    }
    return r;
  }

  std::optional<proto::Reply> round_trip(const proto::Request& q, Clock::time_point start, Problem* failure) {
    const auto deadline = start + std::chrono::microseconds(std::max<int64_t>(budget->left_us(), 0)) + kGrace;
    auto done = [&] {
      budget->spend(std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - start).count());
    };
    if (!proto::write_frame(fd, proto::encode(q))) {
      done();
      *failure = stop_with({ProblemKind::Crashed, "nomec's Tcl worker ended unexpectedly", 0, ""}, true);
      return std::nullopt;
    }
    std::string frame;
    for (;;) {
      bool late = false;
      if (!read_frame(frame, deadline, &late)) {
        done();
        if (late) {
          *failure = stop_with({ProblemKind::Limit,
                                "it did not finish within the " + seconds_text(budget->total_ms()) +
                                    " nomec gives the scene's Tcl" +
                                    (budget->scope().empty() ? "" : " " + budget->scope()) +
                                    ", and nomec stopped it (a loop that never ends, or "
                                    "one command Tcl cannot interrupt, such as `string match` on a long text or a "
                                    "huge `expr`?)",
                                0, ""});
        } else {
          *failure = stop_with({ProblemKind::Crashed, "nomec's Tcl worker ended unexpectedly", 0, ""}, true);
        }
        return std::nullopt;
      }
      std::optional<proto::Op> op = proto::op_of(frame);
      if (op == proto::Op::Reply) {
        std::optional<proto::Reply> r = proto::decode_reply(frame);
        done();
        if (!r) *failure = stop_with({ProblemKind::Crashed, "nomec's Tcl worker sent a reply nomec cannot read", 0, ""});
        return r;
      }
      if (!answer(frame)) {
        done();
        *failure = stop_with({ProblemKind::Crashed, "nomec's Tcl worker asked something nomec cannot answer", 0, ""});
        return std::nullopt;
      }
    }
  }

  Outcome operation(proto::Op op, std::string_view text) {
    std::lock_guard lock(call);
    proto::Request q;
    q.op = op;
    q.text = std::string(text);
    Problem failure;
    std::optional<proto::Reply> r = exchange(std::move(q), &failure);
    if (!r) {
      Outcome o;
      o.problems.push_back(std::move(failure));
      return o;
    }
    return std::move(r->outcome);
  }

  // get/set/watch: a failure is kept as a note (they have no outcome to carry it).
  std::optional<proto::Reply> touch(proto::Request q) {
    std::lock_guard lock(call);
    Problem failure;
    std::optional<proto::Reply> r = exchange(std::move(q), &failure);
    if (!r && failure.kind != ProblemKind::Stopped) notes.push_back(std::move(failure));
    return r;
  }
};

Interp::Interp(std::string dir, ReadFile read_file, Limits limits, Preset preset) : s_(std::make_unique<State>()) {
  s_->dir = std::move(dir);
  s_->read_file = std::move(read_file);
  s_->limits = limits;
  s_->preset = std::move(preset);
  s_->budget = std::make_shared<Budget>(limits.milliseconds);
}

Interp::~Interp() = default;

Outcome Interp::run(std::string_view script) { return s_->operation(proto::Op::Run, script); }
Outcome Interp::run_tracking_writes(std::string_view script) {
  return s_->operation(proto::Op::RunTrackingWrites, script);
}

Outcome Interp::value(std::string_view script) { return s_->operation(proto::Op::Value, script); }

std::optional<std::string> Interp::get(std::string_view name) {
  proto::Request q;
  q.op = proto::Op::Get;
  q.text = std::string(name);
  std::optional<proto::Reply> r = s_->touch(std::move(q));
  return r ? std::move(r->got) : std::nullopt;
}

void Interp::set(std::string_view name, std::string_view value) {
  proto::Request q;
  q.op = proto::Op::Set;
  q.text = std::string(name);
  q.value = std::string(value);
  s_->touch(std::move(q));
}

void Interp::watch(const std::string& name) {
  proto::Request q;
  q.op = proto::Op::Watch;
  q.text = name;
  s_->touch(std::move(q));
}

const std::vector<Slider>& Interp::sliders() const { return s_->sliders; }
const std::vector<SlideCall>& Interp::slide_calls() const { return s_->calls; }

std::vector<Problem> Interp::take_notes() {
  std::lock_guard lock(s_->call);
  std::vector<Problem> out;
  out.swap(s_->notes);
  return out;
}

void Interp::use_budget(std::shared_ptr<Budget> budget) {
  std::lock_guard lock(s_->call);
  if (budget) s_->budget = std::move(budget);
}

bool Interp::stopped() const {
  std::lock_guard lock(s_->call);
  return s_->stop.has_value();
}

}  // namespace nomec::tcl
