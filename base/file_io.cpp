// File reading, atomic writing and folder listing (see file_io.h), with POSIX calls so that
// errors carry the system's reason.
#include "base/file_io.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <utility>

namespace nomec {

std::optional<std::string> read_file_bytes(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  // One string of the file's size, read into directly: a front end's peak memory is a few
  // dozen bytes per source byte, and a stream's growing buffer and its copy would add two
  // or three of them. A file whose size is unknown (a pipe) or changes while it is read is
  // read to its end all the same.
  struct stat st{};
  std::string out;
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) out.resize(static_cast<size_t>(st.st_size));
  size_t done = 0;
  char extra[16 * 1024];
  while (true) {
    // Into the string while it has room, then into `extra` (the end of a file of the size
    // announced is found without growing the string).
    const bool has_room = done < out.size();
    const ssize_t n = has_room ? ::read(fd, out.data() + done, out.size() - done) : ::read(fd, extra, sizeof extra);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {  // e.g. a folder (EISDIR): not a file to read
      const int reason = errno;
      ::close(fd);
      errno = reason;
      return std::nullopt;
    }
    if (n == 0) break;
    if (!has_room) {
      out.resize(done);
      out.append(extra, static_cast<size_t>(n));
      out.resize(std::max(out.size(), 2 * done));
    }
    done += static_cast<size_t>(n);
  }
  ::close(fd);
  out.resize(done);
  return out;
}

namespace {

std::string quoted_error(std::string_view what, const std::string& path) {
  return std::string(what) + " `" + path + "`: " + std::strerror(errno);
}

// Writes all of `content` to `fd`; "" or an error naming `shown`.
std::string write_all(int fd, std::string_view content, const std::string& shown) {
  size_t done = 0;
  while (done < content.size()) {
    ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return quoted_error("cannot write", shown);
    }
    done += static_cast<size_t>(n);
  }
  return {};
}

}  // namespace

// An existing non-regular file (`/dev/null`, a FIFO, a terminal) is written straight into:
// renaming a temporary file over it would replace the device or pipe with a plain file.
AtomicFileWriter::AtomicFileWriter(const std::string& path) : path_(path) {
  struct stat st {};
  exists_ = ::stat(path.c_str(), &st) == 0;
  if (exists_ && !S_ISREG(st.st_mode)) {
    is_in_place_ = true;
    fd_ = ::open(path.c_str(), O_WRONLY | O_TRUNC);
    if (fd_ < 0) error_ = quoted_error("cannot open", path);
    return;
  }
  mode_ = st.st_mode & 07777;
  std::string tmpl = path + ".tmp.XXXXXX";
  std::vector<char> name(tmpl.begin(), tmpl.end());
  name.push_back('\0');
  fd_ = mkstemp(name.data());
  if (fd_ < 0) {
    error_ = quoted_error("cannot create", tmpl);
    return;
  }
  temp_ = name.data();
}

AtomicFileWriter::~AtomicFileWriter() {
  if (fd_ >= 0) ::close(fd_);
  if (!temp_.empty()) ::unlink(temp_.c_str());
}

bool AtomicFileWriter::append(std::string_view piece) {
  if (!error_.empty() || fd_ < 0) return false;
  error_ = write_all(fd_, piece, is_in_place_ ? path_ : temp_);
  return error_.empty();
}

std::string AtomicFileWriter::commit() {
  if (!error_.empty() || fd_ < 0) return error_.empty() ? "cannot write `" + path_ + "`: already committed" : error_;
  const int fd = std::exchange(fd_, -1);
  if (is_in_place_) {
    ::close(fd);
    return {};
  }
  // mkstemp creates 0600: keep the permissions of the file being replaced, or give a new
  // output the ordinary 0666 less the umask.
  mode_t mode = 0;
  if (exists_) {
    mode = static_cast<mode_t>(mode_);
  } else {
    mode_t mask = umask(0);
    umask(mask);
    mode = 0666 & ~mask;
  }
  fchmod(fd, mode);
  if (::close(fd) != 0) return quoted_error("cannot write", temp_);
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
    return "cannot rename `" + temp_ + "` to `" + path_ + "`: " + std::strerror(errno);
  }
  temp_.clear();  // in place now: nothing to remove
  return {};
}

std::string write_file_atomically(const std::string& path, std::string_view content) {
  AtomicFileWriter out(path);
  out.append(content);
  return out.commit();
}

std::optional<FolderListing> list_folder(const std::string& dir) {
  const std::string folder = dir.empty() ? "." : dir;
  DIR* d = ::opendir(folder.c_str());
  if (d == nullptr) return std::nullopt;
  FolderListing out;
  if (char* real = ::realpath(folder.c_str(), nullptr)) {
    std::string abs(real);
    std::free(real);
    out.name = abs.substr(abs.find_last_of('/') + 1);
  }
  while (const dirent* e = ::readdir(d)) {
    std::string name = e->d_name;
    if (name == "." || name == "..") continue;
    struct stat st {};
    if (::stat((folder + "/" + name).c_str(), &st) == 0 && S_ISREG(st.st_mode)) out.files.push_back(std::move(name));
  }
  ::closedir(d);
  std::sort(out.files.begin(), out.files.end());
  return out;
}

}  // namespace nomec
