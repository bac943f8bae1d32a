// A whole file mapped read-only into memory.
//
// Why: the database cache of MERL's full grid is 1.75 GB. Read into a fresh
// buffer, every page of that buffer is zeroed by the kernel before the copy
// lands in it, and on a virtual machine that zeroing is most of a `fit` or
// `basis` command's wall time (docs/benchmarks.md). A mapping shares the page
// cache's copy of the file instead: nothing is zeroed or copied, and commands
// run at once on one machine share one copy in memory.
//
// POSIX mmap directly: Boost.Iostreams' mapped_file does the same, but would add
// a library to the build for these few lines.
//
// The mapping is private and read-only. `populate` maps every page at once
// (MAP_POPULATE, which reads the file in if it is not in the page cache): for
// a file that is read whole, one pass is cheaper than a fault per page; a
// reader of a few parts leaves it off and faults in only those. brdfshot replaces its files by rename
// (util/atomic_file.h), which leaves a mapped file's old contents in place;
// a program that truncates a mapped file under it would make reads past the
// new end fault, as with any mapping.
#pragma once

#include <cstddef>
#include <string>

namespace brdfshot {

class MappedFile {
 public:
  // Maps all of `path`; FileError naming it if it cannot be opened or mapped.
  // An empty file maps to data() == nullptr, size() == 0.
  explicit MappedFile(const std::string& path, bool populate = false);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  const unsigned char* data() const { return data_; }
  std::size_t size() const { return size_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  const unsigned char* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace brdfshot
