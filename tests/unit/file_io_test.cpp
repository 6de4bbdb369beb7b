// The one file reader (base/file_io.h): every byte of a file of any size, files whose size
// the system does not announce (a pipe, /proc), and a refusal with the reason for what is
// not a readable file (a folder, a missing path).
#include <gtest/gtest.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <sys/stat.h>
#include <thread>
#include <unistd.h>

#include "base/file_io.h"

namespace nomec {
namespace {

namespace fs = std::filesystem;

class FileIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nomec_file_io_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& bytes) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  fs::path dir_;
};

// Bytes of every value, a NUL and a `\r\n` among them, at sizes around the reader's 16 KiB
// buffer and the empty file.
TEST_F(FileIoTest, ReadsEveryByteOfAFile) {
  std::mt19937 rng(7);
  for (const size_t size : {size_t{0}, size_t{1}, size_t{16 * 1024 - 1}, size_t{16 * 1024}, size_t{16 * 1024 + 1},
                            size_t{300 * 1000}}) {
    std::string bytes(size, '\0');
    for (char& c : bytes) c = static_cast<char>(rng());
    if (size > 4) bytes.replace(1, 3, std::string("\r\n\0", 3));
    const std::string path = write("f" + std::to_string(size), bytes);
    const std::optional<std::string> read = read_file_bytes(path);
    ASSERT_TRUE(read.has_value()) << size;
    EXPECT_EQ(*read, bytes) << size;
    // Read into a string of the file's size, not grown past it.
    EXPECT_LE(read->capacity(), std::max<size_t>(size, 15)) << size;
  }
}

// /proc files announce no size: they are read to their end all the same.
TEST_F(FileIoTest, ReadsAFileOfUnannouncedSize) {
  const std::optional<std::string> status = read_file_bytes("/proc/self/status");
  ASSERT_TRUE(status.has_value());
  EXPECT_NE(status->find("Name:"), std::string::npos);
  EXPECT_NE(status->find("VmRSS:"), std::string::npos);
}

// A pipe gives its bytes as the writer writes them: everything it wrote is read.
TEST_F(FileIoTest, ReadsAPipeToItsEnd) {
  const std::string path = (dir_ / "fifo").string();
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  std::string bytes;
  for (int i = 0; i < 20000; ++i) bytes += "point p" + std::to_string(i) + " (0 0 0) endpoint\n";
  std::thread writer([&] {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    for (size_t at = 0; at < bytes.size(); at += 1000) {
      std::fwrite(bytes.data() + at, 1, std::min<size_t>(1000, bytes.size() - at), f);
      std::fflush(f);
    }
    std::fclose(f);
  });
  const std::optional<std::string> read = read_file_bytes(path);
  writer.join();
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->size(), bytes.size());
  EXPECT_TRUE(*read == bytes);
}

TEST_F(FileIoTest, RefusesAFolderAndAMissingFileWithTheReason) {
  errno = 0;
  EXPECT_FALSE(read_file_bytes(dir_.string()).has_value());
  EXPECT_EQ(errno, EISDIR);
  errno = 0;
  EXPECT_FALSE(read_file_bytes((dir_ / "missing.nome").string()).has_value());
  EXPECT_EQ(errno, ENOENT);
}

}  // namespace
}  // namespace nomec
