// GroundGeoreference: where the terrain's local x (east), z (north), y (up) lie on WGS-84.
#pragma once

#include <array>
#include <memory>
#include <string>

namespace dt {

// A geodetic position: WGS-84 latitude and longitude in degrees, height in metres.
struct GeodeticPoint {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double height_m = 0.0;
};

// The terrain's ground plane is a metric map projection (the file's own when it is projected in
// metres, else an orthographic projection on WGS-84 at the area's centre: the east-north plane
// tangent there, docs/conventions.md "Real ground"); terrain (x, z) is that projection's
// (x0 + x, z0 + z). Heights are y, above the ellipsoid (docs/real-ground.md says what is left out).
// Conversions are serialised by a mutex: GDAL's transformations are not thread-safe.
class GroundGeoreference {
 public:
  // Throws std::invalid_argument if the CRS cannot be read or transformed to WGS-84.
  GroundGeoreference(const std::string& local_crs_wkt, double x0, double z0,
                     std::string description);
  ~GroundGeoreference();
  GroundGeoreference(const GroundGeoreference&) = delete;
  GroundGeoreference& operator=(const GroundGeoreference&) = delete;

  // Terrain (x, y, z) on WGS-84 (height = y). NaN latitude and longitude where PROJ cannot
  // (never inside the area; these serve network input, which must not throw).
  GeodeticPoint ToGeodetic(double x_m, double y_m, double z_m) const;
  // The terrain {x, z} of a latitude and longitude; NaN where PROJ cannot (the far side of the
  // Earth from a tangent plane).
  std::array<double, 2> FromGeodetic(double latitude_deg, double longitude_deg) const;
  // Terrain (0, 0, 0) on WGS-84: the exercise's geodetic origin.
  GeodeticPoint origin() const { return origin_; }
  // "WGS 84 / UTM zone 33N" or "tangent plane at 47.1 N 8.2 E", for logs and messages.
  const std::string& description() const { return description_; }
  const std::string& local_crs_wkt() const { return wkt_; }
  double x0() const { return x0_; }
  double z0() const { return z0_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string wkt_;
  double x0_;
  double z0_;
  std::string description_;
  GeodeticPoint origin_;
};

// The straight-line (geocentric) distance between two geodetic points, metres.
double GeocentricDistanceM(const GeodeticPoint& a, const GeodeticPoint& b);

}  // namespace dt
