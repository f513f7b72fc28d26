// ProcessRow: one line of the live view's process panel and where each field comes from
// (docs/view.md "The process panel").
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "base/result.h"

namespace dt {

struct ProcessRow {
  std::string name;
  std::string role;  // "server", "standby", "node", "observer"
  std::string address;
  // From the process's control socket (`status`): false while it does not answer.
  bool reachable = false;
  bool signed_on = false, caught_up = false, diverged = false;
  std::string digest;
  int64_t features = 0;
  std::map<std::string, int64_t> counters;  // sent, received, rejected, played_back, ...
  // From the protocol, as the observer hears it: milliseconds since its last PDU (-1: never).
  int64_t last_heard_ago_ms = -1;
  bool silent = true;  // not heard for silence_ms (the protocol's own rule)
  bool operator==(const ProcessRow&) const = default;
  nlohmann::json ToJson() const;
};

// Fills the control-socket fields from a `status` reply (runtime/status_report.h). A reply that
// does not read is an Error naming the key or line and leaves the row as it was.
Status ParseStatusInto(const std::string& status_text, ProcessRow& row);

}  // namespace dt
