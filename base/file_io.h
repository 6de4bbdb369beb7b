// Files on disk, for the clients of the library: the one reader (whole files as bytes) and
// the one atomic writer (a temporary file next to the target, then a rename; whole or in
// pieces), shared by the CLI's outputs, `nomec fmt -i`, the language server and the tests;
// and the listing of a folder's file names, which the checker asks for (through
// CheckOptions) to find the base scene of saved work. The front end itself never touches the disk.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/folder_listing.h"

namespace nomec {

/// Reads a whole file as bytes (no newline conversion); nullopt when it cannot be opened or
/// read (e.g. a folder), with `errno` saying why.
std::optional<std::string> read_file_bytes(const std::string& path);

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
