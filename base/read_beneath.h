// Reading a file by a name relative to a folder without leaving that folder: no `..` above
// it, no absolute path, and no symbolic link that points out of it (resolved by the kernel,
// `openat2` with RESOLVE_BENEATH, so no check can be raced). What SLIDE's Tcl `source`s
// and imports next to a scene is read this way: a scene must not read `/etc/passwd`
// through a link placed beside it. Only regular files are read, opened without blocking (a
// FIFO or device beside the scene is refused, never waited on), and at most `max_bytes`.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace nomec {

/// The text of `relative` inside `folder` ("" = the working directory), or nullopt with
/// `errno` saying why: EXDEV (the name leads out of the folder), EINVAL (not a regular
/// file), EFBIG (larger than `max_bytes`), or what opening or reading failed with.
std::optional<std::string> read_file_beneath(const std::string& folder, const std::string& relative,
                                             size_t max_bytes = size_t{64} << 20);

}  // namespace nomec
