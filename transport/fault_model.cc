#include "transport/fault_model.h"

#include <stdexcept>

#include <fmt/format.h>

namespace dt {

void CheckFaultConfig(const FaultConfig& c) {
  for (auto [name, p] : {std::pair{"drop_probability", c.drop_probability},
                         std::pair{"duplicate_probability", c.duplicate_probability},
                         std::pair{"reorder_probability", c.reorder_probability}}) {
    if (!(p >= 0.0 && p <= 1.0)) {
      throw std::invalid_argument(fmt::format("FaultConfig: {} = {} is outside [0, 1]", name, p));
    }
  }
  if (c.min_delay < 0 || c.max_delay < c.min_delay || c.reorder_window < 0) {
    throw std::invalid_argument(
        fmt::format("FaultConfig: delays min {} max {} reorder_window {} must satisfy 0 <= min <= "
                    "max and window >= 0",
                    c.min_delay, c.max_delay, c.reorder_window));
  }
  if (c.other_site_min_delay < 0 || c.other_site_max_delay < c.other_site_min_delay) {
    throw std::invalid_argument(
        fmt::format("FaultConfig: other-site delays min {} max {} must satisfy 0 <= min <= max",
                    c.other_site_min_delay, c.other_site_max_delay));
  }
}

std::pair<int64_t, int64_t> DelayRange(int64_t delay, int64_t jitter) {
  if (delay < 0 || jitter < 0 || jitter > delay) {
    throw std::invalid_argument(fmt::format(
        "delay {} and jitter {} must satisfy 0 <= jitter <= delay (a delay never goes below 0)",
        delay, jitter));
  }
  return {delay - jitter, delay + jitter};
}

FaultModel::FaultModel(FaultConfig config, uint64_t seed) : rng_(seed) { set_config(config); }

void FaultModel::set_config(FaultConfig config) {
  CheckFaultConfig(config);
  config_ = config;
}

double FaultModel::Uniform01() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }

int64_t FaultModel::UniformInt(int64_t lo, int64_t hi) {
  if (hi <= lo) return lo;
  const auto span = static_cast<uint64_t>(hi - lo) + 1;
  return lo + static_cast<int64_t>(rng_() % span);  // the bias is negligible for small spans
}

std::vector<int64_t> FaultModel::Fate(NodeAddress from, NodeAddress to) {
  if (from == to) return {0};
  if (Partitioned(from, to)) return {};
  // Every draw happens whatever the config, so changing one probability does not shift the
  // random sequence the others see.
  const bool drop = Uniform01() < config_.drop_probability;
  const bool duplicate = Uniform01() < config_.duplicate_probability;
  std::vector<int64_t> delays;
  for (int copy = 0; copy < 2; ++copy) {
    int64_t d = UniformInt(config_.min_delay, config_.max_delay);
    const bool reorder = Uniform01() < config_.reorder_probability;
    const int64_t extra = UniformInt(1, std::max<int64_t>(1, config_.reorder_window));
    if (reorder && config_.reorder_window > 0) d += extra;
    if (from.site != to.site && config_.other_site_max_delay > 0) {
      d += UniformInt(config_.other_site_min_delay, config_.other_site_max_delay);
    }
    if (copy == 0 || duplicate) delays.push_back(d);
  }
  if (drop) return {};
  return delays;
}

void FaultModel::Partition(const std::vector<NodeAddress>& a, const std::vector<NodeAddress>& b) {
  for (const auto& x : a) {
    for (const auto& y : b) {
      if (x != y) blocked_.insert(std::minmax(x, y));
    }
  }
}

void FaultModel::Isolate(NodeAddress node) { isolated_.insert(node); }

void FaultModel::Heal() {
  blocked_.clear();
  isolated_.clear();
}

bool FaultModel::Partitioned(NodeAddress from, NodeAddress to) const {
  if (from == to) return false;
  if (isolated_.count(from) || isolated_.count(to)) return true;
  return blocked_.count(std::minmax(from, to)) > 0;
}

}  // namespace dt
