#include "view/view_model.h"

#include <algorithm>
#include <utility>

#include "vehicle/bridge_solids.h"
#include "view/vehicle_frame.h"

namespace dt {
namespace {

const char* KindName(ChangeKind k) {
  switch (k) {
    case ChangeKind::kConstruct:
      return "create";
    case ChangeKind::kUpdate:
      return "update";
    case ChangeKind::kDestruct:
      return "destroy";
  }
  return "unknown";
}

// The plan of each solid a vehicle meets (vehicle/bridge_solids.h, the geometry the physics and
// the renderer use): its kind and its four corners (x, z), so the page draws the bridge driven.
nlohmann::json BridgePlanJson(const FeatureParams& p) {
  nlohmann::json out = nlohmann::json::array();
  for (const Solid& s : BridgeSolidPlans(p)) {
    nlohmann::json corners = nlohmann::json::array();
    for (const auto& [a, r] : {std::pair{s.a0_m, s.r0_m}, std::pair{s.a1_m, s.r0_m},
                               std::pair{s.a1_m, s.r1_m}, std::pair{s.a0_m, s.r1_m}}) {
      corners.push_back({s.origin_x_m + a * s.ux + r * s.uz, s.origin_z_m + a * s.uz - r * s.ux});
    }
    out.push_back({{"kind", s.deck     ? "deck"
                            : s.rubble ? "rubble"
                                       : "pier"},
                   {"corners", std::move(corners)}});
  }
  return out;
}

// A vehicle's row with its slot: [id, owner, type, x, z, heading, speed, alive, slot].
nlohmann::json VehicleRow(const VehicleView& v, uint32_t slot) {
  nlohmann::json row = v.ToJson();
  row.push_back(slot);
  return row;
}

}  // namespace

nlohmann::json FeatureJson(FeatureId id, const Record& record) {
  const FeatureParams& p = record.params;
  nlohmann::json j = {{"id", id.ToString()},
                      {"type", std::string(FeatureTypeName(p.type))},
                      {"x", p.x_m},
                      {"z", p.z_m},
                      {"placed", record.placed}};
  switch (p.type) {
    case FeatureType::kCrater:
      j["radius"] = p.length_m[0];
      break;
    case FeatureType::kBerm:
      j["dir"] = p.direction_rad;
      j["length"] = p.length_m[0];
      j["width"] = p.width_m;
      j["height"] = p.height_m[0];
      break;
    case FeatureType::kBridge:
      j["dir"] = p.direction_rad;
      j["width"] = p.width_m;
      j["span"] = p.length_m[0];
      j["ramp1"] = p.length_m[1];
      j["ramp2"] = p.length_m[2];
      j["h1"] = p.height_m[0];
      j["h2"] = p.height_m[1];
      j["status"] = p.status == BridgeStatus::kDestroyed ? "destroyed" : "intact";
      j["solids"] = BridgePlanJson(p);
      break;
    case FeatureType::kDitch:
    case FeatureType::kBermLine:
    case FeatureType::kArea: {
      // Each point's cross-section: height (a ditch's depth) and width; an area's are 0.
      nlohmann::json points = nlohmann::json::array();
      for (const FeaturePoint& q : p.points)
        points.push_back({q.x_m, q.z_m, q.height_m, q.width_m});
      j["points"] = std::move(points);
      if (p.type == FeatureType::kArea) {
        j["soil"] = std::string(MaterialName(p.material));
        if (p.material == Material::kWater) j["level"] = p.height_m[0];
      }
      break;
    }
    case FeatureType::kEarthMove:
      // Blade work is in the ground the view draws; the feature only counts its posts.
      j["posts"] = p.post_deltas.size();
      break;
  }
  return j;
}

nlohmann::json ViewModel::Event::ToJson() const {
  nlohmann::json j = {{"t_ms", t_ms}, {"kind", kind}, {"by", by}};
  if (!feature.empty()) j["feature"] = feature;
  if (change_seq > 0) j["change_seq"] = change_seq;
  return j;
}

ViewModel::ViewModel(const Replica& replica, MemberNames names, size_t events_kept)
    : replica_(replica), names_(std::move(names)), events_kept_(events_kept) {}

std::string ViewModel::Name(NodeAddress a) const {
  auto it = names_.find(a);
  return it == names_.end() ? a.ToString() : it->second;
}

void ViewModel::Note(const Change& c, int64_t now_ms, std::vector<Event>& events) {
  Event e{now_ms, KindName(c.kind), c.id.ToString(), Name(c.author()), c.stamp.change_seq};
  const NodeAddress author = c.author();
  // Berms, berm lines and ditches are what a breach cuts (engine/replica.h Breach).
  const bool breachable = c.params.type == FeatureType::kBerm ||
                          c.params.type == FeatureType::kBermLine ||
                          c.params.type == FeatureType::kDitch;
  if (c.kind == ChangeKind::kDestruct && breachable) {
    last_berm_destruct_[author] = {c.stamp.change_seq, c.id};
  } else if (c.kind == ChangeKind::kConstruct && breachable) {
    // A breach is one Destruct of the berm and a Construct per piece, in consecutive sequences.
    auto it = last_berm_destruct_.find(author);
    if (it != last_berm_destruct_.end() && c.stamp.change_seq - it->second.first <= 2) {
      e.kind = "breach";
      it->second.first = c.stamp.change_seq;
      Event parent = e;
      parent.feature = it->second.second.ToString();
      history_[it->second.second].push_back(parent);
      history_changed_.insert(it->second.second);
    }
  }
  history_[c.id].push_back(e);
  history_changed_.insert(c.id);
  events.push_back(e);
}

void ViewModel::Refresh(const std::set<FeatureId>& ids, nlohmann::json& changed,
                        nlohmann::json& removed) {
  const auto& all = replica_.records().all();
  for (FeatureId id : ids) {
    auto it = all.find(id);
    if (it == all.end() || it->second.destroyed) {
      if (features_.erase(id) != 0) removed.push_back(id.ToString());
      bridges_.erase(id);
      continue;
    }
    nlohmann::json j = FeatureJson(id, it->second);
    if (it->second.params.type == FeatureType::kBridge) bridges_.insert(id);
    HeldFeature& held = features_[id];
    const bool fields_changed = held.fields != j;
    if (!fields_changed && held.text && history_changed_.count(id) == 0) continue;
    nlohmann::json out = j;
    nlohmann::json history = nlohmann::json::array();
    for (const Event& e : history_[id]) history.push_back(e.ToJson());
    out["history"] = std::move(history);
    held.text = std::make_shared<const std::string>(out.dump());
    if (fields_changed) {
      held.fields = std::move(j);
      changed.push_back(std::move(out));
    }
  }
}

void ViewModel::ForgetDropped() {
  std::set<std::pair<std::string, int64_t>> gone;  // (author's name, change_seq)
  for (auto& [author, upto] : noted_upto_) {
    const ChangeLog* log = replica_.log(author);
    std::set<int64_t>& beyond = noted_beyond_[author];
    const int64_t held_upto = log == nullptr ? 0 : log->contiguous();
    for (int64_t seq = held_upto + 1; seq <= upto; ++seq) {
      if (log != nullptr && log->Find(seq) != nullptr) {
        beyond.insert(seq);  // still held: noted, beyond the new gap-free point
      } else {
        gone.insert({Name(author), seq});
      }
    }
    upto = std::min(upto, held_upto);
    std::erase_if(beyond, [&](int64_t seq) {
      if (log != nullptr && log->Find(seq) != nullptr) return false;
      gone.insert({Name(author), seq});
      return true;
    });
  }
  if (gone.empty()) return;
  for (auto& [id, history] : history_) {
    if (std::erase_if(history, [&](const Event& e) {
          return gone.count({e.by, e.change_seq}) != 0;
        }) != 0)
      history_changed_.insert(id);
  }
}

void ViewModel::NoteProcesses(int64_t now_ms, const std::vector<ProcessRow>& rows,
                              std::vector<Event>& events) {
  for (const ProcessRow& r : rows) {
    auto old = std::find_if(processes_.begin(), processes_.end(),
                            [&](const ProcessRow& o) { return o.name == r.name; });
    // Joining, silence and coming back are the protocol's (PDUs heard), not the control
    // socket's: a process that is slow to answer `status` is not silent.
    const bool was_live = old != processes_.end() && !old->silent;
    const bool live = !r.silent;
    if (live && !was_live) {
      const bool back = !seen_live_.insert(r.name).second;
      events.push_back({now_ms, back ? "back" : "joined", "", r.name, 0});
    } else if (was_live && !live) {
      events.push_back({now_ms, "silent", "", r.name, 0});
    }
    const bool was_diverged = old != processes_.end() && old->diverged;
    if (r.diverged && !was_diverged) events.push_back({now_ms, "diverged", "", r.name, 0});
    if (!r.diverged && was_diverged) events.push_back({now_ms, "agrees", "", r.name, 0});
  }
  NoteDiffering(now_ms, rows, events);
}

void ViewModel::NoteDiffering(int64_t now_ms, const std::vector<ProcessRow>& rows,
                              std::vector<Event>& events) {
  // The exercise's digest as the page shows it: the server's, else the most common.
  std::map<std::string, int> counts;
  const ProcessRow* server = nullptr;
  for (const ProcessRow& r : rows) {
    if (!r.reachable) continue;
    ++counts[r.digest];
    if (r.role == "server" && server == nullptr) server = &r;
  }
  std::string agreed;
  if (server != nullptr) {
    agreed = server->digest;
  } else {
    int most = 0;
    for (const auto& [digest, n] : counts) {
      if (n > most) agreed = digest, most = n;
    }
  }
  for (const ProcessRow& r : rows) {
    // An unreachable process has no digest to compare: it keeps its state until it answers.
    if (!r.reachable) continue;
    auto it = differing_.find(r.name);
    if (r.digest == agreed) {
      if (it == differing_.end()) continue;
      if (it->second.reported) events.push_back({now_ms, "matches", "", r.name, 0});
      differing_.erase(it);
      continue;
    }
    if (it == differing_.end()) it = differing_.emplace(r.name, Differing{now_ms, false}).first;
    if (!it->second.reported && now_ms - it->second.since_ms >= kDiffersAfterMs) {
      it->second.reported = true;
      events.push_back({now_ms, "differs", "", r.name, 0});
    }
  }
}

nlohmann::json ViewModel::Update(int64_t now_ms, const std::vector<ProcessRow>& processes,
                                 const std::vector<VehicleView>& vehicles, int relief_version,
                                 std::string* vehicle_frame) {
  std::vector<Event> events;
  std::set<FeatureId> touched;
  bool bridge = false;
  // A dropped change takes records back without a new change, like a repair: look at everything.
  const uint64_t drops = replica_.anti_entropy().stats().slots_dropped;
  const bool dropped = drops != drops_seen_;
  drops_seen_ = drops;
  if (dropped) ForgetDropped();
  for (const auto& [author, contiguous] : replica_.contiguous_change_seq()) {
    const ChangeLog* log = replica_.log(author);
    if (log == nullptr) continue;
    int64_t& upto = noted_upto_[author];
    std::set<int64_t>& beyond = noted_beyond_[author];
    if (log->max_held() <= upto) continue;
    for (const Change* c : log->Range(upto + 1, log->max_held())) {
      if (!beyond.insert(c->stamp.change_seq).second) continue;
      Note(*c, now_ms, events);
      touched.insert(c->id);
      bridge = bridge || c->params.type == FeatureType::kBridge;
    }
    while (beyond.count(upto + 1) != 0) beyond.erase(++upto);
  }
  // A repaired slot (anti-entropy) changes records without a new change: look at everything.
  const uint64_t repairs = replica_.anti_entropy().stats().slots_repaired;
  const bool everything = repairs != repairs_seen_ || dropped;
  repairs_seen_ = repairs;
  if (everything) {
    for (const auto& [id, r] : replica_.records().all()) touched.insert(id);
    for (const auto& [id, j] : features_) touched.insert(id);
  } else if (bridge) {
    // A bridge change re-places every bridge (docs/protocol.md "Materialisation"), and nothing
    // else: every other feature changes only by its own changes, noted above. A bridge the
    // records hold is noted (so held) or repaired (everything, above).
    touched.insert(bridges_.begin(), bridges_.end());
  }
  // A history that changed without its feature's fields (a breach's parent, a dropped change)
  // still changes the snapshot's text.
  touched.insert(history_changed_.begin(), history_changed_.end());
  NoteProcesses(now_ms, processes, events);

  nlohmann::json delta = {{"type", "delta"}, {"t_ms", now_ms}};
  nlohmann::json changed = nlohmann::json::array(), removed = nlohmann::json::array();
  Refresh(touched, changed, removed);
  history_changed_.clear();
  if (!changed.empty()) delta["features"] = std::move(changed);
  if (!removed.empty()) delta["removed"] = std::move(removed);
  if (!events.empty()) {
    nlohmann::json ev = nlohmann::json::array();
    for (const Event& e : events) ev.push_back(e.ToJson());
    delta["events"] = std::move(ev);
    events_.insert(events_.end(), events.begin(), events.end());
    if (events_.size() > events_kept_) {
      events_.erase(events_.begin(),
                    events_.begin() + static_cast<std::ptrdiff_t>(events_.size() - events_kept_));
    }
  }
  if (processes != processes_) {
    nlohmann::json rows = nlohmann::json::array();
    for (const ProcessRow& r : processes) rows.push_back(r.ToJson());
    delta["processes"] = std::move(rows);
    processes_ = processes;
  }
  // Only the vehicles that moved or changed, and the IDs of those no longer listed.
  nlohmann::json moved = nlohmann::json::array(), gone = nlohmann::json::array();
  std::vector<std::pair<uint32_t, const VehicleView*>> framed;
  const uint64_t listing = ++listings_;
  for (const VehicleView& v : vehicles) {
    auto [it, fresh] = vehicles_.try_emplace(v.id);
    HeldVehicle& held = it->second;
    held.listed_at = listing;
    if (fresh) {
      if (free_slots_.empty()) {
        held.slot = next_slot_++;
      } else {
        held.slot = free_slots_.back();
        free_slots_.pop_back();
      }
    }
    if (!fresh && held.view == v) continue;
    // A new vehicle, or one whose owner or type changed, needs its row; a move only its record.
    const bool known = !fresh && held.view.owner == v.owner && held.view.type == v.type;
    held.view = v;
    if (vehicle_frame != nullptr && known) {
      framed.emplace_back(held.slot, &v);
    } else {
      moved.push_back(VehicleRow(v, held.slot));
    }
  }
  for (auto it = vehicles_.begin(); it != vehicles_.end();) {
    if (it->second.listed_at == listing) {
      ++it;
      continue;
    }
    gone.push_back(it->first);
    free_slots_.push_back(it->second.slot);
    it = vehicles_.erase(it);
  }
  if (!moved.empty()) delta["vehicles"] = std::move(moved);
  if (!gone.empty()) delta["vehicles_removed"] = std::move(gone);
  if (relief_version != relief_version_) {
    delta["relief"] = relief_version;
    relief_version_ = relief_version;
  }
  if (vehicle_frame != nullptr) vehicle_frame->clear();
  if (delta.size() == 2 && framed.empty()) return nullptr;  // nothing changed
  ++seq_;
  if (!framed.empty()) {
    *vehicle_frame = VehicleFrameHeader(seq_, now_ms, static_cast<uint32_t>(framed.size()));
    for (const auto& [slot, v] : framed) AppendVehicleRecord(*vehicle_frame, slot, *v);
  }
  if (delta.size() == 2) return nullptr;  // the vehicles' moves only: the frame says them
  delta["seq"] = seq_;
  return delta;
}

SnapshotCopy ViewModel::Copy() const {
  SnapshotCopy c;
  c.seq = seq_;
  c.relief_version = relief_version_;
  c.features.reserve(features_.size());
  for (const auto& [id, held] : features_) c.features.push_back(held.text);
  nlohmann::json events = nlohmann::json::array();
  for (const Event& e : events_) events.push_back(e.ToJson());
  c.events = events.dump();
  nlohmann::json rows = nlohmann::json::array();
  for (const ProcessRow& r : processes_) rows.push_back(r.ToJson());
  c.processes = rows.dump();
  c.vehicles.reserve(vehicles_.size());
  c.slots.reserve(vehicles_.size());
  for (const auto& [id, v] : vehicles_) {
    c.vehicles.push_back(v.view);
    c.slots.push_back(v.slot);
  }
  return c;
}

std::string SnapshotCopy::Text(int64_t now_ms, const nlohmann::json& extra) const {
  size_t size = 256 + events.size() + processes.size() + 80 * vehicles.size();
  for (const auto& f : features) size += f->size() + 1;
  std::string out;
  out.reserve(size);
  out +=
      R"({"type":"snapshot","seq":)" + std::to_string(seq) + R"(,"t_ms":)" + std::to_string(now_ms);
  for (const auto& [key, value] : extra.items()) {
    out += ',' + nlohmann::json(key).dump() + ':' + value.dump();
  }
  out += R"(,"features":[)";
  for (size_t i = 0; i < features.size(); ++i) {
    if (i != 0) out += ',';
    out += *features[i];
  }
  out += R"(],"events":)" + events + R"(,"processes":)" + processes + R"(,"vehicles":[)";
  for (size_t i = 0; i < vehicles.size(); ++i) {
    if (i != 0) out += ',';
    out += VehicleRow(vehicles[i], slots[i]).dump();
  }
  out += R"(],"relief":)" + std::to_string(relief_version) + '}';
  return out;
}

nlohmann::json ViewModel::Snapshot(int64_t now_ms) const {
  return nlohmann::json::parse(Copy().Text(now_ms, nlohmann::json::object()));
}

}  // namespace dt
