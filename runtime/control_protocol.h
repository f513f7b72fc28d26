// Control protocol: the framing of requests and replies on a process's control socket.
#pragma once

#include <string>
#include <string_view>

namespace dt {

// One request is one line. A reply is a status line, "ok" or "error: <message>", then any body
// lines, then a line holding a single "." (docs/node.md "Control socket"). Body lines never
// consist of a lone "."; the server escapes one as "..".
struct ControlReply {
  bool ok = true;
  std::string error;  // when !ok
  std::string body;   // lines joined by '\n', no trailing newline

  static ControlReply Ok(std::string body = {}) { return {true, {}, std::move(body)}; }
  static ControlReply Fail(std::string message) { return {false, std::move(message), {}}; }
};

// The reply as sent on the socket, ending in ".\n".
std::string EncodeControlReply(const ControlReply& reply);

// Longest request line a server accepts; longer ones get an error.
inline constexpr size_t kMaxControlLineBytes = 4096;

}  // namespace dt
