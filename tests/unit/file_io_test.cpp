// The one file reader (base/file_io.h): every byte of a regular file, files whose size the
// system does not announce (/proc), and a refusal with the reason for what is not a regular
// file (a folder, a FIFO, a device, a missing path) or is larger than the cap, without
// blocking on it or reading it; standard input read to its end within the cap.
#include <gtest/gtest.h>

#include <cerrno>
#include <cstdio>
#include <fcntl.h>
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

// A FIFO is refused without waiting for a writer (it once blocked `include` forever), and
// a device without reading it (`/dev/zero` once grew a string to 2 GB), also behind a
// symbolic link; the error says what the path is.
TEST_F(FileIoTest, RefusesAFifoAndADeviceWithoutReadingThem) {
  const std::string fifo = (dir_ / "fifo.nome").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const fs::path to_zero = dir_ / "zero.nome";
  fs::create_symlink("/dev/zero", to_zero);
  const fs::path to_fifo = dir_ / "to_fifo.nome";
  fs::create_symlink(fifo, to_fifo);
  for (const auto& [path, what] : std::vector<std::pair<std::string, std::string>>{
           {fifo, "a named pipe (FIFO)"},
           {"/dev/zero", "a character device"},
           {to_zero.string(), "a character device"},
           {to_fifo.string(), "a named pipe (FIFO)"},
           {dir_.string(), "a folder"}}) {
    const FileRead r = read_input_file(path);
    EXPECT_EQ(r.refusal, ReadRefusal::NotRegular) << path;
    EXPECT_EQ(r.error, "cannot read `" + path + "`: it is " + what + ", not a regular file");
    EXPECT_TRUE(r.bytes.empty());
  }
  errno = 0;
  EXPECT_FALSE(read_file_bytes(fifo).has_value());
  EXPECT_EQ(errno, EINVAL);
}

// A file larger than the cap is refused before a byte is read (a sparse file of 3 GiB takes
// no disk), one at the cap is read, and a file whose size is not announced (/proc) is read
// only up to the cap.
TEST_F(FileIoTest, RefusesAFileLargerThanTheCap) {
  const std::string huge = (dir_ / "huge.nome").string();
  {
    std::ofstream(huge, std::ios::binary).put('x');
  }
  fs::resize_file(huge, std::uintmax_t{3} << 30);
  FileRead r = read_input_file(huge);
  EXPECT_EQ(r.refusal, ReadRefusal::TooLarge);
  EXPECT_EQ(r.error, "cannot read `" + huge + "`: it is 3.0 GiB, more than the " + byte_size_text(kDefaultMaxFileBytes) +
                         " nomec reads (`--max-file-size`)");
  // A flat mesh has a cap of its own, and the message names its flag.
  const std::string mesh = (dir_ / "huge.stl").string();
  {
    std::ofstream(mesh, std::ios::binary).put('x');
  }
  fs::resize_file(mesh, std::uintmax_t{3} << 30);
  FileRead m = read_input_file(mesh);
  EXPECT_EQ(m.refusal, ReadRefusal::TooLarge);
  EXPECT_EQ(m.error, "cannot read `" + mesh + "`: it is 3.0 GiB, more than the " +
                         byte_size_text(kDefaultMaxMeshFileBytes) + " nomec reads (`--max-mesh-size`)");
  errno = 0;
  EXPECT_FALSE(read_file_bytes(huge).has_value());
  EXPECT_EQ(errno, EFBIG);

  const std::string ten = write("ten.nome", "0123456789");
  EXPECT_EQ(read_input_file(ten, 10).bytes, "0123456789");
  EXPECT_EQ(read_input_file(ten, 9).refusal, ReadRefusal::TooLarge);

  r = read_input_file("/proc/self/status", 16);
  EXPECT_EQ(r.refusal, ReadRefusal::TooLarge);
  EXPECT_EQ(r.reason, "it holds more than the 16 bytes nomec reads (`--max-file-size`)");
}

// Standard input is the one stream read (`nomec -`): a pipe to its end, within the cap.
TEST_F(FileIoTest, ReadsAStreamToItsEndWithinTheCap) {
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  std::string bytes;
  for (int i = 0; i < 20000; ++i) bytes += "point p" + std::to_string(i) + " (0 0 0) endpoint\n";
  std::thread writer([&] {
    for (size_t at = 0; at < bytes.size(); at += 1000) {
      ASSERT_GT(::write(fds[1], bytes.data() + at, std::min<size_t>(1000, bytes.size() - at)), 0);
    }
    ::close(fds[1]);
  });
  const FileRead r = read_input_stream(fds[0], "standard input");
  writer.join();
  ::close(fds[0]);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_TRUE(r.bytes == bytes);

  // An endless stream stops at the cap.
  const int zero = ::open("/dev/zero", O_RDONLY);
  ASSERT_GE(zero, 0);
  const FileRead endless = read_input_stream(zero, "-", 1 << 20);
  ::close(zero);
  EXPECT_EQ(endless.refusal, ReadRefusal::TooLarge);
  EXPECT_EQ(endless.error, "cannot read `-`: it holds more than the 1.0 MiB nomec reads (`--max-file-size`)");
}

// The checker's reader remembers why it refused a path, for the diagnostic at the include.
TEST_F(FileIoTest, InputReaderSaysWhyItRefused) {
  const InputReader reader = input_reader(4);
  const std::string ok = write("ok.slf", "1234");
  const std::string big = write("big.slf", "12345");
  EXPECT_EQ(reader.read(ok), std::optional<std::string>("1234"));
  EXPECT_EQ(reader.problem(ok), "");
  EXPECT_FALSE(reader.read(big).has_value());
  EXPECT_EQ(reader.problem(big), "it is 5 bytes, more than the 4 bytes nomec reads (`--max-file-size`)");
  EXPECT_FALSE(reader.read("/dev/zero").has_value());
  EXPECT_EQ(reader.problem("/dev/zero"), "it is a character device, not a regular file");
  EXPECT_FALSE(reader.read((dir_ / "missing.slf").string()).has_value());
  EXPECT_EQ(reader.problem((dir_ / "missing.slf").string()), "no such file or directory");
}

TEST_F(FileIoTest, RefusesAFolderAndAMissingFileWithTheReason) {
  errno = 0;
  EXPECT_FALSE(read_file_bytes(dir_.string()).has_value());
  EXPECT_EQ(errno, EISDIR);
  EXPECT_EQ(read_input_file((dir_ / "missing.nome").string()).reason, "no such file or directory");
  errno = 0;
  EXPECT_FALSE(read_file_bytes((dir_ / "missing.nome").string()).has_value());
  EXPECT_EQ(errno, ENOENT);
}

}  // namespace
}  // namespace nomec
