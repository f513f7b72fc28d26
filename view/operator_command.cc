#include "view/operator_command.h"

#include <cmath>
#include <regex>

#include <fmt/format.h>

namespace dt {
namespace {

Result<double> Number(const nlohmann::json& m, const char* key) {
  auto it = m.find(key);
  if (it == m.end() || !it->is_number()) {
    return Error{fmt::format("operator command: \"{}\" is missing or not a number", key)};
  }
  const double v = it->get<double>();
  if (!std::isfinite(v)) return Error{fmt::format("operator command: \"{}\" is {}", key, v)};
  return v;
}

}  // namespace

Result<OperatorCommand> ParseOperatorCommand(const nlohmann::json& m,
                                             const std::set<std::string>& nodes) {
  if (!m.is_object()) return Error{"operator command: not a JSON object"};
  const std::string op = m.value("op", std::string());
  const std::string node = m.value("node", std::string());
  if (nodes.count(node) == 0) {
    return Error{fmt::format("operator command: \"node\" {} is no node of the exercise",
                             nlohmann::json(node).dump())};
  }
  std::vector<const char*> keys;
  if (op == "crater") {
    keys = {"x", "z", "radius"};
  } else if (op == "berm") {
    keys = {"x", "z", "dir_deg", "length", "width", "height"};
  } else if (op == "bridge") {
    keys = {"x", "z", "dir_deg", "width", "ramp1", "span", "ramp2", "h1", "h2"};
  } else if (op == "breach") {
    keys = {"gap_start", "gap_width"};
  } else if (op != "destroy") {
    return Error{
        fmt::format("operator command: \"op\" {} is not crater, berm, bridge, destroy or breach",
                    nlohmann::json(op).dump())};
  }
  std::string line = op;
  if (op == "destroy" || op == "breach") {
    const std::string id = m.value("id", std::string());
    static const std::regex kId("[0-9]+:[0-9]+:[0-9]+");
    if (!std::regex_match(id, kId)) {
      return Error{fmt::format("operator command: \"id\" {} is not a feature ID site:host:number",
                               nlohmann::json(id).dump())};
    }
    line += " " + id;
  }
  for (const char* k : keys) {
    auto v = Number(m, k);
    if (!v) return v.error();
    line += fmt::format(" {}", v.value());
  }
  return OperatorCommand{node, line};
}

}  // namespace dt
