#include "terrain/terrain_digest.h"

#include <bit>
#include <memory>
#include <string_view>

#include <fmt/format.h>
#include <xxhash.h>

#include "base/bytes.h"
#include "base/demand.h"

namespace dt {
namespace {

// Distinguishes this encoding from any other hashed byte string; bump the version if the
// encoding ever changes.
constexpr std::string_view kDigestTag = "dynterrain state v1";
constexpr size_t kFlushBytes = 64 * 1024;

// Feeds little-endian encoded values to XXH3-128 in bounded chunks, so a large grid is never
// copied whole.
class DigestStream {
 public:
  DigestStream() : state_(XXH3_createState(), &XXH3_freeState) {
    DT_DEMAND(state_ && XXH3_128bits_reset(state_.get()) == XXH_OK);
  }
  ByteWriter& out() {
    if (out_.bytes().size() >= kFlushBytes) Flush();
    return out_;
  }
  // Hashes n bytes as they are, after what out() holds: the same digest as writing them one by
  // one, without the copy.
  void Raw(const void* data, size_t n) {
    Flush();
    DT_DEMAND(XXH3_128bits_update(state_.get(), data, n) == XXH_OK);
  }
  // The state so far, to go on from (Resume) without hashing it again.
  std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> Save() {
    Flush();
    std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> copy(XXH3_createState(),
                                                                  &XXH3_freeState);
    DT_DEMAND(copy);
    XXH3_copyState(copy.get(), state_.get());
    return copy;
  }
  void Resume(const XXH3_state_t& saved) { XXH3_copyState(state_.get(), &saved); }
  TerrainDigest Finish() {
    Flush();
    const XXH128_hash_t h = XXH3_128bits_digest(state_.get());
    return {h.high64, h.low64};
  }

 private:
  void Flush() {
    auto& bytes = out_.bytes();
    DT_DEMAND(XXH3_128bits_update(state_.get(), bytes.data(), bytes.size()) == XXH_OK);
    bytes.clear();
  }
  std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> state_;
  ByteWriter out_;
};

void EncodeGround(const HeightGrid& ground, DigestStream& stream) {
  for (char c : kDigestTag) stream.out().U8(static_cast<uint8_t>(c));
  // A square grid hashes its side as it always has, so the digests of square terrains stay what
  // they were; any other grid writes 0 (no grid has 0 posts a side) then both counts, so no two
  // shapes share an encoding.
  if (ground.is_square()) {
    stream.out().U32(static_cast<uint32_t>(ground.posts_x()));
  } else {
    stream.out().U32(0);
    stream.out().U32(static_cast<uint32_t>(ground.posts_x()));
    stream.out().U32(static_cast<uint32_t>(ground.posts_z()));
  }
  stream.out().F64(ground.spacing_m());
  // Bit patterns, so the digest never depends on how a machine compares floats: little-endian
  // u32 per post and u16 per soil, which on a little-endian machine are the bytes in memory, so
  // the spans are hashed in place (a 10^8-post ground in a fraction of a second, not seconds).
  static_assert(std::endian::native == std::endian::little, "the digest hashes LE bytes in place");
  static_assert(sizeof(float) == sizeof(uint32_t) && sizeof(Material) == sizeof(uint16_t));
  stream.Raw(ground.posts().data(), ground.posts().size_bytes());
  stream.Raw(ground.soils().data(), ground.soils().size_bytes());
}

void EncodeFeatures(const Terrain& terrain, DigestStream& stream) {
  const auto features = terrain.FeaturesById();
  stream.out().U32(static_cast<uint32_t>(features.size()));
  for (const Feature* f : features) {
    ByteWriter& out = stream.out();
    out.U16(f->id().site);
    out.U16(f->id().host);
    out.U32(f->id().number);
    EncodeFeatureParams(f->params(), out);
  }
}

}  // namespace

std::string TerrainDigest::ToHex() const { return fmt::format("{:016x}{:016x}", high, low); }

std::optional<TerrainDigest> TerrainDigest::FromHex(std::string_view hex) {
  if (hex.size() != 32) return std::nullopt;
  uint64_t halves[2] = {0, 0};
  for (size_t k = 0; k < 32; ++k) {
    const char c = hex[k];
    unsigned digit;
    if (c >= '0' && c <= '9') {
      digit = static_cast<unsigned>(c - '0');
    } else if (c >= 'a' && c <= 'f') {
      digit = static_cast<unsigned>(c - 'a' + 10);
    } else if (c >= 'A' && c <= 'F') {
      digit = static_cast<unsigned>(c - 'A' + 10);
    } else {
      return std::nullopt;
    }
    halves[k / 16] = (halves[k / 16] << 4) | digit;
  }
  return TerrainDigest{halves[0], halves[1]};
}

TerrainDigest ComputeDigest(const HeightGrid& ground) {
  DigestStream stream;
  EncodeGround(ground, stream);
  stream.out().U32(0);  // no features
  return stream.Finish();
}

TerrainDigest ComputeDigest(const Terrain& terrain) {
  DigestStream stream;
  EncodeGround(terrain.ground(), stream);
  EncodeFeatures(terrain, stream);
  return stream.Finish();
}

struct TerrainDigester::GroundState {
  std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> state{nullptr, &XXH3_freeState};
};

TerrainDigester::TerrainDigester() = default;
TerrainDigester::~TerrainDigester() = default;
TerrainDigester::TerrainDigester(TerrainDigester&&) noexcept = default;
TerrainDigester& TerrainDigester::operator=(TerrainDigester&&) noexcept = default;

TerrainDigest TerrainDigester::Of(const Terrain& terrain) {
  if (digest_ && stamp_ == terrain.stamp()) return *digest_;
  DigestStream stream;
  if (ground_ && ground_stamp_ == terrain.ground_stamp()) {
    stream.Resume(*ground_->state);
  } else {
    EncodeGround(terrain.ground(), stream);
    if (!ground_) ground_ = std::make_unique<GroundState>();
    ground_->state = stream.Save();
    ground_stamp_ = terrain.ground_stamp();
  }
  EncodeFeatures(terrain, stream);
  digest_ = stream.Finish();
  stamp_ = terrain.stamp();
  return *digest_;
}

}  // namespace dt
