#include "vehicle/physical_type.h"

#include <cmath>
#include <numbers>
#include <string>

#include <fmt/format.h>

namespace dt {
namespace {

// Rolling resistance of every built-in's running gear on a paved road.
constexpr double kRoadRollingResistance = 0.03;

struct Extra {
  RunningGear gear;
  double mass_kg, hull_height_m, clearance_m, cg_height_m, engine_power_w, min_turn_radius_m,
      land_immobilise_mps, land_kill_mps;
};

Result<Extra> ExtraOf(std::string_view name) {
  // M1 tank, M35 truck (loaded), M998 utility vehicle, rounded.
  if (name == "tank")
    return Extra{RunningGear::kTracked, 60000, 2.4, 0.48, 1.2, 1.1e6, 0.0, 6.5, 8.5};
  if (name == "truck")
    return Extra{RunningGear::kWheeled, 10000, 2.9, 0.40, 1.3, 1.35e5, 11.0, 5.5, 7.5};
  if (name == "jeep")
    return Extra{RunningGear::kWheeled, 2500, 1.8, 0.40, 0.8, 1.1e5, 7.5, 5.5, 7.5};
  // A D7-class dozer: 25 t, 3.3 m to the cab roof, 150 kW.
  if (name == "bulldozer")
    return Extra{RunningGear::kTracked, 25000, 3.3, 0.40, 1.2, 1.5e5, 0.0, 5.5, 7.5};
  return Error{
      fmt::format("unknown vehicle type '{}' (built-in: tank, truck, jeep, bulldozer)", name)};
}

Status CheckRange(std::string_view type, std::string_view field, double value, double min,
                  double max) {
  if (!std::isfinite(value) || !(value >= min) || !(value <= max)) {
    return Error{fmt::format("vehicle type '{}': {} = {} is outside [{}, {}]", type, field, value,
                             min, max)};
  }
  return Status::Ok();
}

}  // namespace

double PhysicalVehicleType::StaticRollLimitRad() const {
  return std::atan2(base.width_m / 2.0, cg_height_m);
}
double PhysicalVehicleType::StaticPitchLimitRad() const {
  return std::atan2(base.length_m / 2.0, cg_height_m);
}

double RollingResistanceFactor(Material material) {
  switch (material) {
    case Material::kAsphalt:
    case Material::kConcrete:
    case Material::kSteel:
    case Material::kOil:  // a slick on firm ground: it takes grip, not rolling effort
      return 1.0;
    case Material::kRock:
    case Material::kGravel:
      return 1.5;
    case Material::kDirt:
    case Material::kGrass:
    case Material::kBurnt:  // ash over the ground
      return 2.0;
    case Material::kSand:
      return 5.0;
    case Material::kMud:
    case Material::kWater:  // wading over a soaked bed
      return 8.0;
    case Material::kFromGround:
      break;
  }
  return 1.0;
}

Result<PhysicalVehicleType> BuiltInPhysicalType(std::string_view name,
                                                const FrictionTable& friction) {
  Result<VehicleType> base = BuiltInVehicleType(name);
  if (!base) return base.error();
  Result<Extra> extra = ExtraOf(name);
  if (!extra) return extra.error();
  const Extra& e = extra.value();
  PhysicalVehicleType t;
  t.base = base.value();
  t.gear = e.gear;
  t.mass_kg = e.mass_kg;
  t.hull_height_m = e.hull_height_m;
  t.clearance_m = e.clearance_m;
  t.cg_height_m = e.cg_height_m;
  t.engine_power_w = e.engine_power_w;
  t.min_turn_radius_m = e.min_turn_radius_m;
  t.land_immobilise_mps = e.land_immobilise_mps;
  t.land_kill_mps = e.land_kill_mps;
  std::string traction_class;
  try {
    traction_class = friction.ClassOf(name);
  } catch (const std::invalid_argument& ex) {
    return Error{fmt::format("vehicle type '{}': {}", name, ex.what())};
  }
  for (uint16_t m = 1; m < kMaterialCount; ++m) {
    const Material material = static_cast<Material>(m);
    const Friction f = friction.Lookup(material, traction_class);
    t.grip[m] = {f.static_coefficient, f.dynamic_coefficient,
                 kRoadRollingResistance * RollingResistanceFactor(material)};
  }
  return t;
}

Status ValidatePhysicalType(const PhysicalVehicleType& t) {
  if (Status s = ValidateVehicleType(t.base); !s) return s;
  const std::string_view n = t.base.name;
  struct Field {
    std::string_view name;
    double value, min, max;
  };
  for (const Field& f :
       {Field{"mass_kg", t.mass_kg, 1.0, 1e6}, Field{"hull_height_m", t.hull_height_m, 0.1, 20.0},
        Field{"clearance_m", t.clearance_m, 0.05, t.hull_height_m - 0.05},
        Field{"cg_height_m", t.cg_height_m, 0.05, t.hull_height_m},
        Field{"engine_power_w", t.engine_power_w, 0.0, 1e8},
        Field{"min_turn_radius_m", t.min_turn_radius_m, 0.0, 1000.0},
        Field{"land_immobilise_mps", t.land_immobilise_mps, 0.1, 1000.0},
        Field{"land_kill_mps", t.land_kill_mps, t.land_immobilise_mps, 1000.0}}) {
    if (Status s = CheckRange(n, f.name, f.value, f.min, f.max); !s) return s;
  }
  for (uint16_t m = 1; m < kMaterialCount; ++m) {
    const SoilGrip& g = t.grip[m];
    const std::string_view mat = MaterialName(static_cast<Material>(m));
    if (Status s = CheckRange(n, fmt::format("{} static friction", mat), g.static_friction, 1e-3,
                              kMaxFrictionCoefficient);
        !s) {
      return s;
    }
    if (Status s = CheckRange(n, fmt::format("{} dynamic friction", mat), g.dynamic_friction, 1e-3,
                              g.static_friction);
        !s) {
      return s;
    }
    if (Status s = CheckRange(n, fmt::format("{} rolling resistance", mat), g.rolling_resistance,
                              0.0, 1.0);
        !s) {
      return s;
    }
  }
  return Status::Ok();
}

}  // namespace dt
