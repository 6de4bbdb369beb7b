// `nomec view FILE [--port N] [--open]`: the live preview in a browser (view_command.cpp).
#pragma once

#include <string>

namespace nomec::tools {

struct ViewCommand {
  std::string file;
  int port = 8642;  // 0: any free port
  bool open = false;
  std::string app_dir;  // where the built preview app is; empty: the default places
};

/// At most this many pages are served at once: each has a language server of its own (four
/// threads), counted from its start until its threads are joined. A page past it is refused
/// with a WebSocket close (code 1013, "try again later") whose reason the page shows.
inline constexpr int kViewMaxPages = 16;
/// At most this many connections (pages' WebSockets and HTTP requests) are open at once;
/// one past it is answered 503 and closed.
inline constexpr int kViewMaxConnections = 64;
/// How long Ctrl-C (SIGINT/SIGTERM) waits for the pages' language servers to stop before
/// the process ends without them (a page whose scene is still being checked).
inline constexpr int kViewStopGraceMs = 2000;

/// Serves the preview until Ctrl-C (exit 0), or fails to start (exit 1).
int run_view(const ViewCommand& command);

}  // namespace nomec::tools
