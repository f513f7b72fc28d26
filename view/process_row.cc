#include "view/process_row.h"

#include <charconv>
#include <sstream>

namespace dt {
namespace {

// The PDU counters the panel shows (docs/node.md "status" has them all).
constexpr const char* kCounters[] = {"sent", "received", "rejected", "played_back", "applied"};

bool ParseInt(const std::string& s, int64_t& out) {
  const char* end = s.data() + s.size();
  auto [p, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc() && p == end;
}

}  // namespace

nlohmann::json ProcessRow::ToJson() const {
  return {{"name", name},
          {"role", role},
          {"address", address},
          {"reachable", reachable},
          {"signed_on", signed_on},
          {"caught_up", caught_up},
          {"diverged", diverged},
          {"digest", digest},
          {"features", features},
          {"counters", counters},
          {"last_heard_ago_ms", last_heard_ago_ms},
          {"silent", silent}};
}

void ParseStatusInto(const std::string& status_text, ProcessRow& row) {
  std::istringstream in(status_text);
  std::string line;
  while (std::getline(in, line)) {
    const size_t space = line.find(' ');
    if (space == std::string::npos) continue;
    const std::string key = line.substr(0, space);
    const std::string value = line.substr(space + 1);
    int64_t n = 0;
    if (key == "digest") {
      row.digest = value;
    } else if (key == "signed_on" && ParseInt(value, n)) {
      row.signed_on = n != 0;
    } else if (key == "caught_up" && ParseInt(value, n)) {
      row.caught_up = n != 0;
    } else if (key == "diverged" && ParseInt(value, n)) {
      row.diverged = n != 0;
    } else if (key == "features" && ParseInt(value, n)) {
      row.features = n;
    } else {
      for (const char* c : kCounters) {
        if (key == c && ParseInt(value, n)) row.counters[key] = n;
      }
    }
  }
}

}  // namespace dt
