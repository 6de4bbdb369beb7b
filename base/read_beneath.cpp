// read_file_beneath (see read_beneath.h): `openat2` with RESOLVE_BENEATH on the folder's
// descriptor. A kernel older than Linux 5.6 has no `openat2`: then the name is opened with
// O_NOFOLLOW at each step below the folder, which refuses every symbolic link.
#include "base/read_beneath.h"

#include <fcntl.h>
#include <linux/openat2.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace nomec {

namespace {

constexpr int kFileFlags = O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC;

// Each component opened below the previous one without following links (old kernels).
int open_step_by_step(int dir, const std::string& relative) {
  int at = dup(dir);
  size_t from = 0;
  while (at >= 0) {
    const size_t slash = relative.find('/', from);
    const std::string part = relative.substr(from, slash == std::string::npos ? std::string::npos : slash - from);
    from = slash == std::string::npos ? relative.size() : slash + 1;
    if (part.empty() || part == ".") {
      if (slash == std::string::npos) break;
      continue;
    }
    if (part == "..") {
      close(at);
      errno = EXDEV;
      return -1;
    }
    const bool last = slash == std::string::npos;
    const int next = openat(at, part.c_str(), (last ? kFileFlags : O_PATH | O_DIRECTORY | O_CLOEXEC) | O_NOFOLLOW);
    const int reason = errno;
    close(at);
    errno = reason;
    if (next < 0) return errno == ELOOP ? (errno = EXDEV, -1) : -1;
    at = next;
    if (last) return at;
  }
  if (at >= 0) close(at);
  errno = EISDIR;
  return -1;
}

}  // namespace

std::optional<std::string> read_file_beneath(const std::string& folder, const std::string& relative,
                                             size_t max_bytes) {
  if (relative.empty() || relative[0] == '/') {
    errno = EXDEV;
    return std::nullopt;
  }
  const int dir = open(folder.empty() ? "." : folder.c_str(), O_PATH | O_DIRECTORY | O_CLOEXEC);
  if (dir < 0) return std::nullopt;
  open_how how{};
  how.flags = kFileFlags;
  how.resolve = RESOLVE_BENEATH | RESOLVE_NO_MAGICLINKS;
  int fd = static_cast<int>(syscall(SYS_openat2, dir, relative.c_str(), &how, sizeof how));
  if (fd < 0 && errno == ENOSYS) fd = open_step_by_step(dir, relative);
  const int open_error = errno;
  close(dir);
  if (fd < 0) {
    errno = open_error;
    return std::nullopt;
  }
  struct stat st{};
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || static_cast<uint64_t>(st.st_size) > max_bytes) {
    const int reason = !S_ISREG(st.st_mode) ? EINVAL : EFBIG;
    close(fd);
    errno = reason;
    return std::nullopt;
  }
  std::string out(static_cast<size_t>(st.st_size), '\0');
  size_t done = 0;
  while (true) {
    if (done == out.size()) {
      // A file that grew while it is read is read to the cap.
      if (out.size() >= max_bytes) break;
      out.resize(std::min(max_bytes, std::max<size_t>(out.size() * 2, 4096)));
    }
    const ssize_t n = read(fd, out.data() + done, out.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int reason = errno;
      close(fd);
      errno = reason;
      return std::nullopt;
    }
    if (n == 0) break;
    done += static_cast<size_t>(n);
  }
  close(fd);
  out.resize(done);
  return out;
}

}  // namespace nomec
