#include "base/mapped_memory.h"

#include <sys/mman.h>

#include <cerrno>
#include <new>
#include <utility>

#include <fmt/format.h>

namespace dt {

Result<MappedMemory> MappedMemory::MapFilePrivate(int fd, size_t size) {
  if (size == 0) return Error{"cannot map 0 bytes"};
  void* p = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE, fd, 0);
  if (p == MAP_FAILED) {
    return Error{fmt::format("mmap of {} bytes failed: {}", size, std::strerror(errno))};
  }
  return MappedMemory(static_cast<std::byte*>(p), size);
}

MappedMemory MappedMemory::Zeroed(size_t size) {
  void* p = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE,
                 -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
  return MappedMemory(static_cast<std::byte*>(p), size);
}

MappedMemory::MappedMemory(MappedMemory&& other) noexcept
    : data_(std::exchange(other.data_, nullptr)), size_(std::exchange(other.size_, 0)) {}

MappedMemory& MappedMemory::operator=(MappedMemory&& other) noexcept {
  if (this != &other) {
    if (data_ != nullptr) munmap(data_, size_);
    data_ = std::exchange(other.data_, nullptr);
    size_ = std::exchange(other.size_, 0);
  }
  return *this;
}

MappedMemory::~MappedMemory() {
  if (data_ != nullptr) munmap(data_, size_);
}

}  // namespace dt
