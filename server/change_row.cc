#include "server/change_row.h"

#include <algorithm>
#include <limits>
#include <optional>

#include <fmt/format.h>
#include <xxhash.h>

#include "base/bytes.h"
#include "pdu/pdu_type.h"
#include "pdu/validation.h"

namespace dt {
namespace {

struct ColumnRange {
  int64_t min;
  int64_t max;
};

// What each column's value must fit in to be carried by a Change at all; the PDU rules behind
// (change_seq >= 1 and the rest) are validation.h's.
constexpr std::array<ColumnRange, kRowIntegerColumns> kRanges = {{
    {0, std::numeric_limits<uint16_t>::max()},  // author_site
    {0, std::numeric_limits<uint16_t>::max()},  // author_host
    {0, std::numeric_limits<uint32_t>::max()},  // seq
    {0, std::numeric_limits<int64_t>::max()},   // lamport (a PDU carries it as int64)
    {0, 2},                                     // kind: ChangeKind
    {0, std::numeric_limits<uint16_t>::max()},  // origin_site
    {0, std::numeric_limits<uint16_t>::max()},  // origin_host
    {0, std::numeric_limits<uint32_t>::max()},  // number
    {0, std::numeric_limits<uint16_t>::max()},  // feature_type
}};

// Fills the header and sender as PduBus::Publish does, so only the change's own fields decide.
template <typename Pdu>
std::optional<Rejection> ValidateAsPdu(Pdu pdu, const Change& c, double terrain_size_x_m,
                                       double terrain_size_z_m) {
  const ValidationContext ctx{0, terrain_size_x_m, terrain_size_z_m};
  pdu.header.protocol_version = kProtocolVersion;
  pdu.header.exercise_id = ctx.exercise_id;
  pdu.header.pdu_type = static_cast<uint8_t>(PduTraits<Pdu>::kType);
  pdu.sender = ToPdu(c.author());
  pdu.sender_seq = 1;
  return Validate(pdu, ctx);
}

}  // namespace

const std::array<const char*, kRowIntegerColumns> kRowColumnNames = {
    "author_site", "author_host", "seq",    "lamport",     "kind",
    "origin_site", "origin_host", "number", "feature_type"};

ChangeRow ToRow(const Change& c) {
  ChangeRow row;
  row.ints = {c.stamp.changed_by.site,
              c.stamp.changed_by.host,
              c.stamp.change_seq,
              static_cast<int64_t>(c.stamp.lamport),
              static_cast<int64_t>(c.kind),
              c.id.site,
              c.id.host,
              c.id.number,
              static_cast<int64_t>(c.params.type)};
  if (c.kind != ChangeKind::kDestruct) {
    ByteWriter w;
    EncodeFeatureParams(c.params, w);
    row.params = std::move(w.bytes());
  }
  return row;
}

uint64_t RowChecksum(const ChangeRow& row) {
  std::vector<uint8_t> content(8 * kRowIntegerColumns + row.params.size());
  for (size_t i = 0; i < kRowIntegerColumns; ++i) {
    const auto v = static_cast<uint64_t>(row.ints[i]);
    for (size_t k = 0; k < 8; ++k) content[8 * i + k] = static_cast<uint8_t>(v >> (8 * k));
  }
  std::copy(row.params.begin(), row.params.end(), content.begin() + 8 * kRowIntegerColumns);
  return XXH3_64bits(content.data(), content.size());
}

std::string RowName(const ChangeRow& row) {
  return fmt::format("author {}:{} change_seq {}", row.at(RowColumn::kAuthorSite),
                     row.at(RowColumn::kAuthorHost), row.at(RowColumn::kSeq));
}

Result<Change> FromRow(const ChangeRow& row, double terrain_size_x_m, double terrain_size_z_m) {
  for (size_t i = 0; i < kRowIntegerColumns; ++i) {
    if (row.ints[i] < kRanges[i].min || row.ints[i] > kRanges[i].max) {
      return Error{fmt::format("{} {} is outside [{}, {}]", kRowColumnNames[i], row.ints[i],
                               kRanges[i].min, kRanges[i].max)};
    }
  }
  auto u16 = [&](RowColumn c) { return static_cast<uint16_t>(row.at(c)); };
  auto u32 = [&](RowColumn c) { return static_cast<uint32_t>(row.at(c)); };
  Change c;
  c.kind = static_cast<ChangeKind>(row.at(RowColumn::kKind));
  c.id = {u16(RowColumn::kOriginSite), u16(RowColumn::kOriginHost), u32(RowColumn::kNumber)};
  c.stamp.changed_by = {u16(RowColumn::kAuthorSite), u16(RowColumn::kAuthorHost)};
  c.stamp.change_seq = u32(RowColumn::kSeq);
  c.stamp.lamport = static_cast<uint64_t>(row.at(RowColumn::kLamport));
  const uint16_t type = u16(RowColumn::kFeatureType);
  if (!IsValidFeatureType(type)) return Error{fmt::format("feature_type {} is unknown", type)};
  c.params.type = static_cast<FeatureType>(type);
  if (c.kind != ChangeKind::kDestruct) {
    ByteReader r(row.params);
    auto p = DecodeFeatureParams(r);
    if (!p) return Error{fmt::format("parameters: {}", p.error().message)};
    if (r.remaining() != 0) {
      return Error{fmt::format("parameters: {} bytes left over after {} bytes of parameters",
                               r.remaining(), r.offset())};
    }
    if (p.value().type != c.params.type) {
      return Error{fmt::format("feature_type {} but the parameters are of type {}", type,
                               static_cast<int>(p.value().type))};
    }
    c.params = std::move(p).value();
  } else if (!row.params.empty()) {
    return Error{fmt::format("a Destruct with {} bytes of parameters", row.params.size())};
  }
  std::optional<Rejection> refused;
  const char* as = "";
  switch (c.kind) {
    case ChangeKind::kConstruct:
      if (c.params.type == FeatureType::kEarthMove) {
        refused =
            ValidateAsPdu(ToEarthMove(ToFeaturePdu(c)), c, terrain_size_x_m, terrain_size_z_m);
        as = "EarthMove";
        break;
      }
      refused = ValidateAsPdu(ToConstruct(ToFeaturePdu(c)), c, terrain_size_x_m, terrain_size_z_m);
      as = "Construct";
      break;
    case ChangeKind::kUpdate:
      refused = ValidateAsPdu(ToUpdate(ToFeaturePdu(c)), c, terrain_size_x_m, terrain_size_z_m);
      as = "Update";
      break;
    case ChangeKind::kDestruct:
      refused = ValidateAsPdu(ToDestruct(ToDestructPdu(c)), c, terrain_size_x_m, terrain_size_z_m);
      as = "Destruct";
      break;
  }
  if (refused) {
    return Error{fmt::format("refused as a {} PDU would be: {}: {}", as,
                             RejectReasonName(refused->reason), refused->detail)};
  }
  return c;
}

}  // namespace dt
