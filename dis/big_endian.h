// Big-endian (network order) byte writing and bounds-checked reading for DIS PDUs.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "base/demand.h"

namespace dt::dis {

// Writes big-endian fields into a byte vector sized once for the whole PDU (each PDU's size is
// known before it is written). Writing past that size is a broken invariant.
// A field's bytes reversed: network order on a little-endian host.
inline uint16_t ByteSwap(uint16_t v) { return __builtin_bswap16(v); }
inline uint32_t ByteSwap(uint32_t v) { return __builtin_bswap32(v); }
inline uint64_t ByteSwap(uint64_t v) { return __builtin_bswap64(v); }

class BigEndianWriter {
 public:
  // The vector is sized once here and its data pointer and size kept: each byte written through
  // a uint8_t* may alias the vector's own members, which would otherwise be reloaded per field.
  BigEndianWriter(std::vector<uint8_t>& out, size_t total) {
    out.resize(total);
    data_ = out.data();
    size_ = total;
  }
  void U8(uint8_t v) { *Take(1) = v; }
  // Each field is stored whole (one store, not one per byte, each of which could alias the
  // writer's position and force it to be reloaded).
  void U16(uint16_t v) { Put(v); }
  void U32(uint32_t v) { Put(v); }
  void U64(uint64_t v) { Put(v); }
  void F32(float v) { U32(std::bit_cast<uint32_t>(v)); }
  void F64(double v) { U64(std::bit_cast<uint64_t>(v)); }
  void Zeros(size_t n) { std::memset(Take(n), 0, n); }
  void Bytes(std::span<const uint8_t> bytes) {
    std::memcpy(Take(bytes.size()), bytes.data(), bytes.size());
  }
  // True once exactly the announced size has been written.
  bool complete() const { return pos_ == size_; }

 private:
  template <typename T>
  void Put(T v) {
    if constexpr (std::endian::native == std::endian::little) v = ByteSwap(v);
    std::memcpy(Take(sizeof v), &v, sizeof v);
  }
  uint8_t* Take(size_t n) {
    DT_DEMAND(n <= size_ - pos_);  // the size was computed first
    uint8_t* p = data_ + pos_;
    pos_ += n;
    return p;
  }
  uint8_t* data_ = nullptr;
  size_t size_ = 0;
  size_t pos_ = 0;
};

// Reads big-endian fields from a span. The caller checks the total size first (each PDU's
// length is known before its fields are read), so reading past the end is a broken invariant.
class BigEndianReader {
 public:
  explicit BigEndianReader(std::span<const uint8_t> in) : in_(in) {}
  uint8_t U8() { return Take(1)[0]; }
  // Each field is loaded whole and its bytes swapped, one load per field.
  uint16_t U16() { return Get<uint16_t>(); }
  uint32_t U32() { return Get<uint32_t>(); }
  uint64_t U64() { return Get<uint64_t>(); }
  float F32() { return std::bit_cast<float>(U32()); }
  double F64() { return std::bit_cast<double>(U64()); }
  void Skip(size_t n) { Take(n); }
  void Copy(std::span<uint8_t> out) { std::memcpy(out.data(), Take(out.size()), out.size()); }
  size_t remaining() const { return in_.size() - pos_; }

 private:
  template <typename T>
  T Get() {
    T v;
    std::memcpy(&v, Take(sizeof v), sizeof v);
    if constexpr (std::endian::native == std::endian::little) v = ByteSwap(v);
    return v;
  }
  const uint8_t* Take(size_t n);
  std::span<const uint8_t> in_;
  size_t pos_ = 0;
};

inline const uint8_t* BigEndianReader::Take(size_t n) {
  DT_DEMAND(n <= in_.size() - pos_);  // sizes are checked first
  const uint8_t* p = in_.data() + pos_;
  pos_ += n;
  return p;
}

}  // namespace dt::dis
