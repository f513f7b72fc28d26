#include "engine/change.h"

namespace dt {

Change ChangeFrom(const FeaturePdu& feature, ChangeKind kind) {
  Change c;
  c.kind = kind;
  c.id = feature.id;
  c.params = feature.params;
  c.stamp = feature.change;
  return c;
}

Change ChangeFrom(const DestructPdu& destruct) {
  Change c;
  c.kind = ChangeKind::kDestruct;
  c.id = destruct.id;
  c.params.type = destruct.type;
  c.stamp = destruct.change;
  return c;
}

FeaturePdu ToFeaturePdu(const Change& change) {
  return FeaturePdu{change.id, change.params, change.stamp};
}

DestructPdu ToDestructPdu(const Change& change) {
  return DestructPdu{change.id, change.params.type, change.stamp};
}

}  // namespace dt
