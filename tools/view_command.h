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

/// Serves the preview until Ctrl-C (exit 0), or fails to start (exit 1).
int run_view(const ViewCommand& command);

}  // namespace nomec::tools
