// FrictionTable: static and dynamic friction coefficients per material and traction class.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "terrain/material.h"

namespace dt {

// Dimensionless coefficients: static before the running gear slips, dynamic while it slides.
struct Friction {
  double static_coefficient = 0.0;
  double dynamic_coefficient = 0.0;
  bool operator==(const Friction&) const = default;
};

// Largest coefficient a config may give (rubber on dry concrete is about 1).
inline constexpr double kMaxFrictionCoefficient = 2.0;
// Angle of repose of every material when a table has no [repose] section (degrees): loose dirt.
inline constexpr double kDefaultReposeDeg = 35.0;
// Angles of repose a [repose] section may give (degrees), exclusive: flat soil does not stand and
// a vertical face is no slope.
inline constexpr double kMinReposeDeg = 0.0;
inline constexpr double kMaxReposeDeg = 90.0;

// Loaded from a TOML file like configs/friction.toml: a list of traction classes, a map from
// vehicle type name to class, and one {static, dynamic} pair per material and class. Every
// material but from_ground must be present for every class; unknown keys are refused. An optional
// [repose] section gives each material's angle of repose in degrees (blade work slumps to it,
// terrain/slump.h); when present it must name every material but from_ground.
class FrictionTable {
 public:
  // Throws std::invalid_argument naming the source, the key and the value at fault.
  static FrictionTable Parse(std::string_view toml_text, std::string_view source_name);
  // Throws std::invalid_argument if the file cannot be read or is bad (as Parse).
  static FrictionTable LoadFile(const std::filesystem::path& path);

  // Throws std::invalid_argument for from_ground, an unknown material or an unknown class.
  Friction Lookup(Material material, std::string_view traction_class) const;
  // The traction class of a vehicle type ("tank" -> "tracked"); throws for an unknown name.
  const std::string& ClassOf(std::string_view vehicle_type_name) const;
  Friction LookupForVehicle(Material material, std::string_view vehicle_type_name) const {
    return Lookup(material, ClassOf(vehicle_type_name));
  }

  // The angle of repose of a material, radians. Throws std::invalid_argument for from_ground or
  // an unknown material.
  double ReposeRad(Material material) const;

  const std::vector<std::string>& classes() const { return classes_; }
  const std::map<std::string, std::string, std::less<>>& vehicle_classes() const {
    return vehicle_classes_;
  }

 private:
  FrictionTable() = default;

  std::vector<std::string> classes_;
  std::map<std::string, std::string, std::less<>> vehicle_classes_;
  std::vector<Friction> table_;     // [material * classes_.size() + class]
  std::vector<double> repose_rad_;  // [material]
};

}  // namespace dt
