#include "geo/ground_georeference.h"

#include <cmath>
#include <mutex>
#include <stdexcept>

#include <cpl_error.h>
#include <fmt/format.h>
#include <ogr_spatialref.h>
#include <GeographicLib/Geocentric.hpp>

namespace dt {

struct GroundGeoreference::Impl {
  OGRSpatialReference local;
  OGRSpatialReference wgs84;
  std::unique_ptr<OGRCoordinateTransformation> to_wgs84;
  std::unique_ptr<OGRCoordinateTransformation> from_wgs84;
  std::mutex mutex;
};

GroundGeoreference::GroundGeoreference(const std::string& local_crs_wkt, double x0, double z0,
                                       std::string description)
    : impl_(std::make_unique<Impl>()),
      wkt_(local_crs_wkt),
      x0_(x0),
      z0_(z0),
      description_(std::move(description)) {
  // Longitude first, easting first, whatever the CRS's authority says.
  impl_->local.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  impl_->wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  if (impl_->local.importFromWkt(wkt_.c_str()) != OGRERR_NONE ||
      impl_->wgs84.SetWellKnownGeogCS("WGS84") != OGRERR_NONE) {
    throw std::invalid_argument(
        fmt::format("cannot read the ground's CRS ({}): {}", description_, CPLGetLastErrorMsg()));
  }
  impl_->to_wgs84.reset(OGRCreateCoordinateTransformation(&impl_->local, &impl_->wgs84));
  impl_->from_wgs84.reset(OGRCreateCoordinateTransformation(&impl_->wgs84, &impl_->local));
  if (!impl_->to_wgs84 || !impl_->from_wgs84) {
    throw std::invalid_argument(
        fmt::format("no transformation between the ground's CRS ({}) and "
                    "WGS-84: {}",
                    description_, CPLGetLastErrorMsg()));
  }
  origin_ = ToGeodetic(0.0, 0.0, 0.0);
  if (std::isnan(origin_.latitude_deg)) {
    throw std::invalid_argument(fmt::format("cannot place the ground's origin on WGS-84 ({}): {}",
                                            description_, CPLGetLastErrorMsg()));
  }
}

GroundGeoreference::~GroundGeoreference() = default;

GeodeticPoint GroundGeoreference::ToGeodetic(double x_m, double y_m, double z_m) const {
  double x = x0_ + x_m;
  double z = z0_ + z_m;
  std::lock_guard lock(impl_->mutex);
  if (!impl_->to_wgs84->Transform(1, &x, &z)) x = z = std::nan("");
  return {z, x, y_m};
}

std::array<double, 2> GroundGeoreference::FromGeodetic(double latitude_deg,
                                                       double longitude_deg) const {
  double x = longitude_deg;
  double z = latitude_deg;
  std::lock_guard lock(impl_->mutex);
  if (!impl_->from_wgs84->Transform(1, &x, &z)) return {std::nan(""), std::nan("")};
  return {x - x0_, z - z0_};
}

double GeocentricDistanceM(const GeodeticPoint& a, const GeodeticPoint& b) {
  const GeographicLib::Geocentric& earth = GeographicLib::Geocentric::WGS84();
  double ax, ay, az, bx, by, bz;
  earth.Forward(a.latitude_deg, a.longitude_deg, a.height_m, ax, ay, az);
  earth.Forward(b.latitude_deg, b.longitude_deg, b.height_m, bx, by, bz);
  return std::hypot(ax - bx, ay - by, az - bz);
}

}  // namespace dt
