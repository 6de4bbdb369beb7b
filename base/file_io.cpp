// File reading, atomic writing (with the signal handler that removes temporary files and
// the careful rewrite of a source file), and folder listing (see file_io.h), with POSIX
// calls so that errors carry the system's reason. Reading looks at what a path is (stat,
// then fstat of the descriptor opened with O_NONBLOCK) before it reads a byte, and stops
// at the cap.
#include "base/file_io.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <map>
#include <mutex>
#include <random>
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
  const std::string limit =
      byte_size_text(max_bytes) + " nomec reads (" + (is_mesh_file_path(shown) ? "`--max-mesh-size`" : "`--max-file-size`") + ")";
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
  if (max_bytes < 0) max_bytes = is_mesh_file_path(path) ? kDefaultMaxMeshFileBytes : kDefaultMaxFileBytes;
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

InputReader input_reader(int64_t max_bytes, int64_t max_mesh_bytes) {
  struct Problems {
    std::mutex mutex;
    std::map<std::string, std::string> by_path;
  };
  auto problems = std::make_shared<Problems>();
  InputReader r;
  r.read = [problems, max_bytes, max_mesh_bytes](const std::string& path) -> std::optional<std::string> {
    FileRead f = read_input_file(path, is_mesh_file_path(path) ? max_mesh_bytes : max_bytes);
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

// The temporary files that exist now, for the signal handler: a fixed table of pointers to
// the writers' own path strings (a handler may not allocate or lock). A writer lists its
// file once it is created and takes it off once it is renamed or removed; a signal that
// comes in between finds a path that no longer exists, and unlink fails harmlessly.
constexpr int kTempSlots = 64;
std::atomic<const char*> g_temps[kTempSlots];
constexpr int kCleanedSignals[] = {SIGINT, SIGTERM, SIGHUP};

extern "C" void remove_temps_and_die(int sig) {
  const int saved = errno;
  for (std::atomic<const char*>& slot : g_temps) {
    if (const char* p = slot.load()) ::unlink(p);
  }
  errno = saved;
  // SA_RESETHAND made the action the default again: the signal, raised once more, ends
  // the process as it would have without us once this handler returns.
  ::raise(sig);
}

// Installs the handler for each signal whose action is still the default, once.
void install_cleanup_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int sig : kCleanedSignals) {
      struct sigaction old {};
      if (::sigaction(sig, nullptr, &old) != 0 || (old.sa_flags & SA_SIGINFO) != 0 || old.sa_handler != SIG_DFL) continue;
      struct sigaction sa {};
      sa.sa_handler = remove_temps_and_die;
      sigemptyset(&sa.sa_mask);
      for (int other : kCleanedSignals) sigaddset(&sa.sa_mask, other);
      sa.sa_flags = SA_RESETHAND;
      ::sigaction(sig, &sa, nullptr);
    }
  });
}

// Lists `path` (a string that lives until `unlist`) for the handler; the slot or -1 when
// the table is full (the file is then only removed by the writer's own destructor).
int list_temp(const char* path) {
  for (int i = 0; i < kTempSlots; ++i) {
    const char* empty = nullptr;
    if (g_temps[i].compare_exchange_strong(empty, path)) return i;
  }
  return -1;
}

void unlist_temp(int& slot) {
  if (slot >= 0) g_temps[slot].store(nullptr);
  slot = -1;
}

}  // namespace

// An existing non-regular file (`/dev/null`, a FIFO, a terminal) is written straight into:
// renaming a temporary file over it would replace the device or pipe with a plain file.
AtomicFileWriter::AtomicFileWriter(const std::string& path) : path_(path) {
  struct stat st {};
  exists_ = ::stat(path.c_str(), &st) == 0;
  if (exists_ && !S_ISREG(st.st_mode)) {
    is_in_place_ = true;
    fd_ = ::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd_ < 0) error_ = quoted_error("cannot open", path);
    return;
  }
  mode_ = st.st_mode & 07777;
  gid_ = st.st_gid;
  const std::string tmpl = path + ".tmp.XXXXXX";
  // Listed for the signal handler before the file exists, so that a signal taken by any
  // thread at any moment finds it: the name is chosen here (as mkstemp would), listed, then
  // created exclusively.
  install_cleanup_handlers();
  std::random_device rng;
  static constexpr char kChars[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
  for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
    temp_ = tmpl;
    for (size_t i = temp_.size() - 6; i < temp_.size(); ++i) temp_[i] = kChars[rng() % (sizeof kChars - 1)];
    slot_ = list_temp(temp_.c_str());
    fd_ = ::open(temp_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd_ < 0) {
      const int reason = errno;
      unlist_temp(slot_);
      errno = reason;
      if (reason != EEXIST) break;
    }
  }
  if (fd_ < 0) {
    temp_.clear();
    error_ = quoted_error("cannot create", tmpl);
  }
}

AtomicFileWriter::~AtomicFileWriter() {
  if (fd_ >= 0) ::close(fd_);
  drop_temp();
}

void AtomicFileWriter::drop_temp() {
  if (!temp_.empty()) ::unlink(temp_.c_str());
  unlist_temp(slot_);
  temp_.clear();
}

void AtomicFileWriter::require_unchanged(std::string original) { original_ = std::move(original); }

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
  // mkstemp creates 0600: keep the permissions and group of the file being replaced, or
  // give a new output the ordinary 0666 less the umask.
  mode_t mode = 0;
  if (exists_) {
    mode = static_cast<mode_t>(mode_);
    if (fchown(fd, static_cast<uid_t>(-1), static_cast<gid_t>(gid_)) != 0) {
      // Not a member of the group: the file takes ours, as any new file would.
    }
  } else {
    mode_t mask = umask(0);
    umask(mask);
    mode = 0666 & ~mask;
  }
  fchmod(fd, mode);
  if (original_ && ::fsync(fd) != 0) {
    error_ = quoted_error("cannot write", temp_);
    ::close(fd);
    drop_temp();
    return error_;
  }
  if (::close(fd) != 0) {
    error_ = quoted_error("cannot write", temp_);
    drop_temp();
    return error_;
  }
  // The last moment before the rename: the file must still hold what it was read with.
  if (original_) {
    errno = 0;
    std::optional<std::string> now = read_file_bytes(path_);
    if (!now || *now != *original_) {
      drop_temp();
      return "`" + path_ + "` " + (now ? "changed" : "disappeared") +
             " since it was read; it is left as it is now, the change made meanwhile kept";
    }
  }
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
    error_ = "cannot rename `" + temp_ + "` to `" + path_ + "`: " + std::strerror(errno);
    drop_temp();
    return error_;
  }
  unlist_temp(slot_);
  temp_.clear();  // in place now: nothing to remove
  return {};
}

std::string write_file_atomically(const std::string& path, std::string_view content) {
  AtomicFileWriter out(path);
  out.append(content);
  return out.commit();
}

bool is_same_file(const std::string& a, const std::string& b) {
  struct stat sa {}, sb {};
  if (::stat(a.c_str(), &sa) != 0 || ::stat(b.c_str(), &sb) != 0) return false;
  return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

std::string rewrite_file(const std::string& path, std::string_view original, std::string_view content) {
  // Through a symlink: its target is the file rewritten, next to which the temporary file
  // goes (a rename over the link would replace the link itself).
  char* real = ::realpath(path.c_str(), nullptr);
  if (real == nullptr) return quoted_error("cannot find", path);
  const std::string target(real);
  std::free(real);
  struct stat st {};
  if (::stat(target.c_str(), &st) != 0) return quoted_error("cannot find", path);
  if (!S_ISREG(st.st_mode)) return "`" + path + "` is not a regular file";
  if ((st.st_mode & 0222) == 0 || ::access(target.c_str(), W_OK) != 0) {
    return "`" + path + "` is read-only; make it writable to rewrite it";
  }
  if (st.st_nlink > 1) {
    return "`" + path + "` has " + std::to_string(st.st_nlink) +
           " hard links; replacing it would split them (the other names would keep the old text)";
  }
  if (::geteuid() != 0 && st.st_uid != ::geteuid()) {
    return "`" + path + "` belongs to another user; replacing it would make it yours";
  }
  AtomicFileWriter out(target);
  out.require_unchanged(std::string(original));
  out.append(content);
  std::string error = out.commit();
  // Name the file as the user did, not its resolved target.
  if (target != path) {
    for (size_t at = 0; (at = error.find("`" + target + "`", at)) != std::string::npos; at += path.size() + 2) {
      error.replace(at, target.size() + 2, "`" + path + "`");
    }
  }
  return error;
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
