// FolderListing: what a folder holds (its own name and its files' names), as plain data. The
// checker asks for one through CheckOptions to find a saved work's base scene; base/file_io.h
// makes it from the disk.
#pragma once

#include <string>
#include <vector>

namespace nomec {

struct FolderListing {
  std::string name;                // the last component of the folder's absolute path, e.g. `zero`
  std::vector<std::string> files;  // names of the regular files in it, sorted
};

}  // namespace nomec
