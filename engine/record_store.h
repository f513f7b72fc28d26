// RecordStore: one record per feature ID (last writer wins, tombstones) and the terrain they
// materialise.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <memory_resource>
#include <set>
#include <span>
#include <utility>
#include <vector>

#include "base/growing_arena.h"
#include "base/result.h"
#include "engine/change.h"
#include "terrain/base_ground.h"
#include "terrain/terrain.h"

namespace dt {

struct Record {
  FeatureParams params;
  Version version;
  bool destroyed = false;
  bool placed = false;  // live but not placeable (a bridge overlapping a lower-ID bridge): false
};

// In feature-ID order. A record is kept for the rest of the exercise (a destroyed one as a
// tombstone), so the records live in an arena of their own (base/growing_arena.h).
using RecordMap = std::pmr::map<FeatureId, Record>;

// The terrain is a function of the records alone: every live record placed in feature-ID order,
// a record that cannot be placed kept but left out (docs/protocol.md, "Materialisation").
class RecordStore {
 public:
  explicit RecordStore(HeightGrid ground);
  // The base ground's features are in the terrain from the start and are no records: no change
  // names them (their origin is no member's), so they stay as they are (docs/node.md). Throws
  // std::invalid_argument if one does not place.
  explicit RecordStore(BaseGround base);

  enum class Outcome { kApplied, kStale };
  // Last writer wins by Version; a Destruct always wins and is final.
  Outcome Apply(const Change& change);

  // Makes the record of `id` what applying `changes` (every change of `id` held, in any order) to
  // no record gives, and the terrain follow: a held change was replaced (anti-entropy's repair,
  // docs/protocol.md), and last-writer-wins cannot be undone one change at a time. With no
  // changes the record is gone, as if never seen.
  void Rebuild(FeatureId id, std::span<const Change* const> changes);

  const Record* Find(FeatureId id) const;
  const Terrain& terrain() const { return terrain_; }
  size_t live_count() const { return live_; }
  const RecordMap& all() const { return records_; }

  // Would a live record with these parameters be placed now? (Commands are refused otherwise.)
  // The feature it made is kept until the next change, so applying that same record then does
  // not make it again.
  Status CheckPlaceable(FeatureId id, const FeatureParams& params) const;

  // From now on, remembers the ID of every record applied, rebuilt or placed again, so that a
  // reader of a large world (the DIS gateway) follows changes without rescanning every record.
  // Off by default: a replica nobody drains would grow the list without bound.
  void TrackTouched() { tracking_touched_ = true; }
  // The IDs touched since the last call (a record may appear more than once), in order.
  std::vector<FeatureId> TakeTouched() { return std::exchange(touched_, {}); }

 private:
  // `r` is the record of `id` (passed so it is not looked up again).
  void Materialise(FeatureId id, Record& r, bool bridge_involved);
  // The record of `id`, made empty if new (`second` true then).
  std::pair<RecordMap::iterator, bool> Claim(FeatureId id);
  void RematerialiseBridges();
  // Places a live record's feature: the one CheckPlaceable made, if it was made of the same ID
  // and parameters on the terrain as it is, otherwise a new one.
  Status Place(FeatureId id, const FeatureParams& params);

  Terrain terrain_;
  GrowingArena record_memory_;  // before records_, which live in it
  RecordMap records_{&record_memory_};
  std::set<FeatureId> live_bridges_;
  // Per origin, its record with the highest number. Records are never erased, so these stay
  // valid; a node's next feature is inserted after its newest without searching.
  std::map<NodeAddress, RecordMap::iterator> newest_;
  size_t live_ = 0;
  bool tracking_touched_ = false;
  std::vector<FeatureId> touched_;
  // What CheckPlaceable made last, and the terrain's stamp then.
  struct Checked {
    FeatureParams params;
    uint64_t terrain_stamp = 0;
    std::unique_ptr<Feature> feature;
  };
  mutable Checked checked_;
};

}  // namespace dt
