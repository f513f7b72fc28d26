// A node's autonomous group on a terrain with craters, berms and a destroyed bridge: by default it
// is moved by the physical model, so its vehicles rest on the surface (never sunk into a crater's
// rim or a berm) and one that goes off the bridge falls at gravity and dies. The light model,
// which a file may still ask for, keeps the thesis's rules and fails both (docs/vehicles.md
// "Autonomous groups").
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "node/node_app.h"
#include "runtime/exercise_config.h"
#include "vehicle/contact_surface.h"

namespace dt {
namespace {

constexpr int64_t kTickMs = 33;
constexpr double kTickS = 0.033;

class NodeGroupTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() / fmt::format("dt-node-group-test-{}", ::getpid());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // One node on flat ground 320 m a side owning one group of `count` `type`s (`model` empty: the
  // file names none).
  ExerciseConfig Exercise(const std::string& type, int count, const std::string& model) const {
    const std::string text = fmt::format(
        "[exercise]\nname = \"node-group\"\ntransport = \"memq://\"\nrun_dir = \"{}\"\n"
        "[auth]\nmode = \"none\"\n"
        "[terrain]\nposts_per_side = 33\nspacing_m = 10\nrelief_m = 0\n"
        "[protocol]\nrequire_server = false\nmax_feature_period_ms = 50\nsilence_ms = 200\n"
        "[[node]]\nname = \"node-1\"\nsite = 1\nhost = 1\n"
        "[[node.group]]\ntype = \"{}\"\ncount = {}\nseed = 11\n{}"
        "area = {{ x_min_m = 40, x_max_m = 280, z_min_m = 40, z_max_m = 280 }}\n",
        dir_.string(), type, count, model.empty() ? "" : "model = \"" + model + "\"\n");
    return ParseExerciseConfig(text, "ex.toml", dir_);
  }

  std::filesystem::path dir_;
};

// Whether any vehicle's centre is within `clear_m` of (x, z): a feature is made only where none
// stands, so no vehicle starts inside one.
bool AnyVehicleNear(const NodeApp& node, double x_m, double z_m, double clear_m) {
  for (const SimulatedVehicle& v : node.vehicles()) {
    const VehiclePose p = v.pose();
    if (std::hypot(p.x_m - x_m, p.z_m - z_m) < clear_m) return true;
  }
  return false;
}

// How far a vehicle lies below the surface (ground and earthworks) at its worst point, along the
// surface's normal (as vehicle/test/vehicle_property_test.cc measures). A physical vehicle's body
// is its hull box: the bottom face and the running gear's contacts. A light vehicle has no body
// but its footprint on the plane of its pose (elevation, pitch, roll), sampled on a 9 x 5 grid.
double SinkM(const Terrain& terrain, const SimulatedVehicle& v) {
  std::vector<Eigen::Vector3d> points;
  if (const PhysicalVehicle* p = v.physical()) {
    points = p->HullBottomPoints(0.25);
  } else {
    const VehicleType& type = v.type().base;
    const VehiclePose pose = v.pose();
    const double ax = std::cos(pose.heading_rad), az = std::sin(pose.heading_rad);
    for (int i = -4; i <= 4; ++i) {
      for (int k = -2; k <= 2; ++k) {
        const double a = type.length_m / 2 * i / 4, l = type.width_m / 2 * k / 2;
        points.emplace_back(
            pose.x_m + ax * a - az * l,
            pose.elevation_m + a * std::tan(pose.pitch_rad) + l * std::tan(pose.roll_rad),
            pose.z_m + az * a + ax * l);
      }
    }
  }
  double worst_m = -INFINITY;
  for (const Eigen::Vector3d& p : points) {
    if (!terrain.Contains(p.x(), p.z())) continue;
    const SurfaceSample s = SampleSurface(terrain, {}, p.x(), p.z(), p.y());
    worst_m = std::max(worst_m, (terrain.ElevationAt(p.x(), p.z()) - p.y()) * s.normal.y());
  }
  return worst_m;
}

// Ticks a started node until it is signed on and caught up (it may then make features).
void TickUntilReady(NodeApp& node, int64_t& now_ms) {
  for (int tick = 0; tick < 300 && !node.ready(); ++tick) node.Tick(now_ms += kTickMs, kTickS);
  ASSERT_TRUE(node.ready());
}

// Craters and berms over the group's area, each where no vehicle stands.
void DigAndPile(NodeApp& node) {
  int made = 0;
  for (double z = 60; z <= 260; z += 25) {
    for (double x = 60; x <= 260; x += 25) {
      if (AnyVehicleNear(node, x, z, 16.0)) continue;
      const bool crater = (static_cast<int>(x + z) / 25) % 2 == 0;
      const FeatureParams p =
          crater ? FeatureParams::Crater(x, z, 7.0)
                 : FeatureParams::Berm(x, z, std::fmod(0.04 * x, std::numbers::pi), 14.0, 5.0, 1.5);
      const Result<FeatureId> id = node.Create(p);
      ASSERT_TRUE(id.ok()) << x << " " << z << ": " << id.error().message;
      ++made;
    }
  }
  ASSERT_GT(made, 40);
}

// Sinking: the deepest any group vehicle's footprint went below the surface over 40 s.
double DeepestSinkM(const ExerciseConfig& exercise) {
  NodeApp node(exercise, exercise.nodes[0]);
  int64_t now_ms = 0;
  node.Start(now_ms);
  TickUntilReady(node, now_ms);
  DigAndPile(node);
  double deepest_m = 0.0;
  for (int tick = 0; tick < 40 * 30; ++tick) {
    node.Tick(now_ms += kTickMs, kTickS);
    if (tick < 30) continue;  // the physical vehicles settle on their springs first
    for (const SimulatedVehicle& v : node.vehicles()) {
      if (!v.alive()) continue;  // a wreck may lie on its side, its footprint anywhere
      const double sink = SinkM(node.replica().terrain(), v);
      if (sink > deepest_m && std::getenv("DT_GROUP_TRACE")) {
        const VehiclePose p = v.pose();
        std::printf("tick %d (%.1f %.1f) y %.2f pitch %.1f roll %.1f speed %.1f %s sink %.2f\n",
                    tick, p.x_m, p.z_m, p.elevation_m, p.pitch_rad * 57.3, p.roll_rad * 57.3,
                    p.speed_mps, std::string(v.damage_name()).c_str(), sink);
      }
      deepest_m = std::max(deepest_m, sink);
    }
  }
  return deepest_m;
}

TEST_F(NodeGroupTest, AGroupIsPhysicalByDefaultAndDoesNotSinkIntoCratersOrBerms) {
  const ExerciseConfig physical = Exercise("tank", 30, "");
  ASSERT_EQ(physical.nodes[0].groups.at(0).model, VehicleModel::kPhysical);
  {
    NodeApp node(physical, physical.nodes[0]);
    ASSERT_EQ(node.vehicles().size(), 30u);
    for (const SimulatedVehicle& v : node.vehicles()) EXPECT_EQ(v.model(), VehicleModel::kPhysical);
  }
  // Springs: a few centimetres, never the half metre and more the light model sinks.
  const double physical_m = DeepestSinkM(physical);
  EXPECT_LT(physical_m, 0.15);
  const double light_m = DeepestSinkM(Exercise("tank", 30, "light"));
  EXPECT_GT(light_m, 0.4) << "the light model was expected to keep the thesis's sinking";
  std::printf("deepest sink: physical %.3f m, light %.3f m\n", physical_m, light_m);
}

// A destroyed 60 m wide bridge (6 m high, ramps 30 m, span 40 m, east-west) across the middle of
// the area: wanderers climb its ramps and some go off the break or a ramp's side. A vehicle whose
// elevation drops 4 m below where it was within the last second has fallen (a ramp descends at
// most 0.2 m a metre). Under the physical model it falls at gravity (4 m from a ramp's 2 m/s of
// descent takes 0.73 s) and lands past every type's limits from the span's 6 m.
struct FallCount {
  int fell = 0, survived = 0;
  int fastest_ticks = 1 << 30;  // the fewest ticks any faller took to drop 4 m
};
FallCount FallsOffTheBridge(const ExerciseConfig& exercise) {
  NodeApp node(exercise, exercise.nodes[0]);
  int64_t now_ms = 0;
  node.Start(now_ms);
  TickUntilReady(node, now_ms);
  // Ramp 1 from x 100 to 130, span to 170, ramp 2 to 200; z 130 .. 190. No vehicle may stand
  // where it is made: those on its footprint are removed first (a group vehicle may be removed
  // like any other).
  for (int i = node.vehicle_count() - 1; i >= 0; --i) {
    const VehiclePose p = node.vehicles()[static_cast<size_t>(i)].pose();
    if (p.x_m > 90 && p.x_m < 210 && p.z_m > 120 && p.z_m < 200) {
      EXPECT_TRUE(node.Remove(i).ok());
    }
  }
  FeatureParams bridge = FeatureParams::Bridge(130, 160, 0.0, 60, 30, 40, 30, 6, 6);
  Result<FeatureId> id = node.Create(bridge);
  EXPECT_TRUE(id.ok()) << id.error().message;
  if (!id) return {};
  bridge.status = BridgeStatus::kDestroyed;
  EXPECT_TRUE(node.Modify(id.value(), bridge).ok());
  const size_t n = node.vehicles().size();
  std::vector<std::deque<double>> recent(n);  // the last second's elevations, oldest first
  std::vector<bool> fell(n, false);
  FallCount c;
  constexpr int kTicks = 60 * 30;
  for (int tick = 0; tick < kTicks + 60; ++tick) {
    node.Tick(now_ms += kTickMs, kTickS);
    for (size_t i = 0; i < n; ++i) {
      const double y = node.vehicles()[i].pose().elevation_m;
      std::deque<double>& r = recent[i];
      r.push_back(y);
      if (r.size() > 30) r.pop_front();
      if (fell[i] || tick >= kTicks) continue;
      // The latest tick of the last second from which it has dropped 4 m.
      for (size_t k = r.size(); k-- > 0;) {
        if (r[k] - y > 4.0) {
          fell[i] = true;
          c.fastest_ticks = std::min(c.fastest_ticks, static_cast<int>(r.size() - 1 - k));
          break;
        }
      }
    }
  }
  for (size_t i = 0; i < n; ++i) {
    if (!fell[i]) continue;
    ++c.fell;
    if (node.vehicles()[i].alive()) ++c.survived;
  }
  return c;
}

TEST_F(NodeGroupTest, AGroupVehicleFallsOffADestroyedBridgeAtGravityAndDies) {
  const FallCount physical = FallsOffTheBridge(Exercise("jeep", 60, ""));
  EXPECT_GT(physical.fell, 0) << "no jeep went off the bridge: the test shows nothing";
  EXPECT_EQ(physical.survived, 0) << "of " << physical.fell << " that fell";
  EXPECT_GE(physical.fastest_ticks, 20) << "a 4 m drop faster than gravity allows";
  // The light model drops a vehicle to the ground in a tick or two.
  const FallCount light = FallsOffTheBridge(Exercise("jeep", 60, "light"));
  EXPECT_GT(light.fell, 0);
  EXPECT_LT(light.fastest_ticks, 5);
  std::printf(
      "off the bridge: physical %d fell, %d survived, fastest 4 m in %d ticks; light %d fell, "
      "%d survived, fastest %d ticks\n",
      physical.fell, physical.survived, physical.fastest_ticks, light.fell, light.survived,
      light.fastest_ticks);
}

}  // namespace
}  // namespace dt
