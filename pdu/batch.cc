#include "pdu/batch.h"

#include <array>

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
    b.members[i].encoding = static_cast<uint8_t>(members[i].encoding);
    b.members[i].num_bytes = static_cast<int16_t>(members[i].bytes.size());
    b.members[i].bytes.assign(members[i].bytes.begin(), members[i].bytes.end());
  }
  EncodePduInto(b, out);
}

std::optional<Rejection> DecodeBatch(std::span<const uint8_t> bytes, const ValidationContext& ctx,
                                     std::vector<MemberPdu>& out) {
  // The batch is read in place: batch_t would copy every member into a vector of its own, one
  // allocation per member received. The checks, their order and their messages are
  // DecodeAndValidate(batch_t)'s (batch_test compares the two on mutated batches).
  if (auto r = CheckPduEnvelope(bytes, static_cast<uint64_t>(dtpdu::batch_t::getHash()))) {
    return r;
  }
  const uint8_t* buf = bytes.data();
  const int size = static_cast<int>(bytes.size());
  dtpdu::batch_t head;  // header, sender and num_members; the members stay in `bytes`
  int pos = 8;
  auto read = [&](int n) {
    if (n >= 0 && pos >= 0)
      pos += n;
    else
      pos = -1;
  };
  read(head.header._decodeNoHash(buf, pos, size - pos));
  if (pos >= 0) read(head.sender._decodeNoHash(buf, pos, size - pos));
  if (pos >= 0) read(__int16_t_decode_array(buf, pos, size - pos, &head.num_members, 1));
  // LCM refuses a negative count or length (resizing to it throws): so does this.
  if (pos >= 0 && head.num_members < 0) pos = -1;
  const int first_member = pos;
  // Member k's type, encoding and bytes, from its place; pos moves past it.
  auto next_member = [&](uint8_t& type, uint8_t& encoding, std::span<const uint8_t>& member) {
    int16_t length = 0;
    read(__byte_decode_array(buf, pos, size - pos, &type, 1));
    if (pos >= 0) read(__byte_decode_array(buf, pos, size - pos, &encoding, 1));
    if (pos >= 0) read(__int16_t_decode_array(buf, pos, size - pos, &length, 1));
    if (pos < 0 || length == 0) return;
    if (length < 0 || length > size - pos) {
      pos = -1;
      return;
    }
    member = bytes.subspan(static_cast<size_t>(pos), static_cast<size_t>(length));
    pos += length;
  };
  uint8_t type = 0, encoding = 0;
  std::span<const uint8_t> member;
  for (int k = 0; pos >= 0 && k < head.num_members; ++k) next_member(type, encoding, member);
  if (auto r = CheckPduDecoded(bytes.size(), pos, PduType::kBatch)) return r;
  if (auto r = Validate(head, ctx)) return r;  // header and count; the members are checked next
  const auto count = static_cast<size_t>(head.num_members);
  pos = first_member;
  for (size_t i = 0; i < count; ++i) {
    next_member(type, encoding, member);
    if (auto r = CheckBatchMember(i, count, type, encoding)) return r;
  }
  const NodeAddress sender = FromPdu(head.sender);
  out.resize(count);
  pos = first_member;
  // A delta is rebuilt over the member before it: two buffers, the one written and the previous.
  std::array<std::array<uint8_t, kMaxPduBytes>, 2> rebuilt;
  std::span<const uint8_t> previous;
  for (size_t i = 0; i < count; ++i) {
    member = {};
    next_member(type, encoding, member);
    const PduType member_type = *PduTypeFromRaw(type);  // checked above
    std::optional<Rejection> r;
    if (static_cast<MemberEncoding>(encoding) == MemberEncoding::kDelta) {
      size_t length = 0;
      std::span<uint8_t> into = rebuilt[i % 2];
      r = ApplyMemberDelta(previous, member, into, &length);
      if (!r) member = into.first(length);
    }
    if (!r) r = DecodeMemberAs(member_type, member, ctx, sender, out[i]);
    if (r) {
      r->detail = fmt::format("member {} of {} ({}): {}", i + 1, count, PduTypeName(member_type),
                              r->detail);
      return r;
    }
    previous = member;
  }
  return std::nullopt;
}

}  // namespace dt
