// The writing side of base/file_io.h (issue 45, "never lose the user's text"): a temporary
// file is removed when SIGINT, SIGTERM or SIGHUP stops the process mid-write (and the
// process still ends by that signal; a program's own handler is left alone); `rewrite_file`
// (`nomec fmt -i`) writes through a symlink, keeps permissions, refuses read-only and
// hard-linked files and keeps an edit saved after the file was read; `is_same_file` sees
// one file through symlinks, hard links and other spellings of its path.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "base/file_io.h"

namespace nomec {
namespace {

namespace fs = std::filesystem;

class WriteTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nomec_write_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(dir_);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string put(const std::string& name, const std::string& bytes) const {
    std::ofstream(path(name), std::ios::binary) << bytes;
    return path(name);
  }
  static std::string get(const std::string& p) { return read_file_bytes(p).value_or("<unreadable>"); }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }
  fs::path dir_;
};

// A child process that writes part of `target` through AtomicFileWriter and is then sent
// `sig`; returns its wait status.
int write_and_signal(const std::string& target, int sig, bool own_handler) {
  const pid_t child = ::fork();
  if (child == 0) {
    if (own_handler) std::signal(sig, [](int) { ::_exit(42); });
    AtomicFileWriter out(target);
    out.append("solid half-written\n");
    ::kill(::getpid(), sig);
    ::_exit(0);  // not reached: the signal ends the process
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  return status;
}

TEST_F(WriteTest, ASignalMidWriteRemovesTheTemporaryFileAndStillEndsTheProcess) {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    const std::string target = put("out.stl", "previous output");
    const int status = write_and_signal(target, sig, false);
    ASSERT_TRUE(WIFSIGNALED(status)) << "signal " << sig << ": status " << status;
    EXPECT_EQ(WTERMSIG(status), sig);
    EXPECT_EQ(names(), std::vector<std::string>{"out.stl"}) << "signal " << sig;
    EXPECT_EQ(get(target), "previous output");
  }
  // A new output: nothing is left at all.
  fs::remove(path("out.stl"));
  const int status = write_and_signal(path("new.stl"), SIGINT, false);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT);
  EXPECT_TRUE(names().empty());
}

TEST_F(WriteTest, AProgramsOwnSignalHandlerIsLeftAlone) {
  const int status = write_and_signal(path("out.stl"), SIGTERM, true);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 42);  // its handler ran, not ours
}

TEST_F(WriteTest, WritersThatFinishFreeTheirPlaceForLaterOnes) {
  const pid_t child = ::fork();
  if (child == 0) {
    std::vector<std::unique_ptr<AtomicFileWriter>> open;
    for (int round = 0; round < 5; ++round) {  // 150 writers made, at most 60 at once
      for (int i = 0; i < 30; ++i) {
        open.push_back(std::make_unique<AtomicFileWriter>(path("f" + std::to_string(round) + "_" + std::to_string(i))));
      }
      if (round < 4 && open.size() > 30) open.erase(open.begin(), open.begin() + 30);
    }
    ::kill(::getpid(), SIGTERM);
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_TRUE(names().empty()) << names().size() << " temporary files left";
}

TEST_F(WriteTest, SameFileThroughSymlinksHardLinksAndSpellings) {
  const std::string a = put("a.nome", "x");
  put("b.nome", "x");
  fs::create_symlink(a, path("link.nome"));
  fs::create_hard_link(a, path("hard.nome"));
  EXPECT_TRUE(is_same_file(a, a));
  EXPECT_TRUE(is_same_file(a, path("link.nome")));
  EXPECT_TRUE(is_same_file(a, path("hard.nome")));
  fs::create_directories(dir_ / "sub");
  EXPECT_TRUE(is_same_file(a, (dir_ / "sub" / ".." / "a.nome").string()));
  EXPECT_TRUE(is_same_file(a, (dir_ / "." / "a.nome").string()));
  EXPECT_FALSE(is_same_file(a, path("b.nome")));
  EXPECT_FALSE(is_same_file(a, path("missing.nome")));
  EXPECT_FALSE(is_same_file(path("missing.nome"), path("missing.nome")));
}

TEST_F(WriteTest, RewriteReplacesAnUnchangedFileKeepingItsPermissions) {
  const std::string f = put("s.nome", "old");
  fs::permissions(f, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  EXPECT_EQ(rewrite_file(f, "old", "new text"), "");
  EXPECT_EQ(get(f), "new text");
  struct stat st {};
  ASSERT_EQ(::stat(f.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u);
  EXPECT_EQ(names(), std::vector<std::string>{"s.nome"});
}

TEST_F(WriteTest, RewriteKeepsAnEditSavedAfterTheFileWasRead) {
  const std::string f = put("s.nome", "the user's edit");
  const std::string error = rewrite_file(f, "what was read", "formatted");
  EXPECT_NE(error.find("changed since it was read"), std::string::npos) << error;
  EXPECT_EQ(get(f), "the user's edit");
  EXPECT_EQ(names(), std::vector<std::string>{"s.nome"});  // no temporary file left
  // A file removed meanwhile is not brought back either.
  const std::string gone = put("gone.nome", "x");
  fs::remove(gone);
  EXPECT_NE(rewrite_file(gone, "x", "y"), "");
  EXPECT_FALSE(fs::exists(gone));
}

TEST_F(WriteTest, RewriteWritesThroughASymlink) {
  fs::create_directories(dir_ / "real");
  const std::string target = put("real/s.nome", "old");
  fs::create_symlink("real/s.nome", path("link.nome"));
  EXPECT_EQ(rewrite_file(path("link.nome"), "old", "new"), "");
  EXPECT_TRUE(fs::is_symlink(path("link.nome")));
  EXPECT_EQ(fs::read_symlink(path("link.nome")), fs::path("real/s.nome"));
  EXPECT_EQ(get(target), "new");
  EXPECT_EQ(names(), (std::vector<std::string>{"link.nome", "real"}));
}

TEST_F(WriteTest, RewriteRefusesReadOnlyAndHardLinkedFiles) {
  const std::string ro = put("ro.nome", "old");
  fs::permissions(ro, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  std::string error = rewrite_file(ro, "old", "new");
  EXPECT_NE(error.find("`" + ro + "` is read-only"), std::string::npos) << error;
  EXPECT_EQ(get(ro), "old");

  const std::string a = put("a.nome", "old");
  fs::create_hard_link(a, path("b.nome"));
  error = rewrite_file(a, "old", "new");
  EXPECT_NE(error.find("has 2 hard links"), std::string::npos) << error;
  EXPECT_EQ(get(a), "old");
  EXPECT_EQ(fs::hard_link_count(a), 2u);

  EXPECT_NE(rewrite_file(dir_.string(), "", "x").find("not a regular file"), std::string::npos);
  for (const std::string& n : names()) EXPECT_EQ(n.find(".tmp."), std::string::npos) << n;
}

}  // namespace
}  // namespace nomec
