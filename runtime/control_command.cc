#include "runtime/control_command.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "runtime/feature_edit.h"

namespace dt {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

std::vector<std::string_view> Split(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

Result<double> Number(std::string_view name, std::string_view text) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) {
    return Error{fmt::format("{} \"{}\" is not a finite number", name, text)};
  }
  return v;
}

Result<uint64_t> Unsigned(std::string_view name, std::string_view text, uint64_t max) {
  uint64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || v > max) {
    return Error{fmt::format("{} \"{}\" is not a whole number in [0, {}]", name, text, max)};
  }
  return v;
}

// Checks the count, then reads every argument after the verb as a number.
Result<std::vector<double>> Numbers(const std::vector<std::string_view>& words,
                                    const std::vector<std::string_view>& names) {
  if (words.size() != names.size() + 1) {
    std::string usage(words[0]);
    for (std::string_view n : names) usage += fmt::format(" <{}>", n);
    return Error{fmt::format("{} takes {} arguments, got {}: {}", words[0], names.size(),
                             words.size() - 1, usage)};
  }
  std::vector<double> out;
  for (size_t i = 0; i < names.size(); ++i) {
    Result<double> v = Number(names[i], words[i + 1]);
    if (!v) return v.error();
    out.push_back(v.value());
  }
  return out;
}

std::string IdLines(const std::vector<FeatureId>& ids) {
  std::string out;
  for (const FeatureId& id : ids) {
    if (!out.empty()) out += '\n';
    out += id.ToString();
  }
  return out;
}

// One line for each commanded value the vehicle clamped to its type's limits; empty if none was.
std::string ClampNotes(const ControlCommand& c, const AppliedDrive& applied) {
  std::string out;
  auto note = [&](const std::string& line) { out += (out.empty() ? "" : "\n") + line; };
  if (applied.speed_mps != c.speed_mps) {
    note(fmt::format("speed {:.6g} m/s clamped to {:.6g} m/s, the {}'s top {}speed", c.speed_mps,
                     applied.speed_mps, applied.vehicle_type, c.speed_mps < 0.0 ? "reverse " : ""));
  }
  if (applied.heading_rate_rad_s != c.heading_rate_rad_s) {
    note(fmt::format("heading rate {:.6g} deg/s clamped to {:.6g} deg/s, the {}'s top turn rate",
                     c.heading_rate_rad_s / kDegToRad, applied.heading_rate_rad_s / kDegToRad,
                     applied.vehicle_type));
  }
  return out;
}

// ditch|berm_line <key>=<value> ... <x,z,height,width> ...; area <soil> [level_m=<m>] <x,z> ...
Result<FeatureParams> ParsePointFeature(const std::vector<std::string_view>& w) {
  const FeatureType type = ParseFeatureType(w[0]).value();
  const bool area = type == FeatureType::kArea;
  FeatureEdit edit;
  size_t first = 1;
  if (area) {
    if (w.size() < 2) return Error{"area takes <soil> [level_m=<m>] <x,z> <x,z> <x,z> ..."};
    const auto soil = ParseMaterial(w[1]);
    if (!soil || *soil == Material::kFromGround) {
      return Error{
          fmt::format("area soil \"{}\" is not a soil (water, burnt, mud, oil, ...)", w[1])};
    }
    edit.soil = *soil;
    first = 2;
  }
  constexpr std::string_view kFields[] = {"x_m", "z_m", "height_m", "width_m"};
  const size_t columns = area ? 2 : 4;
  size_t point = 0;
  for (size_t i = first; i < w.size(); ++i) {
    if (const size_t eq = w[i].find('='); eq != std::string_view::npos) {
      const std::string_view key = w[i].substr(0, eq);
      Result<double> v = Number(key, w[i].substr(eq + 1));
      if (!v) return v.error();
      edit.values.emplace_back(std::string(key), v.value());
      continue;
    }
    std::vector<std::string_view> parts;
    for (size_t a = 0; a <= w[i].size();) {
      const size_t b = std::min(w[i].find(',', a), w[i].size());
      parts.push_back(w[i].substr(a, b - a));
      a = b + 1;
    }
    if (parts.size() != columns) {
      return Error{fmt::format("{} point \"{}\" is not {}", w[0], w[i],
                               area ? "x_m,z_m" : "x_m,z_m,height_m,width_m")};
    }
    for (size_t k = 0; k < columns; ++k) {
      const std::string key = fmt::format("points[{}].{}", point, kFields[k]);
      Result<double> v = Number(key, parts[k]);
      if (!v) return v.error();
      edit.values.emplace_back(key, v.value());
    }
    ++point;
  }
  return MakeFeature(type, edit);
}

}  // namespace

std::string ControlUsage() {
  return "crater <x_m> <z_m> <radius_m> [<depth_m>]\n"
         "ditch side_run_m=<m> [spoil_height_m=<m> spoil_width_m=<m>] <x,z,depth,width> ...\n"
         "berm_line <x,z,height,width> <x,z,height,width> ...\n"
         "area <soil> [level_m=<m>] <x,z> <x,z> <x,z> ...\n"
         "berm <x_m> <z_m> <direction_deg> <length_m> <width_m> <height_m>\n"
         "bridge <x_m> <z_m> <direction_deg> <width_m> <ramp1_m> <span_m> <ramp2_m> "
         "<height1_m> <height2_m>\n"
         "update <site:host:number> <key>=<value> ...\n"
         "destroy <site:host:number>\n"
         "breach <site:host:number> <gap_start_m> <gap_width_m>\n"
         "drive <vehicle> <speed_mps> <heading_rate_deg_s>\n"
         "spawn <type> <x_m> <z_m> <heading_deg> [physical|light] | remove <vehicle> | vehicles\n"
         "blade <vehicle> down <depth_m> | blade <vehicle> up\n"
         "status | digest | features | ping | quit\n"
         "render <file.png>\n"
         "export <file.dtt> | import <file.dtt> (server)\n"
         "loss <drop_probability>\n"
         "partition <site:host> ... | heal";
}

Result<FeatureId> ParseFeatureId(std::string_view text) {
  const size_t a = text.find(':');
  const size_t b = a == std::string_view::npos ? a : text.find(':', a + 1);
  if (b == std::string_view::npos) {
    return Error{fmt::format("feature ID \"{}\" is not site:host:number", text)};
  }
  Result<uint64_t> site = Unsigned("site", text.substr(0, a), 65535);
  Result<uint64_t> host = Unsigned("host", text.substr(a + 1, b - a - 1), 65535);
  Result<uint64_t> number = Unsigned("number", text.substr(b + 1), 0xFFFFFFFFull);
  if (!site) return site.error();
  if (!host) return host.error();
  if (!number) return number.error();
  if (number.value() == 0) return Error{fmt::format("feature ID \"{}\": number 0 is none", text)};
  return FeatureId{static_cast<uint16_t>(site.value()), static_cast<uint16_t>(host.value()),
                   static_cast<uint32_t>(number.value())};
}

Result<NodeAddress> ParseNodeAddress(std::string_view text) {
  const size_t a = text.find(':');
  if (a == std::string_view::npos) {
    return Error{fmt::format("node address \"{}\" is not site:host", text)};
  }
  Result<uint64_t> site = Unsigned("site", text.substr(0, a), 65535);
  Result<uint64_t> host = Unsigned("host", text.substr(a + 1), 65535);
  if (!site) return site.error();
  if (!host) return host.error();
  return NodeAddress{static_cast<uint16_t>(site.value()), static_cast<uint16_t>(host.value())};
}

Result<ControlCommand> ParseControlCommand(std::string_view line) {
  const std::vector<std::string_view> w = Split(line);
  if (w.empty()) return Error{"empty command; commands:\n" + ControlUsage()};
  const std::string_view verb = w[0];
  ControlCommand c;
  auto no_args = [&](ControlVerb v) -> Result<ControlCommand> {
    if (w.size() != 1) return Error{fmt::format("{} takes no arguments", verb)};
    c.verb = v;
    return c;
  };
  if (verb == "ditch" || verb == "berm_line" || verb == "area") {
    c.verb = ControlVerb::kCreate;
    Result<FeatureParams> p = ParsePointFeature(w);
    if (!p) return p.error();
    c.params = p.value();
    return c;
  }
  if (verb == "crater" || verb == "berm" || verb == "bridge") {
    c.verb = ControlVerb::kCreate;
    const FeatureType type = ParseFeatureType(verb).value();
    std::vector<std::string_view> keys = RequiredFeatureKeys(type);
    // A crater may give its depth below the ground as a fourth number.
    if (type == FeatureType::kCrater && w.size() == keys.size() + 2) keys.push_back("depth_m");
    Result<std::vector<double>> v = Numbers(w, keys);
    if (!v) return v.error();
    FeatureEdit edit;
    for (size_t i = 0; i < keys.size(); ++i) edit.values.emplace_back(keys[i], v.value()[i]);
    Result<FeatureParams> p = MakeFeature(type, edit);
    if (!p) return p.error();
    c.params = p.value();
    return c;
  }
  if (verb == "update") {
    if (w.size() < 3) return Error{"update takes <site:host:number> <key>=<value> ..."};
    Result<FeatureId> id = ParseFeatureId(w[1]);
    if (!id) return id.error();
    c.verb = ControlVerb::kUpdate;
    c.target = id.value();
    for (size_t i = 2; i < w.size(); ++i) {
      const size_t eq = w[i].find('=');
      if (eq == std::string_view::npos || eq == 0) {
        return Error{fmt::format("update argument \"{}\" is not key=value", w[i])};
      }
      const std::string_view key = w[i].substr(0, eq);
      if (key == "soil") {  // an area's soil, by name
        const auto soil = ParseMaterial(w[i].substr(eq + 1));
        if (!soil || *soil == Material::kFromGround) {
          return Error{fmt::format("soil \"{}\" is not a soil", w[i].substr(eq + 1))};
        }
        c.edit.soil = *soil;
        continue;
      }
      Result<double> v = Number(key, w[i].substr(eq + 1));
      if (!v) return v.error();
      c.edit.values.emplace_back(std::string(key), v.value());
    }
    return c;
  }
  if (verb == "destroy") {
    if (w.size() != 2) return Error{"destroy takes <site:host:number>"};
    Result<FeatureId> id = ParseFeatureId(w[1]);
    if (!id) return id.error();
    c.verb = ControlVerb::kDestroy;
    c.target = id.value();
    return c;
  }
  if (verb == "breach") {
    if (w.size() != 4) return Error{"breach takes <site:host:number> <gap_start_m> <gap_width_m>"};
    Result<FeatureId> id = ParseFeatureId(w[1]);
    if (!id) return id.error();
    Result<double> start = Number("gap_start_m", w[2]);
    Result<double> width = Number("gap_width_m", w[3]);
    if (!start) return start.error();
    if (!width) return width.error();
    if (start.value() < 0.0 || width.value() <= 0.0) {
      return Error{fmt::format("breach needs gap_start_m >= 0 and gap_width_m > 0, got {} and {}",
                               start.value(), width.value())};
    }
    c.verb = ControlVerb::kBreach;
    c.target = id.value();
    c.gap_start_m = start.value();
    c.gap_width_m = width.value();
    return c;
  }
  if (verb == "drive") {
    Result<std::vector<double>> v = Numbers(w, {"vehicle", "speed_mps", "heading_rate_deg_s"});
    if (!v) return v.error();
    const double index = v.value()[0];
    if (index < 0.0 || index != std::floor(index) || index > 1e6) {
      return Error{fmt::format("vehicle \"{}\" is not an index", w[1])};
    }
    c.verb = ControlVerb::kDrive;
    c.vehicle = static_cast<int>(index);
    c.speed_mps = v.value()[1];
    c.heading_rate_rad_s = v.value()[2] * kDegToRad;
    return c;
  }
  if (verb == "spawn") {
    if (w.size() != 5 && w.size() != 6) {
      return Error{"spawn takes <type> <x_m> <z_m> <heading_deg> [physical|light]"};
    }
    Result<double> x = Number("x_m", w[2]);
    Result<double> z = Number("z_m", w[3]);
    Result<double> h = Number("heading_deg", w[4]);
    if (!x) return x.error();
    if (!z) return z.error();
    if (!h) return h.error();
    c.verb = ControlVerb::kSpawn;
    c.spawn.type = std::string(w[1]);
    c.spawn.x_m = x.value();
    c.spawn.z_m = z.value();
    c.spawn.heading_rad = h.value() * kDegToRad;
    if (w.size() == 6) {
      if (w[5] != "physical" && w[5] != "light") {
        return Error{fmt::format("spawn model \"{}\" is neither physical nor light", w[5])};
      }
      c.spawn.model = std::string(w[5]);
    }
    return c;
  }
  if (verb == "blade") {
    const bool down = w.size() == 4 && w.size() > 2 && w[2] == "down";
    const bool up = w.size() == 3 && w[2] == "up";
    if (!down && !up) return Error{"blade takes <vehicle> down <depth_m> or <vehicle> up"};
    Result<double> index = Number("vehicle", w[1]);
    if (!index) return index.error();
    if (index.value() < 0.0 || index.value() != std::floor(index.value()) || index.value() > 1e6) {
      return Error{fmt::format("vehicle \"{}\" is not an index", w[1])};
    }
    c.verb = ControlVerb::kBlade;
    c.vehicle = static_cast<int>(index.value());
    if (down) {
      Result<double> depth = Number("depth_m", w[3]);
      if (!depth) return depth.error();
      c.blade_depth_m = depth.value();
    }
    return c;
  }
  if (verb == "remove") {
    Result<std::vector<double>> v = Numbers(w, {"vehicle"});
    if (!v) return v.error();
    const double index = v.value()[0];
    if (index < 0.0 || index != std::floor(index) || index > 1e6) {
      return Error{fmt::format("vehicle \"{}\" is not an index", w[1])};
    }
    c.verb = ControlVerb::kRemove;
    c.vehicle = static_cast<int>(index);
    return c;
  }
  if (verb == "render" || verb == "export" || verb == "import") {
    if (w.size() != 2) return Error{fmt::format("{} takes <file>", verb)};
    c.verb = verb == "render" ? ControlVerb::kRender
                              : (verb == "export" ? ControlVerb::kExport : ControlVerb::kImport);
    c.path = std::string(w[1]);
    return c;
  }
  if (verb == "loss") {
    Result<std::vector<double>> v = Numbers(w, {"drop_probability"});
    if (!v) return v.error();
    if (v.value()[0] < 0.0 || v.value()[0] > 1.0) {
      return Error{fmt::format("drop_probability {} is outside [0, 1]", v.value()[0])};
    }
    c.verb = ControlVerb::kLoss;
    c.drop_probability = v.value()[0];
    return c;
  }
  if (verb == "partition") {
    if (w.size() < 2) return Error{"partition takes <site:host> ..."};
    for (size_t i = 1; i < w.size(); ++i) {
      Result<NodeAddress> a = ParseNodeAddress(w[i]);
      if (!a) return a.error();
      c.nodes.push_back(a.value());
    }
    c.verb = ControlVerb::kPartition;
    return c;
  }
  if (verb == "status") return no_args(ControlVerb::kStatus);
  if (verb == "digest") return no_args(ControlVerb::kDigest);
  if (verb == "features") return no_args(ControlVerb::kFeatures);
  if (verb == "heal") return no_args(ControlVerb::kHeal);
  if (verb == "ping") return no_args(ControlVerb::kPing);
  if (verb == "quit") return no_args(ControlVerb::kQuit);
  if (verb == "vehicles") return no_args(ControlVerb::kVehicles);
  return Error{fmt::format("unknown command \"{}\"; commands:\n{}", verb, ControlUsage())};
}

ControlReply RunFeatureCommand(const ControlCommand& c, NodeActions& actions) {
  switch (c.verb) {
    case ControlVerb::kCreate: {
      Result<FeatureId> id = actions.Create(c.params);
      if (!id) return ControlReply::Fail(id.error().message);
      return ControlReply::Ok(id.value().ToString());
    }
    case ControlVerb::kUpdate: {
      std::optional<FeatureParams> old = actions.Params(c.target);
      if (!old) return ControlReply::Fail(fmt::format("no live feature {}", c.target.ToString()));
      Result<FeatureParams> p = ApplyFeatureEdit(*old, c.edit);
      if (!p) return ControlReply::Fail(p.error().message);
      if (Status s = actions.Modify(c.target, p.value()); !s) {
        return ControlReply::Fail(s.error().message);
      }
      return ControlReply::Ok(c.target.ToString());
    }
    case ControlVerb::kDestroy:
      if (Status s = actions.Destroy(c.target); !s) return ControlReply::Fail(s.error().message);
      return ControlReply::Ok(c.target.ToString());
    case ControlVerb::kBreach: {
      Result<std::vector<FeatureId>> ids = actions.Breach(c.target, c.gap_start_m, c.gap_width_m);
      if (!ids) return ControlReply::Fail(ids.error().message);
      return ControlReply::Ok(IdLines(ids.value()));
    }
    case ControlVerb::kDrive: {
      if (c.vehicle >= actions.vehicle_count()) {
        return ControlReply::Fail(fmt::format("vehicle {} does not exist (this node has {})",
                                              c.vehicle, actions.vehicle_count()));
      }
      Result<AppliedDrive> applied = actions.Drive(c.vehicle, c.speed_mps, c.heading_rate_rad_s);
      if (!applied) return ControlReply::Fail(applied.error().message);
      return ControlReply::Ok(ClampNotes(c, applied.value()));
    }
    case ControlVerb::kSpawn: {
      Result<int> index = actions.Spawn(c.spawn);
      if (!index) return ControlReply::Fail(index.error().message);
      return ControlReply::Ok(fmt::format("{}", index.value()));
    }
    case ControlVerb::kRemove:
      if (Status s = actions.Remove(c.vehicle); !s) return ControlReply::Fail(s.error().message);
      return ControlReply::Ok();
    case ControlVerb::kBlade:
      if (c.vehicle >= actions.vehicle_count()) {
        return ControlReply::Fail(fmt::format("vehicle {} does not exist (this node has {})",
                                              c.vehicle, actions.vehicle_count()));
      }
      if (Status s = actions.SetBlade(c.vehicle, c.blade_depth_m); !s) {
        return ControlReply::Fail(s.error().message);
      }
      return ControlReply::Ok(c.blade_depth_m ? fmt::format("blade down {} m", *c.blade_depth_m)
                                              : std::string("blade up"));
    default:
      return ControlReply::Fail("not a feature command");
  }
}

}  // namespace dt
