#include "launcher/drill_config.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "runtime/toml_reader.h"

namespace dt {

DrillConfig ParseDrillConfig(std::string_view toml_text, std::string_view source_name,
                             const std::filesystem::path& base_dir) {
  const toml::table root = TomlReader::ParseText(toml_text, source_name);
  const TomlReader top(root, std::string(source_name), "");
  DrillConfig d;
  d.source = std::string(source_name);
  const TomlReader dr = top.Table("drill");
  d.name = dr.String("name");
  d.exercise = std::filesystem::absolute(base_dir / dr.String("exercise"));
  d.deadline_s = dr.Double("deadline_s", 60.0, 1.0, 3600.0);
  d.settle_s = dr.Double("settle_s", 20.0, 1.0, 3600.0);
  d.ready_timeout_s = dr.Double("ready_timeout_s", 20.0, 1.0, 3600.0);
  dr.Finish();

  const std::vector<TomlReader> entries = top.TableArray("action");
  top.Finish();
  for (size_t i = 0; i < entries.size(); ++i) {
    const TomlReader& r = entries[i];
    DrillAction a;
    a.where = fmt::format("{} action {}", source_name, i + 1);
    a.at_s = r.Double("at_s", 0.0, 0.0, d.deadline_s);
    const std::string kind = r.String("do");
    a.targets = r.StringList("targets");
    if (kind == "random_ops") {
      a.kind = DrillActionKind::kRandomOps;
      a.count = static_cast<int>(r.Int("count", 1, 100000));
      a.duration_s = r.Double("duration_s", 0.0, 3600.0);
      a.seed = static_cast<uint64_t>(r.Int("seed", 1, 0, INT64_MAX));
    } else if (kind == "kill" || kind == "stop" || kind == "restart") {
      a.kind = kind == "kill"   ? DrillActionKind::kKill
               : kind == "stop" ? DrillActionKind::kStop
                                : DrillActionKind::kRestart;
      if (a.targets.empty()) r.Fail("targets", fmt::format("{} needs targets", kind));
    } else if (kind == "chaos") {
      a.kind = DrillActionKind::kChaos;
      a.duration_s = r.Double("duration_s", 0.1, 3600.0);
      a.seed = static_cast<uint64_t>(r.Int("seed", 1, 0, INT64_MAX));
      a.period_s = r.Double("period_s", 10.0, 0.1, 3600.0);
      a.max_down = static_cast<int>(r.Int("max_down", 1, 1, 64));
      a.down_min_s = r.Double("down_min_s", 1.0, 0.0, 3600.0);
      a.down_max_s = r.Double("down_max_s", std::max(5.0, a.down_min_s), 0.0, 3600.0);
      if (a.down_max_s < a.down_min_s) {
        r.Fail("down_max_s",
               fmt::format("down_max_s {} is below down_min_s {}", a.down_max_s, a.down_min_s));
      }
      if (a.at_s + a.duration_s > d.deadline_s) {
        r.Fail("duration_s", fmt::format("chaos from {} s for {} s ends after deadline_s {}",
                                         a.at_s, a.duration_s, d.deadline_s));
      }
      if (a.targets.size() == 1 && a.max_down > 1) {
        r.Fail("max_down", fmt::format("max_down {} with one target", a.max_down));
      }
    } else if (kind == "loss") {
      a.kind = DrillActionKind::kLoss;
      a.drop_probability = r.Double("drop_probability", 0.0, 1.0);
    } else if (kind == "partition") {
      a.kind = DrillActionKind::kPartition;
      a.from = r.StringList("from");
      if (a.targets.empty() || a.from.empty()) {
        r.Fail("from", "a partition needs targets and from");
      }
    } else if (kind == "heal") {
      a.kind = DrillActionKind::kHeal;
    } else if (kind == "command") {
      a.kind = DrillActionKind::kCommand;
      a.line = r.String("line");
    } else if (kind == "vehicles_seen") {
      a.kind = DrillActionKind::kVehiclesSeen;
      a.owner = r.String("owner");
      a.seen = r.Bool("seen", true);
      a.within_s = r.Double("within_s", 15.0, 0.1, 3600.0);
      a.not_before_s = r.Double("not_before_s", 0.0, 0.0, 3600.0);
      if (a.not_before_s >= a.within_s) {
        r.Fail("not_before_s",
               fmt::format("not_before_s {} is not below within_s {}", a.not_before_s, a.within_s));
      }
    } else if (kind == "sample_vehicles") {
      a.kind = DrillActionKind::kSampleVehicles;
      a.owner = r.String("owner", "");
      a.duration_s = r.Double("duration_s", 0.1, 3600.0);
      a.period_s = r.Double("period_s", 0.25, 0.01, 60.0);
      a.min_tilt_deg = r.Has("min_tilt_deg") ? r.Double("min_tilt_deg", 0.0, 90.0) : -1.0;
      a.error_m = r.Double("error_m", 1.0, 0.001, 1000.0);
      a.min_fraction = r.Has("min_fraction") ? r.Double("min_fraction", 0.0, 1.0) : -1.0;
      if (a.min_tilt_deg < 0.0 && a.min_fraction < 0.0) {
        r.Fail("do", "sample_vehicles needs min_tilt_deg or min_fraction (what it checks)");
      }
      if (a.at_s + a.duration_s > d.deadline_s) {
        r.Fail("duration_s", fmt::format("sampling from {} s for {} s ends after deadline_s {}",
                                         a.at_s, a.duration_s, d.deadline_s));
      }
    } else {
      r.Fail("do",
             "expected random_ops, chaos, kill, stop, restart, loss, partition, heal, command, "
             "vehicles_seen or sample_vehicles");
    }
    r.Finish();
    d.actions.push_back(std::move(a));
  }
  std::stable_sort(d.actions.begin(), d.actions.end(),
                   [](const DrillAction& x, const DrillAction& y) { return x.at_s < y.at_s; });
  return d;
}

DrillConfig LoadDrillConfig(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(fmt::format("{}: cannot read the drill", path.string()));
  std::ostringstream text;
  text << in.rdbuf();
  return ParseDrillConfig(text.str(), path.string(), path.parent_path());
}

void OverrideSeeds(DrillConfig& drill, uint64_t seed) {
  uint64_t k = 0;
  for (DrillAction& a : drill.actions) {
    if (a.kind == DrillActionKind::kRandomOps || a.kind == DrillActionKind::kChaos) {
      a.seed = seed + k++;
    }
  }
}

}  // namespace dt
