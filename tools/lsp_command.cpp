// `nomec --lsp`: the language server on stdin/stdout (lsp/). Editors' clients may append
// `--stdio` and `--clientProcessId=N` (vscode-languageclient does); both are accepted.
#include <iostream>
#include <string_view>

#include "tools/cli.h"
#ifdef NOMEC_HAVE_LSP
#include "lsp/server.h"
#endif

namespace nomec::tools {

int run_lsp_command(int argc, char** argv) {
#ifdef NOMEC_HAVE_LSP
  for (int i = 2; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a != "--stdio" && a.rfind("--clientProcessId", 0) != 0) {
      std::cerr << "nomec: --lsp takes no other arguments (got `" << a << "`)\n";
      return 2;
    }
  }
  return lsp::run_stdio();
#else
  (void)argc;
  (void)argv;
  std::cerr << "nomec: built without the language server (NOMEC_BUILD_LSP=OFF)\n";
  return 2;
#endif
}

}  // namespace nomec::tools
