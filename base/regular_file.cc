#include "base/regular_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <utility>

#include <fmt/format.h>

namespace dt {

std::string_view FileTypeName(mode_t mode) {
  if (S_ISREG(mode)) return "a regular file";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a symbolic link";
  return "a file of unknown type";
}

Result<std::vector<uint8_t>> ReadRegularFile(const std::filesystem::path& path,
                                             uint64_t max_bytes) {
  const std::string name = path.string();
  // O_NONBLOCK: opening a FIFO with no writer, or some devices, would otherwise wait.
  const int fd = ::open(name.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) return Error{fmt::format("{}: cannot open: {}", name, std::strerror(errno))};
  auto fail = [&](const std::string& what) -> Error {
    ::close(fd);
    return Error{fmt::format("{}: {}", name, what)};
  };
  struct stat st {};
  if (::fstat(fd, &st) != 0) return fail(fmt::format("fstat failed: {}", std::strerror(errno)));
  if (!S_ISREG(st.st_mode)) {
    return fail(fmt::format("is {}, not a regular file", FileTypeName(st.st_mode)));
  }
  const auto size = static_cast<uint64_t>(st.st_size);
  if (size > max_bytes) {
    return fail(fmt::format("is {} bytes, over the limit of {} bytes", size, max_bytes));
  }
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  size_t got = 0;
  // One byte past the size: a file that grew since fstat is noticed instead of cut short.
  uint8_t extra = 0;
  for (;;) {
    uint8_t* at = got < bytes.size() ? bytes.data() + got : &extra;
    const size_t want = got < bytes.size() ? bytes.size() - got : 1;
    const ssize_t n = ::read(fd, at, want);
    if (n < 0) {
      if (errno == EINTR) continue;
      return fail(fmt::format("read failed after {} bytes: {}", got, std::strerror(errno)));
    }
    if (n == 0) break;
    got += static_cast<size_t>(n);
    if (got > bytes.size()) break;
  }
  if (got != bytes.size()) {
    return fail(
        fmt::format("changed size while being read ({} bytes at the start, {} read)", size, got));
  }
  ::close(fd);
  return bytes;
}

RegularFile::RegularFile(RegularFile&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), size_(other.size_), name_(std::move(other.name_)) {}

RegularFile& RegularFile::operator=(RegularFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    size_ = other.size_;
    name_ = std::move(other.name_);
  }
  return *this;
}

RegularFile::~RegularFile() {
  if (fd_ >= 0) ::close(fd_);
}

Result<RegularFile> RegularFile::Open(const std::filesystem::path& path, uint64_t max_bytes) {
  std::string name = path.string();
  // O_NONBLOCK: opening a FIFO with no writer, or some devices, would otherwise wait.
  const int fd = ::open(name.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) return Error{fmt::format("{}: cannot open: {}", name, std::strerror(errno))};
  RegularFile file(fd, 0, name);
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    return Error{fmt::format("{}: fstat failed: {}", name, std::strerror(errno))};
  }
  if (!S_ISREG(st.st_mode)) {
    return Error{fmt::format("{}: is {}, not a regular file", name, FileTypeName(st.st_mode))};
  }
  file.size_ = static_cast<uint64_t>(st.st_size);
  if (file.size_ > max_bytes) {
    return Error{
        fmt::format("{}: is {} bytes, over the limit of {} bytes", name, file.size_, max_bytes)};
  }
  return file;
}

Status RegularFile::ReadAt(uint64_t offset, std::span<uint8_t> out) const {
  size_t got = 0;
  while (got < out.size()) {
    const ssize_t n =
        ::pread(fd_, out.data() + got, out.size() - got, static_cast<off_t>(offset + got));
    if (n < 0) {
      if (errno == EINTR) continue;
      return Error{
          fmt::format("{}: read at byte {} failed: {}", name_, offset + got, std::strerror(errno))};
    }
    if (n == 0) {
      return Error{
          fmt::format("{}: ends at byte {}, {} bytes at the start (it changed size while "
                      "being read)",
                      name_, offset + got, size_)};
    }
    got += static_cast<size_t>(n);
  }
  return Status::Ok();
}

Status CheckReplaceableFile(const std::filesystem::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return Status::Ok();
    return Error{fmt::format("{}: cannot examine: {}", path.string(), std::strerror(errno))};
  }
  if (!S_ISREG(st.st_mode)) {
    return Error{fmt::format("{}: is {}, not a regular file; refusing to replace it", path.string(),
                             FileTypeName(st.st_mode))};
  }
  return Status::Ok();
}

}  // namespace dt
