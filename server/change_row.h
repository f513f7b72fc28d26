// ChangeRow: one change as a row of the change database holds it, the row's checksum, and the
// checks a row read back must pass before the replica may use it.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "base/result.h"
#include "engine/change.h"

namespace dt {

// The integer columns of table `changes`, in schema order (docs/protocol.md, "The server").
enum class RowColumn : uint8_t {
  kAuthorSite,
  kAuthorHost,
  kSeq,
  kLamport,
  kKind,
  kOriginSite,
  kOriginHost,
  kNumber,
  kFeatureType,
};
inline constexpr size_t kRowIntegerColumns = 9;
extern const std::array<const char*, kRowIntegerColumns> kRowColumnNames;

struct ChangeRow {
  std::array<int64_t, kRowIntegerColumns> ints{};
  std::vector<uint8_t> params;  // EncodeFeatureParams bytes; empty (NULL) for a Destruct

  int64_t at(RowColumn c) const { return ints[static_cast<size_t>(c)]; }
};

ChangeRow ToRow(const Change& change);

// XXH3-64 (seed 0) of the row's canonical content: each integer column in schema order as a
// 64-bit two's-complement little-endian value, then the parameter bytes. Written with the row;
// a row whose content no longer gives its stored checksum was changed outside dynterrain.
uint64_t RowChecksum(const ChangeRow& row);

// "author 1:2 change_seq 5", from the raw columns, so even a damaged row can be named.
std::string RowName(const ChangeRow& row);

// Rebuilds the change and checks it as a received PDU would be checked (pdu/validation.h, against
// a terrain of terrain_size_x_m x terrain_size_z_m): columns within their types' ranges, parameters
// that decode and validate with nothing left over and agree with feature_type, and every PDU rule:
// a Construct by its feature's origin, positions on the terrain, change_seq, lamport and number
// >= 1. The error says what is wrong, without the row's name (the caller adds it).
Result<Change> FromRow(const ChangeRow& row, double terrain_size_x_m, double terrain_size_z_m);

}  // namespace dt
