#include "view/relief_tiles.h"

#include <chrono>

#include "log/log.h"

namespace dt {

ReliefTiles::ReliefTiles(const HeightGrid& ground, size_t cache_bytes)
    : pyramid_(ground.size_x_m(), ground.size_z_m(), ground.spacing_m()),
      elevation_range_m_(SampledElevationRange(ground, pyramid_)),
      cache_(cache_bytes),
      thread_([this] { Run(); }) {}

ReliefTiles::~ReliefTiles() { Stop(); }

void ReliefTiles::Stop() {
  {
    std::lock_guard lock(mu_);
    stop_ = true;
  }
  work_.notify_all();
  done_.notify_all();
  if (thread_.joinable()) thread_.join();
}

int64_t ReliefTiles::VersionLocked(const TileKey& key) const {
  auto it = versions_.find(key);
  return it == versions_.end() ? epoch_ : it->second;
}

int64_t ReliefTiles::Version(const TileKey& key) const {
  std::lock_guard lock(mu_);
  return VersionLocked(key);
}

nlohmann::json ReliefTiles::Track(const Terrain& terrain) {
  const uint64_t stamp = terrain.stamp();
  if (stamp == seen_stamp_) return nullptr;
  const auto areas = terrain.ChangedAreasSince(seen_stamp_);
  seen_stamp_ = stamp;
  std::set<TileKey> touched;
  if (areas) {
    for (const Rect& a : *areas) {
      for (const TileKey& k : pyramid_.TilesChangedBy(a)) touched.insert(k);
    }
    if (touched.empty()) return nullptr;
  }
  std::lock_guard lock(mu_);
  ++generation_;
  nlohmann::json versions = nlohmann::json::object();
  if (!areas) {
    epoch_ = generation_;
    versions_.clear();
  }
  for (const TileKey& k : touched) {
    versions_[k] = generation_;
    versions[k.ToString()] = generation_;
  }
  return {{"type", "relief_tiles"}, {"epoch", epoch_}, {"versions", std::move(versions)}};
}

nlohmann::json ReliefTiles::Describe() const {
  std::lock_guard lock(mu_);
  nlohmann::json versions = nlohmann::json::object();
  for (const auto& [k, v] : versions_) versions[k.ToString()] = v;
  return {{"levels", pyramid_.levels()},
          {"tile_px", ReliefPyramid::kTilePx},
          {"side_m", pyramid_.side_m(0)},
          {"epoch", epoch_},
          {"versions", std::move(versions)}};
}

void ReliefTiles::Serve(const Terrain& terrain, size_t max) {
  std::vector<std::pair<TileKey, int64_t>> take;
  {
    std::lock_guard lock(mu_);
    while (take.size() < max && !wanted_.empty()) {
      const TileKey k = wanted_.front();
      wanted_.pop_front();
      wanted_set_.erase(k);
      const int64_t v = VersionLocked(k);
      in_flight_[k] = v;
      take.emplace_back(k, v);
    }
  }
  if (take.empty()) return;
  std::deque<ReliefTileJob> jobs;
  for (const auto& [k, v] : take)
    jobs.push_back(SampleReliefTile(terrain, pyramid_, k, v, elevation_range_m_));
  {
    std::lock_guard lock(mu_);
    for (ReliefTileJob& j : jobs) jobs_.push_back(std::move(j));
  }
  work_.notify_one();
}

ReliefTiles::Answer ReliefTiles::Get(const TileKey& key, int timeout_ms) {
  std::unique_lock lock(mu_);
  if (broken_) return {503, nullptr, "the relief cannot be drawn (no OSMesa context)"};
  if (stop_) return {503, nullptr, "the view is stopping"};
  const int64_t version = VersionLocked(key);
  const ReliefTileCache::Tile* tile = cache_.Find(key);
  if (tile == nullptr || tile->version < version) {
    auto flying = in_flight_.find(key);
    const bool coming =
        wanted_set_.contains(key) || (flying != in_flight_.end() && flying->second >= version);
    if (!coming) {
      if (wanted_.size() >= kMaxWanted) return {503, nullptr, "too many relief tiles asked"};
      wanted_.push_back(key);
      wanted_set_.insert(key);
    }
    const bool drawn = done_.wait_for(lock, std::chrono::milliseconds(timeout_ms), [&] {
      if (stop_ || broken_) return true;
      tile = cache_.Find(key);
      return tile != nullptr && tile->version >= version;
    });
    if (!drawn || stop_ || broken_) return {503, nullptr, "the relief tile was not drawn in time"};
  }
  return {200, tile->png, {}};
}

size_t ReliefTiles::rendered() const {
  std::lock_guard lock(mu_);
  return rendered_;
}

size_t ReliefTiles::cache_bytes() const {
  std::lock_guard lock(mu_);
  return cache_.bytes();
}

void ReliefTiles::Run() {
  // The thread's own OSMesa context, for the process's life.
  std::unique_ptr<Renderer> renderer;
  try {
    renderer = std::make_unique<Renderer>();
  } catch (const std::exception& e) {
    DT_LOG_ERROR("relief tiles: {}", e.what());
    std::lock_guard lock(mu_);
    broken_ = true;
    done_.notify_all();
    return;
  }
  for (;;) {
    ReliefTileJob job;
    {
      std::unique_lock lock(mu_);
      work_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
      if (stop_) return;
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    Result<std::string> png = RenderReliefTile(*renderer, job);
    if (!png) DT_LOG_WARN("{}", png.error().message);
    std::lock_guard lock(mu_);
    auto flying = in_flight_.find(job.key);
    if (flying != in_flight_.end() && flying->second == job.version) in_flight_.erase(flying);
    if (png) {
      const ReliefTileCache::Tile* held = cache_.Find(job.key);
      if (held == nullptr || held->version <= job.version)
        cache_.Put(job.key, job.version, std::move(png).value());
      ++rendered_;
    }
    done_.notify_all();
  }
}

}  // namespace dt
