#include "engine/change_hash.h"

#include <xxhash.h>

#include <array>
#include <bit>
#include <cstring>

#include "base/demand.h"

namespace dt {
namespace {

// Little-endian values into a buffer on the stack: a log of 10^5 changes is hashed without an
// allocation or a byte-at-a-time append per change. The layout is EncodeFeatureParams's
// (terrain/feature_params.h) for the parameters, after the kind, ID and stamp.
class Bytes {
 public:
  void U8(uint8_t v) { Put(v); }
  void U16(uint16_t v) { Put(v); }
  void U32(uint32_t v) { Put(v); }
  void U64(uint64_t v) { Put(v); }
  void F64(double v) { Put(std::bit_cast<uint64_t>(v)); }
  const uint8_t* data() const { return buf_.data(); }
  size_t size() const { return n_; }
  // Encode checks the sizes once: a change is at most 107 bytes plus 10 per vertex edit, plus a
  // point count and 32 bytes per point for the types with points, or a post count and 8 bytes
  // per post for an earth move (never more than one of the three).
  static constexpr size_t kCapacity =
      107 + 10 * kCraterSpokes * kCraterRings + 2 +
      (32 * kMaxFeaturePoints > 8 * kMaxEarthMovePosts ? 32 * kMaxFeaturePoints
                                                       : 8 * kMaxEarthMovePosts);

 private:
  template <typename T>
  void Put(T v) {
    if constexpr (std::endian::native == std::endian::little) {
      std::memcpy(buf_.data() + n_, &v, sizeof(T));
    } else {
      for (size_t i = 0; i < sizeof(T); ++i) buf_[n_ + i] = static_cast<uint8_t>(v >> (8 * i));
    }
    n_ += sizeof(T);
  }
  std::array<uint8_t, kCapacity> buf_;
  size_t n_ = 0;
};

void Encode(const Change& c, Bytes& w) {
  // Validated parameters hold at most one edit per vertex; more is a broken invariant.
  DT_DEMAND(c.params.vertex_edits.size() <= size_t{kCraterSpokes * kCraterRings});
  DT_DEMAND(c.params.points.size() <= size_t{kMaxFeaturePoints});
  DT_DEMAND(c.params.post_deltas.size() <= size_t{kMaxEarthMovePosts});
  const int lists =
      !c.params.vertex_edits.empty() + !c.params.points.empty() + !c.params.post_deltas.empty();
  DT_DEMAND(lists <= 1);  // validation allows one list per type
  w.U8(static_cast<uint8_t>(c.kind));
  w.U16(c.id.site);
  w.U16(c.id.host);
  w.U32(c.id.number);
  w.U16(c.stamp.changed_by.site);
  w.U16(c.stamp.changed_by.host);
  w.U32(c.stamp.change_seq);
  w.U64(c.stamp.lamport);
  const FeatureParams& p = c.params;
  w.U16(static_cast<uint16_t>(p.type));
  if (c.kind == ChangeKind::kDestruct) return;  // a Destruct carries the type only
  w.F64(p.x_m);
  w.F64(p.z_m);
  w.F64(p.direction_rad);
  for (double h : p.height_m) w.F64(h);
  for (double l : p.length_m) w.F64(l);
  w.F64(p.width_m);
  w.U16(static_cast<uint16_t>(p.material));
  w.U32(static_cast<uint32_t>(p.status));
  w.U16(static_cast<uint16_t>(p.vertex_edits.size()));
  for (const auto& e : p.vertex_edits) {
    w.U8(e.spoke);
    w.U8(e.ring);
    w.F64(e.offset_m);
  }
  if (p.type == FeatureType::kEarthMove) {
    w.U16(static_cast<uint16_t>(p.post_deltas.size()));
    for (const auto& d : p.post_deltas) {
      w.U16(d.i);
      w.U16(d.j);
      w.U32(static_cast<uint32_t>(d.delta_mm));
    }
    return;
  }
  if (!HasFeaturePoints(p.type)) return;
  w.U16(static_cast<uint16_t>(p.points.size()));
  for (const auto& q : p.points) {
    w.F64(q.x_m);
    w.F64(q.z_m);
    w.F64(q.height_m);
    w.F64(q.width_m);
  }
}

}  // namespace

std::vector<uint8_t> CanonicalChangeBytes(const Change& change) {
  Bytes w;
  Encode(change, w);
  return {w.data(), w.data() + w.size()};
}

uint64_t ChangeHash(const Change& change) {
  Bytes w;
  Encode(change, w);
  return XXH3_64bits(w.data(), w.size());
}

}  // namespace dt
