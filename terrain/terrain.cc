#include "terrain/terrain.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iterator>
#include <stdexcept>

#include <fmt/format.h>

#include "base/demand.h"
#include "terrain/area_feature.h"
#include "terrain/earth_move.h"

namespace dt {

namespace {
// Stamps are unique in the process and a terrain's later change draws a greater one; no result
// depends on their values. Each thread hands them out from a block of its own, so replicas on
// separate threads do not contend for one atomic on every change. Blocks are reserved in
// increasing order, so a terrain that moved to a thread whose block is older than its last stamp
// gives that block up and still draws a greater stamp.
constexpr uint64_t kStampBlock = uint64_t{1} << 16;
std::atomic<uint64_t> next_stamp_block{1};

uint64_t DrawStamp(uint64_t after) {
  thread_local uint64_t next = 0;
  thread_local uint64_t end = 0;
  if (next == end || next <= after) {
    next = next_stamp_block.fetch_add(kStampBlock, std::memory_order_relaxed);
    end = next + kStampBlock;
  }
  return next++;
}
}  // namespace

Terrain::Terrain(HeightGrid ground) : ground_(std::move(ground)) {
  const auto tiles = [](int squares) {
    return static_cast<size_t>((squares + kTileSquares - 1) / kTileSquares);
  };
  tiles_x_ = tiles(ground_.squares_x());
  // Whole tiles: the slots past the grid's edge are never touched and cost no memory.
  const size_t squares = tiles_x_ * tiles(ground_.squares_z()) * kTileSquares * kTileSquares;
  squares_ = ZeroPagedArray<SquareEntry>(squares);
  square_stamps_ = ZeroPagedArray<uint64_t>(squares);
  GroundChanged();
  stamps_floor_ = stamp_;
  changes_floor_ = stamp_;
}

SquareList& Terrain::MutableSquareFeatures(size_t slot) {
  SquareEntry& e = squares_[slot];
  uint32_t k = e.list();
  if (k == 0) {
    if (free_lists_.empty()) {
      lists_.emplace_back();
      k = static_cast<uint32_t>(lists_.size());
    } else {
      k = free_lists_.back() + 1;
      free_lists_.pop_back();
    }
    e.set_list(k);
  }
  return lists_[k - 1];
}

void Terrain::ReleaseIfEmpty(size_t slot) {
  SquareEntry& e = squares_[slot];
  const uint32_t k = e.list();
  if (k == 0 || !lists_[k - 1].empty()) return;
  lists_[k - 1].clear();
  free_lists_.push_back(k - 1);
  e.set_list(0);
}

void Terrain::Changed() { stamp_ = DrawStamp(stamp_); }

void Terrain::GroundChanged() {
  Changed();
  ground_stamp_ = stamp_;
}

void Terrain::MarkChanged(const Rect& rect) {
  SquareIndex lo, hi;
  SquareRange(rect, lo, hi);
  LogChange(SquareRect(lo).Union(SquareRect(hi)));
  for (int j = lo.j; j <= hi.j; ++j) {
    for (int i = lo.i; i <= hi.i; ++i) square_stamps_[SquareSlot({i, j})] = stamp_;
  }
}

void Terrain::MarkChanged(SquareIndex square) {
  square_stamps_[SquareSlot(square)] = stamp_;
  LogChange(SquareRect(square));
}

Rect Terrain::SquareRect(SquareIndex square) const {
  const double s = ground_.spacing_m();
  return {square.i * s, square.j * s, (square.i + 1) * s, (square.j + 1) * s};
}

void Terrain::LogChange(const Rect& area) {
  const size_t n = change_stamps_.size();
  if (n > 0) {
    const size_t newest = (change_oldest_ + n - 1) % n;
    if (change_stamps_[newest] == stamp_) {
      change_areas_[newest] = change_areas_[newest].Union(area);
      return;
    }
  }
  if (n < kChangeLogEntries) {
    change_stamps_.push_back(stamp_);
    change_areas_.push_back(area);
    return;
  }
  changes_floor_ = change_stamps_[change_oldest_];
  change_stamps_[change_oldest_] = stamp_;
  change_areas_[change_oldest_] = area;
  change_oldest_ = (change_oldest_ + 1) % n;
}

std::optional<std::vector<Rect>> Terrain::ChangedAreasSince(uint64_t since) const {
  if (since < changes_floor_) return std::nullopt;
  const size_t n = change_stamps_.size();
  size_t newer = 0;  // entries after `since`: the newest ones
  while (newer < n && change_stamps_[(change_oldest_ + n - 1 - newer) % n] > since) ++newer;
  std::vector<Rect> out;
  out.reserve(newer);
  for (size_t k = n - newer; k < n; ++k) out.push_back(change_areas_[(change_oldest_ + k) % n]);
  return out;
}

uint64_t Terrain::AreaStamp(const Rect& area) const {
  SquareIndex lo, hi;
  SquareRange(area, lo, hi);
  uint64_t newest = stamps_floor_;
  for (int j = lo.j; j <= hi.j; ++j) {
    for (int i = lo.i; i <= hi.i; ++i)
      newest = std::max(newest, square_stamps_[SquareSlot({i, j})]);
  }
  return newest;
}

void Terrain::SquareRange(const Rect& rect, SquareIndex& lo, SquareIndex& hi) const {
  const double s = ground_.spacing_m();
  auto clamp_index = [&](double v, int last) {
    const double g = std::floor(v / s);
    if (!(g >= 0.0)) return 0;  // also catches NaN
    if (g > last) return last;
    return static_cast<int>(g);
  };
  const int last_i = ground_.squares_x() - 1, last_j = ground_.squares_z() - 1;
  lo = {clamp_index(rect.min_x, last_i), clamp_index(rect.min_z, last_j)};
  hi = {clamp_index(rect.max_x, last_i), clamp_index(rect.max_z, last_j)};
}

Status Terrain::CheckPlacement(const Feature& candidate, const Feature* replacing) const {
  const Rect b = candidate.Bounds();
  if (!ground_.Contains(b.min_x, b.min_z) || !ground_.Contains(b.max_x, b.max_z)) {
    return Error{
        fmt::format("{} {} covers x [{}, {}] z [{}, {}] m, which leaves the terrain [0, {}] x "
                    "[0, {}] m",
                    FeatureTypeName(candidate.type()), candidate.id().ToString(), b.min_x, b.max_x,
                    b.min_z, b.max_z, ground_.size_x_m(), ground_.size_z_m())};
  }
  if (!candidate.CanConflict()) return Status::Ok();
  SquareIndex lo, hi;
  SquareRange(b, lo, hi);
  for (int j = lo.j; j <= hi.j; ++j) {
    for (int i = lo.i; i <= hi.i; ++i) {
      for (const Feature* other : SquareFeatures(SquareSlot({i, j}))) {
        if (other == replacing || !other->CanConflict()) continue;
        if (candidate.ConflictsWith(*other) || other->ConflictsWith(candidate)) {
          return Error{fmt::format("{} {} overlaps {} {}", FeatureTypeName(candidate.type()),
                                   candidate.id().ToString(), FeatureTypeName(other->type()),
                                   other->id().ToString())};
        }
      }
    }
  }
  return Status::Ok();
}

void Terrain::Index(const Feature* feature) {
  Changed();
  const Rect b = feature->Bounds();  // once: a virtual call, asked again by every square
  SquareIndex lo, hi;
  SquareRange(b, lo, hi);
  // A square's cells depend on its column along x and its row along z apart: each column's and
  // row's are worked out once (the same arithmetic as per square, so the same bits).
  constexpr int kKeptColumns = 16;
  CellSpan columns[kKeptColumns];
  const bool keep_columns = hi.i - lo.i < kKeptColumns;
  for (int j = lo.j; j <= hi.j; ++j) {
    const CellSpan row = CellsReached(b.min_z, b.max_z, j);
    for (int i = lo.i; i <= hi.i; ++i) {
      CellSpan column;
      if (!keep_columns) {
        column = CellsReached(b.min_x, b.max_x, i);
      } else if (j == lo.j) {
        column = columns[i - lo.i] = CellsReached(b.min_x, b.max_x, i);
      } else {
        column = columns[i - lo.i];
      }
      const size_t slot = SquareSlot({i, j});
      MutableSquareFeatures(slot).push_back(feature);
      squares_[slot].bits |= CellsMaybeCovered(*feature, {i, j}, column, row);
      square_stamps_[slot] = stamp_;
    }
  }
  LogChange(SquareRect(lo).Union(SquareRect(hi)));
}

void Terrain::Unindex(const Feature* feature) {
  Changed();
  SquareIndex lo, hi;
  SquareRange(feature->Bounds(), lo, hi);
  for (int j = lo.j; j <= hi.j; ++j) {
    for (int i = lo.i; i <= hi.i; ++i) {
      const size_t slot = SquareSlot({i, j});
      MutableSquareFeatures(slot).erase(feature);
      ReleaseIfEmpty(slot);
      RecomputeBits({i, j});
      MarkChanged(SquareIndex{i, j});
    }
  }
}

Terrain::CellSpan Terrain::CellsReached(double min_m, double max_m, int k) const {
  const double s = ground_.spacing_m();
  const double cell = s / kBitgridCellsPerSide;
  const double origin = k * s;
  // Only the cells the feature's bounds reach are asked (the bounds may end inside the square).
  // Cells are closed rectangles, so a bound on a cell edge reaches the cells on both sides.
  constexpr double kLastCell = kBitgridCellsPerSide - 1;
  return {static_cast<int>(std::clamp(std::ceil((min_m - origin) / cell) - 1.0, 0.0, kLastCell)),
          static_cast<int>(std::clamp(std::floor((max_m - origin) / cell), 0.0, kLastCell))};
}

uint16_t Terrain::CellsMaybeCovered(const Feature& feature, SquareIndex square, CellSpan column,
                                    CellSpan row) const {
  const double s = ground_.spacing_m();
  const double cell = s / kBitgridCellsPerSide;
  const double square_x0 = square.i * s, square_z0 = square.j * s;
  uint16_t mask = 0;
  for (int cz = row.lo; cz <= row.hi; ++cz) {
    for (int cx = column.lo; cx <= column.hi; ++cx) {
      const double x0 = square_x0 + cx * cell;
      const double z0 = square_z0 + cz * cell;
      if (feature.MayCover({x0, z0, x0 + cell, z0 + cell})) {
        mask = static_cast<uint16_t>(mask | (1u << (cz * kBitgridCellsPerSide + cx)));
      }
    }
  }
  return mask;
}

void Terrain::RecomputeBits(SquareIndex square) {
  uint16_t mask = 0;
  for (const Feature* f : SquareFeatures(SquareSlot(square))) {
    const Rect b = f->Bounds();
    mask |= CellsMaybeCovered(*f, square, CellsReached(b.min_x, b.max_x, square.i),
                              CellsReached(b.min_z, b.max_z, square.j));
  }
  squares_[SquareSlot(square)].bits = mask;
}

Status Terrain::Add(FeatureId id, const FeatureParams& params) {
  // The ID's slot is fetched while the feature is made; a taken ID is still the error reported
  // first, whatever the parameters.
  features_.Prefetch(id);
  auto made = MakeFeature(id, params, ground_);
  if (made) return Add(std::move(made).value());  // which refuses a taken ID
  if (features_.Find(id) != nullptr) {
    return Error{fmt::format("feature {} already exists", id.ToString())};
  }
  return made.error();
}

Status Terrain::Add(std::unique_ptr<Feature> made) {
  DT_DEMAND(made != nullptr);
  const FeatureId id = made->id();
  if (features_.Find(id) != nullptr) {
    return Error{fmt::format("feature {} already exists", id.ToString())};
  }
  if (made->type() == FeatureType::kEarthMove) {
    // Not indexed: it covers no point; its work is in the ground posts.
    const auto* move = static_cast<const EarthMoveFeature*>(features_.Insert(id, std::move(made)));
    ApplyEarthMove(move->post_deltas(), +1);
    return Status::Ok();
  }
  if (auto s = CheckPlacement(*made, nullptr); !s) return s;
  Index(features_.Insert(id, std::move(made)));
  return Status::Ok();
}

namespace {
float ComposedPost(float bare_m, int64_t sum_mm) {
  return static_cast<float>(static_cast<double>(bare_m) +
                            static_cast<double>(sum_mm) * kPostDeltaUnitM);
}
}  // namespace

void Terrain::ApplyEarthMove(const std::vector<PostDelta>& deltas, int sign) {
  const int nx = ground_.posts_x();
  std::vector<std::pair<int, int>> posts;
  posts.reserve(deltas.size());
  for (const PostDelta& d : deltas) {
    const uint32_t index = static_cast<uint32_t>(d.j) * static_cast<uint32_t>(nx) + d.i;
    auto [it, inserted] = blade_.try_emplace(index);
    if (inserted) it->second.bare_m = ground_.post(d.i, d.j);
    it->second.sum_mm += sign * static_cast<int64_t>(d.delta_mm);
    const float post = it->second.sum_mm == 0 ? it->second.bare_m
                                              : ComposedPost(it->second.bare_m, it->second.sum_mm);
    DT_DEMAND(std::isfinite(post));  // millimetre sums stay far inside a float's range
    ground_.set_post(d.i, d.j, post);
    posts.emplace_back(d.i, d.j);
  }
  GroundChanged();
  GroundChangedAround(posts);
}

int64_t Terrain::BladeDeltaMm(int i, int j) const {
  const int nx = ground_.posts_x();
  if (i < 0 || j < 0 || i >= nx || j >= ground_.posts_z()) return 0;
  const auto it = blade_.find(static_cast<uint32_t>(j) * static_cast<uint32_t>(nx) + i);
  return it == blade_.end() ? 0 : it->second.sum_mm;
}

std::vector<float> Terrain::BarePosts() const {
  std::vector<float> posts(ground_.posts().begin(), ground_.posts().end());
  for (const auto& [index, post] : blade_) posts[index] = post.bare_m;
  return posts;
}

std::vector<std::pair<uint32_t, float>> Terrain::BladeBarePosts() const {
  std::vector<std::pair<uint32_t, float>> bare;
  bare.reserve(blade_.size());
  for (const auto& [index, post] : blade_) bare.emplace_back(index, post.bare_m);
  std::sort(bare.begin(), bare.end());
  return bare;
}

void Terrain::GroundChangedAround(const std::vector<std::pair<int, int>>& posts) {
  const int mx = ground_.squares_x(), mz = ground_.squares_z();
  // A post is a corner of up to four squares; every feature touching them recomputes once.
  std::vector<Feature*> touched;
  for (auto [i, j] : posts) {
    for (int dj = -1; dj <= 0; ++dj) {
      for (int di = -1; di <= 0; ++di) {
        const int si = i + di, sj = j + dj;
        if (si < 0 || sj < 0 || si >= mx || sj >= mz) continue;
        MarkChanged(SquareIndex{si, sj});
        for (const Feature* f : SquareFeatures(SquareSlot({si, sj}))) {
          touched.push_back(const_cast<Feature*>(f));
        }
      }
    }
  }
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  for (Feature* f : touched) {
    f->OnGroundChanged(ground_);
    MarkChanged(f->Bounds());
  }
}

Status Terrain::Update(FeatureId id, const FeatureParams& params) {
  const Feature* old = features_.Find(id);
  if (old == nullptr) {
    return Error{fmt::format("feature {} does not exist", id.ToString())};
  }
  if (old->type() != params.type) {
    return Error{fmt::format("feature {} is a {}; an update cannot make it a {}", id.ToString(),
                             FeatureTypeName(old->type()), FeatureTypeName(params.type))};
  }
  if (old->type() == FeatureType::kEarthMove) {
    return Error{
        fmt::format("earth_move {} cannot be updated: blade work is added once", id.ToString())};
  }
  auto made = MakeFeature(id, params, ground_);
  if (!made) return made.error();
  if (auto s = CheckPlacement(*made.value(), old); !s) return s;
  Unindex(old);
  Index(features_.Replace(id, std::move(made).value()));
  return Status::Ok();
}

Status Terrain::Remove(FeatureId id) {
  const Feature* f = features_.Find(id);
  if (f == nullptr) {
    return Error{fmt::format("feature {} does not exist", id.ToString())};
  }
  if (f->type() == FeatureType::kEarthMove) {
    const std::vector<PostDelta> deltas = static_cast<const EarthMoveFeature*>(f)->post_deltas();
    features_.Erase(id);
    ApplyEarthMove(deltas, -1);
    return Status::Ok();
  }
  Unindex(f);
  features_.Erase(id);
  return Status::Ok();
}

std::vector<FeatureId> Terrain::RemoveAt(double x_m, double z_m) {
  std::vector<FeatureId> ids;
  for (const Feature* f : FeaturesNear(x_m, z_m)) {
    if (f->Covers(x_m, z_m)) ids.push_back(f->id());
  }
  std::sort(ids.begin(), ids.end());
  for (const auto& id : ids) {
    auto removed = Remove(id);
    DT_DEMAND(removed);  // the ID came from the index: it must exist
  }
  return ids;
}

void Terrain::RemoveAll() {
  features_.Clear();
  const uint32_t nx = static_cast<uint32_t>(ground_.posts_x());
  for (const auto& [index, post] : blade_) {
    ground_.set_post(static_cast<int>(index % nx), static_cast<int>(index / nx), post.bare_m);
  }
  blade_.clear();
  squares_.Clear();
  lists_.clear();
  free_lists_.clear();
  GroundChanged();  // the blade work's posts went back
  square_stamps_.Clear();
  stamps_floor_ = stamp_;
  change_stamps_.clear();
  change_areas_.clear();
  change_oldest_ = 0;
  changes_floor_ = stamp_;
}

Status Terrain::SetPostElevation(int i, int j, float elevation_m) {
  const int nx = ground_.posts_x(), nz = ground_.posts_z();
  if (i < 0 || j < 0 || i >= nx || j >= nz) {
    return Error{fmt::format("post ({}, {}) is outside the {} x {} grid", i, j, nx, nz)};
  }
  if (!std::isfinite(elevation_m)) {
    return Error{fmt::format("post ({}, {}) elevation {} is not finite", i, j, elevation_m)};
  }
  float post = elevation_m;
  if (auto it = blade_.find(static_cast<uint32_t>(j) * static_cast<uint32_t>(nx) + i);
      it != blade_.end()) {
    it->second.bare_m = elevation_m;
    if (it->second.sum_mm != 0) post = ComposedPost(elevation_m, it->second.sum_mm);
    if (!std::isfinite(post)) {
      return Error{fmt::format("post ({}, {}) elevation {} plus its blade work {} mm is not finite",
                               i, j, elevation_m, it->second.sum_mm)};
    }
  }
  ground_.set_post(i, j, post);
  GroundChanged();
  GroundChangedAround({{i, j}});
  return Status::Ok();
}

Status Terrain::SetSoil(SquareIndex square, TriangleHalf half, Material soil) {
  const int mx = ground_.squares_x(), mz = ground_.squares_z();
  if (square.i < 0 || square.j < 0 || square.i >= mx || square.j >= mz) {
    return Error{
        fmt::format("square ({}, {}) is outside the {} x {} squares", square.i, square.j, mx, mz)};
  }
  if (!IsValidMaterial(static_cast<uint16_t>(soil)) || soil == Material::kFromGround) {
    return Error{fmt::format("{} is not a soil", static_cast<uint16_t>(soil))};
  }
  ground_.set_soil(square, half, soil);
  GroundChanged();
  MarkChanged(square);
  return Status::Ok();
}

const Feature* Terrain::Find(FeatureId id) const { return features_.Find(id); }

std::vector<const Feature*> Terrain::FeaturesById() const {
  std::vector<const Feature*> out;
  out.reserve(features_.size());
  features_.ForEach([&](const Feature& f) { out.push_back(&f); });
  std::sort(out.begin(), out.end(),
            [](const Feature* a, const Feature* b) { return a->id() < b->id(); });
  return out;
}

std::span<const Feature* const> Terrain::FeaturesInSquare(SquareIndex square) const {
  return SquareFeatures(SquareSlot(square));
}

std::span<const Feature* const> Terrain::FeaturesNear(double x_m, double z_m) const {
  return SquareFeatures(SquareSlot(ground_.SquareAt(x_m, z_m)));
}

double Terrain::ElevationAt(double x_m, double z_m) const {
  const HeightGrid::Location at = ground_.Locate(x_m, z_m);
  const double ground = ground_.ElevationAt(at);
  const size_t slot = SquareSlot(at.square);
  if (squares_[slot].bits == 0) return ground;
  // The composition rule (docs/terrain.md "Composing the surface"): the highest raise plus the
  // deepest cut. Both are order-independent (max and min), and with no cuts this is the
  // thesis's highest-wins.
  double raise_m = 0.0;  // kNotCovered never wins against the ground's 0
  double cut_m = 0.0;
  for (const Feature* f : SquareFeatures(slot)) {
    const double offset_m = f->OffsetOrNotCovered(x_m, z_m);
    raise_m = std::max(raise_m, offset_m);
    cut_m = std::min(cut_m, offset_m == Feature::kNotCovered ? 0.0 : offset_m);
  }
  return ground + raise_m + cut_m;
}

std::optional<double> Terrain::WaterLevelAt(double x_m, double z_m) const {
  std::optional<double> level;
  for (const Feature* f : FeaturesNear(x_m, z_m)) {
    if (f->type() != FeatureType::kArea) continue;
    const auto* area = static_cast<const AreaFeature*>(f);
    if (!area->is_water() || !area->Inside(x_m, z_m)) continue;
    if (!level || area->water_level_m() > *level) level = area->water_level_m();
  }
  if (level && *level > ElevationAt(x_m, z_m)) return level;
  return std::nullopt;
}

bool Terrain::FeatureBitAt(double x_m, double z_m) const {
  const SquareIndex square = ground_.SquareAt(x_m, z_m);
  const double s = ground_.spacing_m();
  const double cell = s / kBitgridCellsPerSide;
  const int cx =
      std::clamp(static_cast<int>((x_m - square.i * s) / cell), 0, kBitgridCellsPerSide - 1);
  const int cz =
      std::clamp(static_cast<int>((z_m - square.j * s) / cell), 0, kBitgridCellsPerSide - 1);
  return (squares_[SquareSlot(square)].bits >> (cz * kBitgridCellsPerSide + cx)) & 1u;
}

Material Terrain::SoilAt(double x_m, double z_m) const {
  // The earthwork that makes the surface: the highest raise, else the deepest cut, else one
  // lying at the ground (a crater's floor); ties go to the smaller ID, so the answer is
  // independent of insertion order. Only earthworks lie on the ground; a bridge deck is above it
  // (a vehicle on a deck takes the bridge's material from the bridge itself).
  const Feature* raiser = nullptr;
  const Feature* cutter = nullptr;
  const Feature* level = nullptr;
  double raise = 0.0, cut = 0.0;
  const AreaFeature* area = nullptr;
  bool water_seen = false;
  auto earlier = [](const Feature* a, const Feature* b) {
    return b == nullptr || a->id() < b->id();
  };
  for (const Feature* f : FeaturesNear(x_m, z_m)) {
    if (f->type() == FeatureType::kArea) {
      const auto* a = static_cast<const AreaFeature*>(f);
      if (!a->Inside(x_m, z_m)) continue;
      water_seen = water_seen || a->is_water();
      if (a->is_water()) continue;  // decided below, once the surface is known
      if (!area || a->precedence() > area->precedence() ||
          (a->precedence() == area->precedence() && earlier(a, area))) {
        area = a;
      }
      continue;
    }
    const double offset = f->OffsetOrNotCovered(x_m, z_m);
    if (offset == Feature::kNotCovered) continue;
    if (offset > raise || (offset == raise && offset > 0.0 && earlier(f, raiser))) {
      raise = offset;
      raiser = f;
    } else if (offset < cut || (offset == cut && offset < 0.0 && earlier(f, cutter))) {
      cut = offset;
      cutter = f;
    } else if (offset == 0.0 && earlier(f, level)) {
      level = f;
    }
  }
  // Areas lie on the surface, whatever made it; water only where the surface is below its level.
  if (water_seen && WaterLevelAt(x_m, z_m)) return Material::kWater;
  if (area) return area->material();
  if (raiser) return raiser->material();
  if (cutter) return cutter->material();
  if (level) return level->material();
  return ground_.soil(ground_.SquareAt(x_m, z_m), ground_.HalfAt(x_m, z_m));
}

}  // namespace dt
