// ReliefTiles: the live view's relief as tiles (docs/view.md "The relief"): their versions, the
// pages' requests, and the thread that draws them.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "terrain/terrain.h"
#include "view/relief_pyramid.h"
#include "view/relief_tile.h"
#include "view/relief_tile_cache.h"

namespace dt {

// A tile's version is the generation of the last change of the terrain that touched it (or the
// epoch, the generation of the last change of all of it), so a page asks again for exactly the
// tiles a change touched. Tiles are drawn when a page asks for one, one at a time, on a thread
// of their own; the view's loop only takes each asked tile's posts and features (SampleReliefTile).
class ReliefTiles {
 public:
  // 64 MiB: about 800 tiles of 256 x 256 (a PNG of shaded relief is 65-92 kB), the views of a
  // few pages zoomed in and out several times.
  static constexpr size_t kDefaultCacheBytes = size_t{64} << 20;
  // Tiles asked and not yet taken by the loop: more are refused at once (503), so a page cannot
  // queue work without bound.
  static constexpr size_t kMaxWanted = 64;

  // The pyramid over `ground` (its size and spacing; nothing of it is kept).
  explicit ReliefTiles(const HeightGrid& ground, size_t cache_bytes = kDefaultCacheBytes);
  // Stop()s.
  ~ReliefTiles();
  // Pages waiting get 503 at once and later ones too; the drawing thread ends. Before the web
  // server stops, so its threads are not held by a tile.
  void Stop();
  ReliefTiles(const ReliefTiles&) = delete;
  ReliefTiles& operator=(const ReliefTiles&) = delete;

  const ReliefPyramid& pyramid() const { return pyramid_; }

  // On the loop: the tiles the terrain's changes since the last call touched get a new version.
  // Returns the pages' message, {"type":"relief_tiles","epoch":E,"versions":{"L/X/Z":V,...}}
  // (only the tiles that changed; a new epoch changes every tile), or null when none changed.
  nlohmann::json Track(const Terrain& terrain);
  // The pyramid and every tile's version, for a page's snapshot: {"levels","tile_px","side_m",
  // "epoch","versions"}. Consistent with Track's messages when both are called under one lock.
  nlohmann::json Describe() const;
  // On the loop: takes the posts and features of up to `max` tiles pages wait for and hands
  // them to the drawing thread.
  void Serve(const Terrain& terrain, size_t max);

  // On a web server thread: the tile's PNG at its current version (or newer), waiting for it to
  // be drawn up to timeout_ms; status 200, else 503 with why (busy, not drawn in time).
  struct Answer {
    int status = 503;
    std::shared_ptr<const std::string> png;
    std::string why;
  };
  Answer Get(const TileKey& key, int timeout_ms);

  int64_t Version(const TileKey& key) const;
  size_t rendered() const;  // tiles drawn since the start
  size_t cache_bytes() const;

 private:
  void Run();
  int64_t VersionLocked(const TileKey& key) const;

  ReliefPyramid pyramid_;
  std::pair<double, double> elevation_range_m_;  // SampledElevationRange of the ground
  uint64_t seen_stamp_ = 0;  // the loop's: the terrain's stamp at the last Track
  mutable std::mutex mu_;
  std::condition_variable work_;  // the drawing thread waits for jobs
  std::condition_variable done_;  // pages wait for tiles
  int64_t generation_ = 0;
  int64_t epoch_ = 0;
  std::map<TileKey, int64_t> versions_;  // tiles changed since the epoch
  std::deque<TileKey> wanted_;
  std::set<TileKey> wanted_set_;
  std::map<TileKey, int64_t> in_flight_;  // sampled, not yet drawn: the version sampled
  std::deque<ReliefTileJob> jobs_;
  ReliefTileCache cache_;
  size_t rendered_ = 0;
  bool stop_ = false;
  bool broken_ = false;  // no OSMesa context: every Get fails at once
  std::thread thread_;
};

}  // namespace dt
