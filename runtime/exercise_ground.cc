#include "runtime/exercise_ground.h"

#include <malloc.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "base/demand.h"
#include "log/log.h"
#include "runtime/exercise_config.h"
#include "runtime/process_runtime.h"
#include "runtime/toml_reader.h"
#include "terrain/ground_cache.h"
#include "terrain/random_terrain.h"
#include "terrain/terrain_file.h"

namespace dt {

const std::vector<std::string> kElevationKeys = {
    "elevation_file", "area_crs",      "area_lonlat_deg", "resampling",
    "nodata_fill",    "nodata_fill_m", "max_load_mb",     "ground_cache_dir"};

namespace {

// [[x_min, y_min], [x_max, y_max]]: the south-west and north-east corners.
std::array<double, 4> ReadArea(const TomlReader& t, std::string_view key, double lo, double hi) {
  const std::vector<std::vector<double>> rows = t.NumberRows(key, 2, lo, hi);
  if (rows.size() != 2) {
    t.Fail(key, "expected two corners, [[x_min, y_min], [x_max, y_max]] (south-west, north-east)");
  }
  if (!(rows[0][0] < rows[1][0]) || !(rows[0][1] < rows[1][1])) {
    t.Fail(key, "the first corner must lie south-west of the second");
  }
  return {rows[0][0], rows[0][1], rows[1][0], rows[1][1]};
}

}  // namespace

ElevationTerrain ReadElevationTerrain(const TomlReader& t, const std::filesystem::path& base_dir,
                                      bool probe) {
  ElevationTerrain e;
  ElevationSource& s = e.source;
  const std::string file = t.String("elevation_file");
  if (file.empty()) t.Fail("elevation_file", "must name a file");
  s.file = std::filesystem::absolute(base_dir / file).lexically_normal();
  if (t.Has("area_crs") && t.Has("area_lonlat_deg")) {
    t.Fail("area_crs", "give area_crs or area_lonlat_deg, not both");
  }
  if (t.Has("area_crs")) {
    s.area_kind = AreaKind::kFileCrs;
    s.area = ReadArea(t, "area_crs", -1e15, 1e15);
  } else if (t.Has("area_lonlat_deg")) {
    s.area_kind = AreaKind::kLonLat;
    s.area = ReadArea(t, "area_lonlat_deg", -180.0, 180.0);
    if (s.area[1] < -90.0 || s.area[3] > 90.0) {
      t.Fail("area_lonlat_deg", "latitudes (the second of each pair) lie within [-90, 90]");
    }
  }
  s.spacing_m = t.Has("spacing_m") ? t.Double("spacing_m", 0.01, 10000.0) : 0.0;
  const std::string resampling = t.String("resampling", "bilinear");
  if (resampling == "cubic") {
    s.resampling = Resampling::kCubic;
  } else if (resampling != "bilinear") {
    t.Fail("resampling", "expected \"bilinear\" or \"cubic\"");
  }
  const std::string fill = t.String("nodata_fill", "none");
  if (fill == "nearest") {
    s.nodata_fill = NodataFill::kNearest;
  } else if (fill == "constant") {
    s.nodata_fill = NodataFill::kConstant;
    if (!t.Has("nodata_fill_m")) t.Fail("nodata_fill", "\"constant\" needs nodata_fill_m");
  } else if (fill != "none") {
    t.Fail("nodata_fill", "expected \"none\", \"nearest\" or \"constant\"");
  }
  if (t.Has("nodata_fill_m") && s.nodata_fill != NodataFill::kConstant) {
    t.Fail("nodata_fill_m", "only with nodata_fill = \"constant\"");
  }
  s.nodata_fill_m = t.Has("nodata_fill_m") ? t.Double("nodata_fill_m", -12000.0, 12000.0) : 0.0;
  if (t.Has("max_load_mb")) {
    s.max_load_bytes = static_cast<uint64_t>(t.Int("max_load_mb", 1, 1 << 24)) << 20;
  }
  if (t.Has("ground_cache_dir")) {
    const std::string dir = t.String("ground_cache_dir");
    if (dir.empty()) t.Fail("ground_cache_dir", "must name a directory");
    e.ground_cache_dir = std::filesystem::absolute(base_dir / dir).lexically_normal();
  }
  if (!probe) return e;
  try {
    e.layout = ProbeElevation(s);
  } catch (const std::exception& ex) {
    throw std::invalid_argument(
        fmt::format("{}: terrain.elevation_file: {}", t.source(), ex.what()));
  }
  return e;
}

void ApplyFileOrigin(const ElevationTerrain& elevation, bool origin_typed, DisConfig& dis,
                     const std::string& source_name) {
  const GeodeticPoint file = elevation.layout.georeference->origin();
  if (origin_typed) {
    const GeodeticPoint typed{dis.latitude_deg, dis.longitude_deg, dis.height_m};
    const double d = GeocentricDistanceM(typed, file);
    if (d > kOriginToleranceM) {
      throw std::invalid_argument(fmt::format(
          "{}: dis.latitude_deg/longitude_deg/height_m ({:.8f}, {:.8f}, {} m) lie {:.2f} m from "
          "the origin of elevation_file {} ({:.8f}, {:.8f}, {} m; {}): more than {} m; remove "
          "them to take the file's",
          source_name, typed.latitude_deg, typed.longitude_deg, typed.height_m, d,
          elevation.source.file.string(), file.latitude_deg, file.longitude_deg, file.height_m,
          elevation.layout.georeference->description(), kOriginToleranceM));
    }
  }
  dis.latitude_deg = file.latitude_deg;
  dis.longitude_deg = file.longitude_deg;
  dis.height_m = file.height_m;
}

namespace {

std::filesystem::path CacheDirFor(const std::filesystem::path& given, int posts_x, int posts_z) {
  if (!given.empty()) return given;
  const uint64_t posts = static_cast<uint64_t>(posts_x) * static_cast<uint64_t>(posts_z);
  if (posts <= kGroundCachePostsThreshold) return {};
  return std::filesystem::temp_directory_path() / fmt::format("dynterrain-ground-{}", getuid());
}

// The file's size and modification time for a cache key (zeros if it cannot be read: the key
// then names no file built from a readable one).
std::string FileStamp(const std::filesystem::path& file) {
  struct stat st {};
  if (stat(file.c_str(), &st) != 0) st = {};
  return fmt::format("size {} mtime {}.{:09d}", static_cast<int64_t>(st.st_size),
                     static_cast<int64_t>(st.st_mtim.tv_sec), st.st_mtim.tv_nsec);
}

std::invalid_argument GroundFileError(const ExerciseConfig& exercise, const Error& e) {
  return std::invalid_argument(fmt::format("{}: terrain.ground_file: {}: {}",
                                           exercise.source.string(), exercise.ground_file.string(),
                                           e.message));
}

// [terrain] ground_file: the whole file through LoadTerrain where no cache is used or this
// process builds it; otherwise the cache's grid and the file's feature section.
BaseGround BuildGroundFileGround(const ExerciseConfig& exercise) {
  const int64_t t0 = MonotonicMs();
  const std::filesystem::path& file = exercise.ground_file;
  auto load_whole = [&] {
    Result<std::unique_ptr<Terrain>> loaded = LoadTerrain(file);
    if (!loaded) throw GroundFileError(exercise, loaded.error());
    return BaseGroundFromTerrain(*loaded.value());
  };
  const std::filesystem::path cache_dir = GroundFileCacheDir(exercise);
  std::string how = "read by this process";
  std::optional<BaseGround> base;
  if (cache_dir.empty()) {
    base = load_whole();
  } else {
    // The checksum as the file holds it now (the header read at load may be stale).
    const Result<TerrainFileShape> shape = ProbeTerrainFile(file);
    if (!shape) throw GroundFileError(exercise, shape.error());
    std::optional<BaseGround> whole;
    GroundCacheOpened c =
        OpenGroundCache(cache_dir, GroundFileCacheKey(file, shape.value().checksum), [&] {
          whole = load_whole();
          return std::move(whole->grid);  // the features stay in `whole`
        });
    if (whole) {
      base = BaseGround{std::move(c.grid), std::move(whole->features)};
      how = fmt::format("read into the ground cache {} ({})", c.file.string(), c.build_reason);
    } else {
      Result<std::vector<std::pair<FeatureId, FeatureParams>>> features =
          LoadTerrainFileFeatures(file);
      if (!features) throw GroundFileError(exercise, features.error());
      base = BaseGroundFromParts(std::move(c.grid), features.value());
      how = fmt::format("mapped from the ground cache {}", c.file.string());
    }
    for (const std::string& r : c.removed) DT_LOG_INFO("ground cache: removed {}", r);
    // The posts read are freed; give their heap back (see BuildExerciseGround).
    if (c.built) malloc_trim(0);
  }
  const HeightGrid& g = base->grid;
  DT_LOG_INFO(
      "terrain {} x {} posts ({} x {} m at {} m) from ground_file {} with {} features, {}, "
      "in {} ms",
      g.posts_x(), g.posts_z(), g.size_x_m(), g.size_z_m(), g.spacing_m(), file.string(),
      base->features.size(), how, MonotonicMs() - t0);
  return std::move(*base);
}

}  // namespace

std::filesystem::path GroundCacheDir(const ElevationTerrain& e) {
  return CacheDirFor(e.ground_cache_dir, e.layout.posts_x, e.layout.posts_z);
}

std::filesystem::path GroundFileCacheDir(const ExerciseConfig& exercise) {
  DT_DEMAND(exercise.ground_file_shape.has_value());
  return CacheDirFor(exercise.ground_file_cache_dir, exercise.ground_file_shape->posts_x,
                     exercise.ground_file_shape->posts_z);
}

std::string GroundFileCacheKey(const std::filesystem::path& file, uint64_t stored_checksum) {
  return fmt::format("dynterrain ground_file v1\nfile {}\n{}\nchecksum {:016x}\n", file.string(),
                     FileStamp(file), stored_checksum);
}

std::string GroundCacheKey(const ElevationTerrain& e) {
  const ElevationSource& s = e.source;
  struct stat st {};
  if (stat(s.file.c_str(), &st) != 0) st = {};
  const ElevationLayout& L = e.layout;
  return fmt::format(
      "dynterrain ground v1\nfile {}\nsize {} mtime {}.{:09d}\narea {} {:.17g} {:.17g} {:.17g} "
      "{:.17g}\nspacing {:.17g}\nresampling {}\nfill {} {:.17g}\nlayout {} x {} at {:.17g} m, "
      "window {} {} {} {}\n",
      s.file.string(), static_cast<int64_t>(st.st_size), static_cast<int64_t>(st.st_mtim.tv_sec),
      st.st_mtim.tv_nsec, static_cast<int>(s.area_kind), s.area[0], s.area[1], s.area[2], s.area[3],
      s.spacing_m, ResamplingName(s.resampling), static_cast<int>(s.nodata_fill), s.nodata_fill_m,
      L.posts_x, L.posts_z, L.spacing_m, L.window_col0, L.window_row0, L.window_cols,
      L.window_rows);
}

BaseGround BuildExerciseGround(const ExerciseConfig& exercise) {
  DT_DEMAND(exercise.ground_read);
  if (!exercise.ground_file.empty()) return BuildGroundFileGround(exercise);
  const int64_t t0 = MonotonicMs();
  if (!exercise.elevation) {
    HeightGrid g = MakeRandomTerrain(exercise.terrain);
    DT_LOG_INFO("terrain {} x {} posts ({} x {} m, seed {}) ready in {} ms", g.posts_x(),
                g.posts_z(), g.size_x_m(), g.size_z_m(), exercise.terrain.seed, MonotonicMs() - t0);
    return BaseGround{std::move(g), {}};
  }
  const ElevationTerrain& e = *exercise.elevation;
  const std::filesystem::path cache_dir = GroundCacheDir(e);
  std::string cached = "read by this process";
  std::optional<HeightGrid> loaded;
  if (cache_dir.empty()) {
    loaded = LoadElevation(e.source, e.layout);
  } else {
    GroundCacheOpened c = OpenGroundCache(cache_dir, GroundCacheKey(e),
                                          [&] { return LoadElevation(e.source, e.layout); });
    cached =
        c.built ? fmt::format("read into the ground cache {} ({})", c.file.string(), c.build_reason)
                : fmt::format("mapped from the ground cache {}", c.file.string());
    for (const std::string& r : c.removed) DT_LOG_INFO("ground cache: removed {}", r);
    loaded = std::move(c.grid);
    // The pixels and posts read are freed; give their heap back, or the builder of a large
    // world keeps a private copy's worth of memory it no longer uses.
    if (c.built) malloc_trim(0);
  }
  HeightGrid& g = *loaded;
  const GeodeticPoint o = e.layout.georeference->origin();
  DT_LOG_INFO(
      "terrain {} x {} posts ({} x {} m at {} m, {}) from {} ({}), {}, in {} ms; origin {:.8f} "
      "{:.8f} on the {}",
      g.posts_x(), g.posts_z(), g.size_x_m(), g.size_z_m(), g.spacing_m(),
      ResamplingName(e.source.resampling), e.source.file.string(), e.layout.driver, cached,
      MonotonicMs() - t0, o.latitude_deg, o.longitude_deg, e.layout.georeference->description());
  return BaseGround{std::move(g), {}};
}

std::string ExerciseGroundSource(const ExerciseConfig& exercise) {
  if (!exercise.ground_file.empty()) {
    return fmt::format("ground_file {}", exercise.ground_file.string());
  }
  if (exercise.elevation) {
    return fmt::format("elevation_file {}", exercise.elevation->source.file.string());
  }
  const RandomTerrainParams& t = exercise.terrain;
  return fmt::format("random seed {} {}x{} posts spacing {} m relief {} m", t.seed, t.posts_x,
                     t.posts_z, t.spacing_m, t.relief_m);
}

}  // namespace dt
