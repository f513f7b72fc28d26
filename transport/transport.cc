#include "transport/transport.h"

#include <stdexcept>

#include <fmt/format.h>

#include "transport/dds_transport.h"
#include "transport/lcm_transport.h"

namespace dt {

std::unique_ptr<Transport> MakeTransport(std::string_view url, uint8_t exercise_id) {
  const std::string u(url);
  if (u == "memq://" || u.rfind("udpm://", 0) == 0) {
    return std::make_unique<LcmTransport>(u, exercise_id);
  }
  if (u.rfind("dds://", 0) == 0) {
    return std::make_unique<DdsTransport>(ParseDdsUrl(u), exercise_id);
  }
  throw std::invalid_argument(
      fmt::format("unknown transport URL '{}': expected memq://, udpm://<group>:<port>[?...] or "
                  "dds://<domain>[?config=<file>][&durable=1]",
                  u));
}

}  // namespace dt
