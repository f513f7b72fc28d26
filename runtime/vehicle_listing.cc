#include "runtime/vehicle_listing.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <sstream>

#include <fmt/format.h>

namespace dt {
namespace {

bool ParseNumber(std::string_view text, double& out) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return ec == std::errc() && ptr == end && std::isfinite(out);
}

// "<n> more (--offset <next>)", the line a page ends with when it left lines out.
bool IsMoreLine(std::string_view line) {
  const size_t space = line.find(' ');
  if (space == 0 || space == std::string_view::npos) return false;
  for (size_t i = 0; i < space; ++i) {
    if (line[i] < '0' || line[i] > '9') return false;
  }
  return line.substr(space).starts_with(" more");
}

// The owner= value of a vehicle line; empty if none.
std::string_view OwnerOf(std::string_view line) {
  const size_t at = line.find(" owner=");
  if (at == std::string_view::npos) return {};
  const size_t from = at + 7;
  const size_t end = line.find(' ', from);
  return line.substr(from, end == std::string_view::npos ? std::string_view::npos : end - from);
}

}  // namespace

std::string PageVehicleListing(std::string_view listing, const VehiclePage& page) {
  if (page == VehiclePage{}) return std::string(listing);
  std::string out;
  size_t selected = 0, shown = 0;
  for (size_t from = 0; from < listing.size();) {
    size_t end = listing.find('\n', from);
    if (end == std::string_view::npos) end = listing.size();
    const std::string_view line = listing.substr(from, end - from);
    from = end + 1;
    if (line.empty() || IsMoreLine(line)) continue;
    if (!page.owner.empty() && OwnerOf(line) != page.owner) continue;
    const size_t index = selected++;
    if (index < page.offset || (page.limit && shown >= *page.limit)) continue;
    if (!out.empty()) out += '\n';
    out += line;
    ++shown;
  }
  const size_t after = selected - std::min(selected, page.offset) - shown;
  if (after > 0) {
    if (!out.empty()) out += '\n';
    out += fmt::format("{} more (--offset {})", after, page.offset + shown);
  }
  return out;
}

Result<std::vector<ListedVehicle>> ParseVehicleListing(std::string_view body) {
  std::vector<ListedVehicle> out;
  std::istringstream in{std::string(body)};
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || IsMoreLine(line)) continue;
    std::istringstream words(line);
    std::vector<std::string> positional;
    std::map<std::string, std::string, std::less<>> keys;
    for (std::string w; words >> w;) {
      const size_t eq = w.find('=');
      if (eq == std::string::npos) {
        positional.push_back(w);
      } else {
        keys[w.substr(0, eq)] = w.substr(eq + 1);
      }
    }
    ListedVehicle v;
    // local <index> <entity> <type> ...; remote <entity> <type> ...
    if (!positional.empty() && positional[0] == "local" && positional.size() == 4) {
      v.local = true;
      const std::string& index = positional[1];
      const auto [ptr, ec] = std::from_chars(index.data(), index.data() + index.size(), v.index);
      if (ec != std::errc() || ptr != index.data() + index.size()) {
        return Error{
            fmt::format("local vehicle index \"{}\" is not a number in \"{}\"", index, line)};
      }
      v.entity = positional[2];
      v.type = positional[3];
    } else if (!positional.empty() && positional[0] == "remote" && positional.size() == 3) {
      v.entity = positional[1];
      v.type = positional[2];
    } else {
      return Error{fmt::format("not a vehicle line: \"{}\"", line)};
    }
    const auto owner = keys.find("owner");
    if (owner == keys.end() || owner->second.empty()) {
      return Error{fmt::format("no owner= in \"{}\"", line)};
    }
    v.owner = owner->second;
    for (const auto& [key, field] :
         {std::pair{"x_m", &v.x_m}, std::pair{"y_m", &v.y_m}, std::pair{"z_m", &v.z_m},
          std::pair{"heading_deg", &v.heading_deg}, std::pair{"pitch_deg", &v.pitch_deg},
          std::pair{"roll_deg", &v.roll_deg}, std::pair{"speed_mps", &v.speed_mps},
          std::pair{"model_error_m", &v.model_error_m}}) {
      const auto it = keys.find(key);
      if (it == keys.end() || !ParseNumber(it->second, *field)) {
        return Error{fmt::format("{}= missing or not a finite number in \"{}\"", key, line)};
      }
    }
    const auto alive = keys.find("alive");
    if (alive == keys.end() || (alive->second != "0" && alive->second != "1")) {
      return Error{fmt::format("alive= missing or not 0 or 1 in \"{}\"", line)};
    }
    v.alive = alive->second == "1";
    if (!v.local) {
      const auto age = keys.find("age_s");
      if (age == keys.end() || !ParseNumber(age->second, v.age_s)) {
        return Error{fmt::format("age_s= missing or not a finite number in \"{}\"", line)};
      }
    }
    out.push_back(std::move(v));
  }
  return out;
}

std::string VehicleLine(const ListedVehicle& v) {
  const std::string head = v.local ? fmt::format("local {} {} {}", v.index, v.entity, v.type)
                                   : fmt::format("remote {} {}", v.entity, v.type);
  std::string line = fmt::format(
      "{} owner={} x_m={:.2f} y_m={:.2f} z_m={:.2f} heading_deg={:.2f} pitch_deg={:.2f} "
      "roll_deg={:.2f} speed_mps={:.2f} alive={} model_error_m={:.3f}",
      head, v.owner, v.x_m, v.y_m, v.z_m, v.heading_deg, v.pitch_deg, v.roll_deg, v.speed_mps,
      v.alive ? 1 : 0, v.model_error_m);
  if (v.local) return line + fmt::format(" sent={}", v.sent);
  return line +
         fmt::format(" settled={} age_s={:.2f} updates={}", v.settled ? 1 : 0, v.age_s, v.updates);
}

double TiltDeg(const ListedVehicle& v) {
  return std::max(std::abs(v.pitch_deg), std::abs(v.roll_deg));
}

}  // namespace dt
