#include "vehicle/bridge_solids.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace dt {

std::vector<Solid> BridgeSolidPlans(const FeatureParams& p) {
  Solid base;
  base.origin_x_m = p.x_m;
  base.origin_z_m = p.z_m;
  base.ux = std::cos(p.direction_rad);
  base.uz = std::sin(p.direction_rad);
  const double half_w = p.width_m / 2.0;
  const double span = p.length_m[0];
  const bool destroyed = p.status == BridgeStatus::kDestroyed;
  std::vector<Solid> out;
  auto plan = [&](double a0, double a1, double r0, double r1, bool deck) {
    Solid s = base;
    s.a0_m = a0;
    s.a1_m = a1;
    s.r0_m = r0;
    s.r1_m = r1;
    s.deck = deck;
    out.push_back(s);
  };
  // The deck slabs: ramp 1, the span (intact only), ramp 2.
  plan(-p.length_m[1], 0.0, -half_w, half_w, true);
  if (!destroyed) plan(0.0, span, -half_w, half_w, true);
  plan(span, span + p.length_m[2], -half_w, half_w, true);
  // Piers under both deck edges at both joints.
  const double pier = std::min(kPierWidthM, half_w);
  for (const double along : {0.0, span}) {
    for (const double r0 : {-half_w, half_w - pier})
      plan(along - pier / 2.0, along + pier / 2.0, r0, r0 + pier, false);
  }
  // The fallen span between the piers.
  if (destroyed) {
    const double a0 = std::min(pier / 2.0, span / 4.0);
    plan(a0, span - a0, -half_w, half_w, false);
    out.back().rubble = true;
  }
  return out;
}

std::vector<Solid> BridgeSolids(const Bridge& b, const HeightGrid& ground) {
  const FeatureParams p = b.params();
  std::vector<Solid> out = BridgeSolidPlans(p);
  auto ground_at = [&](double along_m, double right_m) {
    // Right of direction d is (sin d, -cos d) = (uz, -ux).
    const Solid& f = out.front();
    const double x = p.x_m + along_m * f.ux + right_m * f.uz;
    const double z = p.z_m + along_m * f.uz - right_m * f.ux;
    return ground.ElevationAt(std::clamp(x, 0.0, ground.size_x_m()),
                              std::clamp(z, 0.0, ground.size_z_m()));
  };
  const std::vector<DeckSection> profile = b.DeckProfile();  // 4 intact, 6 destroyed
  const double foot1 = profile.front().elevation_m, foot2 = profile.back().elevation_m;
  const double top1 = profile[1].elevation_m;
  const double top2 = profile[profile.size() - 2].elevation_m;
  const double span = b.span_length_m();
  // The plans come in BridgeSolidPlans' order: ramp 1, span (intact), ramp 2, four piers,
  // rubble (destroyed).
  size_t k = 0;
  auto slab = [&](double t0, double t1) {
    Solid& s = out[k++];
    s.top0_m = t0;
    s.top1_m = t1;
    s.bottom0_m = t0 - kDeckThicknessM;
    s.bottom1_m = t1 - kDeckThicknessM;
  };
  slab(foot1, top1);
  if (!b.destroyed()) slab(top1, top2);
  slab(top2, foot2);
  // Piers from below the ground to the slab's underside.
  for (const auto& [along, top] : {std::pair{0.0, top1}, std::pair{span, top2}}) {
    for (int side = 0; side < 2; ++side) {
      Solid& s = out[k++];
      const double g = std::min(ground_at(along, s.r0_m), ground_at(along, s.r1_m));
      s.bottom0_m = s.bottom1_m = g - 1.0;
      s.top0_m = s.top1_m = std::max(g, top - kDeckThicknessM);
    }
  }
  if (b.destroyed()) {
    // Rubble never higher than the deck's underside at the joints, so falling from a joint is a
    // drop.
    Solid& s = out[k++];
    const double g1 = ground_at(0.0, 0.0), g2 = ground_at(span, 0.0);
    const double lowest_deck = std::min(top1 - g1, top2 - g2);
    const double h = std::clamp(lowest_deck - kDeckThicknessM, 0.05, kRubbleHeightM);
    const double ga = ground_at(s.a0_m, 0.0), gb = ground_at(s.a1_m, 0.0);
    s.top0_m = ga + h;
    s.top1_m = gb + h;
    s.bottom0_m = ga - 1.0;
    s.bottom1_m = gb - 1.0;
  }
  for (Solid& s : out) {
    s.bridge = b.id();
    s.material = b.material();
  }
  return out;
}

Rect PlanBounds(const Solid& s) {
  // From the bridge frame back to the ground: (dx, dz) = along (ux, uz) + right (uz, -ux).
  Rect out{INFINITY, INFINITY, -INFINITY, -INFINITY};
  for (const double a : {s.a0_m, s.a1_m}) {
    for (const double r : {s.r0_m, s.r1_m}) {
      const double x = s.origin_x_m + a * s.ux + r * s.uz;
      const double z = s.origin_z_m + a * s.uz - r * s.ux;
      out = out.Union(Rect{x, z, x, z});
    }
  }
  return out;
}

std::vector<Solid> SolidsNear(const Terrain& terrain, const Rect& area) {
  std::vector<Solid> out;
  SolidsNear(terrain, area, out);
  return out;
}

void SolidsNear(const Terrain& terrain, const Rect& area, std::vector<Solid>& out) {
  out.clear();
  const HeightGrid& g = terrain.ground();
  const double sx = g.size_x_m(), sz = g.size_z_m();
  const SquareIndex lo =
      g.SquareAt(std::clamp(area.min_x, 0.0, sx), std::clamp(area.min_z, 0.0, sz));
  const SquareIndex hi =
      g.SquareAt(std::clamp(area.max_x, 0.0, sx), std::clamp(area.max_z, 0.0, sz));
  // Bridges are few: gathered in a small array, sorted by ID, duplicates (one bridge indexed in
  // several squares) dropped.
  std::array<const Bridge*, 16> bridges;
  size_t count = 0;
  for (int j = lo.j; j <= hi.j; ++j) {
    for (int i = lo.i; i <= hi.i; ++i) {
      if (terrain.SquareBits({i, j}) == 0) continue;
      for (const Feature* f : terrain.FeaturesInSquare({i, j})) {
        if (f->type() != FeatureType::kBridge) continue;
        const auto* b = static_cast<const Bridge*>(f);
        if (std::find(bridges.begin(), bridges.begin() + count, b) != bridges.begin() + count)
          continue;
        if (count < bridges.size()) bridges[count++] = b;
      }
    }
  }
  std::sort(bridges.begin(), bridges.begin() + count,
            [](const Bridge* x, const Bridge* y) { return x->id() < y->id(); });
  for (size_t k = 0; k < count; ++k) {
    std::vector<Solid> s = BridgeSolids(*bridges[k], g);
    out.insert(out.end(), s.begin(), s.end());
  }
}

}  // namespace dt
