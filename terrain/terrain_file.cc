#include "terrain/terrain_file.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include <fmt/format.h>
#include <xxhash.h>

#include "base/bytes.h"
#include "base/regular_file.h"
#include "terrain/terrain_file_format.h"

namespace dt {
namespace {

namespace fs = std::filesystem;
using namespace terrain_file_format;

uint32_t LittleEndianU32(const uint8_t* p) {
  return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
}

// A terrain file's bytes, all in memory (DecodeTerrainFile) or read piecewise from an open file
// (LoadTerrain), taken in order from a section. A read error of the file is kept: the decoder
// reports it in place of what it was checking.
class FileReader {
 public:
  explicit FileReader(std::span<const uint8_t> bytes) : memory_(bytes), size_(bytes.size()) {}
  explicit FileReader(const RegularFile& file) : file_(&file), size_(file.size()) {}

  uint64_t size() const { return size_; }
  uint64_t offset() const { return at_; }
  uint64_t remaining() const { return limit_ - at_; }
  const std::optional<Error>& io_error() const { return io_error_; }

  // Reads from `offset` on, no further than `limit`.
  void Seek(uint64_t offset, uint64_t limit) {
    at_ = offset;
    limit_ = limit;
  }

  // The next `count` bytes, valid until the next call; nullopt if the section holds fewer or the
  // file cannot be read (io_error()).
  std::optional<std::span<const uint8_t>> Take(size_t count) {
    if (count > remaining()) return std::nullopt;
    const uint64_t at = at_;
    at_ += count;
    if (file_ == nullptr) return memory_.subspan(static_cast<size_t>(at), count);
    if (at < buffer_at_ || at + count > buffer_at_ + buffer_.size()) {
      const auto fill = static_cast<size_t>(
          std::max<uint64_t>(count, std::min<uint64_t>(kChunkBytes, limit_ - at)));
      buffer_.resize(fill);
      buffer_at_ = at;
      if (auto s = file_->ReadAt(at, buffer_); !s) {
        buffer_.clear();
        io_error_ = s.error();
        return std::nullopt;
      }
    }
    return std::span<const uint8_t>(buffer_).subspan(static_cast<size_t>(at - buffer_at_), count);
  }

  // XXH3-64 (seed 0) of bytes [0, count), read piece by piece; nullopt on a read error.
  std::optional<uint64_t> Checksum(uint64_t count) {
    if (file_ == nullptr) return XXH3_64bits(memory_.data(), static_cast<size_t>(count));
    std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> state(XXH3_createState(),
                                                                   &XXH3_freeState);
    XXH3_64bits_reset(state.get());
    Seek(0, count);
    while (remaining() > 0) {
      const auto piece = Take(static_cast<size_t>(std::min<uint64_t>(kChunkBytes, remaining())));
      if (!piece) return std::nullopt;
      XXH3_64bits_update(state.get(), piece->data(), piece->size());
    }
    return XXH3_64bits_digest(state.get());
  }

 private:
  std::span<const uint8_t> memory_;
  const RegularFile* file_ = nullptr;
  uint64_t size_ = 0;
  uint64_t at_ = 0;
  uint64_t limit_ = 0;
  std::vector<uint8_t> buffer_;
  uint64_t buffer_at_ = 0;
  std::optional<Error> io_error_;
};

// What the header and the ground section's first bytes say.
struct FileLayout {
  uint32_t version = 0;
  uint64_t ground_bytes = 0;
  uint64_t feature_bytes = 0;
  uint32_t nx = 0;
  uint32_t nz = 0;
  double spacing_m = 0.0;
};

// The checks of a terrain file, a step at a time in the file's order, so that LoadTerrain takes
// every step, ProbeTerrainFile the header and the grid's shape alone, and
// LoadTerrainFileFeatures the feature section without the ground; each step fails with the
// message and offset LoadTerrain gives.
class TerrainDecoder {
 public:
  TerrainDecoder(FileReader& reader, std::string_view source_name)
      : reader_(reader), source_name_(source_name) {}

  // A read error of the file (it shrank, the disk failed) is named in place of what was checked.
  Error Fail(uint64_t offset, const std::string& what) const {
    if (reader_.io_error()) return Error{reader_.io_error()->message};
    return Error{fmt::format("{}: byte {}: {}", source_name_, offset, what)};
  }

  // The magic, the version and the section lengths against the file's size.
  Status Header(FileLayout& layout) {
    const uint64_t file_bytes = reader_.size();
    constexpr size_t kMinBytes = kTerrainFileHeaderBytes + kTerrainFileChecksumBytes;
    if (file_bytes < kMinBytes) {
      return Fail(file_bytes, fmt::format("file is {} bytes, shorter than the {}-byte header and "
                                          "checksum (truncated?)",
                                          file_bytes, kMinBytes));
    }
    reader_.Seek(0, file_bytes);
    const auto head = reader_.Take(kTerrainFileHeaderBytes);
    if (!head) return Fail(0, "cannot read the header");
    if (!std::equal(kMagic.begin(), kMagic.end(), head->begin())) {
      return Fail(0, "not a dynterrain terrain file (wrong magic)");
    }
    ByteReader header(head->subspan(kVersionOffset));
    layout.version = *header.U32();
    layout.ground_bytes = *header.U64();
    layout.feature_bytes = *header.U64();
    if (layout.version < kOldestTerrainFileVersion || layout.version > kTerrainFileVersion) {
      return Fail(kVersionOffset,
                  fmt::format("format version {} is not supported (this build "
                              "reads versions {} to {})",
                              layout.version, kOldestTerrainFileVersion, kTerrainFileVersion));
    }
    // Written so that no sum can overflow: each length is first checked against the file size.
    const uint64_t body = file_bytes - kMinBytes;
    const uint64_t ground_bytes = layout.ground_bytes, feature_bytes = layout.feature_bytes;
    if (ground_bytes > body || feature_bytes > body - ground_bytes ||
        ground_bytes + feature_bytes != body) {
      return Fail(kGroundLengthOffset,
                  fmt::format("header declares a {}-byte ground section and a {}-byte feature "
                              "section, which does not match the file size of {} bytes "
                              "(truncated or extended?)",
                              ground_bytes, feature_bytes, file_bytes));
    }
    return Status::Ok();
  }

  // The checksum the file's last bytes hold.
  Result<uint64_t> StoredChecksum() {
    const uint64_t checksum_at = reader_.size() - kTerrainFileChecksumBytes;
    reader_.Seek(checksum_at, reader_.size());
    const auto stored_bytes = reader_.Take(kTerrainFileChecksumBytes);
    if (!stored_bytes) return Fail(checksum_at, "cannot read the file");
    return *ByteReader(*stored_bytes).U64();
  }

  // The checksum over every byte before it, against the stored one.
  Status Checksum() {
    const uint64_t checksum_at = reader_.size() - kTerrainFileChecksumBytes;
    const std::optional<uint64_t> computed = reader_.Checksum(checksum_at);
    if (!computed) return Fail(checksum_at, "cannot read the file");
    const Result<uint64_t> stored = StoredChecksum();
    if (!stored) return stored.error();
    if (stored.value() != *computed) {
      return Fail(checksum_at, fmt::format("checksum mismatch: stored {:016x}, computed {:016x} "
                                           "(the file is corrupt)",
                                           stored.value(), *computed));
    }
    return Status::Ok();
  }

  // The ground section's post counts and spacing; leaves the reader at the first post.
  Status Shape(FileLayout& layout) {
    // Offsets in messages are from the start of the file.
    const uint64_t ground_at = kTerrainFileHeaderBytes;
    reader_.Seek(ground_at, ground_at + layout.ground_bytes);
    // Up to version 3 the grid is square: one count. From version 4, posts along x then along z.
    const bool two_counts = layout.version >= 4;
    const auto counts = reader_.Take(two_counts ? 8 : 4);
    if (!counts) {
      return Fail(kGroundLengthOffset, fmt::format("ground section is {} bytes, too short to "
                                                   "hold a grid",
                                                   layout.ground_bytes));
    }
    const uint32_t nx = LittleEndianU32(counts->data());
    const uint32_t nz = two_counts ? LittleEndianU32(counts->data() + 4) : nx;
    if (!two_counts && (nx < 2 || nx > kMaxPosts)) {
      return Fail(ground_at, fmt::format("posts_per_side {} is outside [2, {}]", nx, kMaxPosts));
    }
    for (const auto& [name, n, at] :
         {std::tuple{"posts_x", nx, ground_at}, std::tuple{"posts_z", nz, ground_at + 4}}) {
      if (n < 2 || n > kMaxPosts) {
        return Fail(at, fmt::format("{} {} is outside [2, {}]", name, n, kMaxPosts));
      }
    }
    const uint64_t needed = GroundSectionBytes(layout.version, nx, nz);
    if (layout.ground_bytes != needed) {
      return Fail(kGroundLengthOffset,
                  fmt::format("ground section is {} bytes but a {} x {} grid needs {}",
                              layout.ground_bytes, nx, nz, needed));
    }
    const uint64_t spacing_at = reader_.offset();
    const double spacing_m = std::bit_cast<double>(*ByteReader(*reader_.Take(8)).U64());
    if (!std::isfinite(spacing_m) || spacing_m <= 0.0) {
      return Fail(spacing_at, fmt::format("spacing_m {} must be finite and > 0", spacing_m));
    }
    layout.nx = nx;
    layout.nz = nz;
    layout.spacing_m = spacing_m;
    return Status::Ok();
  }

  // The posts and soils, read on from Shape's end straight into the grid's own storage, a piece
  // at a time.
  Result<HeightGrid> Ground(const FileLayout& layout) {
    const uint32_t nx = layout.nx, nz = layout.nz;
    std::vector<float> posts(static_cast<size_t>(nx) * nz);
    constexpr size_t kPostsPerPiece = kChunkBytes / 4;
    for (size_t k = 0; k < posts.size(); k += kPostsPerPiece) {
      const uint64_t piece_at = reader_.offset();
      const size_t count = std::min(posts.size() - k, kPostsPerPiece);
      const auto piece = reader_.Take(4 * count);
      if (!piece) return Fail(piece_at, "cannot read the posts");
      for (size_t m = 0; m < count; ++m) {
        const float y = std::bit_cast<float>(LittleEndianU32(piece->data() + 4 * m));
        if (!std::isfinite(y)) {
          return Fail(piece_at + 4 * m, fmt::format("post ({}, {}) is not finite ({})",
                                                    (k + m) % nx, (k + m) / nx, y));
        }
        posts[k + m] = y;
      }
    }
    HeightGrid grid(static_cast<int>(nx), static_cast<int>(nz), layout.spacing_m, std::move(posts));
    const size_t squares_x = nx - 1;
    const size_t soil_count = 2 * squares_x * (nz - 1);
    constexpr size_t kSoilsPerPiece = kChunkBytes / 2;
    for (size_t k = 0; k < soil_count; k += kSoilsPerPiece) {
      const uint64_t piece_at = reader_.offset();
      const size_t count = std::min(soil_count - k, kSoilsPerPiece);
      const auto piece = reader_.Take(2 * count);
      if (!piece) return Fail(piece_at, "cannot read the soils");
      for (size_t m = 0; m < count; ++m) {
        const auto raw = static_cast<uint16_t>((*piece)[2 * m] | (*piece)[2 * m + 1] << 8);
        const size_t index = k + m;
        const SquareIndex square{static_cast<int>((index / 2) % squares_x),
                                 static_cast<int>((index / 2) / squares_x)};
        if (!IsValidMaterial(raw) || static_cast<Material>(raw) == Material::kFromGround) {
          return Fail(piece_at + 2 * m, fmt::format("soil {} of square ({}, {}) is not a soil", raw,
                                                    square.i, square.j));
        }
        grid.set_soil(square, static_cast<TriangleHalf>(index % 2), static_cast<Material>(raw));
      }
    }
    return grid;
  }

  // The feature section's records, sorted by ID, each checked and handed to `add` in order; an
  // error of `add` is the record's refusal.
  Status Features(const FileLayout& layout,
                  const std::function<Status(const FeatureId&, const FeatureParams&)>& add) {
    const uint32_t version = layout.version;
    const uint64_t features_at = kTerrainFileHeaderBytes + layout.ground_bytes;
    reader_.Seek(features_at, features_at + layout.feature_bytes);
    auto truncated = [&](std::string_view what) {
      return Fail(reader_.offset(), fmt::format("feature section ends inside {}", what));
    };
    const auto count_bytes = reader_.Take(4);
    if (!count_bytes) return truncated("the feature count");
    const uint32_t count = LittleEndianU32(count_bytes->data());
    FeatureId previous;
    for (uint32_t index = 0; index < count; ++index) {
      const uint64_t record_at = reader_.offset();
      const auto record_header = reader_.Take(12);
      if (!record_header) {
        return truncated(fmt::format("the header of feature record {} of {}", index + 1, count));
      }
      ByteReader fields(*record_header);
      const FeatureId id{*fields.U16(), *fields.U16(), *fields.U32()};
      const uint32_t length = *fields.U32();
      // The origin is the node that created the feature; 0 is no node's site or host (an
      // exercise gives every process a site and host in 1 .. 65535, docs/node.md). Both 0 is the
      // base ground's origin (terrain/base_ground.h): a file exported from an exercise that
      // started on a saved terrain holds that terrain's features under it.
      if ((id.site == 0) != (id.host == 0)) {
        return Fail(id.site == 0 ? record_at : record_at + 2,
                    fmt::format("feature {}: origin {} is 0, which is no node's (a node's site "
                                "and host are 1 .. 65535)",
                                id.ToString(), id.site == 0 ? "site" : "host"));
      }
      if (index > 0 && !(previous < id)) {
        return Fail(record_at, fmt::format("feature {} follows {}: records must be sorted by ID "
                                           "without repeats",
                                           id.ToString(), previous.ToString()));
      }
      previous = id;
      const auto record = reader_.Take(length);
      if (!record) {
        return truncated(fmt::format("feature {} ({} bytes declared)", id.ToString(), length));
      }
      // Version 1 knew craters, berms and bridges only, version 2 no earth moves.
      const auto record_type =
          static_cast<FeatureType>(record->size() >= 2 ? (*record)[0] | (*record)[1] << 8 : 0);
      if (version == 2 && record_type == FeatureType::kEarthMove) {
        return Fail(record_at + 12, fmt::format("feature {}: a version 2 file cannot hold an "
                                                "earth_move",
                                                id.ToString()));
      }
      if (version == 1 && record->size() >= 2 &&
          (HasFeaturePoints(record_type) || record_type == FeatureType::kEarthMove)) {
        return Fail(record_at + 12, fmt::format("feature {}: a version 1 file cannot hold a {}",
                                                id.ToString(), FeatureTypeName(record_type)));
      }
      ByteReader params_reader(*record);
      auto params = DecodeFeatureParams(params_reader);
      const uint64_t params_at = record_at + 12;
      if (!params) {
        return Fail(params_at, fmt::format("feature {}: {} (offsets within the record)",
                                           id.ToString(), params.error().message));
      }
      // ... and craters at the ground.
      if (version == 1 && params.value().type == FeatureType::kCrater &&
          params.value().height_m[0] != 0.0) {
        return Fail(params_at, fmt::format("feature {}: a version 1 file cannot hold a crater "
                                           "below the ground",
                                           id.ToString()));
      }
      if (params_reader.remaining() != 0) {
        return Fail(params_at + params_reader.offset(),
                    fmt::format("feature {}: {} bytes left over after its parameters",
                                id.ToString(), params_reader.remaining()));
      }
      if (auto added = add(id, params.value()); !added) {
        return Fail(record_at, fmt::format("feature {} was refused: {}", id.ToString(),
                                           added.error().message));
      }
    }
    if (reader_.remaining() != 0) {
      return Fail(reader_.offset(),
                  fmt::format("{} bytes left over after the last feature", reader_.remaining()));
    }
    return Status::Ok();
  }

 private:
  FileReader& reader_;
  std::string source_name_;  // a copy: callers pass temporaries (path.string())
};

// DecodeTerrainFile and LoadTerrain: the checksum over the whole file first, then the sections.
Result<std::unique_ptr<Terrain>> DecodeTerrain(FileReader& reader, std::string_view source_name) {
  TerrainDecoder decoder(reader, source_name);
  FileLayout layout;
  if (Status s = decoder.Header(layout); !s) return s.error();
  if (Status s = decoder.Checksum(); !s) return s.error();
  if (Status s = decoder.Shape(layout); !s) return s.error();
  Result<HeightGrid> grid = decoder.Ground(layout);
  if (!grid) return grid.error();
  // Feature section: records sorted by ID, each rebuilt through Terrain::Add.
  auto terrain = std::make_unique<Terrain>(std::move(grid.value()));
  const Status features = decoder.Features(
      layout,
      [&](const FeatureId& id, const FeatureParams& params) { return terrain->Add(id, params); });
  if (!features) return features.error();
  return terrain;
}

}  // namespace

Result<std::unique_ptr<Terrain>> DecodeTerrainFile(std::span<const uint8_t> bytes,
                                                   std::string_view source_name) {
  FileReader reader(bytes);
  return DecodeTerrain(reader, source_name);
}

Result<std::unique_ptr<Terrain>> LoadTerrain(const fs::path& path) {
  auto file = RegularFile::Open(path, kMaxTerrainFileBytes);
  if (!file) return file.error();
  FileReader reader(file.value());
  return DecodeTerrain(reader, path.string());
}

namespace {

// Opens the terrain file at `path`, reads its header and shape, then hands the reader, the decoder
// and the layout to `then` (the part of the file it reads is its own), returning what `then`
// returns. A file refused before that: its error.
template <typename Then>
auto WithFileShape(const fs::path& path, Then&& then)
    -> decltype(then(std::declval<FileReader&>(), std::declval<TerrainDecoder&>(),
                     std::declval<const FileLayout&>())) {
  auto file = RegularFile::Open(path, kMaxTerrainFileBytes);
  if (!file) return file.error();
  FileReader reader(file.value());
  TerrainDecoder decoder(reader, path.string());
  FileLayout layout;
  if (Status s = decoder.Header(layout); !s) return s.error();
  if (Status s = decoder.Shape(layout); !s) return s.error();
  return then(reader, decoder, layout);
}

}  // namespace

Result<TerrainFileShape> ProbeTerrainFile(const fs::path& path) {
  return WithFileShape(path,
                       [](FileReader& reader, TerrainDecoder& decoder,
                          const FileLayout& layout) -> Result<TerrainFileShape> {
                         const Result<uint64_t> checksum = decoder.StoredChecksum();
                         if (!checksum) return checksum.error();
                         return TerrainFileShape{layout.version,
                                                 static_cast<int>(layout.nx),
                                                 static_cast<int>(layout.nz),
                                                 layout.spacing_m,
                                                 reader.size(),
                                                 checksum.value()};
                       });
}

Result<std::vector<std::pair<FeatureId, FeatureParams>>> LoadTerrainFileFeatures(
    const fs::path& path) {
  using Features = std::vector<std::pair<FeatureId, FeatureParams>>;
  return WithFileShape(
      path, [](FileReader&, TerrainDecoder& decoder, const FileLayout& layout) -> Result<Features> {
        Features features;
        const Status read = decoder.Features(
            layout, [&](const FeatureId& id, const FeatureParams& params) -> Status {
              features.emplace_back(id, params);
              return Status::Ok();
            });
        if (!read) return read.error();
        return features;
      });
}

}  // namespace dt
