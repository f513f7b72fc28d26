#include "runtime/control_protocol.h"

namespace dt {

std::string EncodeControlReply(const ControlReply& reply) {
  std::string out;
  if (reply.ok) {
    out = "ok\n";
  } else {
    out = "error: ";
    // The status line is one line whatever the message holds.
    for (char c : reply.error) out += (c == '\n' ? ' ' : c);
    out += '\n';
  }
  size_t start = 0;
  while (!reply.body.empty() && start <= reply.body.size()) {
    size_t end = reply.body.find('\n', start);
    if (end == std::string::npos) end = reply.body.size();
    const std::string_view line(reply.body.data() + start, end - start);
    out += (line == "." ? std::string_view("..") : line);
    out += '\n';
    start = end + 1;
  }
  out += ".\n";
  return out;
}

}  // namespace dt
