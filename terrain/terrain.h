// Terrain: the bare ground plus every dynamic feature, indexed by the grid squares they touch.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "base/feature_id.h"
#include "base/mapped_memory.h"
#include "base/result.h"
#include "terrain/feature.h"
#include "terrain/feature_params.h"
#include "terrain/feature_table.h"
#include "terrain/height_grid.h"
#include "terrain/square_list.h"

namespace dt {

// Each grid square is divided into 4 x 4 cells; bit (cz * 4 + cx) of a square's mask is set when
// some feature may cover cell (cx, cz). Vehicles use it to pick two- or six-point orientation.
inline constexpr int kBitgridCellsPerSide = 4;

// Owns the ground and the features. Every square keeps the features that touch it, wherever their
// placement point is. Not thread-safe: one node's loop owns it.
//
// Mutations validate everything first and change nothing on failure.
class Terrain {
 public:
  explicit Terrain(HeightGrid ground);

  const HeightGrid& ground() const { return ground_; }
  // Changes with every change of the ground or the features and is never the same for two
  // terrains: what a caller cached from the terrain's answers stays valid while it is unchanged.
  // A later change draws a greater stamp.
  uint64_t stamp() const { return stamp_; }
  // Like stamp(), for the ground alone (posts and soils): drawn anew whenever a post or soil is
  // set, so what a caller worked out from the ground stays valid while this is unchanged.
  uint64_t ground_stamp() const { return ground_stamp_; }
  // The greatest stamp of a change that may alter an answer inside the rectangle (clipped to the
  // terrain): a feature touching one of its squares added, replaced, removed or recomputed after
  // the ground moved, a post of one of its squares, a soil of one. At most stamp(); while it is
  // at most a stamp a caller saw, every answer inside is the one it was then.
  uint64_t AreaStamp(const Rect& area) const;
  // The areas changed after stamp `since` (a stamp the caller saw), oldest first: per change the
  // rectangle of the squares it touched (a feature's bounds, the squares around a post). nullopt
  // when the terrain no longer holds them all (more than kChangeLogEntries changes since, or a
  // RemoveAll): the caller takes everything as changed. What a drawing of the terrain needs to
  // redraw only where it changed, without asking every square.
  std::optional<std::vector<Rect>> ChangedAreasSince(uint64_t since) const;
  static constexpr size_t kChangeLogEntries = 4096;

  // Adds a feature. Refused if the ID exists, the parameters are invalid, the feature leaves the
  // terrain, or it conflicts with another (overlapping bridges). An earth move adds its post
  // deltas to the ground (docs/terrain.md "Blade work").
  Status Add(FeatureId id, const FeatureParams& params);
  // Adds a feature made by MakeFeature(id, params, ground()) while the ground was as it is now
  // (a caller that made it to check it first need not have it made again). Refused like Add.
  Status Add(std::unique_ptr<Feature> made);
  // Replaces a feature's parameters (same type). Refused like Add, or if the ID is unknown, and
  // for an earth move: blade work is added once and never replaced.
  Status Update(FeatureId id, const FeatureParams& params);
  // Removes a feature; an earth move's deltas are taken off the ground again.
  Status Remove(FeatureId id);
  // Removes every feature covering (x, z); returns their IDs, sorted.
  std::vector<FeatureId> RemoveAt(double x_m, double z_m);
  void RemoveAll();

  // Sets one post as it stands without blade work (earth moves over it stay added); every feature
  // touching the squares around it recomputes.
  Status SetPostElevation(int i, int j, float elevation_m);
  // The sum of every earth move's change of post (i, j), in millimetres (0 off the grid).
  int64_t BladeDeltaMm(int i, int j) const;
  // The posts as they stand without blade work, row by row (ground().posts() with every earth
  // move taken off): a terrain built on them plus the same features is this terrain.
  std::vector<float> BarePosts() const;
  // The posts blade work has changed, as (index j * posts_x + i, elevation without blade work),
  // sorted by index: BarePosts without a copy of the whole ground.
  std::vector<std::pair<uint32_t, float>> BladeBarePosts() const;
  // Posts some earth move has changed (their sum may have come back to 0).
  size_t blade_post_count() const { return blade_.size(); }
  Status SetSoil(SquareIndex square, TriangleHalf half, Material soil);

  const Feature* Find(FeatureId id) const;
  size_t feature_count() const { return features_.size(); }
  // All features, sorted by ID.
  std::vector<const Feature*> FeaturesById() const;
  // Features touching the square (in no particular order).
  std::span<const Feature* const> FeaturesInSquare(SquareIndex square) const;
  // Features touching the square holding (x, z). Throws std::out_of_range off the terrain.
  std::span<const Feature* const> FeaturesNear(double x_m, double z_m) const;

  bool Contains(double x_m, double z_m) const { return ground_.Contains(x_m, z_m); }
  // Bare ground (thesis `nodef_elev`). Throws std::out_of_range off the terrain or for NaN.
  double GroundElevationAt(double x_m, double z_m) const { return ground_.ElevationAt(x_m, z_m); }
  // The surface at (x, z): the ground plus the highest raise plus the deepest cut of the
  // earthworks covering it (docs/terrain.md "Composing the surface"; with nothing below the
  // ground, the thesis's highest-wins, III.B). Bridges are not included: a vehicle reaches a
  // deck through VehicleTerrain. Water lies on this surface (WaterLevelAt). Throws like
  // GroundElevationAt.
  double ElevationAt(double x_m, double z_m) const;
  // The water level where a flooded area covers (x, z) and the surface there is below it (the
  // highest level where flooded areas overlap); nullopt elsewhere. Throws off the terrain.
  std::optional<double> WaterLevelAt(double x_m, double z_m) const;

  // The feature-presence bit of the cell holding (x, z). Throws off the terrain.
  bool FeatureBitAt(double x_m, double z_m) const;
  uint16_t SquareBits(SquareIndex square) const { return squares_[SquareSlot(square)].bits; }

  // The material at a point on the ground surface: water under a flood's level, else the soil of
  // an area covering it (highest AreaFeature::precedence, then smaller ID), else the material of
  // the earthwork making the surface (highest raise, else deepest cut, else one at the ground;
  // ties to the smaller ID), otherwise the soil of the ground triangle. Bridge decks are not the
  // ground: under a bridge this is the soil below. Throws off the terrain.
  Material SoilAt(double x_m, double z_m) const;

 private:
  // The per-square tables are laid out in tiles of kTileSquares x kTileSquares squares, tile
  // after tile: the squares around a point share a few pages instead of one page per row, so a
  // vehicle's neighbourhood on a 10^4-square-wide world stays within the TLB's reach.
  static constexpr int kTileShift = 5;
  static constexpr int kTileSquares = 1 << kTileShift;
  size_t SquareSlot(SquareIndex s) const {
    constexpr int kMask = kTileSquares - 1;
    const size_t tile =
        static_cast<size_t>(s.j >> kTileShift) * tiles_x_ + static_cast<size_t>(s.i >> kTileShift);
    return (tile << (2 * kTileShift)) | static_cast<size_t>((s.j & kMask) << kTileShift) |
           static_cast<size_t>(s.i & kMask);
  }
  // The squares a rectangle touches, clipped to the grid.
  void SquareRange(const Rect& rect, SquareIndex& lo, SquareIndex& hi) const;
  Status CheckPlacement(const Feature& candidate, const Feature* replacing) const;
  void Index(const Feature* feature);
  void Unindex(const Feature* feature);
  // A range of bitgrid cells along one axis of a square, 0..kBitgridCellsPerSide - 1.
  struct CellSpan {
    int lo = 0;
    int hi = -1;
  };
  // The cells along one axis of the squares in column (or row) k that [min_m, max_m] reaches.
  CellSpan CellsReached(double min_m, double max_m, int k) const;
  // The bitgrid cells of `square`, among those of the column and row spans, the feature may
  // cover.
  uint16_t CellsMaybeCovered(const Feature& feature, SquareIndex square, CellSpan column,
                             CellSpan row) const;
  void RecomputeBits(SquareIndex square);
  void Changed();        // draws a new stamp
  void GroundChanged();  // draws a new stamp for the whole terrain and its ground
  // Gives the squares the rectangle touches (clipped), or one square, the current stamp.
  void MarkChanged(const Rect& rect);
  void MarkChanged(SquareIndex square);
  // Notes the area in the change log under the current stamp (joined with the last entry when it
  // has the same stamp, so one change is one entry).
  void LogChange(const Rect& area);
  Rect SquareRect(SquareIndex square) const;
  // Adds (sign +1) or takes off (-1) an earth move's deltas and recomputes the features on the
  // squares around the posts it changed.
  void ApplyEarthMove(const std::vector<PostDelta>& deltas, int sign);
  // Tells every feature on the squares around the posts that the ground changed.
  void GroundChangedAround(const std::vector<std::pair<int, int>>& posts);

  // The features touching the square in `slot` (empty if none).
  std::span<const Feature* const> SquareFeatures(size_t slot) const {
    const uint32_t k = squares_[slot].list();
    if (k == 0) return {};
    return lists_[k - 1].features();
  }
  // The square's list, made if it has none.
  SquareList& MutableSquareFeatures(size_t slot);
  // Gives an empty list of the square back.
  void ReleaseIfEmpty(size_t slot);

  HeightGrid ground_;
  FeatureTable features_;
  // The per-square tables live in zero-filled pages (ZeroPagedArray): a page costs memory only
  // once a feature or change touches one of its squares, so a world of 10^8 squares holds only
  // what its features touch (docs/real-ground.md "Large worlds").
  // Per square, in one 6-byte entry so a query reads one cache line: the 4 x 4 presence bits and
  // 1 + the index in lists_ of the features touching it (0 for none), as two 16-bit halves.
  struct SquareEntry {
    uint16_t bits = 0;
    uint16_t list_low = 0;
    uint16_t list_high = 0;
    uint32_t list() const { return (uint32_t{list_high} << 16) | list_low; }
    void set_list(uint32_t k) {
      list_low = static_cast<uint16_t>(k);
      list_high = static_cast<uint16_t>(k >> 16);
    }
  };
  size_t tiles_x_ = 0;
  ZeroPagedArray<SquareEntry> squares_;
  std::vector<SquareList> lists_;
  std::vector<uint32_t> free_lists_;  // indices in lists_ no square uses
  uint64_t stamp_ = 0;
  uint64_t ground_stamp_ = 0;
  // Per square: the stamp of its last change (AreaStamp), 0 for none since stamps_floor_, the
  // stamp every square had at the terrain's making or its last RemoveAll.
  ZeroPagedArray<uint64_t> square_stamps_;
  uint64_t stamps_floor_ = 0;
  // The change log (ChangedAreasSince): the changes after changes_floor_, at most
  // kChangeLogEntries, in a ring whose oldest entry is at change_oldest_ once it is full. Stamps
  // and areas apart: the evicted stamp, read on every change, is in 32 KiB that stay in cache.
  std::vector<uint64_t> change_stamps_;
  std::vector<Rect> change_areas_;
  size_t change_oldest_ = 0;
  uint64_t changes_floor_ = 0;
  // Blade work, per post an earth move touched (index j * posts_x + i): the post as set without
  // blade work and the sum of the earth moves' millimetres. The ground post is always float(bare_m
  // + sum_mm * kPostDeltaUnitM), a function of the sum alone, so the ground is the same in every
  // order the earth moves arrived in.
  struct BladePost {
    float bare_m = 0.0f;
    int64_t sum_mm = 0;
  };
  std::unordered_map<uint32_t, BladePost> blade_;
};

}  // namespace dt
