#include "terrain/terrain_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

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
constexpr int kMaxPosts = kMaxGridPostsPerSide;  // HeightGrid's limit
// Files are read and written in pieces of this size: a ground of 10^8 posts never has a second
// copy in memory, and a piece stays well inside the caches.
constexpr size_t kChunkBytes = size_t{1} << 20;

// Bytes of a ground section: the post counts (one for a square grid up to version 3, two from
// version 4), spacing, posts, two soils per square.
uint64_t GroundSectionBytes(uint32_t version, uint64_t nx, uint64_t nz) {
  const uint64_t counts = version >= 4 ? 8 : 4;
  return counts + 8 + 4 * nx * nz + 2 * 2 * (nx - 1) * (nz - 1);
}

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

// Where a terrain file's bytes go: a vector (EncodeTerrainFile) or an open file, through a buffer
// of kChunkBytes (SaveTerrain). Hashes them on the way for the checksum. A write error is kept
// and ends the writing; status() reports it.
class FileWriter {
 public:
  explicit FileWriter(std::vector<uint8_t>& out) : out_(&out) { Reset(); }
  FileWriter(int fd, std::string name) : fd_(fd), name_(std::move(name)) {
    buffer_.reserve(kChunkBytes);
    Reset();
  }

  void Bytes(std::span<const uint8_t> data) {
    XXH3_64bits_update(state_.get(), data.data(), data.size());
    Put(data);
  }
  void U32(uint32_t v) { Little(v, 4); }
  void U64(uint64_t v) { Little(v, 8); }
  // The checksum of every byte so far, written as the file's last 8 bytes; then flushes.
  void Finish() {
    const uint64_t checksum = XXH3_64bits_digest(state_.get());
    ByteWriter tail;
    tail.U64(checksum);
    Put(tail.bytes());
    Flush();
  }
  const Status& status() const { return status_; }

 private:
  void Reset() {
    state_.reset(XXH3_createState());
    XXH3_64bits_reset(state_.get());
  }
  void Little(uint64_t v, int width) {
    std::array<uint8_t, 8> b{};
    for (int i = 0; i < width; ++i) b[static_cast<size_t>(i)] = static_cast<uint8_t>(v >> (8 * i));
    Bytes(std::span<const uint8_t>(b.data(), static_cast<size_t>(width)));
  }
  void Put(std::span<const uint8_t> data) {
    if (out_ != nullptr) {
      out_->insert(out_->end(), data.begin(), data.end());
      return;
    }
    if (buffer_.size() + data.size() > kChunkBytes) Flush();
    if (data.size() >= kChunkBytes) {
      WriteAll(data);
    } else {
      buffer_.insert(buffer_.end(), data.begin(), data.end());
    }
  }
  void Flush() {
    if (out_ == nullptr && !buffer_.empty()) WriteAll(buffer_);
    buffer_.clear();
  }
  void WriteAll(std::span<const uint8_t> data) {
    size_t written = 0;
    while (status_ && written < data.size()) {
      const ssize_t w = ::write(fd_, data.data() + written, data.size() - written);
      if (w < 0) {
        if (errno == EINTR) continue;
        status_ = Error{fmt::format("{}: write failed: {}", name_, std::strerror(errno))};
        return;
      }
      written += static_cast<size_t>(w);
    }
  }

  std::vector<uint8_t>* out_ = nullptr;
  int fd_ = -1;
  std::string name_;
  std::vector<uint8_t> buffer_;
  std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> state_{nullptr, &XXH3_freeState};
  Status status_ = Status::Ok();
};

// A terrain's file, sized before a byte is written (the header holds the section lengths and the
// checksum runs from the first byte): the features are encoded once to count their bytes and
// again as they are written, so neither the ground nor the feature section is held whole.
class TerrainFileLayout {
 public:
  explicit TerrainFileLayout(const Terrain& terrain)
      : terrain_(terrain),
        version_(terrain.ground().is_square() ? kSquareTerrainFileVersion : kTerrainFileVersion),
        features_(terrain.FeaturesById()) {
    const HeightGrid& g = terrain.ground();
    ground_bytes_ = GroundSectionBytes(version_, static_cast<uint64_t>(g.posts_x()),
                                       static_cast<uint64_t>(g.posts_z()));
    feature_bytes_ = 4;
    ByteWriter record;
    for (const Feature* f : features_) {
      record.bytes().clear();
      EncodeFeatureParams(f->params(), record);
      feature_bytes_ += 12 + record.bytes().size();
    }
  }

  uint64_t file_bytes() const {
    return kTerrainFileHeaderBytes + ground_bytes_ + feature_bytes_ + kTerrainFileChecksumBytes;
  }

  void Write(FileWriter& out) const {
    const HeightGrid& g = terrain_.ground();
    out.Bytes(kMagic);
    out.U32(version_);
    out.U64(ground_bytes_);
    out.U64(feature_bytes_);
    out.U32(static_cast<uint32_t>(g.posts_x()));
    if (version_ >= 4) out.U32(static_cast<uint32_t>(g.posts_z()));
    out.U64(std::bit_cast<uint64_t>(g.spacing_m()));
    // The posts without blade work, a piece at a time: the earth moves among the features add it
    // back on loading.
    const std::vector<std::pair<uint32_t, float>> bare = terrain_.BladeBarePosts();
    auto next_bare = bare.begin();
    const std::span<const float> posts = g.posts();
    ByteWriter piece;
    constexpr size_t kPostsPerPiece = kChunkBytes / 4;
    for (size_t k = 0; k < posts.size() && out.status(); k += kPostsPerPiece) {
      const size_t end = std::min(posts.size(), k + kPostsPerPiece);
      piece.bytes().clear();
      for (size_t m = k; m < end; ++m) {
        float y = posts[m];
        if (next_bare != bare.end() && next_bare->first == m) y = (next_bare++)->second;
        piece.F32(y);
      }
      out.Bytes(piece.bytes());
    }
    const std::span<const Material> soils = g.soils();
    constexpr size_t kSoilsPerPiece = kChunkBytes / 2;
    for (size_t k = 0; k < soils.size() && out.status(); k += kSoilsPerPiece) {
      const size_t end = std::min(soils.size(), k + kSoilsPerPiece);
      piece.bytes().clear();
      for (size_t m = k; m < end; ++m) piece.U16(static_cast<uint16_t>(soils[m]));
      out.Bytes(piece.bytes());
    }
    out.U32(static_cast<uint32_t>(features_.size()));
    ByteWriter record;
    for (const Feature* f : features_) {
      if (!out.status()) break;
      record.bytes().clear();
      record.U16(f->id().site);
      record.U16(f->id().host);
      record.U32(f->id().number);
      record.U32(0);  // the parameters' length, set below once they are encoded
      EncodeFeatureParams(f->params(), record);
      const auto length = static_cast<uint32_t>(record.bytes().size() - 12);
      for (size_t i = 0; i < 4; ++i)
        record.bytes()[8 + i] = static_cast<uint8_t>(length >> (8 * i));
      out.Bytes(record.bytes());
    }
    out.Finish();
  }

 private:
  const Terrain& terrain_;
  uint32_t version_;
  std::vector<const Feature*> features_;
  uint64_t ground_bytes_ = 0;
  uint64_t feature_bytes_ = 0;
};

// DecodeTerrainFile and LoadTerrain: the checksum over the whole file first, then the sections.
Result<std::unique_ptr<Terrain>> DecodeTerrain(FileReader& reader, std::string_view source_name) {
  // A read error of the file (it shrank, the disk failed) is named in place of what was checked.
  auto fail = [&](uint64_t offset, const std::string& what) -> Error {
    if (reader.io_error()) return Error{reader.io_error()->message};
    return Error{fmt::format("{}: byte {}: {}", source_name, offset, what)};
  };
  const uint64_t file_bytes = reader.size();
  constexpr size_t kMinBytes = kTerrainFileHeaderBytes + kTerrainFileChecksumBytes;
  if (file_bytes < kMinBytes) {
    return fail(file_bytes, fmt::format("file is {} bytes, shorter than the {}-byte header and "
                                        "checksum (truncated?)",
                                        file_bytes, kMinBytes));
  }
  reader.Seek(0, file_bytes);
  const auto head = reader.Take(kTerrainFileHeaderBytes);
  if (!head) return fail(0, "cannot read the header");
  if (!std::equal(kMagic.begin(), kMagic.end(), head->begin())) {
    return fail(0, "not a dynterrain terrain file (wrong magic)");
  }
  ByteReader header(head->subspan(kVersionOffset));
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
  const uint64_t body = file_bytes - kMinBytes;
  if (ground_bytes > body || feature_bytes > body - ground_bytes ||
      ground_bytes + feature_bytes != body) {
    return fail(kGroundLengthOffset,
                fmt::format("header declares a {}-byte ground section and a {}-byte feature "
                            "section, which does not match the file size of {} bytes (truncated "
                            "or extended?)",
                            ground_bytes, feature_bytes, file_bytes));
  }
  const uint64_t checksum_at = file_bytes - kTerrainFileChecksumBytes;
  const std::optional<uint64_t> computed = reader.Checksum(checksum_at);
  reader.Seek(checksum_at, file_bytes);
  const auto stored_bytes = reader.Take(kTerrainFileChecksumBytes);
  if (!computed || !stored_bytes) return fail(checksum_at, "cannot read the file");
  const uint64_t stored = *ByteReader(*stored_bytes).U64();
  if (stored != *computed) {
    return fail(checksum_at, fmt::format("checksum mismatch: stored {:016x}, computed {:016x} "
                                         "(the file is corrupt)",
                                         stored, *computed));
  }

  // Ground section. Offsets in messages are from the start of the file.
  const uint64_t ground_at = kTerrainFileHeaderBytes;
  reader.Seek(ground_at, ground_at + ground_bytes);
  // Up to version 3 the grid is square: one count. From version 4, posts along x then along z.
  const bool two_counts = version >= 4;
  const auto counts = reader.Take(two_counts ? 8 : 4);
  if (!counts) {
    return fail(kGroundLengthOffset,
                fmt::format("ground section is {} bytes, too short to hold a grid", ground_bytes));
  }
  const uint32_t nx = LittleEndianU32(counts->data());
  const uint32_t nz = two_counts ? LittleEndianU32(counts->data() + 4) : nx;
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
  const uint64_t spacing_at = reader.offset();
  const double spacing_m = std::bit_cast<double>(*ByteReader(*reader.Take(8)).U64());
  if (!std::isfinite(spacing_m) || spacing_m <= 0.0) {
    return fail(spacing_at, fmt::format("spacing_m {} must be finite and > 0", spacing_m));
  }
  // The posts straight into the grid's own vector and the soils into its own, a piece at a time.
  std::vector<float> posts(static_cast<size_t>(nx) * nz);
  constexpr size_t kPostsPerPiece = kChunkBytes / 4;
  for (size_t k = 0; k < posts.size(); k += kPostsPerPiece) {
    const uint64_t piece_at = reader.offset();
    const size_t count = std::min(posts.size() - k, kPostsPerPiece);
    const auto piece = reader.Take(4 * count);
    if (!piece) return fail(piece_at, "cannot read the posts");
    for (size_t m = 0; m < count; ++m) {
      const float y = std::bit_cast<float>(LittleEndianU32(piece->data() + 4 * m));
      if (!std::isfinite(y)) {
        return fail(piece_at + 4 * m,
                    fmt::format("post ({}, {}) is not finite ({})", (k + m) % nx, (k + m) / nx, y));
      }
      posts[k + m] = y;
    }
  }
  HeightGrid grid(static_cast<int>(nx), static_cast<int>(nz), spacing_m, std::move(posts));
  const size_t squares_x = nx - 1;
  const size_t soil_count = 2 * squares_x * (nz - 1);
  constexpr size_t kSoilsPerPiece = kChunkBytes / 2;
  for (size_t k = 0; k < soil_count; k += kSoilsPerPiece) {
    const uint64_t piece_at = reader.offset();
    const size_t count = std::min(soil_count - k, kSoilsPerPiece);
    const auto piece = reader.Take(2 * count);
    if (!piece) return fail(piece_at, "cannot read the soils");
    for (size_t m = 0; m < count; ++m) {
      const auto raw = static_cast<uint16_t>((*piece)[2 * m] | (*piece)[2 * m + 1] << 8);
      const size_t index = k + m;
      const SquareIndex square{static_cast<int>((index / 2) % squares_x),
                               static_cast<int>((index / 2) / squares_x)};
      if (!IsValidMaterial(raw) || static_cast<Material>(raw) == Material::kFromGround) {
        return fail(piece_at + 2 * m, fmt::format("soil {} of square ({}, {}) is not a soil", raw,
                                                  square.i, square.j));
      }
      grid.set_soil(square, static_cast<TriangleHalf>(index % 2), static_cast<Material>(raw));
    }
  }

  // Feature section: records sorted by ID, each rebuilt through Terrain::Add.
  auto terrain = std::make_unique<Terrain>(std::move(grid));
  const uint64_t features_at = ground_at + ground_bytes;
  reader.Seek(features_at, features_at + feature_bytes);
  auto truncated = [&](std::string_view what) {
    return fail(reader.offset(), fmt::format("feature section ends inside {}", what));
  };
  const auto count_bytes = reader.Take(4);
  if (!count_bytes) return truncated("the feature count");
  const uint32_t count = LittleEndianU32(count_bytes->data());
  FeatureId previous;
  for (uint32_t index = 0; index < count; ++index) {
    const uint64_t record_at = reader.offset();
    const auto record_header = reader.Take(12);
    if (!record_header) {
      return truncated(fmt::format("the header of feature record {} of {}", index + 1, count));
    }
    ByteReader fields(*record_header);
    const FeatureId id{*fields.U16(), *fields.U16(), *fields.U32()};
    const uint32_t length = *fields.U32();
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
    const auto record = reader.Take(length);
    if (!record) {
      return truncated(fmt::format("feature {} ({} bytes declared)", id.ToString(), length));
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
      return fail(record_at + 12, fmt::format("feature {}: a version 1 file cannot hold a {}",
                                              id.ToString(), FeatureTypeName(record_type)));
    }
    ByteReader params_reader(*record);
    auto params = DecodeFeatureParams(params_reader);
    const uint64_t params_at = record_at + 12;
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
  if (reader.remaining() != 0) {
    return fail(reader.offset(),
                fmt::format("{} bytes left over after the last feature", reader.remaining()));
  }
  return terrain;
}

}  // namespace

std::vector<uint8_t> EncodeTerrainFile(const Terrain& terrain) {
  const TerrainFileLayout layout(terrain);
  std::vector<uint8_t> bytes;
  bytes.reserve(static_cast<size_t>(layout.file_bytes()));
  FileWriter out(bytes);
  layout.Write(out);
  return bytes;
}

Result<std::unique_ptr<Terrain>> DecodeTerrainFile(std::span<const uint8_t> bytes,
                                                   std::string_view source_name) {
  FileReader reader(bytes);
  return DecodeTerrain(reader, source_name);
}

Status SaveTerrain(const Terrain& terrain, const fs::path& path) {
  // Renaming over a FIFO or device would replace it with a regular file; a directory fails late.
  if (auto s = CheckReplaceableFile(path); !s) return s;
  const TerrainFileLayout layout(terrain);
  if (layout.file_bytes() > kMaxTerrainFileBytes) {
    return Error{
        fmt::format("{}: the terrain file would be {} bytes, over the {}-byte limit that "
                    "readers accept",
                    path.string(), layout.file_bytes(), kMaxTerrainFileBytes)};
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
  FileWriter out(fd, temp);
  layout.Write(out);
  if (!out.status()) {
    ::close(fd);
    ::unlink(temp.c_str());
    return Error{fmt::format("{}: {}", path.string(), out.status().error().message)};
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
  auto file = RegularFile::Open(path, kMaxTerrainFileBytes);
  if (!file) return file.error();
  FileReader reader(file.value());
  return DecodeTerrain(reader, path.string());
}

}  // namespace dt
