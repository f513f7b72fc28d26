#include "node/scenario.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "runtime/toml_reader.h"
#include "terrain/berm_operations.h"
#include "terrain/polyline_earthwork.h"

namespace dt {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kMaxScenarioS = 7 * 24 * 3600.0;

// The keys of a feature step that are not feature parameters.
bool IsStepKey(std::string_view key) {
  return key == "at_s" || key == "action" || key == "name" || key == "target" || key == "points" ||
         key == "soil";
}

// Every numeric key of the step that is not a step key, as an edit (the reader marks them read).
// `points = [[x_m, z_m, height_m, width_m], ...]` ([x_m, z_m] for an area) becomes the point keys
// points[i].* (runtime/feature_edit.h), and `soil = "water"` an area's soil.
FeatureEdit ReadEdit(const TomlReader& r, const toml::table& t, FeatureType type) {
  FeatureEdit edit;
  for (const auto& [k, v] : t) {
    if (IsStepKey(k.str())) continue;
    edit.values.emplace_back(std::string(k.str()), r.Double(k.str(), -1e12, 1e12));
  }
  if (r.Has("points")) {
    const bool area = type == FeatureType::kArea;
    const auto rows = r.NumberRows("points", area ? 2 : 4, -1e12, 1e12);
    constexpr std::string_view kFields[] = {"x_m", "z_m", "height_m", "width_m"};
    for (size_t i = 0; i < rows.size(); ++i) {
      for (size_t k = 0; k < rows[i].size(); ++k) {
        edit.values.emplace_back(fmt::format("points[{}].{}", i, kFields[k]), rows[i][k]);
      }
    }
  }
  if (r.Has("soil")) {
    const std::string name = r.String("soil");
    const auto soil = ParseMaterial(name);
    if (!soil || *soil == Material::kFromGround)
      r.Fail("soil", "is not a soil (terrain/material.h)");
    edit.soil = *soil;
  }
  return edit;
}

}  // namespace

Scenario ParseScenario(std::string_view toml_text, std::string_view source_name,
                       int vehicle_count) {
  const toml::table root = TomlReader::ParseText(toml_text, source_name);
  const TomlReader top(root, std::string(source_name), "");
  Scenario sc;
  sc.source = std::string(source_name);

  // Local names -> parameters (nullopt-like: destroyed names are erased and remembered).
  std::map<std::string, FeatureParams> live;
  std::map<std::string, std::string> gone;  // name -> the step that ended it
  double cursor_s = 0.0;
  std::vector<ScenarioStep> steps;

  const std::vector<TomlReader> entries = top.TableArray("step");
  const toml::array* raw = root["step"].as_array();
  top.Finish();
  for (size_t i = 0; i < entries.size(); ++i) {
    const TomlReader& r = entries[i];
    const toml::table& t = *(*raw)[i].as_table();
    ScenarioStep s;
    s.where = fmt::format("{} step {}", source_name, i + 1);
    if (r.Has("at_s")) {
      s.at_s = r.Double("at_s", 0.0, kMaxScenarioS);
      if (s.at_s < cursor_s) {
        r.Fail("at_s",
               fmt::format("goes back in time (the timeline is already at {} s)", cursor_s));
      }
    } else {
      s.at_s = cursor_s;
    }
    cursor_s = s.at_s;

    const std::string action = r.String("action");
    auto need_target = [&]() -> const FeatureParams& {
      s.target = r.String("target");
      if (auto g = gone.find(s.target); g != gone.end()) {
        r.Fail("target", fmt::format("\"{}\" no longer exists ({})", s.target, g->second));
      }
      auto it = live.find(s.target);
      if (it == live.end()) r.Fail("target", "names no feature created by an earlier step");
      return it->second;
    };
    auto new_name = [&](std::string_view n) {
      if (live.count(std::string(n)) != 0 || gone.count(std::string(n)) != 0) {
        r.Fail("name", fmt::format("\"{}\" is already used", n));
      }
    };

    if (action == "crater" || action == "berm" || action == "bridge" || action == "ditch" ||
        action == "berm_line" || action == "area") {
      s.action = ScenarioAction::kCreate;
      s.name = r.String("name");
      if (s.name.empty()) r.Fail("name", "must not be empty");
      new_name(s.name);
      const FeatureType type = ParseFeatureType(action).value();
      Result<FeatureParams> p = MakeFeature(type, ReadEdit(r, t, type));
      if (!p) r.FailTable(p.error().message);
      s.params = p.value();
      live[s.name] = s.params;
    } else if (action == "update") {
      s.action = ScenarioAction::kUpdate;
      const FeatureParams& old = need_target();
      s.edit = ReadEdit(r, t, old.type);
      if (s.edit.values.empty() && !s.edit.soil) {
        r.FailTable("an update changes at least one key");
      }
      Result<FeatureParams> p = ApplyFeatureEdit(old, s.edit);
      if (!p) r.FailTable(p.error().message);
      live[s.target] = p.value();
    } else if (action == "destroy") {
      s.action = ScenarioAction::kDestroy;
      need_target();
      live.erase(s.target);
      gone[s.target] = "destroyed at " + s.where;
    } else if (action == "breach") {
      s.action = ScenarioAction::kBreach;
      const FeatureParams berm = need_target();
      const bool polyline = berm.type == FeatureType::kDitch || berm.type == FeatureType::kBermLine;
      if (berm.type != FeatureType::kBerm && !polyline) {
        r.Fail("target", "a breach needs a berm, berm line or ditch");
      }
      s.gap_start_m = r.Double("gap_start_m", 0.0, 1e6);
      s.gap_width_m = r.Double("gap_width_m", 1e-3, 1e6);
      const double centre_m = s.gap_start_m + s.gap_width_m / 2.0;
      Result<std::vector<FeatureParams>> pieces =
          polyline ? BreachPolyline(berm, centre_m, s.gap_width_m)
                   : BreachBerm(berm, centre_m, s.gap_width_m);
      if (!pieces) r.Fail("gap_start_m", pieces.error().message);
      live.erase(s.target);
      gone[s.target] = "breached at " + s.where;
      for (size_t k = 0; k < pieces.value().size(); ++k) {
        const std::string piece = fmt::format("{}.{}", s.target, k + 1);
        new_name(piece);
        live[piece] = pieces.value()[k];
      }
    } else if (action == "drive") {
      s.action = ScenarioAction::kDrive;
      s.vehicle = static_cast<int>(r.Int("vehicle", 0, 0, 1 << 20));
      if (s.vehicle >= vehicle_count) {
        r.Fail("vehicle", fmt::format("the node has {} vehicle(s)", vehicle_count));
      }
      s.speed_mps = r.Double("speed_mps", -1000.0, 1000.0);
      s.heading_rate_rad_s = r.Double("heading_rate_deg_s", 0.0, -3600.0, 3600.0) * kDegToRad;
      s.duration_s = r.Double("duration_s", 0.0, 0.0, kMaxScenarioS);
      if (s.duration_s > 0.0) {
        ScenarioStep stop = s;
        stop.at_s = s.at_s + s.duration_s;
        stop.speed_mps = 0.0;
        stop.heading_rate_rad_s = 0.0;
        stop.duration_s = 0.0;
        stop.where = s.where + " (stop)";
        steps.push_back(s);
        s = stop;
      }
    } else if (action == "spawn") {
      s.action = ScenarioAction::kSpawn;
      s.spawn.type = r.String("type", "tank");
      s.spawn.x_m = r.Double("x_m", -1e9, 1e9);
      s.spawn.z_m = r.Double("z_m", -1e9, 1e9);
      s.spawn.heading_rad = r.Double("heading_deg", 0.0, -360.0, 360.0) * kDegToRad;
      s.spawn.model = r.String("model", "physical");
      if (s.spawn.model != "physical" && s.spawn.model != "light") {
        r.Fail("model", "expected physical or light");
      }
      ++vehicle_count;
    } else if (action == "blade") {
      s.action = ScenarioAction::kBlade;
      s.vehicle = static_cast<int>(r.Int("vehicle", 0, 1 << 20));
      if (s.vehicle >= vehicle_count) {
        r.Fail("vehicle", fmt::format("the node has {} vehicle(s) at this step", vehicle_count));
      }
      const std::string position = r.String("position", "down");
      if (position == "down") {
        s.blade_depth_m = r.Double("depth_m", 0.0, 10.0);
      } else if (position != "up") {
        r.Fail("position", "expected down or up");
      }
    } else if (action == "remove") {
      s.action = ScenarioAction::kRemove;
      s.vehicle = static_cast<int>(r.Int("vehicle", 0, 1 << 20));
      if (s.vehicle >= vehicle_count) {
        r.Fail("vehicle", fmt::format("the node has {} vehicle(s) at this step", vehicle_count));
      }
      --vehicle_count;
    } else if (action == "wait") {
      s.action = ScenarioAction::kWait;
      s.duration_s = r.Double("duration_s", 0.0, kMaxScenarioS);
      cursor_s += s.duration_s;
      s.at_s = cursor_s;
    } else {
      r.Fail(
          "action",
          "expected crater, berm, bridge, update, destroy, breach, drive, spawn, remove, blade or "
          "wait");
    }
    r.Finish();
    steps.push_back(std::move(s));
  }
  std::stable_sort(steps.begin(), steps.end(),
                   [](const ScenarioStep& a, const ScenarioStep& b) { return a.at_s < b.at_s; });
  sc.steps = std::move(steps);
  return sc;
}

Scenario LoadScenario(const std::filesystem::path& path, int vehicle_count) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(fmt::format("{}: cannot read the scenario", path.string()));
  std::ostringstream text;
  text << in.rdbuf();
  return ParseScenario(text.str(), path.string(), vehicle_count);
}

}  // namespace dt
