// ByteWriter and ByteReader: explicit little-endian encoding for digests and save files.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace dt {

// Appends fixed-width little-endian values, so encoded bytes are equal on every machine.
class ByteWriter {
 public:
  void U8(uint8_t v) { bytes_.push_back(v); }
  void U16(uint16_t v) { PutLittleEndian(v, 2); }
  void U32(uint32_t v) { PutLittleEndian(v, 4); }
  void U64(uint64_t v) { PutLittleEndian(v, 8); }
  void I32(int32_t v) { U32(static_cast<uint32_t>(v)); }
  void F32(float v) { U32(std::bit_cast<uint32_t>(v)); }
  void F64(double v) { U64(std::bit_cast<uint64_t>(v)); }
  void Bytes(std::span<const uint8_t> data) {
    bytes_.insert(bytes_.end(), data.begin(), data.end());
  }
  void String(const std::string& s) {
    U32(static_cast<uint32_t>(s.size()));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
  }

  const std::vector<uint8_t>& bytes() const { return bytes_; }
  std::vector<uint8_t>& bytes() { return bytes_; }

 private:
  void PutLittleEndian(uint64_t v, int width) {
    for (int i = 0; i < width; ++i) bytes_.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  std::vector<uint8_t> bytes_;
};

// Reads what ByteWriter wrote. Every read past the end returns nullopt, never reads out of bounds.
class ByteReader {
 public:
  explicit ByteReader(std::span<const uint8_t> data) : data_(data) {}

  std::optional<uint8_t> U8() { return GetLittleEndian<uint8_t>(1); }
  std::optional<uint16_t> U16() { return GetLittleEndian<uint16_t>(2); }
  std::optional<uint32_t> U32() { return GetLittleEndian<uint32_t>(4); }
  std::optional<uint64_t> U64() { return GetLittleEndian<uint64_t>(8); }
  std::optional<int32_t> I32() {
    auto v = U32();
    if (!v) return std::nullopt;
    return static_cast<int32_t>(*v);
  }
  std::optional<float> F32() {
    auto v = U32();
    if (!v) return std::nullopt;
    return std::bit_cast<float>(*v);
  }
  std::optional<double> F64() {
    auto v = U64();
    if (!v) return std::nullopt;
    return std::bit_cast<double>(*v);
  }
  std::optional<std::span<const uint8_t>> Bytes(size_t count) {
    if (remaining() < count) return std::nullopt;
    auto out = data_.subspan(offset_, count);
    offset_ += count;
    return out;
  }

  size_t offset() const { return offset_; }
  size_t remaining() const { return data_.size() - offset_; }

 private:
  template <typename T>
  std::optional<T> GetLittleEndian(size_t width) {
    if (remaining() < width) return std::nullopt;
    uint64_t v = 0;
    for (size_t i = 0; i < width; ++i) v |= uint64_t{data_[offset_ + i]} << (8 * i);
    offset_ += width;
    return static_cast<T>(v);
  }
  std::span<const uint8_t> data_;
  size_t offset_ = 0;
};

}  // namespace dt
