#include "geo/test/test_rasters.h"

#include <unistd.h>

#include <cmath>
#include <stdexcept>

#include <cpl_error.h>
#include <fmt/format.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

namespace dt::testing {

void WriteTestRaster(const std::filesystem::path& path, const TestRaster& r) {
  GDALAllRegister();
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* out = GetGDALDriverManager()->GetDriverByName(r.driver.c_str());
  if (mem == nullptr || out == nullptr) throw std::runtime_error("no GDAL driver " + r.driver);
  const GDALDataType type = r.integer ? GDT_Int16 : GDT_Float32;
  GDALDatasetUniquePtr ds(mem->Create("", r.cols, r.rows, 1, type, nullptr));
  if (r.georeferenced) {
    std::array<double, 6> gt = r.geotransform;
    ds->SetGeoTransform(gt.data());
    OGRSpatialReference srs;
    srs.importFromEPSG(r.epsg);
    ds->SetSpatialRef(&srs);
  }
  std::vector<double> v(static_cast<size_t>(r.cols) * r.rows);
  const auto& gt = r.geotransform;
  for (int row = 0; row < r.rows; ++row) {
    for (int c = 0; c < r.cols; ++c) {
      const double x = gt[0] + (c + 0.5) * gt[1];
      const double y = gt[3] + (row + 0.5) * gt[5];
      const double h = r.surface(x, y);
      v[static_cast<size_t>(row) * r.cols + c] = r.integer ? std::round(h) : h;
    }
  }
  GDALRasterBand* band = ds->GetRasterBand(1);
  if (r.nodata) {
    band->SetNoDataValue(*r.nodata);
    for (const auto& [c, row] : r.holes) v[static_cast<size_t>(row) * r.cols + c] = *r.nodata;
  }
  if (band->RasterIO(GF_Write, 0, 0, r.cols, r.rows, v.data(), r.cols, r.rows, GDT_Float64, 0, 0) !=
      CE_None) {
    throw std::runtime_error(fmt::format("writing pixels: {}", CPLGetLastErrorMsg()));
  }
  GDALDatasetUniquePtr copy(
      out->CreateCopy(path.c_str(), ds.get(), TRUE, nullptr, nullptr, nullptr));
  if (!copy) {
    throw std::runtime_error(
        fmt::format("{} {}: {}", r.driver, path.string(), CPLGetLastErrorMsg()));
  }
}

std::filesystem::path FreshTestDir(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    fmt::format("dt_{}_{}", name, static_cast<long>(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace dt::testing
