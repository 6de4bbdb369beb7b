// nomec-file-test: the golden-file runner. Each test file carries its own expectations:
//
//   # ARGS: --emit ir %s                 (optional; default `--check %s`)
//   # ENV: NAME=value                     (optional, repeatable: set for nomec's run)
//   # CHECK:STDOUT: <one line of nomec's stdout>
//   # CHECK:STDERR: <one line of nomec's stderr>
//
// The runner runs `nomec --color never <ARGS>` with the repository root as working
// directory and the test file's path relative to that root (so diagnostics print stable
// paths such as `tests/check/testdata/fail_unknown_name.nome`), then compares stdout and
// stderr line by line, exactly and in order. `%s` is the test file, `%corpus%` the corpus
// folder (`NOMEC_CORPUS_DIR`); occurrences of the corpus path in nomec's output are written
// back as `%corpus%`, so expectations do not depend on where the checkout lives.
//
// Exit codes: a file named `fail_*` must make nomec exit 1 and print at least one
// `error:`; any other file must make it exit 0.
//
// `--update` (or NOMEC_UPDATE_GOLDEN=1) rewrites the expectations in place: old CHECK lines
// are removed and the new ones appended at the end of the file. Review with `git diff`.
//
// Usage: nomec-file-test [--update] [FILE|DIR]...   (no arguments: every test file under
// tests/{parse,check,ir}/testdata/).
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kArgs = "# ARGS:";
constexpr std::string_view kEnv = "# ENV:";
constexpr std::string_view kStdout = "# CHECK:STDOUT:";
constexpr std::string_view kStderr = "# CHECK:STDERR:";

bool is_test_file(const fs::path& p) {
  std::string ext = p.extension().string();
  return ext == ".nome" || ext == ".nom" || ext == ".slf" || ext == ".anom";
}

std::optional<std::string> read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Splits text into lines without their terminators ("\n" or "\r\n"); a final line without
// a terminator counts, an empty text has no lines.
std::vector<std::string> split_lines(std::string_view text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start < text.size()) {
    size_t nl = text.find('\n', start);
    size_t end = nl == std::string_view::npos ? text.size() : nl;
    std::string line(text.substr(start, end - start));
    if (!line.empty() && line.back() == '\r') line.pop_back();
    out.push_back(std::move(line));
    if (nl == std::string_view::npos) break;
    start = nl + 1;
  }
  return out;
}

bool starts_with(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

// The text after a CHECK/ARGS prefix: one optional space is part of the prefix.
std::string after_prefix(std::string_view line, std::string_view prefix) {
  std::string_view rest = line.substr(prefix.size());
  if (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
  return std::string(rest);
}

void replace_all(std::string& s, std::string_view from, std::string_view to) {
  if (from.empty()) return;
  for (size_t pos = 0; (pos = s.find(from, pos)) != std::string::npos; pos += to.size()) {
    s.replace(pos, from.size(), to);
  }
}

// Splits an ARGS line on whitespace; single or double quotes group words.
std::vector<std::string> split_args(std::string_view line) {
  std::vector<std::string> out;
  std::string cur;
  bool have = false;
  char quote = 0;
  for (char c : line) {
    if (quote != 0) {
      if (c == quote) {
        quote = 0;
      } else {
        cur += c;
      }
    } else if (c == '\'' || c == '"') {
      quote = c;
      have = true;
    } else if (c == ' ' || c == '\t') {
      if (have) out.push_back(cur);
      cur.clear();
      have = false;
    } else {
      cur += c;
      have = true;
    }
  }
  if (have) out.push_back(cur);
  return out;
}

struct RunResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// Runs `argv` in `cwd`, capturing stdout and stderr through temporary files (no pipes, so
// large outputs cannot deadlock).
RunResult run(const std::vector<std::string>& argv, const fs::path& cwd, const std::vector<std::string>& env) {
  RunResult r;
  char out_name[] = "/tmp/nomec-file-test-out-XXXXXX";
  char err_name[] = "/tmp/nomec-file-test-err-XXXXXX";
  int out_fd = mkstemp(out_name);
  int err_fd = mkstemp(err_name);
  if (out_fd < 0 || err_fd < 0) {
    r.err = "cannot create temporary files";
    return r;
  }
  pid_t pid = fork();
  if (pid == 0) {
    if (chdir(cwd.c_str()) != 0) _exit(127);
    dup2(out_fd, STDOUT_FILENO);
    dup2(err_fd, STDERR_FILENO);
    int null_fd = open("/dev/null", O_RDONLY);
    if (null_fd >= 0) dup2(null_fd, STDIN_FILENO);
    for (const std::string& e : env) putenv(const_cast<char*>(e.c_str()));
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  int status = 0;
  if (pid > 0) waitpid(pid, &status, 0);
  close(out_fd);
  close(err_fd);
  r.out = read_file(out_name).value_or("");
  r.err = read_file(err_name).value_or("");
  unlink(out_name);
  unlink(err_name);
  if (pid < 0) {
    r.err = "fork failed";
  } else if (WIFEXITED(status)) {
    r.exit_code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    r.exit_code = 128 + WTERMSIG(status);
  }
  return r;
}

struct Config {
  fs::path nomec;
  fs::path root;    // repository root: nomec's working directory
  fs::path corpus;  // ../shared/corpus, absolute
  bool update = false;
};

// Shows expected vs actual for one stream, marking the first difference.
void report_stream(std::ostream& os, std::string_view name, const std::vector<std::string>& want,
                   const std::vector<std::string>& got) {
  size_t first = 0;
  while (first < want.size() && first < got.size() && want[first] == got[first]) ++first;
  os << "  " << name << " differs at line " << first + 1 << " (expected " << want.size()
     << " lines, got " << got.size() << ")\n";
  size_t from = first >= 2 ? first - 2 : 0;
  for (size_t i = from; i < std::max(want.size(), got.size()) && i < first + 8; ++i) {
    bool same = i < want.size() && i < got.size() && want[i] == got[i];
    if (same) {
      os << "      " << want[i] << "\n";
      continue;
    }
    if (i < want.size()) os << "    - " << want[i] << "\n";
    if (i < got.size()) os << "    + " << got[i] << "\n";
  }
}

// Returns true when the file passes (or was updated).
bool run_file(const Config& cfg, const fs::path& file) {
  std::error_code ec;
  fs::path abs = fs::absolute(file, ec);
  fs::path rel = fs::relative(abs, cfg.root, ec);
  if (ec || rel.empty()) rel = abs;
  std::string shown = rel.string();
  std::optional<std::string> content = read_file(abs);
  if (!content) {
    std::cerr << "FAIL " << shown << ": cannot read the file\n";
    return false;
  }
  std::vector<std::string> lines = split_lines(*content);
  std::string args_line = "--check %s";
  std::vector<std::string> want_out, want_err, env;
  for (const std::string& line : lines) {
    if (starts_with(line, kArgs)) {
      args_line = after_prefix(line, kArgs);
    } else if (starts_with(line, kEnv)) {
      env.push_back(after_prefix(line, kEnv));
    } else if (starts_with(line, kStdout)) {
      want_out.push_back(after_prefix(line, kStdout));
    } else if (starts_with(line, kStderr)) {
      want_err.push_back(after_prefix(line, kStderr));
    }
  }
  std::string corpus = cfg.corpus.string();
  std::vector<std::string> argv = {cfg.nomec.string(), "--color", "never"};
  for (std::string a : split_args(args_line)) {
    replace_all(a, "%corpus%", corpus);
    replace_all(a, "%s", shown);
    argv.push_back(std::move(a));
  }
  RunResult r = run(argv, cfg.root, env);
  replace_all(r.out, corpus, "%corpus%");
  replace_all(r.err, corpus, "%corpus%");
  std::vector<std::string> got_out = split_lines(r.out);
  std::vector<std::string> got_err = split_lines(r.err);

  bool expect_fail = starts_with(file.filename().string(), "fail_");
  std::vector<std::string> problems;
  if (expect_fail) {
    if (r.exit_code != 1) {
      problems.push_back("a `fail_` file must make nomec exit 1, it exited " + std::to_string(r.exit_code));
    }
    if (r.err.find("error:") == std::string::npos) {
      problems.push_back("a `fail_` file must produce at least one `error:`");
    }
  } else if (r.exit_code != 0) {
    problems.push_back("nomec exited " + std::to_string(r.exit_code) +
                       "; name the file `fail_*` if errors are expected");
  }

  if (cfg.update) {
    if (want_out != got_out || want_err != got_err) {
      bool crlf = content->find("\r\n") != std::string::npos;
      std::string eol = crlf ? "\r\n" : "\n";
      std::string kept;
      size_t start = 0;
      while (start < content->size()) {
        size_t nl = content->find('\n', start);
        size_t end = nl == std::string::npos ? content->size() : nl + 1;
        std::string_view line(content->data() + start, end - start);
        if (!starts_with(line, kStdout) && !starts_with(line, kStderr)) kept.append(line);
        start = end;
      }
      // Blank lines left at the end by removed expectations go; one blank line separates
      // the input from the new expectations. A file without a final newline keeps that
      // property when it has no expectations (the parse tests rely on it).
      bool had_final_newline = !content->empty() && content->back() == '\n';
      while (!kept.empty() && (kept.back() == '\n' || kept.back() == '\r')) kept.pop_back();
      if (!got_out.empty() || !got_err.empty()) {
        if (!kept.empty()) kept += eol + eol;
        for (const std::string& l : got_out) kept += std::string(kStdout) + (l.empty() ? "" : " " + l) + eol;
        for (const std::string& l : got_err) kept += std::string(kStderr) + (l.empty() ? "" : " " + l) + eol;
      } else if (had_final_newline && !kept.empty()) {
        kept += eol;
      }
      std::ofstream out(abs, std::ios::binary | std::ios::trunc);
      out << kept;
      std::cerr << "UPDATED " << shown << "\n";
    }
    for (const std::string& p : problems) std::cerr << "FAIL " << shown << ": " << p << "\n";
    return problems.empty();
  }

  std::ostringstream report;
  if (want_out != got_out) report_stream(report, "stdout", want_out, got_out);
  if (want_err != got_err) report_stream(report, "stderr", want_err, got_err);
  if (!problems.empty() || !report.str().empty()) {
    std::cerr << "FAIL " << shown << "\n";
    for (const std::string& p : problems) std::cerr << "  " << p << "\n";
    std::cerr << report.str();
    std::cerr << "  command (in " << cfg.root.string() << "):";
    for (const std::string& a : argv) std::cerr << " " << a;
    std::cerr << "\n  to accept the new output: NOMEC_UPDATE_GOLDEN=1 ctest -R golden, then review `git diff`\n";
    return false;
  }
  return true;
}

void collect(const fs::path& p, std::vector<fs::path>& out) {
  std::error_code ec;
  if (fs::is_directory(p, ec)) {
    std::vector<fs::path> found;
    for (const auto& e : fs::recursive_directory_iterator(p, ec)) {
      if (e.is_regular_file() && is_test_file(e.path())) found.push_back(e.path());
    }
    std::sort(found.begin(), found.end());
    out.insert(out.end(), found.begin(), found.end());
  } else {
    out.push_back(p);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Config cfg;
  cfg.nomec = NOMEC_BINARY;
  cfg.root = fs::weakly_canonical(NOMEC_SOURCE_DIR);
  cfg.corpus = fs::weakly_canonical(NOMEC_CORPUS_DIR);
  const char* env = std::getenv("NOMEC_UPDATE_GOLDEN");
  cfg.update = env != nullptr && std::string_view(env) != "" && std::string_view(env) != "0";
  std::vector<fs::path> files;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--update") {
      cfg.update = true;
    } else if (a == "--nomec" && i + 1 < argc) {
      cfg.nomec = argv[++i];
    } else if (a == "--help" || a == "-h") {
      std::cout << "usage: nomec-file-test [--update] [--nomec PATH] [FILE|DIR]...\n";
      return 0;
    } else {
      collect(a, files);
    }
  }
  if (argc == 1 || files.empty()) {
    for (const char* dir : {"tests/parse/testdata", "tests/check/testdata", "tests/ir/testdata"}) {
      if (fs::exists(cfg.root / dir)) collect(cfg.root / dir, files);
    }
  }
  int failed = 0;
  for (const fs::path& f : files) {
    if (!run_file(cfg, f)) ++failed;
  }
  std::cerr << files.size() - failed << "/" << files.size() << " golden files passed"
            << (cfg.update ? " (update mode)" : "") << "\n";
  return failed == 0 ? 0 : 1;
}
