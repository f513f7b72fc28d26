#include "base/feature_id.h"

namespace dt {

std::string FeatureId::ToString() const {
  return std::to_string(site) + ":" + std::to_string(host) + ":" + std::to_string(number);
}

std::string NodeAddress::ToString() const {
  return std::to_string(site) + ":" + std::to_string(host);
}

}  // namespace dt
