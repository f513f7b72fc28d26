#include "runtime/status_report.h"

#include <algorithm>
#include <charconv>
#include <map>
#include <set>
#include <type_traits>

#include <fmt/format.h>

#include "runtime/control_command.h"

namespace dt {
namespace {

std::string RejectedKey(size_t reason) {
  return fmt::format("rejected_{}", RejectReasonName(static_cast<RejectReason>(reason)));
}

// Every single-line key in the text's order, with its field: ToText and Parse both walk this
// list, so the two cannot disagree on a key or its place.
template <typename Report, typename Visit>
void ForEachSingleLine(Report& r, Visit&& visit) {
  visit("name", r.name);
  visit("address", r.address);
  visit("role", r.role);
  visit("require_server", r.require_server);
  visit("signed_on", r.signed_on);
  visit("caught_up", r.caught_up);
  visit("diverged", r.diverged);
  visit("diverged_since_ms", r.diverged_since_ms);
  visit("features", r.features);
  visit("digest", r.digest);
  visit("own_feature_number", r.own_feature_number);
  visit("own_change_seq", r.own_change_seq);
  visit("acknowledged_change_seq", r.acknowledged_change_seq);
  visit("sent", r.sent);
  visit("received", r.received);
  visit("rejected", r.rejected);
  visit("played_back", r.played_back);
  visit("applied", r.applied);
  visit("ignored_stale", r.ignored_stale);
  visit("fault_dropped", r.fault_dropped);
  visit("drop_probability", r.drop_probability);
  visit("write_queued", r.write_queued);
  visit("write_retried", r.write_retried);
  visit("write_failed", r.write_failed);
  visit("write_given_up", r.write_given_up);
  visit("voided", r.voided);
  visit("gave_up", r.gave_up);
  visit("refused_stranger", r.refused_stranger);
  visit("refused_role", r.refused_role);
  visit("refused_claim", r.refused_claim);
  visit("refused_lamport", r.refused_lamport);
  visit("refused_ground", r.refused_ground);
  visit("ground_digest", r.ground_digest);
  visit("ground_source", r.ground_source);
  visit("ground_refused", r.ground_refused);
  visit("exercise_ground_digest", r.exercise_ground_digest);
  for (size_t i = 0; i < kRejectReasonCount; ++i) visit(RejectedKey(i), r.rejected_by_reason[i]);
  visit("authenticated", r.authenticated);
  visit("auth_senders", r.auth_senders);
  visit("clock_suspect_senders", r.clock_suspect_senders);
  visit("clock_worst_offset_ms", r.clock_worst_offset_ms);
  visit("own_clock_suspect", r.own_clock_suspect);
  visit("own_clock_offset_ms", r.own_clock_offset_ms);
}

// The keys of the repeated lines.
constexpr std::string_view kMaxFeatureKey = "max_feature";
constexpr std::string_view kClockSuspectKey = "clock_suspect";
constexpr std::string_view kGroundMismatchKey = "ground_mismatch";
constexpr std::string_view kDivergenceKey = "divergence";
constexpr std::string_view kVehicleKey = "vehicle";

template <typename T>
std::string ValueText(const T& v) {
  if constexpr (std::is_same_v<T, bool>) {
    return v ? "1" : "0";
  } else if constexpr (std::is_same_v<T, NodeAddress>) {
    return v.ToString();
  } else if constexpr (std::is_same_v<T, NodeRole>) {
    return std::string(NodeRoleName(v));
  } else {
    return fmt::format("{}", v);  // strings, whole numbers, and doubles in their shortest form
  }
}

template <typename T>
bool ReadNumber(std::string_view text, T& out) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && end == text.data() + text.size();
}

bool ReadValue(std::string_view text, std::string& out) {
  out = std::string(text);
  return true;
}
bool ReadValue(std::string_view text, bool& out) {
  if (text != "0" && text != "1") return false;
  out = text == "1";
  return true;
}
bool ReadValue(std::string_view text, int64_t& out) { return ReadNumber(text, out); }
bool ReadValue(std::string_view text, uint64_t& out) { return ReadNumber(text, out); }
bool ReadValue(std::string_view text, double& out) { return ReadNumber(text, out); }
bool ReadValue(std::string_view text, NodeAddress& out) {
  Result<NodeAddress> a = ParseNodeAddress(text);
  if (a) out = a.value();
  return a.ok();
}
bool ReadValue(std::string_view text, NodeRole& out) {
  for (NodeRole r : {NodeRole::kNode, NodeRole::kServer, NodeRole::kStandby, NodeRole::kObserver}) {
    if (text == NodeRoleName(r)) {
      out = r;
      return true;
    }
  }
  return false;
}

// What a value of each type must look like, for the error.
template <typename T>
std::string_view Expected() {
  if constexpr (std::is_same_v<T, bool>) return "1 or 0";
  if constexpr (std::is_same_v<T, int64_t>) return "a whole number";
  if constexpr (std::is_same_v<T, uint64_t>) return "a whole number >= 0";
  if constexpr (std::is_same_v<T, double>) return "a number";
  if constexpr (std::is_same_v<T, NodeAddress>) return "site:host";
  if constexpr (std::is_same_v<T, NodeRole>) return "node, server, standby or observer";
  return "text";
}

Error BadValue(std::string_view key, std::string_view value, std::string_view expected) {
  return Error{fmt::format("status \"{}\" value \"{}\" is not {}", key, value, expected)};
}

std::vector<std::string_view> Words(std::string_view text) {
  std::vector<std::string_view> out;
  for (size_t a = 0; a <= text.size();) {
    const size_t b = std::min(text.find(' ', a), text.size());
    out.push_back(text.substr(a, b - a));
    a = b + 1;
  }
  return out;
}

std::string MaxFeatureText(const StatusReport::MaxFeature& m) {
  return fmt::format("{} {}", m.origin.ToString(), m.number);
}

Result<StatusReport::MaxFeature> ReadMaxFeature(std::string_view value) {
  const std::vector<std::string_view> w = Words(value);
  StatusReport::MaxFeature m;
  if (w.size() != 2 || !ReadValue(w[0], m.origin) || !ReadNumber(w[1], m.number)) {
    return BadValue(kMaxFeatureKey, value, "<site:host> <number>");
  }
  return m;
}

std::string ClockSuspectText(const StatusReport::ClockSuspect& c) {
  return fmt::format("{} offset_ms={} stale={}", c.sender.ToString(), c.offset_ms, c.stale);
}

// The value of a "key=value" word, or nullopt if the word is not for `key`.
std::optional<std::string_view> KeyedValue(std::string_view word, std::string_view key) {
  if (word.size() <= key.size() || word.substr(0, key.size()) != key || word[key.size()] != '=') {
    return std::nullopt;
  }
  return word.substr(key.size() + 1);
}

Result<StatusReport::ClockSuspect> ReadClockSuspect(std::string_view value) {
  const std::vector<std::string_view> w = Words(value);
  StatusReport::ClockSuspect c;
  std::optional<std::string_view> offset, stale;
  if (w.size() == 3) {
    offset = KeyedValue(w[1], "offset_ms");
    stale = KeyedValue(w[2], "stale");
  }
  if (!offset || !stale || !ReadValue(w[0], c.sender) || !ReadNumber(*offset, c.offset_ms) ||
      !ReadNumber(*stale, c.stale)) {
    return BadValue(kClockSuspectKey, value, "<site:host> offset_ms=<ms> stale=<n>");
  }
  return c;
}

std::string DivergenceText(const StatusReport::Divergence& d) {
  return fmt::format("{} with {} changes {}..{}{} since_ms {}", d.author.ToString(),
                     d.peer.ToString(), d.first_seq, d.last_seq, d.located ? "" : " (not located)",
                     d.since_ms);
}

Result<StatusReport::Divergence> ReadDivergence(std::string_view value) {
  std::vector<std::string_view> w = Words(value);
  StatusReport::Divergence d;
  d.located = !(w.size() == 9 && w[5] == "(not" && w[6] == "located)");
  if (!d.located) w.erase(w.begin() + 5, w.begin() + 7);
  const size_t dots = w.size() == 7 ? w[4].find("..") : std::string_view::npos;
  if (dots == std::string_view::npos || w[1] != "with" || w[3] != "changes" || w[5] != "since_ms" ||
      !ReadValue(w[0], d.author) || !ReadValue(w[2], d.peer) ||
      !ReadNumber(w[4].substr(0, dots), d.first_seq) ||
      !ReadNumber(w[4].substr(dots + 2), d.last_seq) || !ReadNumber(w[6], d.since_ms)) {
    return BadValue(kDivergenceKey, value,
                    "<site:host> with <site:host> changes <first>..<last>[ (not located)] "
                    "since_ms <ms>");
  }
  return d;
}

std::string VehicleText(const StatusReport::Vehicle& v) {
  return fmt::format(
      "{} {} x_m={:.2f} z_m={:.2f} y_m={:.2f} heading_rad={:.3f} speed_mps={:.2f} on_bridge={} "
      "alive={} model={} damage={}",
      v.index, v.type, v.x_m, v.z_m, v.y_m, v.heading_rad, v.speed_mps,
      v.on_bridge ? v.on_bridge->ToString() : "-", v.alive ? 1 : 0, VehicleModelName(v.model),
      DamageName(v.damage));
}

bool ReadDamage(std::string_view text, Damage& out) {
  for (Damage d : {Damage::kNone, Damage::kImmobilised, Damage::kDestroyed}) {
    if (text == DamageName(d)) {
      out = d;
      return true;
    }
  }
  return false;
}

Result<StatusReport::Vehicle> ReadVehicle(std::string_view value) {
  const std::vector<std::string_view> w = Words(value);
  constexpr std::string_view kKeys[] = {"x_m",       "z_m",   "y_m",   "heading_rad", "speed_mps",
                                        "on_bridge", "alive", "model", "damage"};
  const auto bad = [&] {
    return BadValue(kVehicleKey, value,
                    "<index> <type> x_m= z_m= y_m= heading_rad= speed_mps= on_bridge= alive= "
                    "model= damage=");
  };
  if (w.size() != 2 + std::size(kKeys)) return bad();
  std::string_view values[std::size(kKeys)];
  for (size_t k = 0; k < std::size(kKeys); ++k) {
    const std::optional<std::string_view> v = KeyedValue(w[2 + k], kKeys[k]);
    if (!v) return bad();
    values[k] = *v;
  }
  StatusReport::Vehicle v;
  v.type = std::string(w[1]);
  std::optional<VehicleModel> model = ParseVehicleModel(values[7]);
  if (!ReadNumber(w[0], v.index) || v.type.empty() || !ReadNumber(values[0], v.x_m) ||
      !ReadNumber(values[1], v.z_m) || !ReadNumber(values[2], v.y_m) ||
      !ReadNumber(values[3], v.heading_rad) || !ReadNumber(values[4], v.speed_mps) ||
      !ReadValue(values[6], v.alive) || !model || !ReadDamage(values[8], v.damage)) {
    return bad();
  }
  v.model = *model;
  if (values[5] != "-") {
    Result<FeatureId> bridge = ParseFeatureId(values[5]);
    if (!bridge) return bad();
    v.on_bridge = bridge.value();
  }
  return v;
}

// The single-line keys, for telling them from the process's own lines.
const std::set<std::string, std::less<>>& SingleLineKeys() {
  static const std::set<std::string, std::less<>> keys = [] {
    std::set<std::string, std::less<>> out;
    StatusReport r;
    ForEachSingleLine(r, [&](std::string_view key, auto&) { out.insert(std::string(key)); });
    return out;
  }();
  return keys;
}

}  // namespace

std::string StatusReport::ToText() const {
  std::string s;
  auto line = [&](std::string_view key, const std::string& value) {
    if (!s.empty()) s += '\n';
    s += key;
    s += ' ';
    s += value;
  };
  ForEachSingleLine(*this, [&](std::string_view key, const auto& v) { line(key, ValueText(v)); });
  for (const MaxFeature& m : max_features) line(kMaxFeatureKey, MaxFeatureText(m));
  for (const ClockSuspect& c : clock_suspects) line(kClockSuspectKey, ClockSuspectText(c));
  for (const GroundMismatch& g : ground_mismatches) {
    line(kGroundMismatchKey, fmt::format("{} digest={}", g.member.ToString(), g.digest));
  }
  for (const Divergence& d : divergences) line(kDivergenceKey, DivergenceText(d));
  for (const Vehicle& v : vehicles) line(kVehicleKey, VehicleText(v));
  for (const auto& [key, value] : other_lines) line(key, value);
  return s;
}

Result<StatusReport> StatusReport::Parse(std::string_view text) {
  StatusReport r;
  std::map<std::string_view, std::string_view> single;  // single-line key -> value
  for (size_t a = 0; a < text.size();) {
    const size_t b = std::min(text.find('\n', a), text.size());
    const std::string_view l = text.substr(a, b - a);
    a = b + 1;
    if (l.empty()) continue;
    const size_t space = l.find(' ');
    if (space == std::string_view::npos || space == 0) {
      return Error{fmt::format("status line \"{}\" is not \"key value\"", l)};
    }
    const std::string_view key = l.substr(0, space);
    const std::string_view value = l.substr(space + 1);
    if (key == kMaxFeatureKey) {
      Result<MaxFeature> m = ReadMaxFeature(value);
      if (!m) return m.error();
      r.max_features.push_back(m.value());
    } else if (key == kClockSuspectKey) {
      Result<ClockSuspect> c = ReadClockSuspect(value);
      if (!c) return c.error();
      r.clock_suspects.push_back(c.value());
    } else if (key == kGroundMismatchKey) {
      const size_t gap = value.find(" digest=");
      Result<NodeAddress> member = ParseNodeAddress(value.substr(0, gap));
      if (gap == std::string_view::npos || !member || value.size() == gap + 8) {
        return Error{fmt::format("status line \"{}\" is not \"{} <site:host> digest=<hex>\"", l,
                                 kGroundMismatchKey)};
      }
      r.ground_mismatches.push_back({member.value(), std::string(value.substr(gap + 8))});
    } else if (key == kDivergenceKey) {
      Result<Divergence> d = ReadDivergence(value);
      if (!d) return d.error();
      r.divergences.push_back(d.value());
    } else if (key == kVehicleKey) {
      Result<Vehicle> v = ReadVehicle(value);
      if (!v) return v.error();
      r.vehicles.push_back(std::move(v).value());
    } else if (SingleLineKeys().count(key) != 0) {
      if (!single.emplace(key, value).second) {
        return Error{fmt::format("status line \"{}\" repeats the key \"{}\"", l, key)};
      }
    } else {
      r.other_lines.emplace_back(std::string(key), std::string(value));
    }
  }
  std::optional<Error> error;
  ForEachSingleLine(r, [&](std::string_view key, auto& field) {
    if (error) return;
    const auto it = single.find(key);
    if (it == single.end()) {
      error = Error{fmt::format("status has no \"{}\" line", key)};
    } else if (!ReadValue(it->second, field)) {
      error = BadValue(key, it->second, Expected<std::remove_reference_t<decltype(field)>>());
    }
  });
  if (error) return *error;
  return r;
}

}  // namespace dt
