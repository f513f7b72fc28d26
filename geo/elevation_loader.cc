#include "geo/elevation_loader.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <vector>

#include <cpl_error.h>
#include <fmt/format.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include "geo/raster_window.h"

namespace dt {
namespace {

// Points sampled along each edge of an area when it is carried into another CRS.
constexpr int kEdgeSamples = 33;
// Nodata posts a message lists.
constexpr size_t kListedPosts = 5;
// The ground's two soils per grid square; the terrain's per-square tables lie in zero-filled
// pages and cost memory only where features lie (terrain/terrain.h).
constexpr uint64_t kTerrainBytesPerSquare = 2 * sizeof(Material);
// Per post while loading: its height, its two file coordinates and its nodata mark.
constexpr uint64_t kLoadBytesPerPost = sizeof(float) + 2 * sizeof(double) + 1;

void RegisterDrivers() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

// GDAL's messages go into our exceptions, not to stderr.
class QuietGdal {
 public:
  QuietGdal() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~QuietGdal() { CPLPopErrorHandler(); }
  QuietGdal(const QuietGdal&) = delete;
  QuietGdal& operator=(const QuietGdal&) = delete;
};

std::string GdalMessage() {
  const char* m = CPLGetLastErrorMsg();
  return (m == nullptr || *m == '\0') ? std::string("GDAL gave no message") : std::string(m);
}

GDALDatasetUniquePtr Open(const ElevationSource& source) {
  RegisterDrivers();
  GDALDatasetUniquePtr ds(GDALDataset::Open(
      source.file.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR));
  if (!ds) {
    throw std::runtime_error(fmt::format("elevation_file {}: GDAL cannot read it as a raster: {}",
                                         source.file.string(), GdalMessage()));
  }
  if (ds->GetRasterCount() < 1) {
    throw std::runtime_error(
        fmt::format("elevation_file {}: the raster has no band", source.file.string()));
  }
  return ds;
}

OGRSpatialReference Wgs84() {
  OGRSpatialReference s;
  s.SetWellKnownGeogCS("WGS84");
  s.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return s;
}

struct Transform {
  std::unique_ptr<OGRCoordinateTransformation> t;  // null: the identity
  std::string file;
  void Apply(std::vector<double>& x, std::vector<double>& y) const {
    if (!t || x.empty()) return;
    if (!t->Transform(static_cast<int>(x.size()), x.data(), y.data())) {
      throw std::runtime_error(fmt::format("elevation_file {}: PROJ cannot transform the area: {}",
                                           file, GdalMessage()));
    }
  }
};

Transform MakeTransform(const OGRSpatialReference& from, const OGRSpatialReference& to,
                        bool identity, const std::string& file) {
  Transform tr{nullptr, file};
  if (identity) return tr;
  tr.t.reset(OGRCreateCoordinateTransformation(&from, &to));
  if (!tr.t) {
    throw std::runtime_error(
        fmt::format("elevation_file {}: no transformation between CRSs: {}", file, GdalMessage()));
  }
  return tr;
}

// The boundary of the box {x0, y0, x1, y1}, edge by edge (south, east, north, west), each with
// kEdgeSamples points.
void BoxBoundary(const std::array<double, 4>& b, std::vector<double>& x, std::vector<double>& y) {
  x.clear();
  y.clear();
  for (int e = 0; e < 4; ++e) {
    for (int k = 0; k < kEdgeSamples; ++k) {
      const double t = static_cast<double>(k) / (kEdgeSamples - 1);
      switch (e) {
        case 0:
          x.push_back(b[0] + t * (b[2] - b[0]));
          y.push_back(b[1]);
          break;
        case 1:
          x.push_back(b[2]);
          y.push_back(b[1] + t * (b[3] - b[1]));
          break;
        case 2:
          x.push_back(b[0] + t * (b[2] - b[0]));
          y.push_back(b[3]);
          break;
        default:
          x.push_back(b[0]);
          y.push_back(b[1] + t * (b[3] - b[1]));
          break;
      }
    }
  }
}

std::string Box(const std::array<double, 4>& b) {
  return fmt::format("[{}, {}, {}, {}]", b[0], b[1], b[2], b[3]);
}

}  // namespace

uint64_t DefaultMaxLoadBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return uint64_t{1} << 32;
  return static_cast<uint64_t>(pages) * static_cast<uint64_t>(page) / 4;
}

std::string_view ResamplingName(Resampling r) {
  return r == Resampling::kCubic ? "cubic" : "bilinear";
}

ElevationLayout ProbeElevation(const ElevationSource& source) {
  const QuietGdal quiet;
  const std::string file = source.file.string();
  GDALDatasetUniquePtr ds = Open(source);
  ElevationLayout L;
  L.driver = ds->GetDriver() ? ds->GetDriver()->GetDescription() : "?";
  L.raster_cols = ds->GetRasterXSize();
  L.raster_rows = ds->GetRasterYSize();
  double* gt = L.geotransform.data();
  if (ds->GetGeoTransform(gt) != CE_None) {
    throw std::runtime_error(
        fmt::format("elevation_file {} ({} x {} pixels, {}): no georeference (geotransform): {}",
                    file, L.raster_cols, L.raster_rows, L.driver, GdalMessage()));
  }
  if (gt[2] != 0.0 || gt[4] != 0.0 || gt[1] == 0.0 || gt[5] == 0.0) {
    throw std::runtime_error(fmt::format(
        "elevation_file {}: a rotated or degenerate geotransform [{}, {}, {}, {}, {}, {}] is not "
        "supported (warp it north-up with gdalwarp first)",
        file, gt[0], gt[1], gt[2], gt[3], gt[4], gt[5]));
  }
  const OGRSpatialReference* file_srs_ptr = ds->GetSpatialRef();
  if (file_srs_ptr == nullptr || file_srs_ptr->IsEmpty()) {
    throw std::runtime_error(
        fmt::format("elevation_file {} ({} x {} pixels, {}): no georeference (CRS): {}", file,
                    L.raster_cols, L.raster_rows, L.driver, GdalMessage()));
  }
  OGRSpatialReference file_srs(*file_srs_ptr);
  file_srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  char* wkt = nullptr;
  file_srs.exportToWkt(&wkt);
  L.file_crs_wkt = wkt ? wkt : "";
  CPLFree(wkt);
  L.local_is_file_crs = file_srs.IsProjected() && std::abs(file_srs.GetLinearUnits() - 1.0) < 1e-12;
  const OGRSpatialReference wgs84 = Wgs84();

  // The pixel centres' extent in the file's CRS.
  const auto centre_x = [&](double c) { return gt[0] + (c + 0.5) * gt[1]; };
  const auto centre_y = [&](double r) { return gt[3] + (r + 0.5) * gt[5]; };
  const std::array<double, 4> extent = {std::min(centre_x(0), centre_x(L.raster_cols - 1)),
                                        std::min(centre_y(0), centre_y(L.raster_rows - 1)),
                                        std::max(centre_x(0), centre_x(L.raster_cols - 1)),
                                        std::max(centre_y(0), centre_y(L.raster_rows - 1))};

  // The area, in the CRS it was given in.
  std::array<double, 4> box = extent;
  const bool area_in_file_crs = source.area_kind != AreaKind::kLonLat;
  if (source.area_kind != AreaKind::kWholeFile) box = source.area;
  if (source.area_kind == AreaKind::kFileCrs) {
    const double tol = 1e-9 * std::max({1.0, std::abs(extent[0]), std::abs(extent[3])});
    if (box[0] < extent[0] - tol || box[1] < extent[1] - tol || box[2] > extent[2] + tol ||
        box[3] > extent[3] + tol) {
      throw std::invalid_argument(
          fmt::format("elevation_file {}: area_crs {} reaches beyond the file's data {} (its "
                      "pixel centres, in its CRS)",
                      file, Box(box), Box(extent)));
    }
  }
  const OGRSpatialReference& area_srs = area_in_file_crs ? file_srs : wgs84;

  // The local grid's CRS: the file's when it is projected in metres, else the plane tangent to
  // WGS-84 at the area's centre (orthographic).
  OGRSpatialReference local_srs;
  std::string description;
  if (L.local_is_file_crs) {
    local_srs = file_srs;
    const char* name = file_srs.GetName();
    description = name ? name : "the file's projection";
  } else {
    std::vector<double> cx = {(box[0] + box[2]) / 2};
    std::vector<double> cy = {(box[1] + box[3]) / 2};
    MakeTransform(area_srs, wgs84, !area_in_file_crs, file).Apply(cx, cy);
    local_srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    local_srs.SetProjCS("tangent plane");
    local_srs.SetWellKnownGeogCS("WGS84");
    local_srs.SetOrthographic(cy[0], cx[0], 0.0, 0.0);
    description =
        fmt::format("plane tangent to WGS-84 at latitude {:.6f} longitude {:.6f}", cy[0], cx[0]);
  }
  local_srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);

  // The largest local rectangle inside the area (edges sampled): its sides run east and north.
  std::vector<double> bx, by;
  BoxBoundary(box, bx, by);
  const bool area_is_local = area_in_file_crs && L.local_is_file_crs;
  MakeTransform(area_srs, local_srs, area_is_local, file).Apply(bx, by);
  double x_lo = -std::numeric_limits<double>::infinity(), x_hi = -x_lo, z_lo = x_lo, z_hi = x_hi;
  for (int k = 0; k < kEdgeSamples; ++k) {
    z_lo = std::max(z_lo, by[k]);                     // south
    x_hi = std::min(x_hi, bx[kEdgeSamples + k]);      // east
    z_hi = std::min(z_hi, by[2 * kEdgeSamples + k]);  // north
    x_lo = std::max(x_lo, bx[3 * kEdgeSamples + k]);  // west
  }

  // The spacing: asked for, or the file's pixel in metres (the smaller side, at the centre).
  if (source.spacing_m > 0.0) {
    L.spacing_m = source.spacing_m;
  } else if (L.local_is_file_crs) {
    L.spacing_m = std::min(std::abs(gt[1]), std::abs(gt[5]));
  } else {
    const double mx = (extent[0] + extent[2]) / 2, my = (extent[1] + extent[3]) / 2;
    std::vector<double> px = {mx, mx + gt[1], mx}, py = {my, my, my + gt[5]};
    MakeTransform(file_srs, local_srs, false, file).Apply(px, py);
    L.spacing_m = std::min(std::hypot(px[1] - px[0], py[1] - py[0]),
                           std::hypot(px[2] - px[0], py[2] - py[0]));
  }
  if (!(x_hi > x_lo) || !(z_hi > z_lo)) {
    throw std::invalid_argument(
        fmt::format("elevation_file {}: the area {} holds no ground", file, Box(box)));
  }
  const double span_x = (x_hi - x_lo) / L.spacing_m + 1e-9;
  const double span_z = (z_hi - z_lo) / L.spacing_m + 1e-9;
  if (span_x + 1 > kMaxGridPostsPerSide || span_z + 1 > kMaxGridPostsPerSide || span_x < 1 ||
      span_z < 1) {
    throw std::invalid_argument(fmt::format(
        "elevation_file {}: the area is {:.1f} x {:.1f} m, {:.0f} x {:.0f} posts at {} m spacing: "
        "a side must hold 2 to {} posts (choose a smaller area or a larger spacing_m)",
        file, x_hi - x_lo, z_hi - z_lo, std::floor(span_x) + 1, std::floor(span_z) + 1, L.spacing_m,
        kMaxGridPostsPerSide));
  }
  L.posts_x = static_cast<int>(span_x) + 1;
  L.posts_z = static_cast<int>(span_z) + 1;
  L.georeference = std::make_shared<GroundGeoreference>(
      [&] {
        char* w = nullptr;
        local_srs.exportToWkt(&w);
        std::string s = w ? w : "";
        CPLFree(w);
        return s;
      }(),
      x_lo, z_lo, description);

  // The pixels the posts read: the grid's boundary in the file's pixels.
  const std::array<double, 4> grid = {x_lo, z_lo, x_lo + (L.posts_x - 1) * L.spacing_m,
                                      z_lo + (L.posts_z - 1) * L.spacing_m};
  BoxBoundary(grid, bx, by);
  MakeTransform(local_srs, file_srs, L.local_is_file_crs, file).Apply(bx, by);
  double c_min = std::numeric_limits<double>::infinity(), c_max = -c_min, r_min = c_min,
         r_max = -c_min;
  for (size_t k = 0; k < bx.size(); ++k) {
    const double c = (bx[k] - gt[0]) / gt[1] - 0.5;
    const double r = (by[k] - gt[3]) / gt[5] - 0.5;
    c_min = std::min(c_min, c), c_max = std::max(c_max, c);
    r_min = std::min(r_min, r), r_max = std::max(r_max, r);
  }
  constexpr double kPixelTolerance = 1e-3;
  if (c_min < -kPixelTolerance || r_min < -kPixelTolerance ||
      c_max > L.raster_cols - 1 + kPixelTolerance || r_max > L.raster_rows - 1 + kPixelTolerance) {
    throw std::invalid_argument(fmt::format(
        "elevation_file {}: the area {} reaches beyond the file's data (it needs pixel columns "
        "{:.1f} to {:.1f} and rows {:.1f} to {:.1f} of a {} x {} raster)",
        file, Box(source.area), c_min, c_max, r_min, r_max, L.raster_cols, L.raster_rows));
  }
  const int radius = SupportRadius(source.resampling);
  const int c0 = std::max(0, static_cast<int>(std::floor(c_min)) - radius + 1);
  const int r0 = std::max(0, static_cast<int>(std::floor(r_min)) - radius + 1);
  const int c1 = std::min(L.raster_cols - 1, static_cast<int>(std::ceil(c_max)) + radius - 1);
  const int r1 = std::min(L.raster_rows - 1, static_cast<int>(std::ceil(r_max)) + radius - 1);
  L.window_col0 = c0;
  L.window_row0 = r0;
  L.window_cols = c1 - c0 + 1;
  L.window_rows = r1 - r0 + 1;

  const uint64_t pixels = static_cast<uint64_t>(L.window_cols) * L.window_rows;
  const uint64_t posts = static_cast<uint64_t>(L.posts_x) * L.posts_z;
  const uint64_t squares = static_cast<uint64_t>(L.posts_x - 1) * (L.posts_z - 1);
  L.estimated_bytes =
      pixels * sizeof(float) + posts * kLoadBytesPerPost + squares * kTerrainBytesPerSquare;
  const uint64_t limit = source.max_load_bytes ? source.max_load_bytes : DefaultMaxLoadBytes();
  if (L.estimated_bytes > limit) {
    throw std::invalid_argument(fmt::format(
        "elevation_file {}: loading {} x {} posts from {} x {} pixels would take {} MB, more than "
        "the {} MB allowed ([terrain] max_load_mb; default a quarter of physical memory)",
        file, L.posts_x, L.posts_z, L.window_cols, L.window_rows, L.estimated_bytes >> 20,
        limit >> 20));
  }
  return L;
}

HeightGrid LoadElevation(const ElevationSource& source, const ElevationLayout& L) {
  const QuietGdal quiet;
  const std::string file = source.file.string();
  GDALDatasetUniquePtr ds = Open(source);
  GDALRasterBand* band = ds->GetRasterBand(1);
  RasterWindow w;
  w.cols = L.window_cols;
  w.rows = L.window_rows;
  w.values.resize(static_cast<size_t>(w.cols) * w.rows);
  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);
  w.has_nodata = has_nodata != 0;
  w.nodata = static_cast<float>(nodata);
  if (band->RasterIO(GF_Read, L.window_col0, L.window_row0, w.cols, w.rows, w.values.data(), w.cols,
                     w.rows, GDT_Float32, 0, 0) != CE_None) {
    throw std::runtime_error(
        fmt::format("elevation_file {}: GDAL cannot read pixels {} x {} at column {} row {}: {}",
                    file, w.cols, w.rows, L.window_col0, L.window_row0, GdalMessage()));
  }

  OGRSpatialReference local_srs, file_srs;
  local_srs.importFromWkt(L.georeference->local_crs_wkt().c_str());
  file_srs.importFromWkt(L.file_crs_wkt.c_str());
  local_srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  file_srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  const Transform to_file = MakeTransform(local_srs, file_srs, L.local_is_file_crs, file);

  const double* gt = L.geotransform.data();
  const size_t nx = static_cast<size_t>(L.posts_x);
  const size_t n = nx * static_cast<size_t>(L.posts_z);
  std::vector<float> posts(n);
  std::vector<uint8_t> missing(n, 0);
  std::vector<size_t> missing_list;
  std::vector<double> fx(nx), fy(nx);
  std::vector<std::array<double, 2>> listed_file_xy;
  for (int j = 0; j < L.posts_z; ++j) {
    for (size_t i = 0; i < nx; ++i) {
      fx[i] = L.georeference->x0() + static_cast<double>(i) * L.spacing_m;
      fy[i] = L.georeference->z0() + j * L.spacing_m;
    }
    to_file.Apply(fx, fy);
    for (size_t i = 0; i < nx; ++i) {
      const double col = (fx[i] - gt[0]) / gt[1] - 0.5 - L.window_col0;
      const double row = (fy[i] - gt[3]) / gt[5] - 0.5 - L.window_row0;
      const size_t k = static_cast<size_t>(j) * nx + i;
      const std::optional<double> h = w.Sample(col, row, source.resampling);
      if (h) {
        posts[k] = static_cast<float>(*h);
      } else {
        missing[k] = 1;
        missing_list.push_back(k);
        if (listed_file_xy.size() < kListedPosts) listed_file_xy.push_back({fx[i], fy[i]});
      }
    }
  }
  if (!missing_list.empty()) {
    if (source.nodata_fill == NodataFill::kNone || missing_list.size() == n) {
      std::string where;
      for (size_t m = 0; m < listed_file_xy.size(); ++m) {
        const size_t k = missing_list[m];
        const size_t i = k % nx, j = k / nx;
        where += fmt::format("{}post ({}, {}) at x {} m z {} m (file CRS {:.6f}, {:.6f})",
                             m ? "; " : "", i, j, static_cast<double>(i) * L.spacing_m,
                             static_cast<double>(j) * L.spacing_m, listed_file_xy[m][0],
                             listed_file_xy[m][1]);
      }
      throw std::invalid_argument(fmt::format(
          "elevation_file {}: {} of the {} x {} posts have no data (band 1 nodata {}, or NaN){}: "
          "{}{}",
          file, missing_list.size(), L.posts_x, L.posts_z,
          w.has_nodata ? fmt::format("{}", nodata) : std::string("unset"),
          missing_list.size() > kListedPosts ? fmt::format(", the first {}", kListedPosts) : "",
          where,
          missing_list.size() == n
              ? " (no post has data: nothing to fill from)"
              : "; fill them with [terrain] nodata_fill = \"nearest\" or \"constant\""));
    }
    if (source.nodata_fill == NodataFill::kConstant) {
      for (size_t k : missing_list) posts[k] = static_cast<float>(source.nodata_fill_m);
    } else {
      // Breadth first from every post with data: each missing post takes the value of the
      // post whose wave reaches it first (fewest grid steps; ties by scan order).
      std::deque<size_t> queue;
      for (size_t k = 0; k < n; ++k) {
        if (!missing[k]) queue.push_back(k);
      }
      while (!queue.empty()) {
        const size_t k = queue.front();
        queue.pop_front();
        const size_t i = k % nx;
        const size_t nb[4] = {i > 0 ? k - 1 : n, i + 1 < nx ? k + 1 : n, k >= nx ? k - nx : n,
                              k + nx < n ? k + nx : n};
        for (size_t m : nb) {
          if (m < n && missing[m]) {
            missing[m] = 0;
            posts[m] = posts[k];
            queue.push_back(m);
          }
        }
      }
    }
  }
  return HeightGrid(L.posts_x, L.posts_z, L.spacing_m, std::move(posts));
}

}  // namespace dt
