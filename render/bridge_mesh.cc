#include "render/bridge_mesh.h"

#include <cmath>

#include "render/palette.h"

namespace dt {
namespace {

struct Frame {
  Eigen::Vector3d origin;  // joint of ramp 1 and the span, on y = 0
  Eigen::Vector3d along;   // unit, horizontal
  Eigen::Vector3d right;   // unit, horizontal: direction - pi/2 (docs/conventions.md)

  Eigen::Vector3d At(double along_m, double right_m, double y_m) const {
    Eigen::Vector3d p = origin + along_m * along + right_m * right;
    p.y() = y_m;
    return p;
  }
};

void Face(Mesh& mesh, const Colour& base, const Eigen::Vector3d& normal, const Eigen::Vector3d& a,
          const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  mesh.AddQuad(a, b, c, d, ToRgba(base, ShadeFactor(normal)));
}

}  // namespace

void AppendBridge(const Bridge& bridge, const Terrain& terrain, Mesh& mesh) {
  const FeatureParams p = bridge.params();
  const double d = p.direction_rad;
  const Frame f{Eigen::Vector3d(p.x_m, 0.0, p.z_m), Eigen::Vector3d(std::cos(d), 0.0, std::sin(d)),
                Eigen::Vector3d(std::sin(d), 0.0, -std::cos(d))};
  const double half = 0.5 * bridge.width_m();
  const Colour base = MaterialColour(bridge.material());
  const std::vector<DeckSection> profile = bridge.DeckProfile();
  for (size_t k = 0; k + 1 < profile.size(); ++k) {
    const DeckSection& s0 = profile[k];
    const DeckSection& s1 = profile[k + 1];
    if (s1.along_m <= s0.along_m) continue;  // the zero-length break of a destroyed span
    const Eigen::Vector3d l0 = f.At(s0.along_m, -half, s0.elevation_m);
    const Eigen::Vector3d r0 = f.At(s0.along_m, half, s0.elevation_m);
    const Eigen::Vector3d l1 = f.At(s1.along_m, -half, s1.elevation_m);
    const Eigen::Vector3d r1 = f.At(s1.along_m, half, s1.elevation_m);
    Face(mesh, base, UpwardNormal(l0, r0, r1), l0, r0, r1, l1);
    const Eigen::Vector3d down(0.0, kBridgeDeckThicknessM, 0.0);
    Face(mesh, base, f.right, r0, r1, r1 - down, r0 - down);
    Face(mesh, base, -f.right, l0, l1, l1 - down, l0 - down);
  }
  // Piers under the two joints, which stand whatever the status (the span breaks between them).
  for (const DeckSection& s : profile) {
    if (s.along_m != 0.0 && s.along_m != bridge.span_length_m()) continue;
    const double top = s.elevation_m - kBridgeDeckThicknessM;
    const double a0 = s.along_m - 0.5 * kBridgePierThicknessM;
    const double a1 = s.along_m + 0.5 * kBridgePierThicknessM;
    auto ground = [&](double along_m, double right_m) {
      const Eigen::Vector3d q = f.At(along_m, right_m, 0.0);
      return terrain.Contains(q.x(), q.z()) ? terrain.GroundElevationAt(q.x(), q.z()) : top;
    };
    const double g =
        std::min({ground(a0, -half), ground(a0, half), ground(a1, -half), ground(a1, half)});
    if (!(top > g)) continue;
    Face(mesh, base, -f.along, f.At(a0, -half, top), f.At(a0, half, top), f.At(a0, half, g),
         f.At(a0, -half, g));
    Face(mesh, base, f.along, f.At(a1, -half, top), f.At(a1, half, top), f.At(a1, half, g),
         f.At(a1, -half, g));
    Face(mesh, base, f.right, f.At(a0, half, top), f.At(a1, half, top), f.At(a1, half, g),
         f.At(a0, half, g));
    Face(mesh, base, -f.right, f.At(a0, -half, top), f.At(a1, -half, top), f.At(a1, -half, g),
         f.At(a0, -half, g));
  }
}

}  // namespace dt
