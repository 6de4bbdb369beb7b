// The `nomec` command line as data: every option of the check/emit command (`nomec FILE…`)
// and of `nomec fmt` and `nomec view`, read by CLI11 in cli.cpp; and the one-file-per-command entry points
// that main (nomec.cpp) dispatches to.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "backend/evaluate.h"
#include "frontend/check/check.h"
#include "tools/fmt_command.h"
#include "tools/view_command.h"

namespace nomec::tools {

struct Cli {
  std::vector<std::string> files;
  bool check_only = false;
  std::string emit;  // ir, deps, stl, obj, ply, summary, nome; empty: check only
  std::string dialect;
  std::vector<std::string> defines;  // -D bank.param=value
  bool werror = false;
  bool verbose = false;
  bool allow_out_of_range = false;
  std::string format = "text";  // diagnostics: text or json
  std::string base;
  bool sif_quads = false;  // --sif-quads
  int64_t max_file_bytes = kDefaultMaxFileBytes;       // --max-file-size
  int64_t max_mesh_bytes = kDefaultMaxMeshFileBytes;  // --max-mesh-size
  std::string color = "auto";
  double time = 0;
  double frame = 0;
  double tcl_seconds = 10;  // --tcl-seconds: wall time of a SLIDE file's Tcl in all
  bool no_tcl = false;      // --no-tcl: SLIDE files' Tcl is not run
  std::string output;  // -o
  bool stl_ascii = false;
  bool time_report = false;
  backend::PipelineOptions pipeline;
  std::string rule = "catmull-clark";
  std::string what_if;  // --what-if bank.param=value
  bool is_fmt = false;  // the `fmt` subcommand was given
  FmtCommand fmt;
  bool is_view = false;  // the `view` subcommand was given
  ViewCommand view;

  bool emits_mesh() const { return emit == "stl" || emit == "obj" || emit == "ply" || emit == "summary"; }
};

/// Reads the command line into `cli`. Returns -1 to go on, or the exit code to return now
/// (0 after `--help`/`--version`, 2 on a usage error, with its message printed).
int parse_command_line(int argc, char** argv, Cli& cli);

/// The number `text` spells (`0.5`, `-2`, `1e-3`), or nullopt when it is not a number or not
/// finite (`nan`, `inf`, `1e999999`, which would overflow): every number of the command line
/// (`-D`, `--what-if`, `--offset` …) is read by this.
std::optional<double> parse_finite_number(const std::string& text);

/// The check options the command line asks for; "" or a usage error message.
std::string check_options(const Cli& cli, CheckOptions& out);

/// "" or why the output `target` must not be written: it is one of `inputs`, the files the
/// command read (the same file by device and inode: through a symlink, a hard link or
/// another spelling of its path). `-` (standard output) is never an input.
std::string output_is_input(const std::string& target, const std::vector<std::string>& inputs);

/// `nomec FILE…` with `--check` or `--emit` (check_command.cpp). Returns the exit code.
int run_check_command(const Cli& cli);

/// `nomec --lsp [--stdio] [--clientProcessId=N]` (lsp_command.cpp).
int run_lsp_command(int argc, char** argv);

}  // namespace nomec::tools
