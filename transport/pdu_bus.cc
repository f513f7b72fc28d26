#include "transport/pdu_bus.h"

#include <cmath>

namespace dt {

PduBus::PduBus(Transport& transport, PduBusConfig config)
    : transport_(transport), config_(std::move(config)), reject_log_(config_.reject_log_interval) {
  if (!std::isfinite(config_.terrain_size_m) || !(config_.terrain_size_m > 0.0)) {
    throw std::invalid_argument(
        fmt::format("PduBus: terrain_size_m = {} must be positive", config_.terrain_size_m));
  }
  if (!config_.clock) throw std::invalid_argument("PduBus: clock is empty");
  if (config_.auth.key) auth_.emplace(config_.local, config_.auth);
}

}  // namespace dt
