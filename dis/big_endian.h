// Big-endian (network order) byte writing and bounds-checked reading for DIS PDUs.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>
#include <vector>

namespace dt::dis {

// Writes big-endian fields into a byte vector sized once for the whole PDU (each PDU's size is
// known before it is written). Writing past that size is a broken invariant.
class BigEndianWriter {
 public:
  BigEndianWriter(std::vector<uint8_t>& out, size_t total) : out_(out) { out_.resize(total); }
  void U8(uint8_t v) { *Take(1) = v; }
  void U16(uint16_t v) {
    uint8_t* p = Take(2);
    p[0] = static_cast<uint8_t>(v >> 8);
    p[1] = static_cast<uint8_t>(v);
  }
  void U32(uint32_t v) {
    uint8_t* p = Take(4);
    for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (24 - 8 * i));
  }
  void U64(uint64_t v) {
    uint8_t* p = Take(8);
    for (int i = 0; i < 8; ++i) p[i] = static_cast<uint8_t>(v >> (56 - 8 * i));
  }
  void F32(float v) { U32(std::bit_cast<uint32_t>(v)); }
  void F64(double v) { U64(std::bit_cast<uint64_t>(v)); }
  void Zeros(size_t n) { std::memset(Take(n), 0, n); }
  void Bytes(std::span<const uint8_t> bytes) {
    std::memcpy(Take(bytes.size()), bytes.data(), bytes.size());
  }
  // True once exactly the announced size has been written.
  bool complete() const { return pos_ == out_.size(); }

 private:
  uint8_t* Take(size_t n) {
    if (n > out_.size() - pos_) std::abort();  // broken invariant: the size was computed first
    uint8_t* p = out_.data() + pos_;
    pos_ += n;
    return p;
  }
  std::vector<uint8_t>& out_;
  size_t pos_ = 0;
};

// Reads big-endian fields from a span. The caller checks the total size first (each PDU's
// length is known before its fields are read), so reading past the end is a broken invariant.
class BigEndianReader {
 public:
  explicit BigEndianReader(std::span<const uint8_t> in) : in_(in) {}
  uint8_t U8() { return Take(1)[0]; }
  uint16_t U16() {
    const uint8_t* p = Take(2);
    return static_cast<uint16_t>((p[0] << 8) | p[1]);
  }
  uint32_t U32() {
    const uint8_t* p = Take(4);
    return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | p[3];
  }
  uint64_t U64() {
    const uint64_t high = U32();
    return (high << 32) | U32();
  }
  float F32() { return std::bit_cast<float>(U32()); }
  double F64() { return std::bit_cast<double>(U64()); }
  void Skip(size_t n) { Take(n); }
  void Copy(std::span<uint8_t> out) { std::memcpy(out.data(), Take(out.size()), out.size()); }
  size_t remaining() const { return in_.size() - pos_; }

 private:
  const uint8_t* Take(size_t n);
  std::span<const uint8_t> in_;
  size_t pos_ = 0;
};

inline const uint8_t* BigEndianReader::Take(size_t n) {
  if (n > in_.size() - pos_) std::abort();  // broken invariant: sizes are checked first
  const uint8_t* p = in_.data() + pos_;
  pos_ += n;
  return p;
}

}  // namespace dt::dis
