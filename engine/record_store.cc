#include "engine/record_store.h"

#include <iterator>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>

#include "base/demand.h"
#include "terrain/feature.h"

namespace dt {

RecordStore::RecordStore(HeightGrid ground) : terrain_(std::move(ground)) {}

RecordStore::RecordStore(BaseGround base) : terrain_(std::move(base.grid)) {
  for (const auto& [id, params] : base.features) {
    if (const Status s = terrain_.Add(id, params); !s) {
      throw std::invalid_argument(fmt::format("base ground feature {} does not place: {}",
                                              id.ToString(), s.error().message));
    }
  }
}

const Record* RecordStore::Find(FeatureId id) const {
  auto it = records_.find(id);
  return it == records_.end() ? nullptr : &it->second;
}

std::pair<RecordMap::iterator, bool> RecordStore::Claim(FeatureId id) {
  auto newest = newest_.find(OriginOf(id));
  if (newest != newest_.end() && newest->second->first < id) {
    // Past every number of its origin: the record goes right after that origin's newest one,
    // which the hint makes an insertion without a search of the tree. When that one is the last
    // record (one origin creating), end() is the hint: std::next would climb the tree to find it.
    const auto after =
        newest->second == std::prev(records_.end()) ? records_.end() : std::next(newest->second);
    auto it = records_.emplace_hint(after, std::piecewise_construct, std::forward_as_tuple(id),
                                    std::forward_as_tuple());
    newest->second = it;
    return {it, true};
  }
  auto claimed = records_.try_emplace(id);
  if (claimed.second && newest == newest_.end()) newest_.emplace(OriginOf(id), claimed.first);
  return claimed;
}

RecordStore::Outcome RecordStore::Apply(const Change& change) {
  auto [it, fresh] = Claim(change.id);
  Record& r = it->second;
  const bool was_bridge = !fresh && !r.destroyed && r.params.type == FeatureType::kBridge;
  if (!fresh) {
    if (r.destroyed) return Outcome::kStale;
    if (change.kind != ChangeKind::kDestruct && change.version() <= r.version) {
      return Outcome::kStale;
    }
  }
  const bool was_live = !fresh && !r.destroyed;
  r.version = std::max(r.version, change.version());
  if (change.kind == ChangeKind::kDestruct) {
    r.destroyed = true;
    r.params = FeatureParams{};
    r.params.type = change.params.type;
  } else {
    r.params = change.params;
  }
  const bool is_live = !r.destroyed;
  if (was_live && !is_live) --live_;
  if (!was_live && is_live) ++live_;
  if (was_bridge) live_bridges_.erase(change.id);
  const bool is_bridge = is_live && r.params.type == FeatureType::kBridge;
  if (is_bridge) live_bridges_.insert(change.id);
  Materialise(change.id, r, was_bridge || is_bridge);
  return Outcome::kApplied;
}

void RecordStore::Rebuild(FeatureId id, std::span<const Change* const> changes) {
  if (tracking_touched_) touched_.push_back(id);  // it may be gone for good now
  bool bridge_involved = false;
  if (auto it = records_.find(id); it != records_.end()) {
    Record& r = it->second;
    DT_DEMAND(!r.placed || terrain_.Remove(id));  // placed means the terrain holds it
    if (!r.destroyed) {
      --live_;
      if (r.params.type == FeatureType::kBridge) {
        live_bridges_.erase(id);
        bridge_involved = true;
      }
    }
    const NodeAddress origin = OriginOf(id);
    if (auto n = newest_.find(origin); n != newest_.end() && n->second == it) {
      // The origin's newest record goes: the one before it, if of the same origin, is newest now.
      if (it != records_.begin() && OriginOf(std::prev(it)->first) == origin) {
        n->second = std::prev(it);
      } else {
        newest_.erase(n);
      }
    }
    records_.erase(it);
  }
  for (const Change* c : changes) {
    DT_DEMAND(c->id == id);  // the caller gathers the changes of this feature only
    Apply(*c);
  }
  // A bridge that was there may have kept a later one out: place the live bridges again.
  if (bridge_involved) RematerialiseBridges();
}

void RecordStore::Materialise(FeatureId id, Record& r, bool bridge_involved) {
  if (tracking_touched_) touched_.push_back(id);
  if (r.placed) {
    DT_DEMAND(terrain_.Remove(id));  // placed means the terrain holds it
    r.placed = false;
  }
  if (bridge_involved) {
    RematerialiseBridges();
    return;
  }
  if (!r.destroyed) r.placed = Place(id, r.params).ok();
}

Status RecordStore::Place(FeatureId id, const FeatureParams& params) {
  std::unique_ptr<Feature> made = std::move(checked_.feature);
  if (made != nullptr && made->id() == id && checked_.terrain_stamp == terrain_.stamp() &&
      checked_.params == params) {
    return terrain_.Add(std::move(made));
  }
  return terrain_.Add(id, params);
}

void RecordStore::RematerialiseBridges() {
  // Only bridges conflict with each other, so placing every live bridge again in ID order gives
  // the same terrain as placing every record in ID order.
  for (FeatureId b : live_bridges_) {
    Record& r = records_.at(b);
    if (r.placed) {
      DT_DEMAND(terrain_.Remove(b));
      r.placed = false;
    }
  }
  for (FeatureId b : live_bridges_) {
    Record& r = records_.at(b);
    r.placed = terrain_.Add(b, r.params).ok();
    if (tracking_touched_) touched_.push_back(b);
  }
}

Status RecordStore::CheckPlaceable(FeatureId id, const FeatureParams& params) const {
  checked_.feature.reset();
  auto made = MakeFeature(id, params, terrain_.ground());
  if (!made) return made.error();
  const Feature& candidate = *made.value();
  const Rect bounds = candidate.Bounds();
  const HeightGrid& g = terrain_.ground();
  if (!g.Contains(bounds.min_x, bounds.min_z) || !g.Contains(bounds.max_x, bounds.max_z)) {
    return Error{
        fmt::format("{} {} covers x [{}, {}] z [{}, {}] m, which leaves the terrain "
                    "[0, {}] x [0, {}] m",
                    FeatureTypeName(params.type), id.ToString(), bounds.min_x, bounds.max_x,
                    bounds.min_z, bounds.max_z, g.size_x_m(), g.size_z_m())};
  }
  for (FeatureId b : live_bridges_) {
    if (b == id) continue;
    const Record& r = records_.at(b);
    if (!r.placed) continue;
    const Feature* other = terrain_.Find(b);
    if (other != nullptr && (candidate.ConflictsWith(*other) || other->ConflictsWith(candidate))) {
      return Error{fmt::format("{} {} would overlap bridge {}", FeatureTypeName(params.type),
                               id.ToString(), b.ToString())};
    }
  }
  checked_.params = params;
  checked_.terrain_stamp = terrain_.stamp();
  checked_.feature = std::move(made).value();
  return Status::Ok();
}

}  // namespace dt
