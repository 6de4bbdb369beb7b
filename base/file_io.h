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
std::string write_file_atomically(const std::string& path, std::string_view content);

/// `write_file_atomically` for content made in pieces, e.g. a 200 MB STL written a
/// megabyte at a time, so the whole never sits in memory: the constructor creates the
/// temporary file (or opens a non-regular file in place), `append` writes a piece (false
/// once an error happened), `commit` renames the temporary file over `path` and returns ""
/// or the first error. Without a successful `commit` the temporary file is removed and an
/// existing file at `path` is untouched.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(const std::string& path);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  bool append(std::string_view piece);
  std::string commit();

 private:
  std::string path_;
  std::string temp_;  // the temporary file while it exists
  std::string error_;
  int fd_ = -1;
  bool is_in_place_ = false;
  bool exists_ = false;
  unsigned mode_ = 0;  // permissions of the file being replaced
};

/// Lists folder `dir` ("" = the working directory); nullopt when it cannot be read.
std::optional<FolderListing> list_folder(const std::string& dir);

}  // namespace nomec
