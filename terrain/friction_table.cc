#include "terrain/friction_table.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>

namespace dt {
namespace {

// The value as TOML would print it, for error messages.
std::string Describe(const toml::node& node) {
  std::ostringstream os;
  node.visit([&](auto&& v) { os << v; });
  std::string s = os.str();
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

class ConfigErrors {
 public:
  explicit ConfigErrors(std::string_view source) : source_(source) {}

  [[noreturn]] void Bad(std::string_view key, const toml::node& value,
                        std::string_view problem) const {
    throw std::invalid_argument(fmt::format(
        "{}:{}: {} = {}: {}", source_, value.source().begin.line, key, Describe(value), problem));
  }
  [[noreturn]] void Missing(std::string_view key) const {
    throw std::invalid_argument(fmt::format("{}: {} is missing", source_, key));
  }

 private:
  std::string_view source_;
};

const toml::table& RequireTable(const toml::node& node, std::string_view key,
                                const ConfigErrors& errors) {
  const toml::table* t = node.as_table();
  if (!t) errors.Bad(key, node, "must be a table");
  return *t;
}

double Coefficient(const toml::table& pair, std::string_view key, std::string_view name,
                   const ConfigErrors& errors) {
  const toml::node* node = pair.get(name);
  const std::string full = fmt::format("{}.{}", key, name);
  if (!node) errors.Missing(full);
  const auto v = node->value<double>();
  if (!v || !node->is_number()) errors.Bad(full, *node, "must be a number");
  if (!std::isfinite(*v) || !(*v > 0.0) || *v > kMaxFrictionCoefficient) {
    errors.Bad(full, *node, fmt::format("must be in (0, {}]", kMaxFrictionCoefficient));
  }
  return *v;
}

}  // namespace

FrictionTable FrictionTable::Parse(std::string_view toml_text, std::string_view source_name) {
  const ConfigErrors errors(source_name);
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    throw std::invalid_argument(fmt::format("{}:{}:{}: not valid TOML: {}", source_name,
                                            e.source().begin.line, e.source().begin.column,
                                            e.description()));
  }
  for (auto&& [key, node] : root) {
    if (key.str() != "classes" && key.str() != "vehicles" && key.str() != "friction" &&
        key.str() != "repose") {
      errors.Bad(key.str(), node, "unknown key (expected classes, vehicles, friction, repose)");
    }
  }

  FrictionTable table;
  const toml::node* classes = root.get("classes");
  if (!classes) errors.Missing("classes");
  const toml::array* class_list = classes->as_array();
  if (!class_list || class_list->empty()) {
    errors.Bad("classes", *classes, "must be a non-empty array of names");
  }
  for (const toml::node& entry : *class_list) {
    const auto name = entry.value<std::string>();
    if (!name || !entry.is_string() || name->empty()) {
      errors.Bad("classes", entry, "each class must be a non-empty string");
    }
    if (std::find(table.classes_.begin(), table.classes_.end(), *name) != table.classes_.end()) {
      errors.Bad("classes", entry, "is listed twice");
    }
    table.classes_.push_back(*name);
  }

  if (const toml::node* vehicles = root.get("vehicles")) {
    for (auto&& [key, node] : RequireTable(*vehicles, "vehicles", errors)) {
      const std::string full = fmt::format("vehicles.{}", key.str());
      const auto cls = node.value<std::string>();
      if (!cls || !node.is_string()) errors.Bad(full, node, "must be a class name");
      if (std::find(table.classes_.begin(), table.classes_.end(), *cls) == table.classes_.end()) {
        errors.Bad(full, node, "is not one of the listed classes");
      }
      table.vehicle_classes_.emplace(std::string(key.str()), *cls);
    }
  }

  const toml::node* friction = root.get("friction");
  if (!friction) errors.Missing("friction");
  const toml::table& materials = RequireTable(*friction, "friction", errors);
  for (auto&& [key, node] : materials) {
    const auto material = ParseMaterial(key.str());
    if (!material || *material == Material::kFromGround) {
      errors.Bad(fmt::format("friction.{}", key.str()), node,
                 "is not a material (see terrain/material.h; from_ground has no friction)");
    }
  }
  const size_t class_count = table.classes_.size();
  table.table_.resize(kMaterialCount * class_count);
  for (uint16_t m = 1; m < kMaterialCount; ++m) {
    const std::string_view material_name = MaterialName(static_cast<Material>(m));
    const std::string material_key = fmt::format("friction.{}", material_name);
    const toml::node* per_class = materials.get(material_name);
    if (!per_class) errors.Missing(material_key);
    const toml::table& pairs = RequireTable(*per_class, material_key, errors);
    for (auto&& [key, node] : pairs) {
      if (std::find(table.classes_.begin(), table.classes_.end(), key.str()) ==
          table.classes_.end()) {
        errors.Bad(fmt::format("{}.{}", material_key, key.str()), node,
                   "is not one of the listed classes");
      }
    }
    for (size_t c = 0; c < class_count; ++c) {
      const std::string pair_key = fmt::format("{}.{}", material_key, table.classes_[c]);
      const toml::node* pair_node = pairs.get(table.classes_[c]);
      if (!pair_node) errors.Missing(pair_key);
      const toml::table& pair = RequireTable(*pair_node, pair_key, errors);
      for (auto&& [key, node] : pair) {
        if (key.str() != "static" && key.str() != "dynamic") {
          errors.Bad(fmt::format("{}.{}", pair_key, key.str()), node,
                     "unknown key (expected static, dynamic)");
        }
      }
      Friction f;
      f.static_coefficient = Coefficient(pair, pair_key, "static", errors);
      f.dynamic_coefficient = Coefficient(pair, pair_key, "dynamic", errors);
      if (f.dynamic_coefficient > f.static_coefficient) {
        errors.Bad(pair_key, *pair_node,
                   "dynamic friction must not exceed static friction (a sliding vehicle grips "
                   "less than a rolling one)");
      }
      table.table_[m * class_count + c] = f;
    }
  }

  table.repose_rad_.assign(kMaterialCount, kDefaultReposeDeg * std::numbers::pi / 180.0);
  if (const toml::node* repose = root.get("repose")) {
    const toml::table& angles = RequireTable(*repose, "repose", errors);
    for (auto&& [key, node] : angles) {
      const auto material = ParseMaterial(key.str());
      if (!material || *material == Material::kFromGround) {
        errors.Bad(fmt::format("repose.{}", key.str()), node,
                   "is not a material (see terrain/material.h; from_ground has no soil)");
      }
    }
    for (uint16_t m = 1; m < kMaterialCount; ++m) {
      const std::string key = fmt::format("repose.{}", MaterialName(static_cast<Material>(m)));
      const toml::node* node = angles.get(MaterialName(static_cast<Material>(m)));
      if (!node) errors.Missing(key);
      const auto v = node->value<double>();
      if (!v || !node->is_number()) errors.Bad(key, *node, "must be a number of degrees");
      if (!std::isfinite(*v) || !(*v > kMinReposeDeg) || !(*v < kMaxReposeDeg)) {
        errors.Bad(key, *node,
                   fmt::format("must be in ({}, {}) degrees", kMinReposeDeg, kMaxReposeDeg));
      }
      table.repose_rad_[m] = *v * std::numbers::pi / 180.0;
    }
  }
  return table;
}

FrictionTable FrictionTable::LoadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(fmt::format("{}: cannot open", path.string()));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw std::invalid_argument(fmt::format("{}: read failed", path.string()));
  return Parse(text.str(), path.string());
}

Friction FrictionTable::Lookup(Material material, std::string_view traction_class) const {
  const auto m = static_cast<uint16_t>(material);
  if (!IsValidMaterial(m) || material == Material::kFromGround) {
    throw std::invalid_argument(
        fmt::format("no friction for material {} ({}): resolve "
                    "from_ground to the ground's soil first",
                    m, MaterialName(material)));
  }
  const auto it = std::find(classes_.begin(), classes_.end(), traction_class);
  if (it == classes_.end()) {
    throw std::invalid_argument(fmt::format("unknown traction class '{}' (known: {})",
                                            traction_class, fmt::join(classes_, ", ")));
  }
  return table_[m * classes_.size() + static_cast<size_t>(it - classes_.begin())];
}

double FrictionTable::ReposeRad(Material material) const {
  const auto m = static_cast<uint16_t>(material);
  if (!IsValidMaterial(m) || material == Material::kFromGround) {
    throw std::invalid_argument(fmt::format(
        "no angle of repose for material {} ({}): resolve from_ground to the ground's soil first",
        m, MaterialName(material)));
  }
  return repose_rad_[m];
}

const std::string& FrictionTable::ClassOf(std::string_view vehicle_type_name) const {
  const auto it = vehicle_classes_.find(vehicle_type_name);
  if (it == vehicle_classes_.end()) {
    std::vector<std::string_view> known;
    for (const auto& [name, cls] : vehicle_classes_) known.push_back(name);
    throw std::invalid_argument(
        fmt::format("vehicle type '{}' has no traction class in the "
                    "friction table (known: {})",
                    vehicle_type_name, fmt::join(known, ", ")));
  }
  return it->second;
}

}  // namespace dt
