#include "render/bridge_mesh.h"

#include <array>
#include <cmath>

#include "render/palette.h"
#include "vehicle/bridge_solids.h"

namespace dt {
namespace {

// A destroyed span's rubble is drawn darker than the standing concrete: from above, its top is
// otherwise the colour of an intact span's deck.
constexpr double kRubbleShade = 0.55;

void Face(Mesh& mesh, const Colour& base, const Eigen::Vector3d& normal, const Eigen::Vector3d& a,
          const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  mesh.AddQuad(a, b, c, d, ToRgba(base, ShadeFactor(normal)));
}

// The six faces of a solid: its top and bottom are linear along the bridge, so every face is
// planar.
void AppendSolid(const Solid& s, const Colour& base, Mesh& mesh) {
  const Eigen::Vector3d along(s.ux, 0.0, s.uz);
  const Eigen::Vector3d right(s.uz, 0.0, -s.ux);  // direction - pi/2 (docs/conventions.md)
  auto at = [&](double a, double r, bool top) {
    const double y =
        top ? (a == s.a0_m ? s.top0_m : s.top1_m) : (a == s.a0_m ? s.bottom0_m : s.bottom1_m);
    return Eigen::Vector3d(s.origin_x_m + a * s.ux + r * s.uz, y,
                           s.origin_z_m + a * s.uz - r * s.ux);
  };
  const double a0 = s.a0_m, a1 = s.a1_m, r0 = s.r0_m, r1 = s.r1_m;
  const Eigen::Vector3d t00 = at(a0, r0, true), t10 = at(a1, r0, true), t11 = at(a1, r1, true),
                        t01 = at(a0, r1, true);
  const Eigen::Vector3d b00 = at(a0, r0, false), b10 = at(a1, r0, false), b11 = at(a1, r1, false),
                        b01 = at(a0, r1, false);
  Face(mesh, base, UpwardNormal(t00, t10, t11), t00, t10, t11, t01);
  Face(mesh, base, -Eigen::Vector3d::UnitY(), b00, b01, b11, b10);
  Face(mesh, base, -right, t00, b00, b10, t10);
  Face(mesh, base, right, t01, t11, b11, b01);
  Face(mesh, base, -along, t00, t01, b01, b00);
  Face(mesh, base, along, t10, b10, b11, t11);
}

}  // namespace

void AppendBridge(const Bridge& bridge, const Terrain& terrain, Mesh& mesh) {
  const Colour base = MaterialColour(bridge.material());
  const Colour rubble = base * kRubbleShade;
  for (const Solid& s : BridgeSolids(bridge, terrain.ground()))
    AppendSolid(s, s.rubble ? rubble : base, mesh);
}

}  // namespace dt
