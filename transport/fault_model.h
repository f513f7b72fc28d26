// FaultModel: seeded, deterministic decisions to drop, duplicate, delay and reorder messages, and
// which node pairs are partitioned.
#pragma once

#include <cstdint>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "base/feature_id.h"

namespace dt {

// Faults applied to each delivery of a message to one receiver. Delays are in ticks: virtual
// milliseconds in SimNetwork, HandleTimeout calls in FaultyTransport.
struct FaultConfig {
  double drop_probability = 0.0;       // [0, 1]
  double duplicate_probability = 0.0;  // [0, 1]: one extra copy, with its own delay
  int64_t min_delay = 0;               // every copy waits a uniform delay in [min, max]
  int64_t max_delay = 0;
  double reorder_probability = 0.0;  // [0, 1]: a copy waits up to reorder_window more, so later
  int64_t reorder_window = 0;        // messages overtake it
  // A copy from a node of another site waits a uniform extra delay in [min, max] on top: a
  // WAN's latency between sites, where a site's own LAN has none (docs/deploy.md).
  int64_t other_site_min_delay = 0;
  int64_t other_site_max_delay = 0;
};

// A delay with jitter as one uniform range: [delay - jitter, delay + jitter], as `tc netem delay
// <delay> <jitter>` words it. Throws std::invalid_argument naming both if jitter > delay or either
// is negative.
std::pair<int64_t, int64_t> DelayRange(int64_t delay, int64_t jitter);

// Throws std::invalid_argument naming the field if a probability is outside [0, 1] or a delay is
// negative or a min delay exceeds its max.
void CheckFaultConfig(const FaultConfig& config);

// The same seed and the same sequence of calls give the same decisions, on every platform (the
// generator is std::mt19937_64, whose output the standard fixes; no std distributions are used).
class FaultModel {
 public:
  FaultModel(FaultConfig config, uint64_t seed);

  void set_config(FaultConfig config);
  const FaultConfig& config() const { return config_; }

  // The delays (ticks) of the copies of one message from `from` to `to`: empty if dropped or
  // partitioned, one entry normally, two when duplicated. Messages a node sends itself are never
  // faulted (loopback). The other-site delay is drawn only when it is configured and the sites
  // differ, so exercises without it keep the decisions their seeds gave before it existed.
  std::vector<int64_t> Fate(NodeAddress from, NodeAddress to);

  // No traffic in either direction between any node of a and any node of b.
  void Partition(const std::vector<NodeAddress>& a, const std::vector<NodeAddress>& b);
  // No traffic between node and anyone else.
  void Isolate(NodeAddress node);
  // Ends every partition and isolation.
  void Heal();
  bool Partitioned(NodeAddress from, NodeAddress to) const;

 private:
  double Uniform01();
  int64_t UniformInt(int64_t lo, int64_t hi);  // inclusive

  FaultConfig config_;
  std::mt19937_64 rng_;
  std::set<std::pair<NodeAddress, NodeAddress>> blocked_;  // (lower, higher) address
  std::set<NodeAddress> isolated_;
};

}  // namespace dt
