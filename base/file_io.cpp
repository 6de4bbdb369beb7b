// File reading, atomic writing and folder listing (see file_io.h), with POSIX calls so that
// errors carry the system's reason. Reading looks at what a path is (stat, then fstat of
// the descriptor opened with O_NONBLOCK) before it reads a byte, and stops at the cap.
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

#include <map>
#include <mutex>
#include <utility>

namespace nomec {

namespace {

// What a file that is not regular is, for messages.
std::string_view file_type_name(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a named pipe (FIFO)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "";
}

FileRead refused(ReadRefusal why, std::string_view shown, std::string reason, int error_number = 0) {
  FileRead r;
  r.refusal = why;
  r.error = "cannot read `" + std::string(shown) + "`: " + reason;
  r.reason = std::move(reason);
  r.error_number = error_number;
  return r;
}

// The system's reason for a failed call on `shown` (strerror's text, lowercase).
FileRead system_refusal(ReadRefusal why, std::string_view shown) {
  const int number = errno;
  std::string reason = std::strerror(number);
  if (!reason.empty() && reason[0] >= 'A' && reason[0] <= 'Z' && (reason.size() < 2 || reason[1] < 'A' || reason[1] > 'Z')) {
    reason[0] = static_cast<char>(reason[0] - 'A' + 'a');
  }
  return refused(why, shown, std::move(reason), number);
}

FileRead not_regular(std::string_view shown, mode_t mode) {
  const std::string_view type = file_type_name(mode);
  return refused(ReadRefusal::NotRegular, shown,
                 type.empty() ? "it is not a regular file" : "it is " + std::string(type) + ", not a regular file");
}

// `size` is the file's, or 0 when only reading found it larger.
FileRead too_large(std::string_view shown, int64_t size, int64_t max_bytes) {
  const std::string limit = byte_size_text(max_bytes) + " nomec reads (`--max-file-size`)";
  return refused(ReadRefusal::TooLarge, shown,
                 size > 0 ? "it is " + byte_size_text(size) + ", more than the " + limit : "it holds more than the " + limit);
}

// Reads `fd` to its end into `out`, which holds the bytes expected (the file's announced
// size, or nothing) and is grown only past them; at most `max_bytes`. Refuses with a message
// naming `shown`; `fd` stays open.
FileRead read_all(int fd, std::string_view shown, int64_t max_bytes, std::string out) {
  const size_t cap = static_cast<size_t>(std::max<int64_t>(max_bytes, 0));
  size_t done = 0;
  char extra[16 * 1024];
  while (true) {
    // Into the string while it has room, then into `extra` (the end of a file of the size
    // announced is found without growing the string).
    const bool has_room = done < out.size();
    const ssize_t n = has_room ? ::read(fd, out.data() + done, out.size() - done) : ::read(fd, extra, sizeof extra);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {  // e.g. a folder opened on a system that allows it (EISDIR)
      return system_refusal(ReadRefusal::ReadFailed, shown);
    }
    if (n == 0) break;
    if (done + static_cast<size_t>(n) > cap) {
      return too_large(shown, 0, max_bytes);
    }
    if (!has_room) {
      out.resize(done);
      out.append(extra, static_cast<size_t>(n));
      out.resize(std::min(std::max(out.size(), 2 * done), cap));
    }
    done += static_cast<size_t>(n);
  }
  out.resize(done);
  FileRead r;
  r.bytes = std::move(out);
  return r;
}

}  // namespace

FileRead read_input_file(const std::string& path, int64_t max_bytes) {
  // Looked at before it is opened: opening a FIFO for reading would wait for a writer, and
  // opening a device can do something (a tape rewinds).
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    return system_refusal(ReadRefusal::CannotOpen, path);
  }
  if (!S_ISREG(st.st_mode)) return not_regular(path, st.st_mode);
  if (st.st_size > max_bytes) return too_large(path, st.st_size, max_bytes);
  // O_NONBLOCK: should a FIFO have taken the file's place since, opening it does not wait.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) return system_refusal(ReadRefusal::CannotOpen, path);
  FileRead r;
  if (::fstat(fd, &st) != 0) {
    r = system_refusal(ReadRefusal::CannotOpen, path);
  } else if (!S_ISREG(st.st_mode)) {
    r = not_regular(path, st.st_mode);
  } else if (st.st_size > max_bytes) {
    r = too_large(path, st.st_size, max_bytes);
  } else {
    // One string of the file's size, read into directly: a front end's peak memory is a few
    // dozen bytes per source byte, and a stream's growing buffer and its copy would add two
    // or three of them. A file whose size is unknown (/proc) or that changes while it is
    // read is read to its end all the same, up to the cap.
    std::string out;
    if (st.st_size > 0) out.resize(static_cast<size_t>(st.st_size));
    r = read_all(fd, path, max_bytes, std::move(out));
  }
  ::close(fd);
  return r;
}

FileRead read_input_stream(int fd, std::string_view shown, int64_t max_bytes) {
  return read_all(fd, shown, max_bytes, std::string());
}

std::optional<std::string> read_file_bytes(const std::string& path) {
  FileRead r = read_input_file(path);
  if (r.ok()) return std::move(r.bytes);
  // The reason as `errno`, for callers that print strerror.
  switch (r.refusal) {
    case ReadRefusal::NotRegular: {
      struct stat st {};
      errno = ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode) ? EISDIR : EINVAL;
      break;
    }
    case ReadRefusal::TooLarge: errno = EFBIG; break;
    case ReadRefusal::None:
    case ReadRefusal::CannotOpen:
    case ReadRefusal::ReadFailed: errno = r.error_number; break;
  }
  return std::nullopt;
}

InputReader input_reader(int64_t max_bytes) {
  struct Problems {
    std::mutex mutex;
    std::map<std::string, std::string> by_path;
  };
  auto problems = std::make_shared<Problems>();
  InputReader r;
  r.read = [problems, max_bytes](const std::string& path) -> std::optional<std::string> {
    FileRead f = read_input_file(path, max_bytes);
    std::lock_guard<std::mutex> lock(problems->mutex);
    if (f.ok()) {
      problems->by_path.erase(path);
      return std::move(f.bytes);
    }
    problems->by_path[path] = std::move(f.reason);
    return std::nullopt;
  };
  r.problem = [problems](const std::string& path) -> std::string {
    std::lock_guard<std::mutex> lock(problems->mutex);
    auto it = problems->by_path.find(path);
    return it == problems->by_path.end() ? std::string() : it->second;
  };
  return r;
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
