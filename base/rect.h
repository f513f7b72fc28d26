// Rect: an axis-aligned rectangle on the ground plane (x, z), in metres.
#pragma once

#include <algorithm>

namespace dt {

struct Rect {
  double min_x = 0.0;
  double min_z = 0.0;
  double max_x = 0.0;
  double max_z = 0.0;

  bool Contains(double x, double z) const {
    return x >= min_x && x <= max_x && z >= min_z && z <= max_z;
  }
  bool Intersects(const Rect& o) const {
    return min_x <= o.max_x && o.min_x <= max_x && min_z <= o.max_z && o.min_z <= max_z;
  }
  Rect Expanded(double margin_m) const {
    return {min_x - margin_m, min_z - margin_m, max_x + margin_m, max_z + margin_m};
  }
  Rect Union(const Rect& o) const {
    return {std::min(min_x, o.min_x), std::min(min_z, o.min_z), std::max(max_x, o.max_x),
            std::max(max_z, o.max_z)};
  }
};

}  // namespace dt
