// ControlClient: sends one request to a process's control socket and reads the reply.
#pragma once

#include <filesystem>
#include <string_view>

#include "base/result.h"
#include "runtime/control_protocol.h"

namespace dt {

// Connects, sends `line` (no newline inside), reads the reply. An unreachable socket, a closed
// connection or no complete reply within timeout_ms is an Error naming the path. A reply with
// status "error" is a successful call whose ControlReply has ok == false.
Result<ControlReply> CallControl(const std::filesystem::path& socket_path, std::string_view line,
                                 int timeout_ms);

}  // namespace dt
