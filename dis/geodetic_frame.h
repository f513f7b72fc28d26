// GeodeticFrame: the terrain's local east/north/up metres placed on WGS-84, and orientations
// as DIS Euler angles relative to geocentric axes (conversions by GeographicLib).
#pragma once

#include <array>
#include <memory>

#include "dis/dis_pdu.h"
#include "geo/ground_georeference.h"

namespace dt::dis {

// Where the terrain's point (x, y, z) = (0, 0, 0) lies: geodetic latitude and longitude in
// degrees, height in metres above the WGS-84 ellipsoid.
struct GeodeticOrigin {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double height_m = 0.0;
  bool operator==(const GeodeticOrigin&) const = default;
};

// Ranges accepted for an origin: latitude within +-90 deg, longitude within +-180 deg, height
// between the deepest ocean floor and well above any terrain.
inline constexpr double kMinOriginHeightM = -12000.0;
inline constexpr double kMaxOriginHeightM = 100000.0;

// A point in the terrain's axes (docs/conventions.md): x east, y up, z north, metres.
struct LocalPoint {
  double x_m = 0.0;
  double y_m = 0.0;
  double z_m = 0.0;
};

// A vehicle's attitude in the terrain's convention: heading counter-clockwise from east (+x),
// pitch positive nose up, roll positive right side down.
struct LocalAttitude {
  double heading_rad = 0.0;
  double pitch_rad = 0.0;
  double roll_rad = 0.0;
};

// The cosines and sines of a local attitude's angles, made once where they are needed twice
// (the DIS orientation and the dead-reckoning matrix of the same state).
struct AttitudeTrig {
  double cos_heading = 1.0, sin_heading = 0.0;
  double cos_pitch = 1.0, sin_pitch = 0.0;
  double cos_roll = 1.0, sin_roll = 0.0;
};
AttitudeTrig TrigOf(const LocalAttitude& a);

// The terrain is a plane tangent to the ellipsoid at the origin: local x, z, y are the east,
// north and up axes there, for every point of the terrain. Conversions are exact inverses of
// each other (to rounding), which a round trip through DIS relies on.
class GeodeticFrame {
 public:
  // Throws std::invalid_argument for an origin outside the ranges above or not finite.
  explicit GeodeticFrame(const GeodeticOrigin& origin);
  // Ground from an elevation file (docs/real-ground.md): positions go through the ground's own
  // georeference (its projection, exact to PROJ's rounding), so they agree with the file's
  // latitudes and longitudes; heights are y above the ellipsoid. Free vectors and orientations
  // given an entity's AxesAt are in its grid axes (true north turned by the convergence there).
  // `origin` must be the ground's origin.
  GeodeticFrame(const GeodeticOrigin& origin, std::shared_ptr<const GroundGeoreference> ground);

  const GeodeticOrigin& origin() const { return origin_; }

  WorldCoordinates ToGeocentric(const LocalPoint& p) const;
  LocalPoint FromGeocentric(const WorldCoordinates& c) const;

  // Columns: the terrain's x (grid east), z (grid north) and y (up) at `at` in geocentric axes
  // (row-major); the origin's east/north/up without an elevation file, or where the ground's
  // projection cannot place `at`.
  using Axes = std::array<double, 9>;
  Axes AxesAt(const LocalPoint& at) const;

  // Velocities and other free vectors: (x, y, z) local to geocentric and back. Without `axes`,
  // in the axes at the origin; with them, in the terrain's axes at the entity (AxesAt).
  Vector3F VectorToGeocentric(const LocalPoint& v) const;
  LocalPoint VectorFromGeocentric(const Vector3F& v) const;
  Vector3F VectorToGeocentric(const LocalPoint& v, const Axes& axes) const;
  LocalPoint VectorFromGeocentric(const Vector3F& v, const Axes& axes) const;

  // DIS orientation (psi, theta, phi: Z, then Y, then X rotation from the geocentric axes to the
  // body axes x forward, y right, z down) of a local attitude, and back. Back, the heading is in
  // (-pi, pi], pitch in [-pi/2, pi/2], roll in (-pi, pi]; straight up or down (pitch +-90 deg)
  // the heading is ambiguous and roll takes it all. Without `axes`, relative to the axes at the
  // origin; with them, to the terrain's axes at the entity's position (AxesAt): on an elevation
  // file's ground +z is grid north there, which differs from true north by the projection's grid
  // convergence (GridConvergenceRad), and up is the ellipsoid's normal there.
  EulerAngles ToDisOrientation(const LocalAttitude& a) const;
  LocalAttitude FromDisOrientation(const EulerAngles& e) const;
  EulerAngles ToDisOrientation(const LocalAttitude& a, const Axes& axes) const;
  LocalAttitude FromDisOrientation(const EulerAngles& e, const Axes& axes) const;

  // The same in double precision (the PDU carries floats); the same bits from the attitude's
  // trigonometry.
  std::array<double, 3> ToDisAnglesRad(const LocalAttitude& a) const;
  std::array<double, 3> ToDisAnglesRadOf(const AttitudeTrig& t) const;
  EulerAngles ToDisOrientationOf(const AttitudeTrig& t) const;
  LocalAttitude FromDisAnglesRad(double psi, double theta, double phi) const;
  std::array<double, 3> ToDisAnglesRadOf(const AttitudeTrig& t, const Axes& axes) const;
  EulerAngles ToDisOrientationOf(const AttitudeTrig& t, const Axes& axes) const;
  LocalAttitude FromDisAnglesRad(double psi, double theta, double phi, const Axes& axes) const;

  // The true bearing of the terrain's +z (grid north) at `at`, radians clockwise from true
  // north (GeographicLib's meridian convergence gamma for a UTM ground): 0 on the tangent plane
  // of an origin without an elevation file (its axes are the origin's everywhere), and where
  // the ground's projection cannot place `at`.
  double GridConvergenceRad(const LocalPoint& at) const;

 private:
  GeodeticOrigin origin_;
  std::shared_ptr<const GroundGeoreference> ground_;  // null: the tangent plane at the origin
  std::array<double, 3> origin_ecef_{};
  // Columns are the local east, north and up unit vectors in geocentric axes (row-major).
  std::array<double, 9> enu_to_ecef_{};
};

}  // namespace dt::dis
