#include "vehicle/blade.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "terrain/slump.h"

namespace dt {

Result<BladeSpec> BladeOf(std::string_view vehicle_type_name) {
  // A D7-class semi-U blade, rounded.
  if (vehicle_type_name == "bulldozer") {
    return BladeSpec{.width_m = 3.7, .capacity_m3 = 4.0, .max_depth_m = 0.5};
  }
  return Error{
      fmt::format("vehicle type '{}' has no blade (types with one: bulldozer)", vehicle_type_name)};
}

Status Blade::Lower(double depth_m) {
  if (!std::isfinite(depth_m) || depth_m < 0.0 || depth_m > spec_.max_depth_m) {
    return Error{fmt::format("blade depth_m = {} is outside [0, {}]", depth_m, spec_.max_depth_m)};
  }
  depth_m_ = depth_m;
  down_ = true;
  edge_mm_.reset();
  return Status::Ok();
}

namespace {

// Sets `amount` millimetre-posts down evenly on `posts` (at most kMaxPostDeltaMm more on each,
// counting what the tick already put there); returns what did not fit.
int64_t SetDown(PostWindow& w, const std::vector<std::pair<int, int>>& posts, int64_t amount) {
  if (posts.empty() || amount <= 0) return amount;
  const int64_t n = static_cast<int64_t>(posts.size());
  const int64_t share = amount / n;
  int64_t left = amount;
  for (int64_t k = 0; k < n; ++k) {
    auto [i, j] = posts[static_cast<size_t>(k)];
    const int64_t room =
        kMaxPostDeltaMm - std::max<int64_t>(0, w.height_mm(i, j) - w.initial_mm(i, j));
    const int64_t give = std::clamp<int64_t>(share + (k < amount % n ? 1 : 0), 0, room);
    w.height_mm(i, j) += give;
    left -= give;
  }
  return left;
}

}  // namespace

std::vector<PostDelta> Blade::Step(const Terrain& terrain, const FrictionTable& soils, double x_m,
                                   double z_m, double heading_rad, double length_m) {
  const HeightGrid& g = terrain.ground();
  const double s = g.spacing_m();
  const double fx = std::cos(heading_rad), fz = std::sin(heading_rad);
  const double rx = fz, rz = -fx;  // to the right of the heading
  const double edge_x = x_m + fx * length_m / 2.0, edge_z = z_m + fz * length_m / 2.0;
  // How far the edge went forward since the last tick (nothing on the first, or backwards).
  double travel = 0.0;
  if (has_last_)
    travel = std::max(0.0, (edge_x - last_edge_x_) * fx + (edge_z - last_edge_z_) * fz);
  travel = std::min(travel, 4.0 * s);
  has_last_ = true;
  last_edge_x_ = edge_x;
  last_edge_z_ = edge_z;
  last_window_posts_ = 0;
  if (!down_ && load_mm_ == 0) return {};
  if (!g.Contains(x_m, z_m)) return {};

  // The window: the blade, a spacing behind it and two ahead, and a margin to slump in.
  const double half = spec_.width_m / 2.0;
  constexpr int kMarginPosts = 3;
  double min_x = edge_x, max_x = edge_x, min_z = edge_z, max_z = edge_z;
  // The cut reaches a spacing ahead of the edge: the surface under the edge interpolates the
  // posts either side of it, so with only the posts behind it cut, the front of the running gear
  // (which reaches the edge) stood on the slope up to the next, uncut post, and a bulldozer in a
  // berm climbed it (pitched 10-23 degrees, a fifth of its speed).
  const double reach = s;
  for (double a : {reach - travel - s, reach + 2.0 * s}) {
    for (double c : {-half, half}) {
      const double px = edge_x + fx * a + rx * c, pz = edge_z + fz * a + rz * c;
      min_x = std::min(min_x, px);
      max_x = std::max(max_x, px);
      min_z = std::min(min_z, pz);
      max_z = std::max(max_z, pz);
    }
  }
  const int i0 = static_cast<int>(std::floor(min_x / s)) - kMarginPosts;
  const int j0 = static_cast<int>(std::floor(min_z / s)) - kMarginPosts;
  const int i1 = static_cast<int>(std::ceil(max_x / s)) + kMarginPosts;
  const int j1 = static_cast<int>(std::ceil(max_z / s)) + kMarginPosts;
  PostWindow w(terrain, i0, j0, std::min(i1 - i0 + 1, kMaxEarthMoveSpanPosts),
               std::min(j1 - j0 + 1, kMaxEarthMoveSpanPosts));

  last_window_posts_ = w.columns() * w.rows();
  // Posts the edge passed over, and the posts just ahead of it, in (j, i) order.
  std::vector<std::pair<int, int>> swept, ahead;
  for (int j = w.j0(); j < w.j0() + w.rows(); ++j) {
    for (int i = w.i0(); i < w.i0() + w.columns(); ++i) {
      const double dx = i * s - edge_x, dz = j * s - edge_z;
      const double along = dx * fx + dz * fz, across = dx * rx + dz * rz;
      if (std::abs(across) > half) continue;
      if (along <= reach && along > reach - travel) swept.emplace_back(i, j);
      if (along > reach && along <= reach + 1.5 * s) ahead.emplace_back(i, j);
    }
  }

  if (down_) {
    if (!edge_mm_) {
      const double ex = std::clamp(edge_x, 0.0, g.size_x_m()),
                   ez = std::clamp(edge_z, 0.0, g.size_z_m());
      edge_mm_ = std::llround((terrain.ElevationAt(ex, ez) - depth_m_) / kPostDeltaUnitM);
    }
    const int64_t edge_mm = *edge_mm_;
    for (auto [i, j] : swept) {
      const int64_t cut = std::min<int64_t>(w.height_mm(i, j) - edge_mm, kMaxPostDeltaMm);
      if (cut <= 0) continue;
      w.height_mm(i, j) -= cut;
      load_mm_ += cut;
    }
    const auto capacity_mm = static_cast<int64_t>(spec_.capacity_m3 / (s * s) / kPostDeltaUnitM);
    if (load_mm_ > capacity_mm) {
      load_mm_ = capacity_mm + SetDown(w, ahead, load_mm_ - capacity_mm);
    }
  } else {
    load_mm_ = SetDown(w, ahead, load_mm_);
  }
  if (w.Deltas().empty()) return {};  // nothing cut or set down this tick
  Slump(w, [&](Material m) {
    return soils.ReposeRad(m == Material::kFromGround ? Material::kDirt : m);
  });
  return w.Deltas();
}

}  // namespace dt
