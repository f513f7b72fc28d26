// MappedMemory: pages mapped privately from a file (copy-on-write) or zero-filled on first touch.
#pragma once

#include <cstddef>
#include <cstring>
#include <memory>
#include <type_traits>

#include "base/result.h"

namespace dt {

// One private mapping, readable and writable. Mapped from a file, its pages stay the file's
// page-cache pages, shared with every other process mapping the file, until one is written: the
// write copies that page alone into this process (MAP_PRIVATE), and the file never changes.
// Mapped anonymously, a page costs nothing resident until it is first written. Move-only;
// unmaps when destroyed.
class MappedMemory {
 public:
  MappedMemory() = default;
  // Maps bytes [0, size) of the open file `fd` (the mapping keeps no reference to fd). An error
  // names the size and errno's text.
  static Result<MappedMemory> MapFilePrivate(int fd, size_t size);
  // size bytes of zeros; the kernel backs untouched pages with its one zero page. Throws
  // std::bad_alloc if the address space is exhausted.
  static MappedMemory Zeroed(size_t size);

  MappedMemory(MappedMemory&& other) noexcept;
  MappedMemory& operator=(MappedMemory&& other) noexcept;
  MappedMemory(const MappedMemory&) = delete;
  MappedMemory& operator=(const MappedMemory&) = delete;
  ~MappedMemory();

  std::byte* data() const { return data_; }
  size_t size() const { return size_; }

 private:
  MappedMemory(std::byte* data, size_t size) : data_(data), size_(size) {}
  std::byte* data_ = nullptr;
  size_t size_ = 0;
};

// n values of a trivial type, all zero bits at first, in anonymous pages: a large sparse table
// (one entry per grid square) costs resident memory only for the pages written.
template <typename T>
class ZeroPagedArray {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  ZeroPagedArray() = default;
  explicit ZeroPagedArray(size_t n)
      : memory_(n == 0 ? MappedMemory() : MappedMemory::Zeroed(n * sizeof(T))), n_(n) {}

  size_t size() const { return n_; }
  T& operator[](size_t k) { return reinterpret_cast<T*>(memory_.data())[k]; }
  const T& operator[](size_t k) const { return reinterpret_cast<const T*>(memory_.data())[k]; }
  // Every entry back to zero bits, the pages given back to the kernel.
  void Clear() { *this = ZeroPagedArray(n_); }

 private:
  MappedMemory memory_;
  size_t n_ = 0;
};

}  // namespace dt
