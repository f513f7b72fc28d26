#include "transport/pdu_bus.h"

#include <cmath>

namespace dt {

PduBus::PduBus(Transport& transport, PduBusConfig config)
    : transport_(transport), config_(std::move(config)), reject_log_(config_.reject_log_interval) {
  for (const auto& [name, size_m] : {std::pair{"terrain_size_x_m", config_.terrain_size_x_m},
                                     std::pair{"terrain_size_z_m", config_.terrain_size_z_m}}) {
    if (!std::isfinite(size_m) || !(size_m > 0.0)) {
      throw std::invalid_argument(fmt::format("PduBus: {} = {} must be positive", name, size_m));
    }
  }
  if (!config_.clock) throw std::invalid_argument("PduBus: clock is empty");
  if (config_.auth.key) auth_.emplace(config_.local, config_.auth);
}

}  // namespace dt
