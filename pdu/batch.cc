#include "pdu/batch.h"

#include <fmt/format.h>

#include "pdu/conversion.h"

namespace dt {
namespace {

template <typename Pdu>
std::optional<Rejection> DecodeMember(std::span<const uint8_t> bytes, const ValidationContext& ctx,
                                      NodeAddress sender, MemberPdu& out) {
  Pdu& pdu = out.emplace<Pdu>();
  if (auto r = DecodeAndValidate(bytes, ctx, pdu)) return r;
  if (FromPdu(pdu.sender) != sender) {
    return Rejection{RejectReason::kSenderMismatch,
                     fmt::format("member sender {} in a batch from {}",
                                 FromPdu(pdu.sender).ToString(), sender.ToString())};
  }
  return std::nullopt;
}

std::optional<Rejection> DecodeMemberAs(PduType type, std::span<const uint8_t> bytes,
                                        const ValidationContext& ctx, NodeAddress sender,
                                        MemberPdu& out) {
  switch (type) {
    case PduType::kConstruct:
      return DecodeMember<dtpdu::construct_t>(bytes, ctx, sender, out);
    case PduType::kUpdate:
      return DecodeMember<dtpdu::update_t>(bytes, ctx, sender, out);
    case PduType::kDestruct:
      return DecodeMember<dtpdu::destruct_t>(bytes, ctx, sender, out);
    case PduType::kMaxFeature:
      return DecodeMember<dtpdu::max_feature_t>(bytes, ctx, sender, out);
    case PduType::kPlayback:
      return DecodeMember<dtpdu::playback_t>(bytes, ctx, sender, out);
    case PduType::kAntiEntropy:
      return DecodeMember<dtpdu::anti_entropy_t>(bytes, ctx, sender, out);
    case PduType::kVehicleState:
      return DecodeMember<dtpdu::vehicle_state_t>(bytes, ctx, sender, out);
    case PduType::kEarthMove:
      return DecodeMember<dtpdu::earth_move_t>(bytes, ctx, sender, out);
    case PduType::kBatch:
      break;  // Validate(batch_t) refused nested batches already
  }
  return Rejection{RejectReason::kUnknownPduType, "a batch inside a batch"};
}

}  // namespace

void EncodeBatchInto(uint8_t exercise_id, uint32_t timestamp_dis, NodeAddress sender,
                     std::span<const BatchMember> members, std::vector<uint8_t>& out) {
  dtpdu::batch_t b{};
  b.header.protocol_version = static_cast<uint8_t>(kProtocolVersion);
  b.header.exercise_id = static_cast<uint8_t>(exercise_id);
  b.header.pdu_type = static_cast<uint8_t>(PduType::kBatch);
  b.header.timestamp_dis = static_cast<int32_t>(timestamp_dis);
  b.sender.site = static_cast<int16_t>(sender.site);
  b.sender.host = static_cast<int16_t>(sender.host);
  b.num_members = static_cast<int16_t>(members.size());
  b.members.resize(members.size());
  for (size_t i = 0; i < members.size(); ++i) {
    b.members[i].pdu_type = static_cast<uint8_t>(members[i].type);
    b.members[i].num_bytes = static_cast<int16_t>(members[i].bytes.size());
    b.members[i].bytes.assign(members[i].bytes.begin(), members[i].bytes.end());
  }
  EncodePduInto(b, out);
}

std::optional<Rejection> DecodeBatch(std::span<const uint8_t> bytes, const ValidationContext& ctx,
                                     std::vector<MemberPdu>& out) {
  dtpdu::batch_t batch;
  if (auto r = DecodeAndValidate(bytes, ctx, batch)) return r;
  const NodeAddress sender = FromPdu(batch.sender);
  out.resize(batch.members.size());
  for (size_t i = 0; i < batch.members.size(); ++i) {
    const auto& m = batch.members[i];
    const PduType type = *PduTypeFromRaw(m.pdu_type);  // Validate(batch_t) checked it
    if (auto r = DecodeMemberAs(type, m.bytes, ctx, sender, out[i])) {
      r->detail = fmt::format("member {} of {} ({}): {}", i + 1, batch.members.size(),
                              PduTypeName(type), r->detail);
      return r;
    }
  }
  return std::nullopt;
}

}  // namespace dt
