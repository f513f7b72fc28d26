// Dynamic features (craters, bridges, berms) as DIS Point and Linear Object State PDUs, and
// back (docs/dis.md "Features").
#pragma once

#include <cstdint>
#include <variant>

#include "base/feature_id.h"
#include "base/result.h"
#include "dis/dis_pdu.h"
#include "dis/geodetic_frame.h"
#include "dis/pdu_context.h"
#include "terrain/feature_params.h"

namespace dt::dis {

// DIS object numbers 0 (none), 65534 (assign on request) and 65535 (all) are reserved.
inline constexpr uint32_t kMaxDisObjectNumber = 65533;

// A feature's DIS object ID: site -> site, host -> application, number -> object number.
// Fails for a feature number above kMaxDisObjectNumber (DIS numbers are 16 bits).
Result<EntityId> ObjectIdOf(const FeatureId& id);
FeatureId FeatureIdOf(const EntityId& object_id);

using ObjectStatePdu = std::variant<PointObjectStatePdu, LinearObjectStatePdu>;

// The object state of a feature. ground_elevation_m is the bare ground's elevation (terrain y)
// at the placement point (x_m, z_m): DIS places objects in three dimensions. Craters and bridges
// become Point Object State, berms Linear Object State with one segment. Fails when the ID has
// no DIS object number or a value has no DIS form; throws std::invalid_argument for parameters
// ValidateFeatureParams refuses.
Result<ObjectStatePdu> FeatureToDis(const FeatureId& id, const FeatureParams& params,
                                    double ground_elevation_m, uint16_t update_number,
                                    const GeodeticFrame& frame, const PduContext& context);

// How a removed feature leaves DIS: its last state again, with the next update number and the
// general appearance's deactivated bit set (on every segment of a linear object).
ObjectStatePdu Deactivated(const ObjectStatePdu& last, uint16_t update_number,
                           const PduContext& context);
bool IsDeactivated(const ObjectStatePdu& pdu);

// What a DIS object state says of a feature.
struct FeatureFromDis {
  FeatureId id;
  // crater: x, z, radius (from the whole-metre diameter); berm: x, z, direction, length, width,
  // height; bridge: x, z, direction and status only (DIS carries no bridge geometry).
  FeatureParams params;
  double ground_elevation_m = 0.0;  // terrain y of the object's location
  uint16_t update_number = 0;
  bool deactivated = false;
  bool complete = false;  // params define the whole feature (crater, berm; not a bridge)
};

// Fails (naming the values) for a reserved object number (0, 65534, 65535), object types
// that are none of dynterrain's, a crater of
// diameter 0, a linear object without exactly one segment, a location beyond
// kMaxFeatureCoordinateM of the origin, or a result ValidateFeatureParams refuses.
Result<FeatureFromDis> FeatureFromDisPdu(const ObjectStatePdu& pdu, const GeodeticFrame& frame);

}  // namespace dt::dis
