#include "terrain/ground_cache.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <xxhash.h>

#include "base/bytes.h"
#include "base/demand.h"
#include "base/mapped_memory.h"
#include "terrain/terrain_digest.h"

namespace dt {
namespace {

constexpr char kMagic[8] = {'D', 'T', 'G', 'R', 'O', 'U', 'N', 'D'};
constexpr size_t kPage = 4096;

size_t RoundUpToPage(size_t n) { return (n + kPage - 1) / kPage * kPage; }

struct Header {
  uint32_t version = 0;
  uint32_t posts_x = 0;
  uint32_t posts_z = 0;
  double spacing_m = 0.0;
  XXH128_hash_t key{};
  XXH128_hash_t payload{};
  TerrainDigest digest;
  uint64_t posts_offset = 0;
  uint64_t soils_offset = 0;
  uint64_t file_size = 0;
};

std::vector<uint8_t> EncodeHeader(const Header& h) {
  ByteWriter w;
  for (char c : kMagic) w.U8(static_cast<uint8_t>(c));
  w.U32(h.version);
  w.U32(h.posts_x);
  w.U32(h.posts_z);
  w.F64(h.spacing_m);
  for (const XXH128_hash_t& x : {h.key, h.payload}) {
    w.U64(x.high64);
    w.U64(x.low64);
  }
  w.U64(h.digest.high);
  w.U64(h.digest.low);
  w.U64(h.posts_offset);
  w.U64(h.soils_offset);
  w.U64(h.file_size);
  std::vector<uint8_t> bytes = w.bytes();
  DT_DEMAND(bytes.size() <= kGroundCacheHeaderBytes);
  bytes.resize(kGroundCacheHeaderBytes, 0);
  return bytes;
}

// The header is read from the file's first kGroundCacheHeaderBytes, which the caller checked are
// there: every field is in place.
std::optional<Header> DecodeHeader(const std::byte* data) {
  ByteReader r(
      std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(data), kGroundCacheHeaderBytes));
  for (char c : kMagic) {
    if (r.U8().value_or(0) != static_cast<uint8_t>(c)) return std::nullopt;
  }
  Header h;
  h.version = r.U32().value_or(0);
  h.posts_x = r.U32().value_or(0);
  h.posts_z = r.U32().value_or(0);
  h.spacing_m = r.F64().value_or(0.0);
  for (XXH128_hash_t* x : {&h.key, &h.payload}) {
    x->high64 = r.U64().value_or(0);
    x->low64 = r.U64().value_or(0);
  }
  h.digest.high = r.U64().value_or(0);
  h.digest.low = r.U64().value_or(0);
  h.posts_offset = r.U64().value_or(0);
  h.soils_offset = r.U64().value_or(0);
  h.file_size = r.U64().value_or(0);
  return h;
}

std::runtime_error Errno(std::string_view what, const std::filesystem::path& path) {
  return std::runtime_error(
      fmt::format("ground cache: {} {}: {}", what, path.string(), std::strerror(errno)));
}

class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() {
    if (fd_ >= 0) close(fd_);
  }
  int get() const { return fd_; }
  int release() { return std::exchange(fd_, -1); }

 private:
  int fd_;
};

void WriteAll(int fd, const void* data, size_t n, const std::filesystem::path& path) {
  const auto* p = static_cast<const uint8_t*>(data);
  while (n > 0) {
    const ssize_t w = write(fd, p, std::min<size_t>(n, size_t{1} << 26));
    if (w < 0) {
      if (errno == EINTR) continue;
      throw Errno("writing", path);
    }
    p += w;
    n -= static_cast<size_t>(w);
  }
}

// Opens and checks the file; nullopt with the reason in *why if it is absent or fails a check.
std::optional<HeightGrid> TryOpen(const std::filesystem::path& path, const XXH128_hash_t& key,
                                  std::string* why) {
  Fd fd(open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) {
    if (errno != ENOENT) throw Errno("opening", path);
    *why = "absent";
    return std::nullopt;
  }
  struct stat st {};
  if (fstat(fd.get(), &st) != 0) throw Errno("reading the size of", path);
  const auto size = static_cast<size_t>(st.st_size);
  if (size < kGroundCacheHeaderBytes) {
    *why = fmt::format("{} bytes, shorter than its header", size);
    return std::nullopt;
  }
  Result<MappedMemory> map = MappedMemory::MapFilePrivate(fd.get(), size);
  if (!map)
    throw std::runtime_error(
        fmt::format("ground cache: {}: {}", path.string(), map.error().message));
  const std::optional<Header> h = DecodeHeader(map.value().data());
  if (!h || h->version != kGroundCacheVersion) {
    *why = "not a ground cache file of this version";
    return std::nullopt;
  }
  if (!XXH128_isEqual(h->key, key)) {
    *why = "built for another key";
    return std::nullopt;
  }
  const uint64_t posts = uint64_t{h->posts_x} * h->posts_z;
  const uint64_t soils =
      h->posts_x < 2 || h->posts_z < 2 ? 0 : uint64_t{h->posts_x - 1} * (h->posts_z - 1) * 2;
  const uint64_t soils_offset = RoundUpToPage(kGroundCacheHeaderBytes + posts * sizeof(float));
  if (h->posts_offset != kGroundCacheHeaderBytes || h->soils_offset != soils_offset ||
      h->file_size != soils_offset + soils * sizeof(Material) || h->file_size != size) {
    *why = fmt::format("{} bytes, not the {} its header's {} x {} posts take", size,
                       soils_offset + soils * sizeof(Material), h->posts_x, h->posts_z);
    return std::nullopt;
  }
  const XXH128_hash_t payload =
      XXH3_128bits(map.value().data() + kGroundCacheHeaderBytes, size - kGroundCacheHeaderBytes);
  if (!XXH128_isEqual(payload, h->payload)) {
    *why = "its contents do not match the hash in its header";
    return std::nullopt;
  }
  // Marks the file used, so pruning takes the ones nobody opens; best effort (another user's
  // file may not be ours to touch).
  (void)futimens(fd.get(), nullptr);
  auto source = std::make_shared<GroundFileSource>();
  source->fd = fd.release();
  source->file_size = size;
  source->posts_offset = h->posts_offset;
  source->soils_offset = h->soils_offset;
  return HeightGrid::Mapped(static_cast<int>(h->posts_x), static_cast<int>(h->posts_z),
                            h->spacing_m, std::move(source));
}

void Write(const std::filesystem::path& path, const XXH128_hash_t& key, const HeightGrid& g) {
  const std::filesystem::path tmp = path.string() + fmt::format(".tmp.{}", getpid());
  Fd fd(open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
  if (fd.get() < 0) throw Errno("creating", tmp);
  try {
    Header h;
    h.version = kGroundCacheVersion;
    h.posts_x = static_cast<uint32_t>(g.posts_x());
    h.posts_z = static_cast<uint32_t>(g.posts_z());
    h.spacing_m = g.spacing_m();
    h.key = key;
    h.digest = ComputeDigest(g);
    h.posts_offset = kGroundCacheHeaderBytes;
    const size_t posts_bytes = g.post_count() * sizeof(float);
    h.soils_offset = RoundUpToPage(kGroundCacheHeaderBytes + posts_bytes);
    h.file_size = h.soils_offset + g.soils().size() * sizeof(Material);
    static_assert(std::endian::native == std::endian::little, "the file is little-endian");
    const std::vector<uint8_t> pad(h.soils_offset - kGroundCacheHeaderBytes - posts_bytes, 0);
    std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> state(XXH3_createState(),
                                                                   &XXH3_freeState);
    DT_DEMAND(state && XXH3_128bits_reset(state.get()) == XXH_OK);
    DT_DEMAND(XXH3_128bits_update(state.get(), g.posts().data(), posts_bytes) == XXH_OK);
    DT_DEMAND(XXH3_128bits_update(state.get(), pad.data(), pad.size()) == XXH_OK);
    DT_DEMAND(XXH3_128bits_update(state.get(), g.soils().data(),
                                  g.soils().size() * sizeof(Material)) == XXH_OK);
    h.payload = XXH3_128bits_digest(state.get());
    const std::vector<uint8_t> header = EncodeHeader(h);
    WriteAll(fd.get(), header.data(), header.size(), tmp);
    WriteAll(fd.get(), g.posts().data(), posts_bytes, tmp);
    WriteAll(fd.get(), pad.data(), pad.size(), tmp);
    WriteAll(fd.get(), g.soils().data(), g.soils().size() * sizeof(Material), tmp);
    if (fsync(fd.get()) != 0) throw Errno("syncing", tmp);
    if (rename(tmp.c_str(), path.c_str()) != 0) throw Errno("renaming into place", tmp);
  } catch (...) {
    unlink(tmp.c_str());
    throw;
  }
}

// This user's cache files in `dir` other than `keep`, by last use; pruned by age (temp files
// of builds that died too), then by the budget, oldest first. A file whose lock another process
// holds is being rebuilt and stays.
std::vector<std::string> Prune(const std::filesystem::path& dir, const std::filesystem::path& keep,
                               const GroundCachePruning& pruning) {
  struct Found {
    std::filesystem::path path;
    int64_t used_s;  // modification time, seconds since the epoch
    uint64_t bytes;
    bool temp;
  };
  std::vector<Found> found;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with("ground-") || entry.path() == keep) continue;
    const bool dtg = name.ends_with(".dtg");
    const bool temp = name.find(".dtg.tmp.") != std::string::npos;
    if (!dtg && !temp) continue;
    struct stat st {};
    if (lstat(entry.path().c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_uid != getuid()) {
      continue;
    }
    found.push_back(
        {entry.path(), static_cast<int64_t>(st.st_mtime), static_cast<uint64_t>(st.st_size), temp});
  }
  std::sort(found.begin(), found.end(),
            [](const Found& a, const Found& b) { return a.used_s < b.used_s; });
  const int64_t now_s = std::chrono::duration_cast<std::chrono::seconds>(
                            std::chrono::system_clock::now().time_since_epoch())
                            .count();
  struct stat kept {};
  uint64_t total = stat(keep.c_str(), &kept) == 0 ? static_cast<uint64_t>(kept.st_size) : 0;
  for (const Found& f : found) {
    if (!f.temp) total += f.bytes;
  }
  std::vector<std::string> removed;
  auto remove = [&](const Found& f, std::string why) {
    if (f.temp) {
      if (unlink(f.path.c_str()) == 0)
        removed.push_back(fmt::format("{} ({})", f.path.string(), why));
      return;
    }
    // Under the file's own lock, taken without waiting: a process holding it is rebuilding the
    // file and would rename its new one into place, which must not be removed; so it is skipped.
    const std::filesystem::path lock_path = f.path.string() + ".lock";
    Fd lock(open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644));
    if (lock.get() < 0 || flock(lock.get(), LOCK_EX | LOCK_NB) != 0) return;
    if (unlink(f.path.c_str()) != 0) return;
    unlink(lock_path.c_str());
    total -= f.bytes;
    removed.push_back(fmt::format("{} ({})", f.path.string(), why));
  };
  const int64_t max_age_s = int64_t{pruning.max_age_days} * 86400;
  std::vector<const Found*> left;
  for (const Found& f : found) {
    if (now_s - f.used_s > max_age_s) {
      remove(f, fmt::format("unused for {} days", (now_s - f.used_s) / 86400));
    } else if (!f.temp) {
      left.push_back(&f);
    }
  }
  for (const Found* f : left) {
    if (total <= pruning.budget_bytes) break;
    remove(*f, fmt::format("this user's cache files take {} bytes, over the budget of {}", total,
                           pruning.budget_bytes));
  }
  return removed;
}

}  // namespace

std::filesystem::path GroundCacheFile(const std::filesystem::path& dir, std::string_view key) {
  const XXH128_hash_t h = XXH3_128bits(key.data(), key.size());
  return dir / fmt::format("ground-{:016x}{:016x}.dtg", h.high64, h.low64);
}

GroundCacheOpened OpenGroundCache(const std::filesystem::path& dir, std::string_view key,
                                  const std::function<HeightGrid()>& build,
                                  const GroundCachePruning& pruning) {
  const XXH128_hash_t key_hash = XXH3_128bits(key.data(), key.size());
  GroundCacheOpened out{HeightGrid(2, 1.0), GroundCacheFile(dir, key), false, "", {}};
  std::string why;
  // Without the lock first: a whole file is there once renamed into place.
  if (std::optional<HeightGrid> g = TryOpen(out.file, key_hash, &why)) {
    out.grid = std::move(*g);
    return out;
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    throw std::runtime_error(
        fmt::format("ground cache: creating {}: {}", dir.string(), ec.message()));
  }
  const std::filesystem::path lock_path = out.file.string() + ".lock";
  Fd lock(open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644));
  if (lock.get() < 0) throw Errno("creating", lock_path);
  while (flock(lock.get(), LOCK_EX) != 0) {
    if (errno != EINTR) throw Errno("locking", lock_path);
  }
  // Another process may have built it while this one waited.
  if (std::optional<HeightGrid> g = TryOpen(out.file, key_hash, &why)) {
    out.grid = std::move(*g);
    return out;
  }
  out.build_reason = why;
  Write(out.file, key_hash, build());
  out.built = true;
  std::optional<HeightGrid> g = TryOpen(out.file, key_hash, &why);
  if (!g) {
    throw std::runtime_error(fmt::format(
        "ground cache: {} fails its checks just after it was written: {}", out.file.string(), why));
  }
  out.grid = std::move(*g);
  // Still under the lock: no other process of this key builds meanwhile.
  out.removed = Prune(dir, out.file, pruning);
  return out;
}

}  // namespace dt
