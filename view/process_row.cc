#include "view/process_row.h"

#include "runtime/status_report.h"

namespace dt {

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

Status ParseStatusInto(const std::string& status_text, ProcessRow& row) {
  Result<StatusReport> parsed = StatusReport::Parse(status_text);
  if (!parsed) return parsed.error();
  const StatusReport& s = parsed.value();
  row.digest = s.digest;
  row.signed_on = s.signed_on;
  row.caught_up = s.caught_up;
  row.diverged = s.diverged;
  row.features = static_cast<int64_t>(s.features);
  // The PDU counters the panel shows (docs/node.md "status" has them all).
  const std::pair<const char*, uint64_t> shown[] = {{"sent", s.sent},
                                                    {"received", s.received},
                                                    {"rejected", s.rejected},
                                                    {"played_back", s.played_back},
                                                    {"applied", s.applied}};
  for (const auto& [key, value] : shown) row.counters[key] = static_cast<int64_t>(value);
  return Status::Ok();
}

}  // namespace dt
