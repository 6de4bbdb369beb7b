// `nomec fmt` implementation: reads each file (or stdin), calls format_source, and prints,
// checks or rewrites in place (`rewrite_file`: a temporary file next to it, then a rename,
// only if the file is unchanged since it was read; through symlinks; read-only and
// hard-linked files refused with the reason).
#include "base/file_io.h"
#include "tools/fmt_command.h"

#include <cerrno>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <iterator>
#include <optional>
#include <sstream>
#include <unistd.h>

#include "frontend/format/format.h"
#include "frontend/source/source_manager.h"

namespace nomec::tools {

namespace {

// A regular file (or standard input, `-`) under the cap: a FIFO or device is refused
// without waiting on it.
FileRead read_input(const std::string& path, int64_t max_bytes) {
  if (path == "-") return read_input_stream(STDIN_FILENO, "<stdin>", max_bytes);
  return read_input_file(path, max_bytes);
}

}  // namespace

int run_fmt(const FmtCommand& command) {
  if (command.in_place && command.check) {
    std::cerr << "nomec fmt: --in-place and --check cannot be used together\n";
    return 2;
  }
  if (!command.in_place && !command.check && command.files.size() != 1) {
    std::cerr << "nomec fmt: give one file to print, or use --in-place or --check\n";
    return 2;
  }
  for (const std::string& f : command.files) {
    if (f == "-" && (command.in_place || command.files.size() != 1)) {
      std::cerr << "nomec fmt: `-` (standard input) must be the only file and cannot be "
                   "rewritten in place\n";
      return 2;
    }
  }
  FormatOptions options;
  options.indent_width = command.indent_width;
  options.insert_spaces = !command.use_tabs;
  int status = 0;
  for (const std::string& path : command.files) {
    FileRead input = read_input(path, command.max_file_bytes);
    if (!input.ok()) {
      std::cerr << fmt::format("nomec fmt: {}\n", input.error);
      return 2;
    }
    const std::optional<std::string> text = std::move(input.bytes);
    FormatResult result = format_source(*text, options);
    std::string shown = path == "-" ? "<stdin>" : path;
    if (!result.ok) {
      // result.error is "line:col: message".
      size_t colon = result.error.find(": ");
      std::string where = colon == std::string::npos ? "1:1" : result.error.substr(0, colon);
      std::string message = colon == std::string::npos ? result.error : result.error.substr(colon + 2);
      std::cerr << fmt::format("{}:{}: error: {} (file not formatted)\n", shown, where, message);
      status = std::max(status, 1);
      continue;
    }
    if (command.check) {
      if (result.text != *text) {
        std::cout << shown << "\n";
        status = std::max(status, 1);
      }
    } else if (command.in_place) {
      // Only if the file still holds what was read, through a symlink, never over a
      // read-only or hard-linked file (base/file_io.h, rewrite_file); the other files are
      // formatted all the same.
      if (result.text == *text) continue;
      if (std::string error = rewrite_file(path, *text, result.text); !error.empty()) {
        std::cerr << "nomec fmt: not rewritten: " << error << "\n";
        status = 2;
      }
    } else {
      std::cout << result.text;
    }
  }
  return status;
}

}  // namespace nomec::tools
