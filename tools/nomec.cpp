// The `nomec` command line: checks NOME/NOME3/SLIDE files and prints diagnostics (text like
// clang, or JSON), or emits the IR dump, the dependency graph, meshes (STL/OBJ/PLY through
// backend/), a JSON topology summary of them or the saved scene; `nomec fmt` formats,
// `nomec view` serves the live preview and `nomec --lsp` is the language server. The
// first client of the nomec libraries; it knows only what they expose. One file per command: cli.cpp reads the command line,
// check_command.cpp, emit_mesh.cpp, emit_nome.cpp, what_if.cpp, fmt_command.cpp,
// view_command.cpp and lsp_command.cpp do the work.
#include <string_view>

#include "tools/allocator.h"
#include "tools/cli.h"

NOMEC_JEMALLOC_CONFIG();

int main(int argc, char** argv) {
  if (argc >= 2 && std::string_view(argv[1]) == "--lsp") return nomec::tools::run_lsp_command(argc, argv);
  nomec::tools::Cli cli;
  if (int code = nomec::tools::parse_command_line(argc, argv, cli); code >= 0) return code;
  if (cli.is_fmt) return nomec::tools::run_fmt(cli.fmt);
  if (cli.is_view) return nomec::tools::run_view(cli.view);
  return nomec::tools::run_check_command(cli);
}
