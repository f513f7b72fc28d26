// Change: one create, update or destroy of a feature, as the protocol logs, sends and stores it.
#pragma once

#include <cstdint>
#include <optional>

#include "base/feature_id.h"
#include "dtpdu/construct_t.hpp"
#include "dtpdu/destruct_t.hpp"
#include "dtpdu/update_t.hpp"
#include "pdu/conversion.h"
#include "terrain/feature_params.h"

namespace dt {

enum class ChangeKind : uint8_t { kConstruct = 0, kUpdate = 1, kDestruct = 2 };

// The order of changes to one feature (docs/protocol.md, last writer wins): Lamport clock first,
// the changing node second.
struct Version {
  uint64_t lamport = 0;
  NodeAddress changed_by;
  auto operator<=>(const Version&) const = default;
};

struct Change {
  ChangeKind kind = ChangeKind::kConstruct;
  FeatureId id;
  FeatureParams params;  // Construct and Update; for Destruct only params.type is meaningful
  ChangeStamp stamp;

  Version version() const { return {stamp.lamport, stamp.changed_by}; }
  NodeAddress author() const { return stamp.changed_by; }
  bool operator==(const Change&) const = default;
};

// PDU conversions (pdu/conversion.h does the field work).
Change ChangeFrom(const FeaturePdu& feature, ChangeKind kind);
Change ChangeFrom(const DestructPdu& destruct);
FeaturePdu ToFeaturePdu(const Change& change);
DestructPdu ToDestructPdu(const Change& change);

}  // namespace dt
