// Blade: a bulldozer's blade, cutting the ground ahead, carrying the soil and setting it down,
// as post deltas an earth move carries (docs/vehicles.md "Bulldozer").
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "base/result.h"
#include "terrain/feature_params.h"
#include "terrain/friction_table.h"
#include "terrain/terrain.h"

namespace dt {

// The blade of a vehicle type. Lengths in metres, volume in cubic metres.
struct BladeSpec {
  double width_m = 0.0;      // across the heading, centred
  double capacity_m3 = 0.0;  // soil the blade carries before it spills
  double max_depth_m = 0.0;  // deepest cut below the tracks
  bool operator==(const BladeSpec&) const = default;
};

// The blade of a built-in type ("bulldozer": 3.7 m wide, 4 m3, 0.5 m deep); an error for a
// type without one, naming the types that have one.
Result<BladeSpec> BladeOf(std::string_view vehicle_type_name);

// One blade on one vehicle. Step is called once a tick with the vehicle's pose; it returns the
// post changes of that tick: with the blade down, every post the cut passed over since the last
// tick whose surface stood above the edge is cut down to it and its soil joins the load. The cut
// runs a post spacing ahead of the edge, so the surface under the edge (where the running gear
// ends) is cut, not the slope up to the next post.
// The edge is held level, as on a grader's laser: at the surface under the edge when the blade
// was lowered, less the depth (over rising ground and through a berm it cuts deeper and fills,
// over falling ground it carries); beyond the capacity the load spills
// onto the posts just ahead of the blade; when the blade rises the whole load is set down there.
// The changed posts and their neighbours then slump to the soils' angles of repose
// (terrain/slump.h). Soil is conserved: every millimetre cut is carried or set down.
class Blade {
 public:
  explicit Blade(BladeSpec spec) : spec_(spec) {}

  // Lowers the blade to cut depth_m below the tracks. Refused (naming the value) outside
  // [0, max_depth_m] or for NaN.
  Status Lower(double depth_m);
  // Raises the blade: the next Step sets the load down.
  void Raise() {
    down_ = false;
    edge_mm_.reset();
  }
  bool down() const { return down_; }
  double depth_m() const { return depth_m_; }
  // The soil carried, millimetre-posts (one post's area times one millimetre).
  int64_t load_mm() const { return load_mm_; }
  double LoadM3(double spacing_m) const {
    return static_cast<double>(load_mm_) * kPostDeltaUnitM * spacing_m * spacing_m;
  }
  const BladeSpec& spec() const { return spec_; }
  // Posts of the window the last Step worked in (the blade, its reach and the slump's margin; 0
  // when it had nothing to do): what the blade touched that tick.
  int last_window_posts() const { return last_window_posts_; }

  // The tick's post changes, sorted by (j, i) (empty when nothing changed). (x, z) is the
  // vehicle's centre, heading_rad its heading, length_m its length (the blade's edge is at the
  // front). Does not change the terrain: the caller makes an earth move of the changes.
  std::vector<PostDelta> Step(const Terrain& terrain, const FrictionTable& soils, double x_m,
                              double z_m, double heading_rad, double length_m);

 private:
  BladeSpec spec_;
  bool down_ = false;
  double depth_m_ = 0.0;
  int64_t load_mm_ = 0;
  std::optional<int64_t> edge_mm_;  // the edge's elevation, set on the first tick down
  int last_window_posts_ = 0;
  bool has_last_ = false;
  double last_edge_x_ = 0.0, last_edge_z_ = 0.0;
};

}  // namespace dt
