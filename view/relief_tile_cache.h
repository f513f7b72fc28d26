// ReliefTileCache: the relief tiles drawn, least recently used first out, bounded in bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <string>

#include "view/relief_pyramid.h"

namespace dt {

// Not thread-safe: its owner locks it.
class ReliefTileCache {
 public:
  // Holds at most max_bytes of PNG bytes (keys and bookkeeping not counted: about 100 bytes a
  // tile). Throws std::invalid_argument for 0.
  explicit ReliefTileCache(size_t max_bytes);

  struct Tile {
    int64_t version = 0;
    std::shared_ptr<const std::string> png;
  };
  // The tile's picture if held (marked as just used), else nullptr.
  const Tile* Find(const TileKey& key);
  // Holds the picture for key, replacing an older one, then drops least recently used tiles
  // until the bytes fit (the one just put is kept even when it alone is larger).
  void Put(const TileKey& key, int64_t version, std::string png);
  size_t bytes() const { return bytes_; }
  size_t tiles() const { return entries_.size(); }
  size_t max_bytes() const { return max_bytes_; }

 private:
  struct Entry {
    Tile tile;
    std::list<TileKey>::iterator used;  // its place in used_
  };
  size_t max_bytes_;
  size_t bytes_ = 0;
  std::map<TileKey, Entry> entries_;
  std::list<TileKey> used_;  // most recently used first
};

}  // namespace dt
