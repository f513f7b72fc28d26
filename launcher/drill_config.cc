#include "launcher/drill_config.h"

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "runtime/toml_reader.h"

namespace dt {

std::vector<std::string> NamesUsed(std::string_view line) {
  std::vector<std::string> out;
  for (size_t open = line.find('{'); open != std::string_view::npos;
       open = line.find('{', open + 1)) {
    const size_t close = line.find('}', open);
    if (close == std::string_view::npos) break;
    out.emplace_back(line.substr(open + 1, close - open - 1));
  }
  return out;
}

std::string WithNames(std::string_view line, const std::map<std::string, std::string>& kept) {
  std::string out;
  size_t from = 0;
  for (size_t open = line.find('{'); open != std::string_view::npos; open = line.find('{', from)) {
    const size_t close = line.find('}', open);
    if (close == std::string_view::npos) break;
    out += line.substr(from, open - from);
    const auto it = kept.find(std::string(line.substr(open + 1, close - open - 1)));
    out += it != kept.end() ? it->second : std::string(line.substr(open, close - open + 1));
    from = close + 1;
  }
  out += line.substr(from);
  return out;
}

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
      a.as = r.String("as", "");
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
    } else if (kind == "vehicle_reaches") {
      a.kind = DrillActionKind::kVehicleReaches;
      a.owner = r.String("owner");
      a.vehicle = static_cast<size_t>(r.Int("vehicle", 0, 0, 60000));
      a.within_s = r.Double("within_s", 15.0, 0.1, 3600.0);
      a.x_min_m = r.Double("x_min_m", -1e300, -1e9, 1e9);
      a.x_max_m = r.Double("x_max_m", 1e300, -1e9, 1e9);
      a.z_min_m = r.Double("z_min_m", -1e300, -1e9, 1e9);
      a.z_max_m = r.Double("z_max_m", 1e300, -1e9, 1e9);
      if (!r.Has("x_min_m") && !r.Has("x_max_m") && !r.Has("z_min_m") && !r.Has("z_max_m")) {
        r.Fail("do", "vehicle_reaches needs at least one of x_min_m, x_max_m, z_min_m, z_max_m");
      }
      if (a.x_min_m >= a.x_max_m) {
        r.Fail("x_max_m", fmt::format("x_max_m {} is not above x_min_m {}", a.x_max_m, a.x_min_m));
      }
      if (a.z_min_m >= a.z_max_m) {
        r.Fail("z_max_m", fmt::format("z_max_m {} is not above z_min_m {}", a.z_max_m, a.z_min_m));
      }
      if (!a.targets.empty()) {
        r.Fail("targets", "vehicle_reaches watches the owner's own vehicle: no targets");
      }
    } else if (kind == "digest") {
      a.kind = DrillActionKind::kDigest;
      a.mark = r.String("mark");
      a.within_s = r.Double("within_s", 15.0, 0.1, 3600.0);
      if (!a.targets.empty()) r.Fail("targets", "digest asks every live process: no targets");
    } else {
      r.Fail("do",
             "expected random_ops, chaos, kill, stop, restart, loss, partition, heal, command, "
             "vehicles_seen, sample_vehicles, vehicle_reaches or digest");
    }
    r.Finish();
    d.actions.push_back(std::move(a));
  }
  std::stable_sort(d.actions.begin(), d.actions.end(),
                   [](const DrillAction& x, const DrillAction& y) { return x.at_s < y.at_s; });
  // A "{name}" in a command line must name what an earlier command kept `as`.
  std::set<std::string> kept = {"run_dir"};  // the run directory, always known
  for (const DrillAction& a : d.actions) {
    if (a.kind != DrillActionKind::kCommand) continue;
    for (const std::string& name : NamesUsed(a.line)) {
      if (kept.count(name) == 0) {
        throw std::invalid_argument(
            fmt::format("{}: line \"{}\": {{{}}} is kept by no earlier command (as = \"{}\")",
                        a.where, a.line, name, name));
      }
    }
    if (!a.as.empty() && !kept.insert(a.as).second) {
      throw std::invalid_argument(
          fmt::format("{}: as = \"{}\" is kept by an earlier command already{}", a.where, a.as,
                      a.as == "run_dir" ? " (run_dir is the run directory)" : ""));
    }
  }
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
