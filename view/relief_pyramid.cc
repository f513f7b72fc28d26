#include "view/relief_pyramid.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace dt {

std::string TileKey::ToString() const { return fmt::format("{}/{}/{}", level, tx, tz); }

ReliefPyramid::ReliefPyramid(double size_x_m, double size_z_m, double spacing_m)
    : size_x_m_(size_x_m), size_z_m_(size_z_m), spacing_m_(spacing_m) {
  if (!(size_x_m > 0.0) || !(size_z_m > 0.0) || !(spacing_m > 0.0) || !std::isfinite(size_x_m) ||
      !std::isfinite(size_z_m) || !std::isfinite(spacing_m)) {
    throw std::invalid_argument(fmt::format(
        "relief pyramid of {} x {} m at {} m spacing: sizes and spacing must be finite and > 0",
        size_x_m, size_z_m, spacing_m));
  }
  side0_m_ = std::max(size_x_m, size_z_m);
  // 30 levels reach a 2^-30 of the side: far below any spacing an exercise allows.
  while (levels_ < 30 && metres_per_pixel(levels_ - 1) > spacing_m_) ++levels_;
}

double ReliefPyramid::side_m(int level) const { return std::ldexp(side0_m_, -level); }

int ReliefPyramid::tiles_x(int level) const {
  return std::max(1, static_cast<int>(std::ceil(size_x_m_ / side_m(level) - 1e-9)));
}

int ReliefPyramid::tiles_z(int level) const {
  return std::max(1, static_cast<int>(std::ceil(size_z_m_ / side_m(level) - 1e-9)));
}

bool ReliefPyramid::Valid(const TileKey& key) const {
  return key.level >= 0 && key.level < levels_ && key.tx >= 0 && key.tz >= 0 &&
         key.tx < tiles_x(key.level) && key.tz < tiles_z(key.level);
}

Rect ReliefPyramid::TileRect(const TileKey& key) const {
  const double s = side_m(key.level);
  return {key.tx * s, key.tz * s, (key.tx + 1) * s, (key.tz + 1) * s};
}

int ReliefPyramid::SampleStride(int level) const {
  return std::max(1, static_cast<int>(std::floor(metres_per_pixel(level) / spacing_m_ + 1e-9)));
}

std::vector<TileKey> ReliefPyramid::TilesOver(const Rect& area, int level) const {
  std::vector<TileKey> out;
  if (!(area.max_x >= 0.0 && area.max_z >= 0.0 && area.min_x <= size_x_m_ &&
        area.min_z <= size_z_m_)) {
    return out;
  }
  const double s = side_m(level);
  auto index = [s](double v, int count) {
    return std::clamp(static_cast<int>(std::floor(std::max(0.0, v) / s)), 0, count - 1);
  };
  const int nx = tiles_x(level), nz = tiles_z(level);
  for (int tz = index(area.min_z, nz); tz <= index(area.max_z, nz); ++tz) {
    for (int tx = index(area.min_x, nx); tx <= index(area.max_x, nx); ++tx)
      out.push_back({level, tx, tz});
  }
  return out;
}

std::vector<TileKey> ReliefPyramid::TilesChangedBy(const Rect& area) const {
  std::vector<TileKey> out;
  for (int level = 0; level < levels_; ++level) {
    const auto over = TilesOver(area.Expanded(SampleStride(level) * spacing_m_), level);
    out.insert(out.end(), over.begin(), over.end());
  }
  return out;
}

Result<TileKey> ParseTileKey(std::string_view text, const ReliefPyramid& pyramid) {
  std::string_view rest = text;
  if (rest.ends_with(".png")) rest.remove_suffix(4);
  int v[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    const char* end = rest.data() + rest.size();
    auto [p, ec] = std::from_chars(rest.data(), end, v[k]);
    const bool last = k == 2;
    if (ec != std::errc{} || p == rest.data() || (last ? p != end : (p == end || *p != '/'))) {
      return Error{fmt::format("relief tile \"{}\" is not level/x/z", text)};
    }
    rest.remove_prefix(static_cast<size_t>(p - rest.data()) + (last ? 0 : 1));
  }
  const TileKey key{v[0], v[1], v[2]};
  if (!pyramid.Valid(key)) {
    return Error{fmt::format("relief tile {} is not one of this terrain's ({} levels)",
                             key.ToString(), pyramid.levels())};
  }
  return key;
}

}  // namespace dt
