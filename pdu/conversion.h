// Conversion between features (FeatureId + FeatureParams) and Construct/Update/Destruct PDUs.
#pragma once

#include <cstdint>

#include "base/feature_id.h"
#include "base/result.h"
#include "dtpdu/construct_t.hpp"
#include "dtpdu/destruct_t.hpp"
#include "dtpdu/earth_move_t.hpp"
#include "dtpdu/node_address_t.hpp"
#include "dtpdu/update_t.hpp"
#include "terrain/feature_params.h"

namespace dt {

// Who made a change and where it sits in the causal order (docs/pdu.md, extensions).
struct ChangeStamp {
  NodeAddress changed_by;
  uint32_t change_seq = 0;  // changed_by's change-log number, 1, 2, ...
  uint64_t lamport = 0;     // Lamport clock of the change, >= 1
  auto operator<=>(const ChangeStamp&) const = default;
};

// A feature as a Construct or Update PDU carries it.
struct FeaturePdu {
  FeatureId id;
  FeatureParams params;
  ChangeStamp change;
  bool operator==(const FeaturePdu&) const = default;
};

// A removal as a Destruct PDU carries it.
struct DestructPdu {
  FeatureId id;
  FeatureType type = FeatureType::kCrater;
  ChangeStamp change;
  bool operator==(const DestructPdu&) const = default;
};

dtpdu::node_address_t ToPdu(const NodeAddress& address);
NodeAddress FromPdu(const dtpdu::node_address_t& address);

// Fill the feature fields; the header, sender and sender_seq are PduBus's to set. Doubles are
// copied bit for bit, so FromConstruct(ToConstruct(f)) == f for every f.
dtpdu::construct_t ToConstruct(const FeaturePdu& feature);
dtpdu::update_t ToUpdate(const FeaturePdu& feature);
dtpdu::destruct_t ToDestruct(const DestructPdu& destruct);

// The inverse. Fails (naming the field) only when a field cannot be represented: feature number
// or change numbers out of range, an unknown feature type (or an earth move, which travels only
// as EarthMove), material or status, or a
// vertex-edit count that disagrees with the array. Value ranges are checked by validation.h.
Result<FeaturePdu> FromConstruct(const dtpdu::construct_t& pdu);
Result<FeaturePdu> FromUpdate(const dtpdu::update_t& pdu);
Result<DestructPdu> FromDestruct(const dtpdu::destruct_t& pdu);

// An earth move (params.type earth_move, valid) as an EarthMove PDU: the rectangle of its posts,
// a bit per post of it set where the post changes, and the changes in that order (docs/pdu.md
// "EarthMove"). FromEarthMove(ToEarthMove(f)) == f for every valid f.
dtpdu::earth_move_t ToEarthMove(const FeaturePdu& feature);
// The inverse. Fails (naming the field) when a number is out of range, the rectangle is empty,
// larger than kMaxEarthMoveSpanPosts or reaches past the largest grid, the mask's length or its
// set bits disagree with the rectangle or num_posts, or num_posts with the array. Delta values
// and the grid the posts must lie on are checked by validation.h and Terrain::Add.
Result<FeaturePdu> FromEarthMove(const dtpdu::earth_move_t& pdu);

}  // namespace dt
