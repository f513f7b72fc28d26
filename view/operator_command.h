// OperatorCommand: a page's request (place a crater, berm or bridge; destroy or breach a feature)
// as the control command a chosen node runs, so nothing bypasses the protocol (docs/view.md).
#pragma once

#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "base/result.h"

namespace dt {

struct OperatorCommand {
  std::string node;  // the node that runs it
  std::string line;  // its control command, e.g. "crater 300 400 12"
};

// Checks the message: "op" one of crater, berm, bridge, destroy, breach; "node" one of `nodes`;
// every number the op needs present and finite; "id" a feature ID "site:host:number". An Error
// names the field and the value; nothing is sent for it.
Result<OperatorCommand> ParseOperatorCommand(const nlohmann::json& message,
                                             const std::set<std::string>& nodes);

}  // namespace dt
