// Regular files only: a bounded read that never blocks on a FIFO or device, and a check for paths
// about to be replaced.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "base/result.h"

namespace dt {

// "a directory", "a FIFO", "a character device", ... for a st_mode, as messages name files.
std::string_view FileTypeName(mode_t mode);

// Reads the whole of `path`, which must be a regular file of at most `max_bytes` bytes. The file
// is opened with O_NONBLOCK, so a FIFO without a writer or a device cannot hold the caller, and
// its type and size are checked (fstat) before a byte is read: a directory, FIFO, device or
// socket, or a file over the cap, is refused with an error naming the path and the reason, as is
// a file whose size changes while it is read. Never throws.
Result<std::vector<uint8_t>> ReadRegularFile(const std::filesystem::path& path, uint64_t max_bytes);

// An open regular file, read piecewise: for files too large to hold in memory at once. Closes
// the file when destroyed.
class RegularFile {
 public:
  RegularFile(RegularFile&& other) noexcept;
  RegularFile& operator=(RegularFile&& other) noexcept;
  RegularFile(const RegularFile&) = delete;
  RegularFile& operator=(const RegularFile&) = delete;
  ~RegularFile();

  // Opens `path` as ReadRegularFile does (O_NONBLOCK, then fstat): a directory, FIFO, device or
  // socket, or a file over `max_bytes`, is refused with an error naming the path and the reason.
  static Result<RegularFile> Open(const std::filesystem::path& path, uint64_t max_bytes);

  // The size when opened.
  uint64_t size() const { return size_; }
  // Fills `out` from byte `offset`; an error names the path, the offset and the cause, a file
  // that ended early (it shrank since it was opened) too.
  Status ReadAt(uint64_t offset, std::span<uint8_t> out) const;

 private:
  RegularFile(int fd, uint64_t size, std::string name) : fd_(fd), size_(size), name_(name) {}
  int fd_ = -1;
  uint64_t size_ = 0;
  std::string name_;
};

// Ok if `path` does not exist or names a regular file (following symbolic links); otherwise an
// error naming the path and what it is. For writers about to rename a new file over `path`.
Status CheckReplaceableFile(const std::filesystem::path& path);

}  // namespace dt
