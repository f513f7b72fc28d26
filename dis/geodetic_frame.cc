#include "dis/geodetic_frame.h"

#include <fmt/format.h>
#include <GeographicLib/Geocentric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace dt::dis {
namespace {

using Vec = std::array<double, 3>;

Vec Cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double Dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Body axes (forward, right, down) in east/north/up of a local attitude.
struct BodyAxes {
  Vec forward, right, down;
};
BodyAxes AxesOf(const AttitudeTrig& t) {
  const double ch = t.cos_heading, sh = t.sin_heading;
  const double cp = t.cos_pitch, sp = t.sin_pitch;
  const double cr = t.cos_roll, sr = t.sin_roll;
  const Vec forward = {cp * ch, cp * sh, sp};
  const Vec level_right = {sh, -ch, 0.0};  // direction heading - pi/2, on the ground plane
  const Vec level_down = Cross(forward, level_right);
  BodyAxes axes;
  axes.forward = forward;
  // Positive roll turns the right axis towards down (right side down).
  for (int i = 0; i < 3; ++i) {
    axes.right[i] = cr * level_right[i] + sr * level_down[i];
    axes.down[i] = -sr * level_right[i] + cr * level_down[i];
  }
  return axes;
}

LocalAttitude AttitudeOf(const Vec& forward, const Vec& right) {
  LocalAttitude a;
  const double up = std::clamp(forward[2], -1.0, 1.0);
  a.pitch_rad = std::asin(up);
  // forward is a unit vector, so its ground part cannot overflow: no need for hypot.
  const double horizontal = std::sqrt(forward[0] * forward[0] + forward[1] * forward[1]);
  Vec level_right;
  if (horizontal > 1e-12) {
    a.heading_rad = std::atan2(forward[1], forward[0]);
    // The heading's sine and cosine are the ground direction itself: no sin/cos of the angle.
    level_right = {forward[1] / horizontal, -forward[0] / horizontal, 0.0};
  } else {
    // Straight up or down: heading 0 and the whole rotation about the vertical goes to roll.
    a.heading_rad = 0.0;
    level_right = {0.0, -1.0, 0.0};
  }
  const Vec level_down = Cross(forward, level_right);
  a.roll_rad = std::atan2(Dot(right, level_down), Dot(right, level_right));
  return a;
}

}  // namespace

AttitudeTrig TrigOf(const LocalAttitude& a) {
  AttitudeTrig t;
  t.cos_heading = std::cos(a.heading_rad);
  t.sin_heading = std::sin(a.heading_rad);
  t.cos_pitch = std::cos(a.pitch_rad);
  t.sin_pitch = std::sin(a.pitch_rad);
  t.cos_roll = std::cos(a.roll_rad);
  t.sin_roll = std::sin(a.roll_rad);
  return t;
}

GeodeticFrame::GeodeticFrame(const GeodeticOrigin& o) : origin_(o) {
  if (!std::isfinite(o.latitude_deg) || std::abs(o.latitude_deg) > 90.0) {
    throw std::invalid_argument(
        fmt::format("geodetic origin latitude {} deg outside [-90, 90]", o.latitude_deg));
  }
  if (!std::isfinite(o.longitude_deg) || std::abs(o.longitude_deg) > 180.0) {
    throw std::invalid_argument(
        fmt::format("geodetic origin longitude {} deg outside [-180, 180]", o.longitude_deg));
  }
  if (!std::isfinite(o.height_m) || o.height_m < kMinOriginHeightM ||
      o.height_m > kMaxOriginHeightM) {
    throw std::invalid_argument(fmt::format("geodetic origin height {} m outside [{}, {}]",
                                            o.height_m, kMinOriginHeightM, kMaxOriginHeightM));
  }
  std::vector<double> m(9);
  GeographicLib::Geocentric::WGS84().Forward(o.latitude_deg, o.longitude_deg, o.height_m,
                                             origin_ecef_[0], origin_ecef_[1], origin_ecef_[2], m);
  // GeographicLib: geocentric = M * (east, north, up).
  std::copy(m.begin(), m.end(), enu_to_ecef_.begin());
}

GeodeticFrame::GeodeticFrame(const GeodeticOrigin& origin,
                             std::shared_ptr<const GroundGeoreference> ground)
    : GeodeticFrame(origin) {
  ground_ = std::move(ground);
}

WorldCoordinates GeodeticFrame::ToGeocentric(const LocalPoint& p) const {
  if (ground_) {
    const GeodeticPoint g = ground_->ToGeodetic(p.x_m, p.y_m, p.z_m);
    WorldCoordinates c;
    GeographicLib::Geocentric::WGS84().Forward(g.latitude_deg, g.longitude_deg, g.height_m, c.x,
                                               c.y, c.z);
    return c;
  }
  const Vec enu = {p.x_m, p.z_m, p.y_m};
  const auto& m = enu_to_ecef_;
  WorldCoordinates c;
  c.x = origin_ecef_[0] + m[0] * enu[0] + m[1] * enu[1] + m[2] * enu[2];
  c.y = origin_ecef_[1] + m[3] * enu[0] + m[4] * enu[1] + m[5] * enu[2];
  c.z = origin_ecef_[2] + m[6] * enu[0] + m[7] * enu[1] + m[8] * enu[2];
  return c;
}

LocalPoint GeodeticFrame::FromGeocentric(const WorldCoordinates& c) const {
  if (ground_) {
    double lat = 0, lon = 0, h = 0;
    GeographicLib::Geocentric::WGS84().Reverse(c.x, c.y, c.z, lat, lon, h);
    const std::array<double, 2> xz = ground_->FromGeodetic(lat, lon);
    return {xz[0], h, xz[1]};
  }
  const Vec d = {c.x - origin_ecef_[0], c.y - origin_ecef_[1], c.z - origin_ecef_[2]};
  const auto& m = enu_to_ecef_;
  // The inverse of a rotation is its transpose.
  const double e = m[0] * d[0] + m[3] * d[1] + m[6] * d[2];
  const double n = m[1] * d[0] + m[4] * d[1] + m[7] * d[2];
  const double u = m[2] * d[0] + m[5] * d[1] + m[8] * d[2];
  return {e, u, n};
}

namespace {

using Axes = GeodeticFrame::Axes;

Vector3F ToEcef(const Axes& m, const LocalPoint& v) {
  const Vec enu = {v.x_m, v.z_m, v.y_m};
  return {static_cast<float>(m[0] * enu[0] + m[1] * enu[1] + m[2] * enu[2]),
          static_cast<float>(m[3] * enu[0] + m[4] * enu[1] + m[5] * enu[2]),
          static_cast<float>(m[6] * enu[0] + m[7] * enu[1] + m[8] * enu[2])};
}

LocalPoint FromEcef(const Axes& m, const Vector3F& v) {
  const Vec d = {v.x, v.y, v.z};
  const double e = m[0] * d[0] + m[3] * d[1] + m[6] * d[2];
  const double n = m[1] * d[0] + m[4] * d[1] + m[7] * d[2];
  const double u = m[2] * d[0] + m[5] * d[1] + m[8] * d[2];
  return {e, u, n};
}

std::array<double, 3> DisAngles(const Axes& m, const AttitudeTrig& t) {
  const BodyAxes b = AxesOf(t);
  auto to_ecef = [&m](const Vec& v) {
    return Vec{m[0] * v[0] + m[1] * v[1] + m[2] * v[2], m[3] * v[0] + m[4] * v[1] + m[5] * v[2],
               m[6] * v[0] + m[7] * v[1] + m[8] * v[2]};
  };
  // R = Rz(psi) Ry(theta) Rx(phi) has the body axes in geocentric axes as its columns.
  const Vec f = to_ecef(b.forward), r = to_ecef(b.right), d = to_ecef(b.down);
  const double theta = std::asin(std::clamp(-f[2], -1.0, 1.0));
  double psi, phi;
  if (std::abs(f[2]) < 1.0 - 1e-12) {
    psi = std::atan2(f[1], f[0]);
    phi = std::atan2(r[2], d[2]);
  } else {
    // Gimbal lock: the X and Z rotations are about the same axis; psi takes the whole of it.
    phi = 0.0;
    psi = std::atan2(-r[0], r[1]);
  }
  return {psi, theta, phi};
}

LocalAttitude AttitudeOfDis(const Axes& m, double psi, double theta, double phi) {
  const double cps = std::cos(psi), sps = std::sin(psi);
  const double ct = std::cos(theta), st = std::sin(theta);
  const double cph = std::cos(phi), sph = std::sin(phi);
  // Columns of Rz(psi) Ry(theta) Rx(phi): forward (x) and right (y) body axes, geocentric.
  const Vec f = {cps * ct, sps * ct, -st};
  const Vec r = {cps * st * sph - sps * cph, sps * st * sph + cps * cph, ct * sph};
  auto to_enu = [&m](const Vec& v) {
    return Vec{m[0] * v[0] + m[3] * v[1] + m[6] * v[2], m[1] * v[0] + m[4] * v[1] + m[7] * v[2],
               m[2] * v[0] + m[5] * v[1] + m[8] * v[2]};
  };
  return AttitudeOf(to_enu(f), to_enu(r));
}

EulerAngles ToFloat(const std::array<double, 3>& a) {
  return {static_cast<float>(a[0]), static_cast<float>(a[1]), static_cast<float>(a[2])};
}

bool Finite(const GeodeticPoint& g) {
  return std::isfinite(g.latitude_deg) && std::isfinite(g.longitude_deg) &&
         std::isfinite(g.height_m);
}

// Half the baseline over which grid north is measured: long enough that PROJ's rounding (well
// under a millimetre) moves the angle by under 1e-5 rad, short enough that the convergence's
// change along it (about 1e-5 rad per km) does not count.
constexpr double kGridNorthHalfBaselineM = 50.0;

}  // namespace

double GeodeticFrame::GridConvergenceRad(const LocalPoint& at) const {
  if (!ground_) return 0.0;
  const GeodeticPoint g = ground_->ToGeodetic(at.x_m, at.y_m, at.z_m);
  const GeodeticPoint south = ground_->ToGeodetic(at.x_m, at.y_m, at.z_m - kGridNorthHalfBaselineM);
  const GeodeticPoint north = ground_->ToGeodetic(at.x_m, at.y_m, at.z_m + kGridNorthHalfBaselineM);
  if (!Finite(g) || !Finite(south) || !Finite(north)) return 0.0;
  const auto& earth = GeographicLib::Geocentric::WGS84();
  std::vector<double> m(9);
  double x = 0, y = 0, z = 0, sx = 0, sy = 0, sz = 0, nx = 0, ny = 0, nz = 0;
  earth.Forward(g.latitude_deg, g.longitude_deg, g.height_m, x, y, z, m);
  earth.Forward(south.latitude_deg, south.longitude_deg, south.height_m, sx, sy, sz);
  earth.Forward(north.latitude_deg, north.longitude_deg, north.height_m, nx, ny, nz);
  const Vec d = {nx - sx, ny - sy, nz - sz};
  // Grid north's east and north parts at `at` (M's columns are east, north, up).
  const double east = m[0] * d[0] + m[3] * d[1] + m[6] * d[2];
  const double true_north = m[1] * d[0] + m[4] * d[1] + m[7] * d[2];
  return std::atan2(east, true_north);
}

GeodeticFrame::Axes GeodeticFrame::AxesAt(const LocalPoint& at) const {
  if (!ground_) return enu_to_ecef_;
  const GeodeticPoint g = ground_->ToGeodetic(at.x_m, at.y_m, at.z_m);
  if (!Finite(g)) return enu_to_ecef_;  // network input: never throws
  std::vector<double> m(9);
  double x = 0, y = 0, z = 0;
  GeographicLib::Geocentric::WGS84().Forward(g.latitude_deg, g.longitude_deg, g.height_m, x, y, z,
                                             m);
  // Grid north is true north turned clockwise by gamma, grid east likewise (a conformal
  // projection keeps them square): (east, north) parts (sin g, cos g) and (cos g, -sin g).
  const double gamma = GridConvergenceRad(at);
  const double c = std::cos(gamma), s = std::sin(gamma);
  Axes out{};
  for (int row = 0; row < 3; ++row) {
    const double e = m[row * 3 + 0], n = m[row * 3 + 1], u = m[row * 3 + 2];
    out[row * 3 + 0] = c * e - s * n;
    out[row * 3 + 1] = s * e + c * n;
    out[row * 3 + 2] = u;
  }
  return out;
}

Vector3F GeodeticFrame::VectorToGeocentric(const LocalPoint& v) const {
  return ToEcef(enu_to_ecef_, v);
}
LocalPoint GeodeticFrame::VectorFromGeocentric(const Vector3F& v) const {
  return FromEcef(enu_to_ecef_, v);
}
Vector3F GeodeticFrame::VectorToGeocentric(const LocalPoint& v, const Axes& axes) const {
  return ToEcef(axes, v);
}
LocalPoint GeodeticFrame::VectorFromGeocentric(const Vector3F& v, const Axes& axes) const {
  return FromEcef(axes, v);
}

std::array<double, 3> GeodeticFrame::ToDisAnglesRad(const LocalAttitude& a) const {
  return ToDisAnglesRadOf(TrigOf(a));
}
std::array<double, 3> GeodeticFrame::ToDisAnglesRadOf(const AttitudeTrig& t) const {
  return DisAngles(enu_to_ecef_, t);
}
std::array<double, 3> GeodeticFrame::ToDisAnglesRadOf(const AttitudeTrig& t,
                                                      const Axes& axes) const {
  return DisAngles(axes, t);
}

LocalAttitude GeodeticFrame::FromDisAnglesRad(double psi, double theta, double phi) const {
  return AttitudeOfDis(enu_to_ecef_, psi, theta, phi);
}
LocalAttitude GeodeticFrame::FromDisAnglesRad(double psi, double theta, double phi,
                                              const Axes& axes) const {
  return AttitudeOfDis(axes, psi, theta, phi);
}

EulerAngles GeodeticFrame::ToDisOrientation(const LocalAttitude& a) const {
  return ToDisOrientationOf(TrigOf(a));
}
EulerAngles GeodeticFrame::ToDisOrientation(const LocalAttitude& a, const Axes& axes) const {
  return ToDisOrientationOf(TrigOf(a), axes);
}
EulerAngles GeodeticFrame::ToDisOrientationOf(const AttitudeTrig& t) const {
  return ToFloat(ToDisAnglesRadOf(t));
}
EulerAngles GeodeticFrame::ToDisOrientationOf(const AttitudeTrig& t, const Axes& axes) const {
  return ToFloat(ToDisAnglesRadOf(t, axes));
}

LocalAttitude GeodeticFrame::FromDisOrientation(const EulerAngles& e) const {
  return FromDisAnglesRad(e.psi, e.theta, e.phi);
}
LocalAttitude GeodeticFrame::FromDisOrientation(const EulerAngles& e, const Axes& axes) const {
  return FromDisAnglesRad(e.psi, e.theta, e.phi, axes);
}

}  // namespace dt::dis
