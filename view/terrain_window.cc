#include "view/terrain_window.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "terrain/bridge.h"
#include "vehicle/bridge_solids.h"

namespace dt {
namespace {

// Centimetres are finer than any post's elevation matters on a screen and halve the text.
double Cm(double v) { return std::round(v * 100.0) / 100.0; }

Result<double> Number(const std::string& key, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) {
    return Error{fmt::format("/terrain3d: {}=\"{}\" is not a finite number", key, text)};
  }
  return v;
}

}  // namespace

Result<TerrainWindowRequest> ParseTerrainWindowQuery(const std::string& query) {
  TerrainWindowRequest r;
  bool has_x = false, has_z = false, has_half = false;
  size_t at = 0;
  while (at <= query.size()) {
    size_t amp = query.find('&', at);
    if (amp == std::string::npos) amp = query.size();
    const std::string pair = query.substr(at, amp - at);
    at = amp + 1;
    if (pair.empty()) continue;
    const size_t eq = pair.find('=');
    const std::string key = pair.substr(0, eq);
    const std::string value = eq == std::string::npos ? "" : pair.substr(eq + 1);
    if (key != "x" && key != "z" && key != "half" && key != "posts") {
      return Error{fmt::format("/terrain3d: unknown key \"{}\" (x, z, half, posts)", key)};
    }
    auto v = Number(key, value);
    if (!v) return v.error();
    if (key == "x") r.x_m = v.value(), has_x = true;
    if (key == "z") r.z_m = v.value(), has_z = true;
    if (key == "half") r.half_m = v.value(), has_half = true;
    if (key == "posts") {
      if (v.value() < 2 || v.value() > kMaxWindowPosts || v.value() != std::floor(v.value())) {
        return Error{fmt::format("/terrain3d: posts={} is not a whole number in 2..{}", value,
                                 kMaxWindowPosts)};
      }
      r.posts = static_cast<int>(v.value());
    }
  }
  if (!has_x || !has_z || !has_half) {
    return Error{fmt::format("/terrain3d: \"{}\" lacks x, z or half", query)};
  }
  if (r.half_m <= 0.0) return Error{fmt::format("/terrain3d: half={} is not positive", r.half_m)};
  return r;
}

std::string TerrainWindowJson(const Terrain& terrain, const TerrainWindowRequest& request) {
  const HeightGrid& g = terrain.ground();
  const double spacing = g.spacing_m();
  // The part of the square asked for that is on the terrain, covered by the posts asked for: at
  // whole post spacings when that is coarser than the terrain's posts, else at a power-of-two
  // fraction of the spacing (down to an eighth): the surface is defined between posts too (an
  // earthwork is a shape, not posts), so a window close up shows a crater finer than the grid.
  const double lo_x = std::clamp(request.x_m - request.half_m, 0.0, g.size_x_m());
  const double hi_x = std::clamp(request.x_m + request.half_m, 0.0, g.size_x_m());
  const double lo_z = std::clamp(request.z_m - request.half_m, 0.0, g.size_z_m());
  const double hi_z = std::clamp(request.z_m + request.half_m, 0.0, g.size_z_m());
  const double wanted = std::max(hi_x - lo_x, hi_z - lo_z) / (request.posts - 1);
  double step = spacing;
  if (wanted > spacing) {
    step = spacing * std::ceil(wanted / spacing - 1e-9);
  } else {
    while (step / 2 >= wanted && step > spacing / 8 * 1.5) step /= 2;
  }
  // On the step's lattice from the terrain's origin, so a window that moves keeps its samples
  // (lattice indices kept as whole doubles: a fine step on a large terrain passes 2^31).
  auto first = [&](double lo) { return std::floor(lo / step + 1e-9); };
  auto count = [&](double k0, double hi, double size) {
    const double n = 1 + std::ceil((hi - k0 * step) / step - 1e-9);
    const double on_terrain = std::floor(size / step + 1e-9) - k0 + 1;
    return static_cast<int>(std::clamp(n, 1.0, std::min<double>(request.posts, on_terrain)));
  };
  const double i0 = first(lo_x), j0 = first(lo_z);
  const int nx = count(i0, hi_x, g.size_x_m()), nz = count(j0, hi_z, g.size_z_m());
  nlohmann::json h = nlohmann::json::array(), d = nlohmann::json::array();
  for (int j = 0; j < nz; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double x = std::min((i0 + i) * step, g.size_x_m());
      const double z = std::min((j0 + j) * step, g.size_z_m());
      const double surface = terrain.ElevationAt(x, z);
      h.push_back(Cm(surface));
      d.push_back(Cm(surface - terrain.GroundElevationAt(x, z)));
    }
  }
  const Rect area{i0 * step, j0 * step, (i0 + nx - 1) * step, (j0 + nz - 1) * step};
  nlohmann::json solids = nlohmann::json::array();
  int bridges = 0;
  // Every feature, not the square index: a window of a large terrain covers millions of squares,
  // and bridges are few.
  for (const Feature* f : terrain.FeaturesById()) {
    if (f->type() != FeatureType::kBridge || !f->Bounds().Intersects(area)) continue;
    if (++bridges > kMaxWindowBridges) break;
    for (const Solid& s : BridgeSolids(*static_cast<const Bridge*>(f), g)) {
      solids.push_back({{"bridge", f->id().ToString()},
                        {"kind", s.deck     ? "deck"
                                 : s.rubble ? "rubble"
                                            : "pier"},
                        {"o", {s.origin_x_m, s.origin_z_m}},
                        {"u", {s.ux, s.uz}},
                        {"a", {s.a0_m, s.a1_m}},
                        {"r", {s.r0_m, s.r1_m}},
                        {"bottom", {s.bottom0_m, s.bottom1_m}},
                        {"top", {s.top0_m, s.top1_m}}});
    }
  }
  const nlohmann::json out = {{"x0", i0 * step},
                              {"z0", j0 * step},
                              {"step", step},
                              {"nx", nx},
                              {"nz", nz},
                              {"spacing", spacing},
                              {"size_x", g.size_x_m()},
                              {"size_z", g.size_z_m()},
                              {"h", std::move(h)},
                              {"d", std::move(d)},
                              {"solids", std::move(solids)}};
  return out.dump();
}

}  // namespace dt
