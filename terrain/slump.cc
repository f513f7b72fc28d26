#include "terrain/slump.h"

#include <algorithm>
#include <cmath>

#include "base/demand.h"

namespace dt {

PostWindow::PostWindow(const Terrain& terrain, int i0, int j0, int columns, int rows) {
  const HeightGrid& g = terrain.ground();
  const int nx = g.posts_x(), nz = g.posts_z();
  const int i1 = std::min(nx, i0 + columns), j1 = std::min(nz, j0 + rows);
  i0_ = std::clamp(i0, 0, nx);
  j0_ = std::clamp(j0, 0, nz);
  columns_ = std::max(0, i1 - i0_);
  rows_ = std::max(0, j1 - j0_);
  spacing_m_ = g.spacing_m();
  h_mm_.resize(static_cast<size_t>(columns_) * rows_);
  soil_.resize(h_mm_.size());
  for (int j = j0_; j < j0_ + rows_; ++j) {
    for (int i = i0_; i < i0_ + columns_; ++i) {
      const double x = std::min(i * spacing_m_, g.size_x_m());
      const double z = std::min(j * spacing_m_, g.size_z_m());
      h_mm_[Slot(i, j)] = std::llround(terrain.ElevationAt(x, z) / kPostDeltaUnitM);
      soil_[Slot(i, j)] = terrain.SoilAt(x, z);
    }
  }
  initial_mm_ = h_mm_;
}

int64_t PostWindow::VolumeChangeMm() const {
  int64_t sum = 0;
  for (size_t k = 0; k < h_mm_.size(); ++k) sum += h_mm_[k] - initial_mm_[k];
  return sum;
}

std::vector<PostDelta> PostWindow::Deltas() const {
  std::vector<PostDelta> out;
  for (int j = j0_; j < j0_ + rows_; ++j) {
    for (int i = i0_; i < i0_ + columns_; ++i) {
      const int64_t d = h_mm_[Slot(i, j)] - initial_mm_[Slot(i, j)];
      if (d == 0) continue;
      DT_DEMAND(d <= kMaxPostDeltaMm && d >= -kMaxPostDeltaMm);
      out.push_back({static_cast<uint16_t>(i), static_cast<uint16_t>(j), static_cast<int32_t>(d)});
    }
  }
  return out;
}

int Slump(PostWindow& w, const std::function<double(Material)>& repose_rad, int max_sweeps) {
  const int c = w.columns(), r = w.rows();
  if (c == 0 || r == 0) return 0;
  auto slot = [&](int i, int j) {
    return static_cast<size_t>(j - w.j0()) * static_cast<size_t>(c) +
           static_cast<size_t>(i - w.i0());
  };
  // Largest rise to a neighbour, per post, from its soil's angle of repose.
  std::vector<int64_t> limit_mm(static_cast<size_t>(c) * r);
  std::vector<uint8_t> active(limit_mm.size(), 0), next(limit_mm.size(), 0);
  for (int j = w.j0(); j < w.j0() + r; ++j) {
    for (int i = w.i0(); i < w.i0() + c; ++i) {
      const double angle = repose_rad(w.soil(i, j));
      limit_mm[slot(i, j)] =
          static_cast<int64_t>(std::floor(std::tan(angle) * w.spacing_m() / kPostDeltaUnitM));
    }
  }
  constexpr int kNeighbours[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  // The changed posts and their neighbours (a post above a hole the blade dug slides into it).
  for (int j = w.j0(); j < w.j0() + r; ++j) {
    for (int i = w.i0(); i < w.i0() + c; ++i) {
      if (w.height_mm(i, j) == w.initial_mm(i, j)) continue;
      active[slot(i, j)] = 1;
      for (const auto& d : kNeighbours) {
        if (w.Contains(i + d[0], j + d[1])) active[slot(i + d[0], j + d[1])] = 1;
      }
    }
  }
  auto mark = [&](int i, int j) {
    next[slot(i, j)] = 1;
    for (const auto& d : kNeighbours) {
      if (w.Contains(i + d[0], j + d[1])) next[slot(i + d[0], j + d[1])] = 1;
    }
  };
  int sweeps = 0;
  while (sweeps < max_sweeps) {
    ++sweeps;
    bool moved = false;
    std::fill(next.begin(), next.end(), uint8_t{0});
    for (int j = w.j0(); j < w.j0() + r; ++j) {
      for (int i = w.i0(); i < w.i0() + c; ++i) {
        if (!active[slot(i, j)]) continue;
        for (const auto& d : kNeighbours) {
          const int qi = i + d[0], qj = j + d[1];
          if (!w.Contains(qi, qj)) continue;
          const int64_t excess = w.height_mm(i, j) - w.height_mm(qi, qj) - limit_mm[slot(i, j)];
          if (excess <= 0) continue;
          // Half the excess levels the pair at the limit; at least 1 mm so it ends.
          const int64_t move = std::max<int64_t>(1, excess / 2);
          w.height_mm(i, j) -= move;
          w.height_mm(qi, qj) += move;
          mark(i, j);
          mark(qi, qj);
          moved = true;
        }
      }
    }
    active.swap(next);
    if (!moved) break;
  }
  return sweeps;
}

std::vector<std::vector<PostDelta>> SplitEarthMove(const std::vector<PostDelta>& deltas) {
  std::vector<std::vector<PostDelta>> out;
  int min_i = 0, max_i = 0, first_j = 0;
  for (const PostDelta& d : deltas) {
    const bool fits =
        !out.empty() && out.back().size() < static_cast<size_t>(kMaxEarthMovePosts) &&
        d.j - first_j < kMaxEarthMoveSpanPosts &&
        std::max<int>(max_i, d.i) - std::min<int>(min_i, d.i) < kMaxEarthMoveSpanPosts;
    if (!fits) {
      out.emplace_back();
      min_i = max_i = d.i;
      first_j = d.j;
    }
    out.back().push_back(d);
    min_i = std::min<int>(min_i, d.i);
    max_i = std::max<int>(max_i, d.i);
  }
  return out;
}

}  // namespace dt
