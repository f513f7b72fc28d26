#include "engine/replica.h"

#include <fmt/format.h>

#include "terrain/berm.h"
#include "terrain/berm_operations.h"
#include "terrain/polyline_earthwork.h"
#include "terrain/terrain_digest.h"

namespace dt {

Status Replica::CheckSignedOn(int64_t changes) const {
  if (observer()) {
    return Error{fmt::format("{} is an observer: it creates, changes and destroys nothing",
                             config_.address.ToString())};
  }
  if (exercise_ground_) {
    return Error{fmt::format(
        "node {} is on ground {} ({}), not the exercise's {} (as {} reports): it takes no part",
        config_.address.ToString(), ground_digest_.ToHex(), config_.ground_source,
        exercise_ground_->ToHex(), exercise_ground_reporter_.ToString())};
  }
  if (!signed_on_) {
    return Error{
        fmt::format("node {} has not signed on yet: it does not know its last feature "
                    "number, so it may not issue one",
                    config_.address.ToString())};
  }
  // At most a window of changes unacknowledged: after a crash the node skips that many feature
  // numbers past what the server reported, so it never reissues one (docs/protocol.md).
  const int64_t unacknowledged = own_change_seq_ - acknowledged_change_seq_;
  if (!IsServerRole(config_.role) && config_.require_server &&
      unacknowledged + changes > config_.playback_window) {
    return Error{
        fmt::format("node {} has {} changes the server has not acknowledged yet (at most "
                    "{}); try again when the server has stored them",
                    config_.address.ToString(), unacknowledged, config_.playback_window)};
  }
  return Status::Ok();
}

Change Replica::NewChange(ChangeKind kind, FeatureId id, const FeatureParams& params) {
  Change c;
  c.kind = kind;
  c.id = id;
  c.params = params;
  c.stamp.changed_by = config_.address;
  c.stamp.change_seq = static_cast<uint32_t>(++own_change_seq_);
  c.stamp.lamport = ++lamport_;
  return c;
}

void Replica::Issue(const Change& change) {
  Accept(change, false);
  Publish(change, std::nullopt);
}

Result<FeatureId> Replica::Create(const FeatureParams& params) {
  if (auto s = CheckSignedOn(1); !s) return s.error();
  if (own_feature_number_ >= kMaxSerial || own_change_seq_ >= kMaxSerial) {
    return Error{fmt::format("node {} has used every feature number or change sequence",
                             config_.address.ToString())};
  }
  const FeatureId id{config_.address.site, config_.address.host,
                     static_cast<uint32_t>(own_feature_number_ + 1)};
  if (auto s = records_.CheckPlaceable(id, params); !s) return s.error();
  // Recorded before the number is handed out, so no later incarnation hands it out again.
  if (auto s = ReserveFeatureNumbers(id.number); !s) return s.error();
  ++own_feature_number_;
  Issue(NewChange(ChangeKind::kConstruct, id, params));
  return id;
}

Status Replica::Modify(FeatureId id, const FeatureParams& params) {
  if (auto s = CheckSignedOn(1); !s) return s;
  const Record* r = records_.Find(id);
  if (r == nullptr) return Error{fmt::format("no feature {}", id.ToString())};
  if (r->destroyed) return Error{fmt::format("feature {} is destroyed", id.ToString())};
  if (r->params.type == FeatureType::kEarthMove) {
    return Error{
        fmt::format("earth_move {} cannot be updated: blade work is added once; make "
                    "another earth move",
                    id.ToString())};
  }
  if (r->params.type != params.type) {
    return Error{fmt::format("feature {} is a {}, not a {}", id.ToString(),
                             FeatureTypeName(r->params.type), FeatureTypeName(params.type))};
  }
  if (own_change_seq_ >= kMaxSerial) return Error{"change sequence exhausted"};
  if (auto s = records_.CheckPlaceable(id, params); !s) return s;
  Issue(NewChange(ChangeKind::kUpdate, id, params));
  return Status::Ok();
}

Status Replica::Destroy(FeatureId id) {
  if (auto s = CheckSignedOn(1); !s) return s;
  const Record* r = records_.Find(id);
  if (r == nullptr) return Error{fmt::format("no feature {}", id.ToString())};
  if (r->destroyed) return Error{fmt::format("feature {} is already destroyed", id.ToString())};
  if (own_change_seq_ >= kMaxSerial) return Error{"change sequence exhausted"};
  FeatureParams p;
  p.type = r->params.type;
  Issue(NewChange(ChangeKind::kDestruct, id, p));
  return Status::Ok();
}

Result<std::vector<FeatureId>> Replica::Breach(FeatureId berm, double gap_start_m,
                                               double gap_width_m) {
  if (auto s = CheckSignedOn(3); !s) return s.error();
  const Record* r = records_.Find(berm);
  if (r == nullptr) return Error{fmt::format("no feature {}", berm.ToString())};
  if (r->destroyed) return Error{fmt::format("feature {} is destroyed", berm.ToString())};
  const FeatureType type = r->params.type;
  if (type != FeatureType::kBerm && type != FeatureType::kDitch && type != FeatureType::kBermLine) {
    return Error{fmt::format("feature {} is a {}, not a berm, berm line or ditch", berm.ToString(),
                             FeatureTypeName(type))};
  }
  const double centre_m = gap_start_m + gap_width_m / 2.0;
  const auto* placed = dynamic_cast<const Berm*>(records_.terrain().Find(berm));
  auto pieces = type != FeatureType::kBerm ? BreachPolyline(r->params, centre_m, gap_width_m)
                : placed != nullptr        ? BreachBerm(*placed, centre_m, gap_width_m)
                                           : BreachBerm(r->params, centre_m, gap_width_m);
  if (!pieces) return pieces.error();
  // As BreachBerm(const Berm&) does: a from_ground piece would take the soil under its own
  // start, so the pieces keep the original's resolved material.
  if (const Feature* f = records_.terrain().Find(berm);
      f != nullptr && type != FeatureType::kBerm) {
    for (FeatureParams& p : pieces.value()) {
      if (p.material == Material::kFromGround) p.material = f->material();
    }
  }
  const auto n = static_cast<int64_t>(pieces.value().size());
  if (own_feature_number_ + n > kMaxSerial || own_change_seq_ + n + 1 > kMaxSerial) {
    return Error{"feature numbers or change sequences exhausted"};
  }
  for (int64_t i = 0; i < n; ++i) {
    const FeatureId id{config_.address.site, config_.address.host,
                       static_cast<uint32_t>(own_feature_number_ + 1 + i)};
    if (auto s = records_.CheckPlaceable(id, pieces.value()[static_cast<size_t>(i)]); !s) {
      return Error{
          fmt::format("breach of {}: piece {}: {}", berm.ToString(), i + 1, s.error().message)};
    }
  }
  if (auto s = ReserveFeatureNumbers(own_feature_number_ + n); !s) return s.error();
  FeatureParams gone;
  gone.type = type;
  Issue(NewChange(ChangeKind::kDestruct, berm, gone));
  std::vector<FeatureId> ids;
  for (const FeatureParams& p : pieces.value()) {
    const FeatureId id{config_.address.site, config_.address.host,
                       static_cast<uint32_t>(++own_feature_number_)};
    Issue(NewChange(ChangeKind::kConstruct, id, p));
    ids.push_back(id);
  }
  return ids;
}

Status Replica::Import(const Terrain& terrain) {
  if (auto s = CheckSignedOn(0); !s && observer()) return s;
  if (ComputeDigest(terrain.ground()) != ComputeDigest(records_.terrain().ground())) {
    return Error{"the imported terrain's ground differs from this replica's ground"};
  }
  // The base ground's features (a file exported from an exercise that started on a saved
  // terrain holds them) are this replica's already and are no records: equal ones are left out,
  // another one under their origin is refused.
  std::vector<const Feature*> features;
  for (const Feature* f : terrain.FeaturesById()) {
    if (OriginOf(f->id()) != kGroundOrigin) {
      features.push_back(f);
      continue;
    }
    const Feature* base = records_.terrain().Find(f->id());
    if (base == nullptr || records_.Find(f->id()) != nullptr || !(base->params() == f->params())) {
      return Error{
          fmt::format("imported feature {} is of the base ground's origin {} but is not "
                      "that ground's feature",
                      f->id().ToString(), kGroundOrigin.ToString())};
    }
  }
  for (const Feature* f : features) {
    const Record* r = records_.Find(f->id());
    if (r != nullptr && r->destroyed) {
      return Error{
          fmt::format("imported feature {} was destroyed in this exercise", f->id().ToString())};
    }
    if (r != nullptr && r->params.type != f->type()) {
      return Error{fmt::format("imported feature {} is a {}, the exercise's is a {}",
                               f->id().ToString(), FeatureTypeName(f->type()),
                               FeatureTypeName(r->params.type))};
    }
  }
  if (own_change_seq_ + static_cast<int64_t>(features.size()) > kMaxSerial) {
    return Error{"change sequence exhausted"};
  }
  // Updates, not Constructs: only a feature's origin constructs it (PDU validation), and an
  // Update carries every parameter, so it creates the record where none exists.
  for (const Feature* f : features) Issue(NewChange(ChangeKind::kUpdate, f->id(), f->params()));
  return Status::Ok();
}

}  // namespace dt
