#include "view/relief_tile_cache.h"

#include <stdexcept>

namespace dt {

ReliefTileCache::ReliefTileCache(size_t max_bytes) : max_bytes_(max_bytes) {
  if (max_bytes == 0) throw std::invalid_argument("a relief tile cache of 0 bytes holds nothing");
}

const ReliefTileCache::Tile* ReliefTileCache::Find(const TileKey& key) {
  auto it = entries_.find(key);
  if (it == entries_.end()) return nullptr;
  used_.splice(used_.begin(), used_, it->second.used);
  return &it->second.tile;
}

void ReliefTileCache::Put(const TileKey& key, int64_t version, std::string png) {
  auto it = entries_.find(key);
  if (it != entries_.end()) {
    bytes_ -= it->second.tile.png->size();
    used_.erase(it->second.used);
    entries_.erase(it);
  }
  bytes_ += png.size();
  used_.push_front(key);
  entries_[key] =
      Entry{{version, std::make_shared<const std::string>(std::move(png))}, used_.begin()};
  while (bytes_ > max_bytes_ && used_.size() > 1) {
    auto old = entries_.find(used_.back());
    bytes_ -= old->second.tile.png->size();
    entries_.erase(old);
    used_.pop_back();
  }
}

}  // namespace dt
