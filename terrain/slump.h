// PostWindow and Slump: blade work on a window of posts in whole millimetres, relaxed to the
// soils' angles of repose by moves that conserve the soil's volume exactly.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "terrain/feature_params.h"
#include "terrain/terrain.h"

namespace dt {

// The surface heights (Terrain::ElevationAt at each post, rounded to whole millimetres) of the
// posts [i0, i0 + columns) x [j0, j0 + rows), clipped to the grid. Work done on the window is
// its heights' changes; Deltas() gives them as one earth move's post deltas.
class PostWindow {
 public:
  PostWindow(const Terrain& terrain, int i0, int j0, int columns, int rows);

  int i0() const { return i0_; }
  int j0() const { return j0_; }
  int columns() const { return columns_; }
  int rows() const { return rows_; }
  double spacing_m() const { return spacing_m_; }
  bool Contains(int i, int j) const {
    return i >= i0_ && j >= j0_ && i < i0_ + columns_ && j < j0_ + rows_;
  }
  // Height of post (i, j) (must be Contains), millimetres.
  int64_t& height_mm(int i, int j) { return h_mm_[Slot(i, j)]; }
  int64_t height_mm(int i, int j) const { return h_mm_[Slot(i, j)]; }
  int64_t initial_mm(int i, int j) const { return initial_mm_[Slot(i, j)]; }
  // The soil under post (i, j) as the terrain had it when the window was read.
  Material soil(int i, int j) const { return soil_[Slot(i, j)]; }
  // Sum of the changes (millimetre-posts): 0 when soil was only moved inside the window.
  int64_t VolumeChangeMm() const;
  // The changed posts, sorted by (j, i); a change beyond kMaxPostDeltaMm aborts (the blade and
  // the slump never make one).
  std::vector<PostDelta> Deltas() const;

 private:
  size_t Slot(int i, int j) const {
    return static_cast<size_t>(j - j0_) * static_cast<size_t>(columns_) +
           static_cast<size_t>(i - i0_);
  }
  int i0_ = 0, j0_ = 0, columns_ = 0, rows_ = 0;
  double spacing_m_ = 1.0;
  std::vector<int64_t> h_mm_;
  std::vector<int64_t> initial_mm_;
  std::vector<Material> soil_;
};

// Moves soil downhill between 4-neighbour posts of the window until no slope starting at a
// changed post is steeper than the angle of repose of the higher post's soil
// (repose_rad(soil), in (0, pi/2)), or max_sweeps sweeps have run. Only posts changed since the
// window was read and their neighbours take part at first, then the posts soil moved from or to
// and theirs, so earthworks away from the work keep their sides.
// Each move takes whole millimetres from one post and gives them to its neighbour, so the
// window's volume is unchanged; the order (sweeps over (j, i), neighbours +x, -x, +z, -z) is
// fixed, so the result depends only on the window. Returns the sweeps run.
int Slump(PostWindow& window, const std::function<double(Material)>& repose_rad,
          int max_sweeps = 64);

// Cuts sorted post deltas into earth moves that each satisfy ValidateFeatureParams (at most
// kMaxEarthMovePosts posts in a kMaxEarthMoveSpanPosts square), in (j, i) order.
std::vector<std::vector<PostDelta>> SplitEarthMove(const std::vector<PostDelta>& deltas);

}  // namespace dt
