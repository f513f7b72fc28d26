// Regular files only: a bounded read that never blocks on a FIFO or device, and a check for paths
// about to be replaced.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
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

// Ok if `path` does not exist or names a regular file (following symbolic links); otherwise an
// error naming the path and what it is. For writers about to rename a new file over `path`.
Status CheckReplaceableFile(const std::filesystem::path& path);

}  // namespace dt
