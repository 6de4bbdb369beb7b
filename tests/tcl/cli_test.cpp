// `nomec` on SLIDE files whose Tcl reaches for what is not the scene's: `source` through a
// symbolic link beside the scene that points out of its folder (the linked file's text must
// not appear anywhere in the output), `..` out of the folder, a FIFO beside the scene (refused
// without waiting on it), and `--what-if` on a slider whose variable has a trace that never
// ends (the move is an error within its budget, and the command ends).
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/common/tcl_scenes.h"

namespace {

namespace fs = std::filesystem;

struct Ran {
  int status = -1;
  std::string output;  // stdout and stderr
};

Ran run(const std::string& args) {
  Ran r;
  // `timeout` separates "hung" from "slow" (a hang is the failure these tests exist for).
  const std::string command = "timeout 120 " + std::string(NOMEC_BINARY) + " --color never " + args + " 2>&1";
  FILE* p = popen(command.c_str(), "r");
  if (p == nullptr) return r;
  char buf[4096];
  size_t n = 0;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int status = pclose(p);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

fs::path scratch(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("nomec-tcl-cli-" + name + "-" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

TEST(TclCli, SourceDoesNotFollowALinkOutOfTheScenesFolder) {
  const fs::path dir = scratch("link");
  const fs::path outside = dir.parent_path() / ("nomec-tcl-cli-secret-" + std::to_string(getpid()) + ".tcl");
  write(outside, "set secret SECRET_TEXT_OUTSIDE_THE_FOLDER\n");
  fs::create_symlink(outside, dir / "lib.tcl");
  fs::create_symlink("/etc/passwd", dir / "passwd.tcl");
  fs::create_directories(dir / "sub");
  write(dir / "scene.slf",
        "tclinit { source lib.tcl }\ntclinit { source passwd.tcl }\ntclinit { source sub/../../x.tcl }\n"
        "tclinit { set have [slide import m passwd.tcl] }\npoint p (1 2 3) endpoint\n");
  const Ran r = run("--check " + (dir / "scene.slf").string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_EQ(r.output.find("SECRET_TEXT"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("root:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("couldn't read file \"lib.tcl\""), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("may only source files in its own folder"), std::string::npos) << r.output;
  fs::remove(outside);
  fs::remove_all(dir);
}

TEST(TclCli, AFifoBesideTheSceneIsNotWaitedOn) {
  const fs::path dir = scratch("fifo");
  ASSERT_EQ(mkfifo((dir / "lib.tcl").c_str(), 0600), 0);
  write(dir / "scene.slf", "tclinit { source lib.tcl }\npoint p (1 2 3) endpoint\n");
  const Ran r = run("--check " + (dir / "scene.slf").string());
  EXPECT_EQ(r.status, 1) << r.output;  // ended by itself, not by `timeout`
  EXPECT_NE(r.output.find("couldn't read file \"lib.tcl\""), std::string::npos) << r.output;
  fs::remove_all(dir);
}

TEST(TclCli, ASliderMoveWhoseTraceNeverEndsIsAnErrorWithinItsBudget) {
  const fs::path dir = scratch("whatif");
  write(dir / "trace.slf", nomec::testing_scenes::kSliderTraceNeverEnds);
  const Ran r = run("--what-if par.x=0.7 " + (dir / "trace.slf").string());
  EXPECT_NE(r.output.find("\"update_ms\""), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("nomec gives it for each slider move"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

}  // namespace
