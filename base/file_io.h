// Files on disk, for the clients of the library: the one reader (whole regular files as
// bytes, under a size cap, refusing FIFOs and devices without blocking on them) and
// the one atomic writer (a temporary file next to the target, then a rename; whole or in
// pieces), shared by the CLI's outputs, `nomec fmt -i`, the language server and the tests;
// and the listing of a folder's file names, which the checker asks for (through
// CheckOptions) to find the base scene of saved work. The front end itself never touches the disk.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/folder_listing.h"
#include "base/input_limits.h"

namespace nomec {

/// Why a read gave no bytes.
enum class ReadRefusal : uint8_t {
  None,        // read
  CannotOpen,  // missing, no permission, … (the system's reason is in the message)
  NotRegular,  // a folder, FIFO, device or socket: never read
  TooLarge,    // more bytes than the cap
  ReadFailed,  // an error while reading
};

/// A whole input read, or why it was not: `reason` is "" when read, else lowercase and
/// without the path, e.g. "it is a character device, not a regular file", "it is 40.0 MiB,
/// more than the 32.0 MiB nomec reads (`--max-file-size`)" or "no such file or directory";
/// `error` is the message that names the path: "cannot read `/dev/zero`: it is a character
/// device, not a regular file".
struct FileRead {
  std::string bytes;
  std::string reason;
  std::string error;
  ReadRefusal refusal = ReadRefusal::None;
  int error_number = 0;  // the system's reason (`errno`) for CannotOpen and ReadFailed
  bool ok() const { return refusal == ReadRefusal::None; }
};

/// Reads a whole regular file as bytes (no newline conversion), at most `max_bytes` of them.
/// Anything else is refused without blocking and without reading a byte: the path is looked
/// at before it is opened, then opened with O_NONBLOCK and looked at again (fstat), so a FIFO
/// (even one put in its place meanwhile) never waits for a writer and a device such as
/// `/dev/zero` is never read. A file larger than the cap is refused before it is read, and a
/// file whose size the system does not announce (/proc) or that grows while it is read is
/// read only up to the cap. Symbolic links are followed. For every input nomec reads from a
/// path (scenes, includes, base scenes, meshes, SLIDE's `source`). A negative `max_bytes` is
/// the default cap of the file's kind: `kDefaultMaxMeshFileBytes` for a flat mesh file
/// (`is_mesh_file_path`), else `kDefaultMaxFileBytes`; the message names the flag of that kind.
FileRead read_input_file(const std::string& path, int64_t max_bytes = -1);

/// Reads descriptor `fd` (standard input: a pipe or a terminal, which may block as the user
/// means it to) to its end, at most `max_bytes` bytes; `shown` names it in messages.
FileRead read_input_stream(int fd, std::string_view shown, int64_t max_bytes = kDefaultMaxFileBytes);

/// `read_input_file` with the default cap of the file's kind, as an optional; nullopt when refused, with `errno`
/// saying why (the system's reason when it cannot be opened, EISDIR for a folder, EINVAL for
/// another file that is not regular, EFBIG for one larger than the cap).
std::optional<std::string> read_file_bytes(const std::string& path);

/// The readers of one check's inputs (its includes and base scene), for `CheckOptions`:
/// `read` is `read_input_file` under `max_bytes` (nullopt when refused) and `problem` gives
/// the `reason` it refused a path ("" if it did not), for the diagnostic at the `include`. Copies
/// share what they remember; safe to use from several threads.
struct InputReader {
  std::function<std::optional<std::string>(const std::string& path)> read;
  std::function<std::string(const std::string& path)> problem;
};
InputReader input_reader(int64_t max_bytes = kDefaultMaxFileBytes, int64_t max_mesh_bytes = kDefaultMaxMeshFileBytes);

/// Writes `content` to `path` through `path.tmp.XXXXXX` and a rename, so readers never see
/// a half-written file and a failure leaves an existing file untouched. A file that exists
/// keeps its permissions; a new one gets 0666 less the umask. An existing non-regular file
/// (`/dev/null`, a FIFO) is written in place instead. Returns "" or an error message
/// (lowercase, e.g. "cannot create `out/x.stl.tmp.XXXXXX`: No such file or directory").
/// The temporary file is removed if the process is stopped by SIGINT, SIGTERM or SIGHUP
/// meanwhile (see AtomicFileWriter).
std::string write_file_atomically(const std::string& path, std::string_view content);

/// Whether `a` and `b` name one existing file: the same device and inode, so a symlink, a
/// hard link or another spelling (`./x`, `dir/../x`) of a path is that file. The check an
/// output makes against the inputs it must not overwrite.
bool is_same_file(const std::string& a, const std::string& b);

/// Rewrites the existing file `path` with `content` — a source file reformatted in place
/// (`nomec fmt -i`) — the way a careful user expects: only if the file still holds exactly
/// `original` (the bytes it was read with) just before it is replaced, so an edit saved
/// meanwhile is kept; through a symlink (the link stays, its target gets the new text); with
/// the file's permissions and group; flushed to disk before the rename. Refused, with the
/// file untouched: a file that is not a regular file, a read-only one (no write permission,
/// even for root), one with several hard links (replacing it would split them: the other
/// names would keep the old text) and one owned by another user (it would become ours).
/// Returns "" or why nothing was written (lowercase, naming `path`).
std::string rewrite_file(const std::string& path, std::string_view original, std::string_view content);

/// `write_file_atomically` for content made in pieces, e.g. a 200 MB STL written a
/// megabyte at a time, so the whole never sits in memory: the constructor creates the
/// temporary file (or opens a non-regular file in place), `append` writes a piece (false
/// once an error happened), `commit` renames the temporary file over `path` and returns ""
/// or the first error. Without a successful `commit` the temporary file is removed and an
/// existing file at `path` is untouched. While the temporary file exists it is listed for a
/// signal handler, installed on first use for SIGINT, SIGTERM and SIGHUP where the program
/// left their default action: a Ctrl-C mid-write removes it, then the process ends by the
/// signal as it would have (a program with handlers of its own keeps them).
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(const std::string& path);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  bool append(std::string_view piece);
  std::string commit();
  /// Makes `commit` replace the file only if it still holds exactly `original` at that
  /// moment (compared just before the rename; else the temporary file is removed and the
  /// error says the file changed), and flush the new text to disk first (rewrite_file).
  void require_unchanged(std::string original);

 private:
  void drop_temp();

  std::string path_;
  std::string temp_;  // the temporary file while it exists
  std::optional<std::string> original_;  // require_unchanged's bytes
  std::string error_;
  int fd_ = -1;
  bool is_in_place_ = false;
  bool exists_ = false;
  unsigned mode_ = 0;  // permissions of the file being replaced
  unsigned gid_ = 0;   // its group
  int slot_ = -1;      // its entry in the signal handler's list of temporary files
};

/// Lists folder `dir` ("" = the working directory); nullopt when it cannot be read.
std::optional<FolderListing> list_folder(const std::string& dir);

}  // namespace nomec
