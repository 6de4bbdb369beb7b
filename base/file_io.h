// Files on disk, for the clients of the library: the one reader (whole files as bytes) and
// the one atomic writer (a temporary file next to the target, then a rename), shared by the
// CLI's outputs, `nomec fmt -i`, the language server and the tests; and the listing of a
// folder's file names, which the checker asks for (through CheckOptions) to find the base
// scene of saved work. The front end itself never touches the disk.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/folder_listing.h"

namespace nomec {

/// Reads a whole file as bytes (no newline conversion); nullopt when it cannot be opened.
std::optional<std::string> read_file_bytes(const std::string& path);

/// Writes `content` to `path` through `path.tmp.XXXXXX` and a rename, so readers never see
/// a half-written file and a failure leaves an existing file untouched. A file that exists
/// keeps its permissions; a new one gets 0666 less the umask. An existing non-regular file
/// (`/dev/null`, a FIFO) is written in place instead. Returns "" or an error message
/// (lowercase, e.g. "cannot create `out/x.stl.tmp.XXXXXX`: No such file or directory").
std::string write_file_atomically(const std::string& path, std::string_view content);

/// Lists folder `dir` ("" = the working directory); nullopt when it cannot be read.
std::optional<FolderListing> list_folder(const std::string& dir);

}  // namespace nomec
