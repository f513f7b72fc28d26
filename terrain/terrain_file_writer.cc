// SaveTerrain and EncodeTerrainFile: the writing half of terrain/terrain_file.h.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <xxhash.h>

#include "base/bytes.h"
#include "base/regular_file.h"
#include "terrain/terrain_file.h"
#include "terrain/terrain_file_format.h"

namespace dt {
namespace {

namespace fs = std::filesystem;
using namespace terrain_file_format;

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

}  // namespace

std::vector<uint8_t> EncodeTerrainFile(const Terrain& terrain) {
  const TerrainFileLayout layout(terrain);
  std::vector<uint8_t> bytes;
  bytes.reserve(static_cast<size_t>(layout.file_bytes()));
  FileWriter out(bytes);
  layout.Write(out);
  return bytes;
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

}  // namespace dt
