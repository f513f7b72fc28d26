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

void EncodeSignedPart(const AuthTrailer& t, std::span<uint8_t, kAuthSignedBytes> out) {
  uint8_t* b = out.data();
  std::copy(kAuthMagic.begin(), kAuthMagic.end(), b);
  PutBig(b + 4, t.sender.site, 2);
  PutBig(b + 6, t.sender.host, 2);
  PutBig(b + 8, t.incarnation, 8);
  PutBig(b + 16, t.sequence, 8);
  PutBig(b + 24, t.send_time_ms, 8);
}

void AppendTrailer(const AuthTrailer& t, std::vector<uint8_t>& out) {
  const size_t at = out.size();
  out.resize(at + kAuthTrailerBytes);
  EncodeSignedPart(t, std::span<uint8_t>(out).subspan(at).first<kAuthSignedBytes>());
  std::copy(t.mac.begin(), t.mac.end(),
            out.begin() + static_cast<std::ptrdiff_t>(at + kAuthSignedBytes));
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
