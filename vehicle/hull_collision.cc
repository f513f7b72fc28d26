#include "vehicle/hull_collision.h"

#include <cmath>
#include <limits>

namespace dt {

HullPenetration DeepestPenetration(std::span<const Eigen::Vector3d> points,
                                   std::span<const Solid> solids, double max_vertical_m,
                                   bool prefer_top) {
  HullPenetration best;
  for (const Solid& s : solids) {
    const Eigen::Vector3d along(s.ux, 0.0, s.uz);
    const Eigen::Vector3d right(s.uz, 0.0, -s.ux);  // direction d - pi/2
    for (const Eigen::Vector3d& p : points) {
      double a, r;
      s.ToLocal(p.x(), p.z(), a, r);
      if (!s.InPlan(a, r)) continue;
      const double top = s.TopAt(a), bottom = s.BottomAt(a);
      if (!(p.y() < top && p.y() > bottom)) continue;
      // Candidate exits, shortest first wins; ties keep the earlier (fixed order: deterministic).
      // Through a side; through the top or bottom only if within max_vertical_m (a belly or roof
      // grazing a slab); or level along the bridge out from under a sloping bottom (or off a
      // sloping top), towards where that face moves away from the point.
      struct Exit {
        double depth;
        Eigen::Vector3d dir;
      };
      const double bottom_slope = (s.bottom1_m - s.bottom0_m) / (s.a1_m - s.a0_m);
      const double top_slope = s.TopSlope();
      const double inf = std::numeric_limits<double>::infinity();
      const Exit exits[] = {
          {a - s.a0_m, -along},
          {s.a1_m - a, along},
          {r - s.r0_m, -right},
          {s.r1_m - r, right},
          {top - p.y() <= max_vertical_m ? top - p.y() : inf, Eigen::Vector3d::UnitY()},
          {p.y() - bottom <= max_vertical_m ? p.y() - bottom : inf, -Eigen::Vector3d::UnitY()},
          {bottom_slope != 0.0 ? (p.y() - bottom) / std::abs(bottom_slope) : inf,
           bottom_slope > 0.0 ? along : -along},
          {top_slope != 0.0 ? (top - p.y()) / std::abs(top_slope) : inf,
           top_slope > 0.0 ? -along : along}};
      const Exit* pick = &exits[0];
      for (const Exit& e : exits) {
        if (e.depth < pick->depth) pick = &e;
      }
      if (prefer_top && std::isfinite(exits[4].depth)) pick = &exits[4];
      if (pick->depth > best.depth_m) {
        best.hit = true;
        best.depth_m = pick->depth;
        best.normal = pick->dir;
        best.push_m = pick->dir * pick->depth;
        // Down through a sloping underside the face's normal leans with the slope: the velocity
        // into it includes moving along under a ceiling that comes down, which is what drives
        // the point into it step after step.
        if (pick == &exits[5] && bottom_slope != 0.0)
          best.normal = (bottom_slope * along - Eigen::Vector3d::UnitY()).normalized();
        best.point_m = p;
        best.bridge = s.bridge;
      }
    }
  }
  return best;
}

}  // namespace dt
