#include "terrain/terrain_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <tuple>

#include <fmt/format.h>
#include <xxhash.h>

#include "base/bytes.h"
#include "base/regular_file.h"

namespace dt {
namespace {

namespace fs = std::filesystem;

// A high first byte catches 7-bit transfers, CR LF catches line-ending conversion, 0x1A stops
// `type` on DOS-like systems (the PNG trick).
constexpr std::array<uint8_t, 8> kMagic = {0x89, 'D', 'T', 'E', 'R', '\r', '\n', 0x1A};
constexpr size_t kVersionOffset = 8;
constexpr size_t kGroundLengthOffset = 12;
constexpr size_t kFeatureLengthOffset = 20;
constexpr int kMaxPosts = kMaxPostsPerSide;  // HeightGrid's limit

// Bytes of a ground section: the post counts (one for a square grid up to version 3, two from
// version 4), spacing, posts, two soils per square.
uint64_t GroundSectionBytes(uint32_t version, uint64_t nx, uint64_t nz) {
  const uint64_t counts = version >= 4 ? 8 : 4;
  return counts + 8 + 4 * nx * nz + 2 * 2 * (nx - 1) * (nz - 1);
}

}  // namespace

std::vector<uint8_t> EncodeTerrainFile(const Terrain& terrain) {
  const HeightGrid& g = terrain.ground();
  const uint32_t version = g.is_square() ? kSquareTerrainFileVersion : kTerrainFileVersion;
  const auto nx = static_cast<uint32_t>(g.posts_x()), nz = static_cast<uint32_t>(g.posts_z());
  ByteWriter ground;
  ground.bytes().reserve(GroundSectionBytes(version, nx, nz));
  ground.U32(nx);
  if (version >= 4) ground.U32(nz);
  ground.F64(g.spacing_m());
  // The posts without blade work: the earth moves among the features add it back on loading.
  for (float y : terrain.BarePosts()) ground.F32(y);
  for (Material soil : g.soils()) ground.U16(static_cast<uint16_t>(soil));

  ByteWriter features;
  const auto sorted = terrain.FeaturesById();
  features.U32(static_cast<uint32_t>(sorted.size()));
  for (const Feature* f : sorted) {
    features.U16(f->id().site);
    features.U16(f->id().host);
    features.U32(f->id().number);
    ByteWriter record;
    EncodeFeatureParams(f->params(), record);
    features.U32(static_cast<uint32_t>(record.bytes().size()));
    features.Bytes(record.bytes());
  }

  ByteWriter file;
  file.bytes().reserve(kTerrainFileHeaderBytes + ground.bytes().size() + features.bytes().size() +
                       kTerrainFileChecksumBytes);
  file.Bytes(kMagic);
  file.U32(version);
  file.U64(ground.bytes().size());
  file.U64(features.bytes().size());
  file.Bytes(ground.bytes());
  file.Bytes(features.bytes());
  file.U64(XXH3_64bits(file.bytes().data(), file.bytes().size()));
  return std::move(file.bytes());
}

Result<std::unique_ptr<Terrain>> DecodeTerrainFile(std::span<const uint8_t> bytes,
                                                   std::string_view source_name) {
  auto fail = [&](size_t offset, const std::string& what) -> Error {
    return Error{fmt::format("{}: byte {}: {}", source_name, offset, what)};
  };
  constexpr size_t kMinBytes = kTerrainFileHeaderBytes + kTerrainFileChecksumBytes;
  if (bytes.size() < kMinBytes) {
    return fail(bytes.size(), fmt::format("file is {} bytes, shorter than the {}-byte header and "
                                          "checksum (truncated?)",
                                          bytes.size(), kMinBytes));
  }
  if (!std::equal(kMagic.begin(), kMagic.end(), bytes.begin())) {
    return fail(0, "not a dynterrain terrain file (wrong magic)");
  }
  ByteReader header(bytes.subspan(kVersionOffset, kTerrainFileHeaderBytes - kVersionOffset));
  const uint32_t version = *header.U32();
  const uint64_t ground_bytes = *header.U64();
  const uint64_t feature_bytes = *header.U64();
  if (version < kOldestTerrainFileVersion || version > kTerrainFileVersion) {
    return fail(kVersionOffset,
                fmt::format("format version {} is not supported (this build "
                            "reads versions {} to {})",
                            version, kOldestTerrainFileVersion, kTerrainFileVersion));
  }
  // Written so that no sum can overflow: each length is first checked against the file size.
  const uint64_t body = bytes.size() - kMinBytes;
  if (ground_bytes > body || feature_bytes > body - ground_bytes ||
      ground_bytes + feature_bytes != body) {
    return fail(kGroundLengthOffset,
                fmt::format("header declares a {}-byte ground section and a {}-byte feature "
                            "section, which does not match the file size of {} bytes (truncated "
                            "or extended?)",
                            ground_bytes, feature_bytes, bytes.size()));
  }
  const size_t checksum_at = bytes.size() - kTerrainFileChecksumBytes;
  ByteReader checksum_reader(bytes.subspan(checksum_at));
  const uint64_t stored = *checksum_reader.U64();
  const uint64_t computed = XXH3_64bits(bytes.data(), checksum_at);
  if (stored != computed) {
    return fail(checksum_at, fmt::format("checksum mismatch: stored {:016x}, computed {:016x} "
                                         "(the file is corrupt)",
                                         stored, computed));
  }

  // Ground section. Offsets in messages are from the start of the file.
  const size_t ground_at = kTerrainFileHeaderBytes;
  ByteReader ground(bytes.subspan(ground_at, ground_bytes));
  // Up to version 3 the grid is square: one count. From version 4, posts along x then along z.
  const bool two_counts = version >= 4;
  const auto first_count = ground.U32();
  const auto second_count = two_counts ? ground.U32() : first_count;
  if (!first_count || !second_count) {
    return fail(kGroundLengthOffset,
                fmt::format("ground section is {} bytes, too short to hold a grid", ground_bytes));
  }
  const uint32_t nx = *first_count, nz = *second_count;
  if (!two_counts && (nx < 2 || nx > kMaxPosts)) {
    return fail(ground_at, fmt::format("posts_per_side {} is outside [2, {}]", nx, kMaxPosts));
  }
  for (const auto& [name, n, at] :
       {std::tuple{"posts_x", nx, ground_at}, std::tuple{"posts_z", nz, ground_at + 4}}) {
    if (n < 2 || n > kMaxPosts) {
      return fail(at, fmt::format("{} {} is outside [2, {}]", name, n, kMaxPosts));
    }
  }
  const uint64_t needed = GroundSectionBytes(version, nx, nz);
  if (ground_bytes != needed) {
    return fail(kGroundLengthOffset,
                fmt::format("ground section is {} bytes but a {} x {} grid needs {}", ground_bytes,
                            nx, nz, needed));
  }
  const size_t spacing_at = ground_at + ground.offset();
  const double spacing_m = *ground.F64();
  if (!std::isfinite(spacing_m) || spacing_m <= 0.0) {
    return fail(spacing_at, fmt::format("spacing_m {} must be finite and > 0", spacing_m));
  }
  std::vector<float> posts(static_cast<size_t>(nx) * nz);
  for (size_t k = 0; k < posts.size(); ++k) {
    const size_t at = ground_at + ground.offset();
    posts[k] = *ground.F32();
    if (!std::isfinite(posts[k])) {
      return fail(at, fmt::format("post ({}, {}) is not finite ({})", k % nx, k / nx, posts[k]));
    }
  }
  HeightGrid grid(static_cast<int>(nx), static_cast<int>(nz), spacing_m, std::move(posts));
  const size_t squares_x = nx - 1;
  const size_t soil_count = 2 * squares_x * (nz - 1);
  for (size_t k = 0; k < soil_count; ++k) {
    const size_t at = ground_at + ground.offset();
    const uint16_t raw = *ground.U16();
    const SquareIndex square{static_cast<int>((k / 2) % squares_x),
                             static_cast<int>((k / 2) / squares_x)};
    if (!IsValidMaterial(raw) || static_cast<Material>(raw) == Material::kFromGround) {
      return fail(at,
                  fmt::format("soil {} of square ({}, {}) is not a soil", raw, square.i, square.j));
    }
    grid.set_soil(square, static_cast<TriangleHalf>(k % 2), static_cast<Material>(raw));
  }

  // Feature section: records sorted by ID, each rebuilt through Terrain::Add.
  auto terrain = std::make_unique<Terrain>(std::move(grid));
  const size_t features_at = ground_at + ground_bytes;
  ByteReader features(bytes.subspan(features_at, feature_bytes));
  auto truncated = [&](std::string_view what) {
    return fail(features_at + features.offset(),
                fmt::format("feature section ends inside {}", what));
  };
  const auto count = features.U32();
  if (!count) return truncated("the feature count");
  FeatureId previous;
  for (uint32_t index = 0; index < *count; ++index) {
    const size_t record_at = features_at + features.offset();
    const auto site = features.U16();
    const auto host = features.U16();
    const auto number = features.U32();
    const auto length = features.U32();
    if (!site || !host || !number || !length) {
      return truncated(fmt::format("the header of feature record {} of {}", index + 1, *count));
    }
    const FeatureId id{*site, *host, *number};
    // The origin is the node that created the feature; 0 is no node's site or host (an exercise
    // gives every process a site and host in 1 .. 65535, docs/node.md). Both 0 is the base
    // ground's origin (terrain/base_ground.h): a file exported from an exercise that started on a
    // saved terrain holds that terrain's features under it.
    if ((id.site == 0) != (id.host == 0)) {
      return fail(id.site == 0 ? record_at : record_at + 2,
                  fmt::format("feature {}: origin {} is 0, which is no node's (a node's site "
                              "and host are 1 .. 65535)",
                              id.ToString(), id.site == 0 ? "site" : "host"));
    }
    if (index > 0 && !(previous < id)) {
      return fail(record_at, fmt::format("feature {} follows {}: records must be sorted by ID "
                                         "without repeats",
                                         id.ToString(), previous.ToString()));
    }
    previous = id;
    const auto record = features.Bytes(*length);
    if (!record) {
      return truncated(fmt::format("feature {} ({} bytes declared)", id.ToString(), *length));
    }
    // Version 1 knew craters, berms and bridges only, version 2 no earth moves.
    const auto record_type =
        static_cast<FeatureType>(record->size() >= 2 ? (*record)[0] | (*record)[1] << 8 : 0);
    if (version == 2 && record_type == FeatureType::kEarthMove) {
      return fail(record_at + 12, fmt::format("feature {}: a version 2 file cannot hold an "
                                              "earth_move",
                                              id.ToString()));
    }
    if (version == 1 && record->size() >= 2 &&
        (HasFeaturePoints(record_type) || record_type == FeatureType::kEarthMove)) {
      return fail(
          record_at + 12,
          fmt::format("feature {}: a version 1 file cannot hold a {}", id.ToString(),
                      FeatureTypeName(static_cast<FeatureType>((*record)[0] | (*record)[1] << 8))));
    }
    ByteReader params_reader(*record);
    auto params = DecodeFeatureParams(params_reader);
    const size_t params_at = record_at + 12;
    if (!params) {
      return fail(params_at, fmt::format("feature {}: {} (offsets within the record)",
                                         id.ToString(), params.error().message));
    }
    // ... and craters at the ground.
    if (version == 1 && params.value().type == FeatureType::kCrater &&
        params.value().height_m[0] != 0.0) {
      return fail(params_at, fmt::format("feature {}: a version 1 file cannot hold a crater "
                                         "below the ground",
                                         id.ToString()));
    }
    if (params_reader.remaining() != 0) {
      return fail(params_at + params_reader.offset(),
                  fmt::format("feature {}: {} bytes left over after its parameters", id.ToString(),
                              params_reader.remaining()));
    }
    if (auto added = terrain->Add(id, params.value()); !added) {
      return fail(record_at,
                  fmt::format("feature {} was refused: {}", id.ToString(), added.error().message));
    }
  }
  if (features.remaining() != 0) {
    return fail(features_at + features.offset(),
                fmt::format("{} bytes left over after the last feature", features.remaining()));
  }
  return terrain;
}

Status SaveTerrain(const Terrain& terrain, const fs::path& path) {
  // Renaming over a FIFO or device would replace it with a regular file; a directory fails late.
  if (auto s = CheckReplaceableFile(path); !s) return s;
  const std::vector<uint8_t> bytes = EncodeTerrainFile(terrain);
  if (bytes.size() > kMaxTerrainFileBytes) {
    return Error{
        fmt::format("{}: the terrain file would be {} bytes, over the {}-byte limit that "
                    "readers accept",
                    path.string(), bytes.size(), kMaxTerrainFileBytes)};
  }
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  // fmt, not operator+: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string&&.
  std::string temp = (dir / fmt::format(".{}.tmp.XXXXXX", path.filename().string())).string();
  const int fd = mkstemp(temp.data());
  if (fd < 0) {
    return Error{fmt::format("{}: cannot create a temporary file in {}: {}", path.string(),
                             dir.string(), std::strerror(errno))};
  }
  auto give_up = [&](std::string_view step) -> Error {
    const int saved = errno;
    ::close(fd);
    ::unlink(temp.c_str());
    return Error{fmt::format("{}: {} failed: {}", path.string(), step, std::strerror(saved))};
  };
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t w = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (w < 0) {
      if (errno == EINTR) continue;
      return give_up("write");
    }
    written += static_cast<size_t>(w);
  }
  if (::fchmod(fd, 0644) != 0) return give_up("fchmod");
  if (::fsync(fd) != 0) return give_up("fsync");
  if (::close(fd) != 0) {
    const int saved = errno;
    ::unlink(temp.c_str());
    return Error{fmt::format("{}: close failed: {}", path.string(), std::strerror(saved))};
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const int saved = errno;
    ::unlink(temp.c_str());
    return Error{
        fmt::format("{}: rename from {} failed: {}", path.string(), temp, std::strerror(saved))};
  }
  // The rename is durable only once the directory entry is on disk.
  const int dir_fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dir_fd < 0) {
    return Error{fmt::format("{}: saved, but opening {} to fsync it failed: {}", path.string(),
                             dir.string(), std::strerror(errno))};
  }
  const int synced = ::fsync(dir_fd);
  const int saved = errno;
  ::close(dir_fd);
  if (synced != 0) {
    return Error{fmt::format("{}: saved, but fsync of {} failed: {}", path.string(), dir.string(),
                             std::strerror(saved))};
  }
  return Status::Ok();
}

Result<std::unique_ptr<Terrain>> LoadTerrain(const fs::path& path) {
  auto bytes = ReadRegularFile(path, kMaxTerrainFileBytes);
  if (!bytes) return bytes.error();
  return DecodeTerrainFile(bytes.value(), path.string());
}

}  // namespace dt
