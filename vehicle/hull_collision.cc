#include "vehicle/hull_collision.h"

namespace dt {

HullPenetration DeepestPenetration(std::span<const Eigen::Vector3d> points,
                                   std::span<const Solid> solids, double max_up_m) {
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
      struct Exit {
        double depth;
        Eigen::Vector3d dir;
      };
      const Exit exits[] = {{a - s.a0_m, -along},
                            {s.a1_m - a, along},
                            {r - s.r0_m, -right},
                            {s.r1_m - r, right},
                            {top - p.y(), Eigen::Vector3d::UnitY()},
                            {p.y() - bottom, -Eigen::Vector3d::UnitY()}};
      const Exit* pick = nullptr;
      for (const Exit& e : exits) {
        if (&e == &exits[4] && e.depth > max_up_m) continue;
        if (pick == nullptr || e.depth < pick->depth) pick = &e;
      }
      if (pick->depth > best.depth_m) {
        best.hit = true;
        best.depth_m = pick->depth;
        best.normal = pick->dir;
        best.push_m = pick->dir * pick->depth;
        best.bridge = s.bridge;
      }
    }
  }
  return best;
}

}  // namespace dt
