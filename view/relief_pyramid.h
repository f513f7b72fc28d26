// ReliefPyramid: the live view's relief tiles, a level-of-detail pyramid over the terrain.
#pragma once

#include <compare>
#include <string>
#include <string_view>
#include <vector>

#include "base/rect.h"
#include "base/result.h"

namespace dt {

// One tile: its level (0 = the whole world in one tile) and its column (along x, east) and row
// (along z, north) at that level.
struct TileKey {
  int level = 0;
  int tx = 0;
  int tz = 0;
  auto operator<=>(const TileKey&) const = default;
  // "level/tx/tz", as the page names a tile.
  std::string ToString() const;
};

// Level 0 is one square tile of side max(size_x_m, size_z_m) with its south-west corner at the
// terrain's (0, 0); each level halves the side, so level L has 2^L tiles a side over that square
// (those wholly beyond the terrain are not tiles). Every tile is kTilePx pixels a side. The finest
// level is the first whose pixel is no wider than a post spacing: finer shows nothing more.
class ReliefPyramid {
 public:
  static constexpr int kTilePx = 256;

  // Throws std::invalid_argument unless the sizes and the spacing are finite and > 0.
  ReliefPyramid(double size_x_m, double size_z_m, double spacing_m);

  int levels() const { return levels_; }
  double size_x_m() const { return size_x_m_; }
  double size_z_m() const { return size_z_m_; }
  double spacing_m() const { return spacing_m_; }
  double side_m(int level) const;
  double metres_per_pixel(int level) const { return side_m(level) / kTilePx; }
  int tiles_x(int level) const;
  int tiles_z(int level) const;
  bool Valid(const TileKey& key) const;
  // The tile's square in metres (beyond the terrain at its east and north edges, where the
  // terrain ends inside it).
  Rect TileRect(const TileKey& key) const;
  // Posts between two samples of a tile at `level`: the most that keeps a sample per pixel.
  int SampleStride(int level) const;
  // The tiles of `level` whose square meets `area` (closed rectangles), clipped to the terrain.
  std::vector<TileKey> TilesOver(const Rect& area, int level) const;
  // The tiles whose picture a change of the squares in `area` may alter, at every level: those
  // over it grown by the level's sample spacing (a tile's edge pixels are drawn from posts up to
  // one sample beyond it).
  std::vector<TileKey> TilesChangedBy(const Rect& area) const;

 private:
  double size_x_m_;
  double size_z_m_;
  double spacing_m_;
  double side0_m_;
  int levels_ = 1;
};

// "L/X/Z" or "L/X/Z.png" (a tile's path after /relief/): the key, or an error naming the text
// when it is malformed or not a tile of `pyramid`.
Result<TileKey> ParseTileKey(std::string_view text, const ReliefPyramid& pyramid);

}  // namespace dt
