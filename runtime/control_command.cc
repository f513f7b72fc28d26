#include "runtime/control_command.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <set>

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

using Words = std::vector<std::string_view>;

Error Takes(const ControlVerbSpec& spec) {
  return Error{fmt::format("{} takes {}", spec.word, spec.synopsis)};
}

// A vehicle's index: a whole number in [0, 1e6].
Result<int> VehicleIndex(double index, std::string_view text) {
  if (index < 0.0 || index != std::floor(index) || index > 1e6) {
    return Error{fmt::format("vehicle \"{}\" is not an index", text)};
  }
  return static_cast<int>(index);
}

// ditch|berm_line <key>=<value> ... <x,z,height,width> ...; area <soil> [level_m=<m>] <x,z> ...
Result<ControlCommand> ParsePointFeature(const ControlVerbSpec& spec, const Words& w) {
  const FeatureType type = ParseFeatureType(w[0]).value();
  const bool area = type == FeatureType::kArea;
  FeatureEdit edit;
  size_t first = 1;
  if (area) {
    if (w.size() < 2) return Takes(spec);
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
  Result<FeatureParams> p = MakeFeature(type, edit);
  if (!p) return p.error();
  ControlCommand c;
  c.params = p.value();
  return c;
}

// crater|berm|bridge with the type's required values in order.
Result<ControlCommand> ParsePositionalFeature(const ControlVerbSpec&, const Words& w) {
  const FeatureType type = ParseFeatureType(w[0]).value();
  std::vector<std::string_view> keys = RequiredFeatureKeys(type);
  // A crater may give its depth below the ground as a fourth number.
  if (type == FeatureType::kCrater && w.size() == keys.size() + 2) keys.push_back("depth_m");
  Result<std::vector<double>> v = Numbers(w, keys);
  if (!v) return v.error();
  FeatureEdit edit;
  for (size_t i = 0; i < keys.size(); ++i) edit.values.emplace_back(keys[i], v.value()[i]);
  Result<FeatureParams> p = MakeFeature(type, edit);
  if (!p) return p.error();
  ControlCommand c;
  c.params = p.value();
  return c;
}

Result<ControlCommand> ParseUpdate(const ControlVerbSpec& spec, const Words& w) {
  if (w.size() < 3) return Takes(spec);
  Result<FeatureId> id = ParseFeatureId(w[1]);
  if (!id) return id.error();
  ControlCommand c;
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

Result<ControlCommand> ParseDestroy(const ControlVerbSpec& spec, const Words& w) {
  if (w.size() != 2) return Takes(spec);
  Result<FeatureId> id = ParseFeatureId(w[1]);
  if (!id) return id.error();
  ControlCommand c;
  c.target = id.value();
  return c;
}

Result<ControlCommand> ParseBreach(const ControlVerbSpec& spec, const Words& w) {
  if (w.size() != 4) return Takes(spec);
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
  ControlCommand c;
  c.target = id.value();
  c.gap_start_m = start.value();
  c.gap_width_m = width.value();
  return c;
}

Result<ControlCommand> ParseDrive(const ControlVerbSpec&, const Words& w) {
  Result<std::vector<double>> v = Numbers(w, {"vehicle", "speed_mps", "heading_rate_deg_s"});
  if (!v) return v.error();
  Result<int> index = VehicleIndex(v.value()[0], w[1]);
  if (!index) return index.error();
  ControlCommand c;
  c.vehicle = index.value();
  c.speed_mps = v.value()[1];
  c.heading_rate_rad_s = v.value()[2] * kDegToRad;
  return c;
}

Result<ControlCommand> ParseSpawn(const ControlVerbSpec& spec, const Words& w) {
  if (w.size() != 5 && w.size() != 6) return Takes(spec);
  Result<double> x = Number("x_m", w[2]);
  Result<double> z = Number("z_m", w[3]);
  Result<double> h = Number("heading_deg", w[4]);
  if (!x) return x.error();
  if (!z) return z.error();
  if (!h) return h.error();
  ControlCommand c;
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

Result<ControlCommand> ParseRemove(const ControlVerbSpec&, const Words& w) {
  Result<std::vector<double>> v = Numbers(w, {"vehicle"});
  if (!v) return v.error();
  Result<int> index = VehicleIndex(v.value()[0], w[1]);
  if (!index) return index.error();
  ControlCommand c;
  c.vehicle = index.value();
  return c;
}

Result<ControlCommand> ParseBlade(const ControlVerbSpec&, const Words& w) {
  const bool down = w.size() == 4 && w[2] == "down";
  const bool up = w.size() == 3 && w[2] == "up";
  if (!down && !up) return Error{"blade takes <vehicle> down <depth_m> or <vehicle> up"};
  Result<double> number = Number("vehicle", w[1]);
  if (!number) return number.error();
  Result<int> index = VehicleIndex(number.value(), w[1]);
  if (!index) return index.error();
  ControlCommand c;
  c.vehicle = index.value();
  if (down) {
    Result<double> depth = Number("depth_m", w[3]);
    if (!depth) return depth.error();
    c.blade_depth_m = depth.value();
  }
  return c;
}

// render, export, import <file>.
Result<ControlCommand> ParsePath(const ControlVerbSpec&, const Words& w) {
  if (w.size() != 2) return Error{fmt::format("{} takes <file>", w[0])};
  ControlCommand c;
  c.path = std::string(w[1]);
  return c;
}

Result<ControlCommand> ParseLoss(const ControlVerbSpec&, const Words& w) {
  Result<std::vector<double>> v = Numbers(w, {"drop_probability"});
  if (!v) return v.error();
  if (v.value()[0] < 0.0 || v.value()[0] > 1.0) {
    return Error{fmt::format("drop_probability {} is outside [0, 1]", v.value()[0])};
  }
  ControlCommand c;
  c.drop_probability = v.value()[0];
  return c;
}

Result<ControlCommand> ParsePartition(const ControlVerbSpec& spec, const Words& w) {
  if (w.size() < 2) return Takes(spec);
  ControlCommand c;
  for (size_t i = 1; i < w.size(); ++i) {
    Result<NodeAddress> a = ParseNodeAddress(w[i]);
    if (!a) return a.error();
    c.nodes.push_back(a.value());
  }
  return c;
}

Result<ControlCommand> ParseNoArguments(const ControlVerbSpec&, const Words& w) {
  if (w.size() != 1) return Error{fmt::format("{} takes no arguments", w[0])};
  return ControlCommand{};
}

// vehicles [--owner <site:host>] [--offset <n>] [--limit <n> | --all]: each option once.
Result<ControlCommand> ParseVehicles(const ControlVerbSpec& spec, const Words& w) {
  ControlCommand c;
  std::set<std::string_view> seen;
  for (size_t i = 1; i < w.size(); ++i) {
    const std::string_view option = w[i];
    if (!seen.insert(option).second) return Error{fmt::format("vehicles: {} given twice", option)};
    if (option == "--all") {
      if (seen.count("--limit") != 0)
        return Error{"vehicles: --all and --limit exclude each other"};
      continue;
    }
    if (option != "--owner" && option != "--offset" && option != "--limit") {
      return Error{fmt::format("vehicles: unknown option \"{}\"; usage: vehicles {}", option,
                               spec.synopsis)};
    }
    if (i + 1 >= w.size()) return Error{fmt::format("vehicles: {} needs a value", option)};
    const std::string_view value = w[++i];
    if (option == "--owner") {
      if (!ParseNodeAddress(value)) {
        return Error{fmt::format("vehicles: --owner \"{}\" is not a site:host address", value)};
      }
      c.vehicle_page.owner = std::string(value);
      continue;
    }
    if (option == "--limit" && seen.count("--all") != 0) {
      return Error{"vehicles: --all and --limit exclude each other"};
    }
    size_t n = 0;
    const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), n);
    if (ec != std::errc() || ptr != value.data() + value.size() ||
        (option == "--limit" && n == 0)) {
      return Error{fmt::format("vehicles: {} \"{}\" is not a whole number{}", option, value,
                               option == "--limit" ? " of at least 1" : "")};
    }
    if (option == "--offset") c.vehicle_page.offset = n;
    if (option == "--limit") c.vehicle_page.limit = n;
  }
  return c;
}

// Every command word, in the usage's order (the usage text and the dispatch both come from it).
constexpr bool kOwnLine = false;  // starts a usage line
constexpr bool kJoins = true;     // on the previous row's usage line
constexpr ControlVerbSpec kVerbTable[] = {
    {"crater", ControlVerb::kCreate, "<x_m> <z_m> <radius_m> [<depth_m>]",
     "makes a crater; a fourth number is its depth below the ground", kOwnLine,
     ParsePositionalFeature},
    {"ditch", ControlVerb::kCreate,
     "side_run_m=<m> [spoil_height_m=<m> spoil_width_m=<m>] <x,z,depth,width> ...",
     "digs a ditch along the points, its spoil heaped beside it", kOwnLine, ParsePointFeature},
    {"berm_line", ControlVerb::kCreate, "<x,z,height,width> <x,z,height,width> ...",
     "raises a berm along the points", kOwnLine, ParsePointFeature},
    {"area", ControlVerb::kCreate, "<soil> [level_m=<m>] <x,z> <x,z> <x,z> ...",
     "covers a polygon with a soil; water floods it to level_m", kOwnLine, ParsePointFeature},
    {"berm", ControlVerb::kCreate, "<x_m> <z_m> <direction_deg> <length_m> <width_m> <height_m>",
     "raises a straight berm", kOwnLine, ParsePositionalFeature},
    {"bridge", ControlVerb::kCreate,
     "<x_m> <z_m> <direction_deg> <width_m> <ramp1_m> <span_m> <ramp2_m> <height1_m> <height2_m>",
     "lays a bridge: a ramp, a span and a ramp", kOwnLine, ParsePositionalFeature},
    {"update", ControlVerb::kUpdate, "<site:host:number> <key>=<value> ...",
     "changes a live feature's values (an area's soil=<name> too)", kOwnLine, ParseUpdate},
    {"destroy", ControlVerb::kDestroy, "<site:host:number>", "destroys a live feature", kOwnLine,
     ParseDestroy},
    {"breach", ControlVerb::kBreach, "<site:host:number> <gap_start_m> <gap_width_m>",
     "cuts a gap in a berm, leaving the pieces on either side", kOwnLine, ParseBreach},
    {"drive", ControlVerb::kDrive, "<vehicle> <speed_mps> <heading_rate_deg_s>",
     "commands a vehicle's speed and turn rate, clamped to its type's limits", kOwnLine,
     ParseDrive},
    {"spawn", ControlVerb::kSpawn, "<type> <x_m> <z_m> <heading_deg> [physical|light]",
     "adds a vehicle to a node", kOwnLine, ParseSpawn},
    {"remove", ControlVerb::kRemove, "<vehicle>", "removes a node's vehicle", kJoins, ParseRemove},
    {"vehicles", ControlVerb::kVehicles,
     "[--owner <site:host>] [--offset <n>] [--limit <n> | --all]",
     "a node's local and remote vehicles, one a line: all, or a page of them", kOwnLine,
     ParseVehicles},
    // Two forms, shown as the usage has always shown them.
    {"blade", ControlVerb::kBlade, "<vehicle> down <depth_m> | blade <vehicle> up",
     "lowers a bulldozer's blade to cut and carry, or raises it to set its load down", kOwnLine,
     ParseBlade},
    {"status", ControlVerb::kStatus, "",
     "the process's state and counters, key value lines (runtime/status_report.h)", kOwnLine,
     ParseNoArguments},
    {"digest", ControlVerb::kDigest, "", "the terrain digest", kJoins, ParseNoArguments},
    {"features", ControlVerb::kFeatures, "", "every live feature ID, one a line", kJoins,
     ParseNoArguments},
    {"ping", ControlVerb::kPing, "", "answers pong", kJoins, ParseNoArguments},
    {"quit", ControlVerb::kQuit, "", "stops the process", kJoins, ParseNoArguments},
    {"render", ControlVerb::kRender, "<file.png>", "draws a map of the terrain and vehicles",
     kOwnLine, ParsePath},
    {"export", ControlVerb::kExport, "<file.dtt>", "the server saves its terrain as a terrain file",
     kOwnLine, ParsePath},
    // "(server)" covers both, as the usage has always shown it.
    {"import", ControlVerb::kImport, "<file.dtt> (server)",
     "the server issues a terrain file's features", kJoins, ParsePath},
    {"loss", ControlVerb::kLoss, "<drop_probability>",
     "drops received messages with this probability", kOwnLine, ParseLoss},
    {"partition", ControlVerb::kPartition, "<site:host> ...",
     "drops everything received from these nodes", kOwnLine, ParsePartition},
    {"heal", ControlVerb::kHeal, "", "ends partitions", kJoins, ParseNoArguments},
};

// The command words of kCreate: one per feature type but kEarthMove (blade work makes those).
constexpr int kCreateWords = 6;

// Each verb has its row (kCreate its kCreateWords), each word one row, and the usage starts a line.
constexpr bool VerbTableIsWhole() {
  for (int v = 0; v < static_cast<int>(ControlVerb::kCount); ++v) {
    int rows = 0;
    for (const ControlVerbSpec& s : kVerbTable) rows += static_cast<int>(s.verb) == v ? 1 : 0;
    if (rows != (static_cast<ControlVerb>(v) == ControlVerb::kCreate ? kCreateWords : 1)) {
      return false;
    }
  }
  for (size_t i = 0; i < std::size(kVerbTable); ++i) {
    if (kVerbTable[i].verb == ControlVerb::kCount) return false;
    for (size_t j = i + 1; j < std::size(kVerbTable); ++j) {
      if (kVerbTable[i].word == kVerbTable[j].word) return false;
    }
  }
  return !kVerbTable[0].joins_usage_line;
}
static_assert(VerbTableIsWhole(), "every ControlVerb needs its row in kVerbTable, once");

}  // namespace

std::span<const ControlVerbSpec> ControlVerbTable() { return kVerbTable; }

std::string ControlUsage() {
  std::string out;
  for (const ControlVerbSpec& s : kVerbTable) {
    if (!out.empty()) out += s.joins_usage_line ? " | " : "\n";
    out += s.word;
    if (!s.synopsis.empty()) {
      out += ' ';
      out += s.synopsis;
    }
  }
  return out;
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
  const Words w = Split(line);
  if (w.empty()) return Error{"empty command; commands:\n" + ControlUsage()};
  for (const ControlVerbSpec& spec : kVerbTable) {
    if (spec.word != w[0]) continue;
    Result<ControlCommand> c = spec.parse(spec, w);
    if (c) c.value().verb = spec.verb;
    return c;
  }
  return Error{fmt::format("unknown command \"{}\"; commands:\n{}", w[0], ControlUsage())};
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
