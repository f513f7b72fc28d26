#include "dis/feature_mapping.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dis/object_types.h"
#include "terrain/crater.h"

namespace dt::dis {
namespace {

// Percent complete: a dynterrain feature exists whole or not at all.
constexpr uint16_t kComplete = 100;
// Receiving ID "all simulations".
constexpr SimulationAddress kAllSimulations{0xFFFF, 0xFFFF};

uint8_t Saturate(double value) {
  return static_cast<uint8_t>(std::clamp(std::round(value), 0.0, 255.0));
}

CraterAppearance CraterAppearanceOf(const FeatureParams& p) {
  const double radius = p.length_m[0];
  double lowest = 0.0, highest = 0.0;
  std::array<double, kCraterSpokes * kCraterRings> offsets{};
  for (int spoke = 0; spoke < kCraterSpokes; ++spoke) {
    for (int ring = 0; ring < kCraterRings; ++ring) {
      offsets[spoke * kCraterRings + ring] =
          ring == 1 || ring == 2 ? kCraterRimHeightFraction * radius : 0.0;
    }
  }
  for (const CraterVertexEdit& e : p.vertex_edits)
    offsets[e.spoke * kCraterRings + e.ring] = e.offset_m;
  for (double o : offsets) {
    lowest = std::min(lowest, o);
    highest = std::max(highest, o);
  }
  return {Saturate(2.0 * radius), Saturate(-lowest * 100.0), Saturate(highest * 100.0)};
}

// In the terrain's axes at the object (its grid north on a UTM ground).
EulerAngles LevelOrientation(const GeodeticFrame& frame, double heading_rad, const LocalPoint& at) {
  return frame.ToDisOrientation({heading_rad, 0.0, 0.0}, frame.AxesAt(at));
}

Header HeaderOf(const PduContext& c) {
  Header h;
  h.exercise_id = c.exercise_id;
  h.timestamp = c.timestamp;
  return h;
}

bool SameType(const ObjectType& a, const ObjectType& b) { return a == b; }

std::string TypeText(const ObjectType& t) {
  return fmt::format("{}/{}/{}/{}", t.domain, t.kind, t.category, t.subcategory);
}

}  // namespace

Result<EntityId> ObjectIdOf(const FeatureId& id) {
  if (id.number == 0 || id.number > kMaxDisObjectNumber) {
    return Error{fmt::format("feature {} has no DIS object number (DIS numbers are 1..{})",
                             id.ToString(), kMaxDisObjectNumber)};
  }
  return EntityId{id.site, id.host, static_cast<uint16_t>(id.number)};
}

FeatureId FeatureIdOf(const EntityId& o) { return {o.site, o.application, o.entity}; }

Result<ObjectStatePdu> FeatureToDis(const FeatureId& id, const FeatureParams& params,
                                    double ground_elevation_m, uint16_t update_number,
                                    const GeodeticFrame& frame, const PduContext& context) {
  if (Status s = ValidateFeatureParams(params); !s.ok()) {
    throw std::invalid_argument("FeatureToDis: " + s.error().message);
  }
  if (!std::isfinite(ground_elevation_m)) {
    throw std::invalid_argument(fmt::format("FeatureToDis: ground elevation {} m of {}",
                                            ground_elevation_m, id.ToString()));
  }
  Result<EntityId> object_id = ObjectIdOf(id);
  if (!object_id.ok()) return object_id.error();
  const LocalPoint at{params.x_m, ground_elevation_m, params.z_m};
  const WorldCoordinates location = frame.ToGeocentric(at);
  const SimulationAddress requester{id.site, id.host};

  if (params.type == FeatureType::kBerm) {
    LinearObjectStatePdu pdu;
    pdu.header = HeaderOf(context);
    pdu.object_id = object_id.value();
    pdu.update_number = update_number;
    pdu.requester_id = requester;
    pdu.receiving_id = kAllSimulations;
    pdu.object_type = kBermObjectType;
    LinearSegment s;
    s.segment_number = 1;
    s.general_appearance = kComplete;
    s.location = location;
    s.orientation = LevelOrientation(frame, params.direction_rad, at);
    s.length_m = static_cast<float>(params.length_m[0]);
    s.width_m = static_cast<float>(params.width_m);
    s.height_m = static_cast<float>(params.height_m[0]);
    s.depth_m = 0.0f;
    pdu.segments.push_back(s);
    return ObjectStatePdu(std::move(pdu));
  }

  PointObjectStatePdu pdu;
  pdu.header = HeaderOf(context);
  pdu.object_id = object_id.value();
  pdu.update_number = update_number;
  pdu.location = location;
  pdu.requester_id = requester;
  pdu.receiving_id = kAllSimulations;
  pdu.general_appearance = kComplete;
  if (params.type == FeatureType::kCrater) {
    pdu.object_type = kCraterObjectType;
    pdu.orientation = LevelOrientation(frame, 0.0, at);
    pdu.specific_appearance = PackCraterAppearance(CraterAppearanceOf(params));
  } else {
    pdu.object_type = kBridgeObjectType;
    pdu.orientation = LevelOrientation(frame, params.direction_rad, at);
    if (params.status == BridgeStatus::kDestroyed) {
      pdu.general_appearance |= general_appearance::kDamageDestroyed
                                << general_appearance::kDamageShift;
    }
  }
  return ObjectStatePdu(std::move(pdu));
}

ObjectStatePdu Deactivated(const ObjectStatePdu& last, uint16_t update_number,
                           const PduContext& context) {
  ObjectStatePdu out = last;
  std::visit(
      [&](auto& pdu) {
        pdu.header.exercise_id = context.exercise_id;
        pdu.header.timestamp = context.timestamp;
        pdu.update_number = update_number;
        if constexpr (std::is_same_v<std::decay_t<decltype(pdu)>, PointObjectStatePdu>) {
          pdu.general_appearance |= general_appearance::kDeactivated;
        } else {
          for (LinearSegment& s : pdu.segments)
            s.general_appearance |= general_appearance::kDeactivated;
        }
      },
      out);
  return out;
}

bool IsDeactivated(const ObjectStatePdu& pdu) {
  if (const auto* point = std::get_if<PointObjectStatePdu>(&pdu)) {
    return (point->general_appearance & general_appearance::kDeactivated) != 0;
  }
  const auto& linear = std::get<LinearObjectStatePdu>(pdu);
  // A linear object is gone when every segment is (an empty one has nothing left to show).
  return std::all_of(linear.segments.begin(), linear.segments.end(), [](const LinearSegment& s) {
    return (s.general_appearance & general_appearance::kDeactivated) != 0;
  });
}

Result<FeatureFromDis> FeatureFromDisPdu(const ObjectStatePdu& any, const GeodeticFrame& frame) {
  const EntityId object_id = std::visit([](const auto& p) { return p.object_id; }, any);
  if (object_id.entity == 0 || object_id.entity > kMaxDisObjectNumber) {
    return Error{fmt::format("object {}:{}:{} has a reserved object number (objects are 1..{})",
                             object_id.site, object_id.application, object_id.entity,
                             kMaxDisObjectNumber)};
  }
  FeatureFromDis out;
  out.deactivated = IsDeactivated(any);
  if (const auto* point = std::get_if<PointObjectStatePdu>(&any)) {
    out.id = FeatureIdOf(point->object_id);
    out.update_number = point->update_number;
    const LocalPoint at = frame.FromGeocentric(point->location);
    out.ground_elevation_m = at.y_m;
    const LocalAttitude attitude = frame.FromDisOrientation(point->orientation, frame.AxesAt(at));
    if (SameType(point->object_type, kCraterObjectType)) {
      const CraterAppearance a = UnpackCraterAppearance(point->specific_appearance);
      if (a.diameter_m == 0) {
        return Error{fmt::format("crater object {}:{}:{} of diameter 0 m", point->object_id.site,
                                 point->object_id.application, point->object_id.entity)};
      }
      out.params = FeatureParams::Crater(at.x_m, at.z_m, a.diameter_m / 2.0);
      out.complete = true;
    } else if (SameType(point->object_type, kBridgeObjectType)) {
      out.params.type = FeatureType::kBridge;
      out.params.x_m = at.x_m;
      out.params.z_m = at.z_m;
      out.params.direction_rad = attitude.heading_rad;
      const uint16_t damage = (point->general_appearance & general_appearance::kDamageMask) >>
                              general_appearance::kDamageShift;
      out.params.status = damage == general_appearance::kDamageDestroyed ? BridgeStatus::kDestroyed
                                                                         : BridgeStatus::kIntact;
      out.complete = false;
      // Incomplete: not a FeatureParams ValidateFeatureParams would accept, so its placement
      // is checked here.
      for (double v : {at.x_m, at.y_m, at.z_m}) {
        if (!(std::abs(v) <= kMaxFeatureCoordinateM)) {
          return Error{fmt::format("bridge from DIS at ({}, {}, {}) m, beyond +-{} m", at.x_m,
                                   at.y_m, at.z_m, kMaxFeatureCoordinateM)};
        }
      }
      return out;
    } else {
      return Error{fmt::format("point object type {} is none of dynterrain's features",
                               TypeText(point->object_type))};
    }
  } else {
    const auto& linear = std::get<LinearObjectStatePdu>(any);
    out.id = FeatureIdOf(linear.object_id);
    out.update_number = linear.update_number;
    if (!SameType(linear.object_type, kBermObjectType)) {
      return Error{fmt::format("linear object type {} is none of dynterrain's features",
                               TypeText(linear.object_type))};
    }
    if (linear.segments.size() != 1) {
      return Error{fmt::format("berm object with {} segments (dynterrain sends exactly 1)",
                               linear.segments.size())};
    }
    const LinearSegment& s = linear.segments[0];
    const LocalPoint at = frame.FromGeocentric(s.location);
    out.ground_elevation_m = at.y_m;
    const LocalAttitude attitude = frame.FromDisOrientation(s.orientation, frame.AxesAt(at));
    out.params = FeatureParams::Berm(at.x_m, at.z_m, attitude.heading_rad, s.length_m, s.width_m,
                                     s.height_m);
    out.complete = true;
  }
  if (Status s = ValidateFeatureParams(out.params); !s.ok()) {
    return Error{"feature from DIS: " + s.error().message};
  }
  if (!(std::abs(out.ground_elevation_m) <= kMaxFeatureCoordinateM)) {
    return Error{fmt::format("feature from DIS: elevation {} m beyond +-{} m",
                             out.ground_elevation_m, kMaxFeatureCoordinateM)};
  }
  return out;
}

}  // namespace dt::dis
