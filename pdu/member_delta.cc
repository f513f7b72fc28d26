#include "pdu/member_delta.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>

#include <fmt/format.h>

#include "base/demand.h"
#include "pdu/pdu_type.h"

namespace dt {
namespace {

constexpr size_t kMaxRunField = 255;  // skip and count are one byte each
// A stretch of equal bytes this long or shorter between two differing ones is cheaper written
// as literals than as the start of a new run.
constexpr size_t kMaxBridgedBytes = kMemberDeltaRunBytes;
// The longest delta of a member: every byte a literal, each run taking two bytes more, and an
// empty run for every 255 equal bytes skipped.
constexpr size_t kMaxDeltaBytes = kMemberDeltaLengthBytes + 3 * kMaxPduBytes +
                                  kMemberDeltaRunBytes * (kMaxPduBytes / kMaxRunField + 1);

}  // namespace

void EncodeMemberDelta(std::span<const uint8_t> previous, std::span<const uint8_t> member,
                       std::vector<uint8_t>& out) {
  DT_DEMAND(!member.empty() && member.size() <= kMaxPduBytes);
  const size_t n = member.size();
  const uint8_t* m = member.data();
  // The member before, cut or padded with zeros to this one's length: what the receiver starts
  // from.
  std::array<uint8_t, kMaxPduBytes> base;
  const size_t kept = std::min(n, previous.size());
  // copy_n and fill, not memcpy: an empty `previous` may have no data pointer at all.
  std::copy_n(previous.begin(), kept, base.begin());
  std::fill(base.begin() + static_cast<std::ptrdiff_t>(kept),
            base.begin() + static_cast<std::ptrdiff_t>(n), uint8_t{0});
  auto differs = [&](size_t i) { return m[i] != base[i]; };
  // The first difference at or after i (n if none), eight bytes at a time: the lowest differing
  // bit of two little-endian words is in their first differing byte.
  auto next_difference = [&](size_t i) {
    if constexpr (std::endian::native == std::endian::little) {
      for (; i + sizeof(uint64_t) <= n; i += sizeof(uint64_t)) {
        uint64_t a = 0, b = 0;
        std::memcpy(&a, m + i, sizeof a);
        std::memcpy(&b, base.data() + i, sizeof b);
        if (a != b) return i + static_cast<size_t>(std::countr_zero(a ^ b)) / 8;
      }
    }
    while (i < n && !differs(i)) ++i;
    return i;
  };
  // Written through a pointer into room for the longest delta, then copied out once: this runs
  // for every PDU a batch packs.
  std::array<uint8_t, kMaxDeltaBytes> room;
  uint8_t* o = room.data();
  *o++ = static_cast<uint8_t>(n >> 8);
  *o++ = static_cast<uint8_t>(n);
  size_t cursor = 0;  // where the last run ended
  for (size_t i = next_difference(0); i < n; i = next_difference(i)) {
    size_t skip = i - cursor;
    for (; skip > kMaxRunField; skip -= kMaxRunField) {  // a long equal stretch: empty runs
      *o++ = static_cast<uint8_t>(kMaxRunField);
      *o++ = 0;
    }
    // The run: from i while bytes differ, bridging short equal stretches, at most 255 bytes.
    size_t end = i + 1;
    while (end < n && end - i < kMaxRunField) {
      if (differs(end)) {
        ++end;
        continue;
      }
      size_t resumes = end;
      while (resumes < n && resumes - end <= kMaxBridgedBytes && !differs(resumes)) ++resumes;
      if (resumes == n || resumes - end > kMaxBridgedBytes || resumes + 1 - i > kMaxRunField) {
        break;
      }
      end = resumes + 1;
    }
    *o++ = static_cast<uint8_t>(skip);
    *o++ = static_cast<uint8_t>(end - i);
    std::memcpy(o, m + i, end - i);
    o += end - i;
    cursor = i = end;
  }
  out.assign(room.data(), o);
}

std::optional<Rejection> ApplyMemberDelta(std::span<const uint8_t> previous,
                                          std::span<const uint8_t> delta, std::span<uint8_t> out,
                                          size_t* length) {
  DT_DEMAND(out.size() >= kMaxPduBytes);
  if (delta.size() < kMemberDeltaLengthBytes) {
    return Rejection{RejectReason::kTruncated,
                     fmt::format("delta of {} bytes has no length", delta.size())};
  }
  const auto n = static_cast<int16_t>((delta[0] << 8) | delta[1]);
  if (n < 1 || static_cast<size_t>(n) > kMaxPduBytes) {
    return Rejection{RejectReason::kOutOfRange,
                     fmt::format("delta length {} outside 1..{}", n, kMaxPduBytes)};
  }
  const auto size = static_cast<size_t>(n);
  const size_t kept = std::min(size, previous.size());
  std::copy_n(previous.begin(), kept, out.begin());
  std::fill(out.begin() + static_cast<std::ptrdiff_t>(kept),
            out.begin() + static_cast<std::ptrdiff_t>(size), uint8_t{0});
  size_t cursor = 0;
  for (size_t at = kMemberDeltaLengthBytes; at < delta.size();) {
    if (delta.size() - at < kMemberDeltaRunBytes) {
      return Rejection{RejectReason::kTruncated,
                       fmt::format("delta run at byte {} of {} cut short", at, delta.size())};
    }
    const size_t skip = delta[at], count = delta[at + 1];
    at += kMemberDeltaRunBytes;
    if (count > delta.size() - at) {
      return Rejection{
          RejectReason::kTruncated,
          fmt::format("delta run of {} bytes at byte {} of {} cut short", count, at, delta.size())};
    }
    if (cursor + skip + count > size) {
      return Rejection{RejectReason::kTruncated,
                       fmt::format("delta run to byte {} past the member's {} bytes",
                                   cursor + skip + count, size)};
    }
    cursor += skip;
    std::memcpy(out.data() + cursor, delta.data() + at, count);
    cursor += count;
    at += count;
  }
  *length = size;
  return std::nullopt;
}

}  // namespace dt
