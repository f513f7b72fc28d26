#include "pdu/auth_trailer.h"

#include <algorithm>

namespace dt {
namespace {

void PutBig(uint8_t* p, uint64_t v, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) {
    p[i] = static_cast<uint8_t>(v & 0xFF);
    v >>= 8;
  }
}

uint64_t GetBig(const uint8_t* p, int bytes) {
  uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return v;
}

// The LCM fingerprint: no PDU is shorter.
constexpr size_t kMinPduBytes = 8;

}  // namespace

std::array<uint8_t, kAuthSignedBytes> EncodeSignedPart(const AuthTrailer& t) {
  std::array<uint8_t, kAuthSignedBytes> b{};
  std::copy(kAuthMagic.begin(), kAuthMagic.end(), b.begin());
  PutBig(b.data() + 4, t.sender.site, 2);
  PutBig(b.data() + 6, t.sender.host, 2);
  PutBig(b.data() + 8, t.incarnation, 8);
  PutBig(b.data() + 16, t.sequence, 8);
  PutBig(b.data() + 24, t.send_time_ms, 8);
  return b;
}

void AppendTrailer(const AuthTrailer& t, std::vector<uint8_t>& out) {
  const auto signed_part = EncodeSignedPart(t);
  out.insert(out.end(), signed_part.begin(), signed_part.end());
  out.insert(out.end(), t.mac.begin(), t.mac.end());
}

std::optional<AuthTrailer> ParseTrailer(std::span<const uint8_t> bytes) {
  if (bytes.size() < kMinPduBytes + kAuthTrailerBytes) return std::nullopt;
  const uint8_t* p = bytes.data() + (bytes.size() - kAuthTrailerBytes);
  if (!std::equal(kAuthMagic.begin(), kAuthMagic.end(), p)) return std::nullopt;
  AuthTrailer t;
  t.sender.site = static_cast<uint16_t>(GetBig(p + 4, 2));
  t.sender.host = static_cast<uint16_t>(GetBig(p + 6, 2));
  t.incarnation = GetBig(p + 8, 8);
  t.sequence = GetBig(p + 16, 8);
  t.send_time_ms = GetBig(p + 24, 8);
  std::copy(p + kAuthSignedBytes, p + kAuthTrailerBytes, t.mac.begin());
  return t;
}

}  // namespace dt
